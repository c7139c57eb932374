"""The stress pairs' runs: every gradient, its mass-matched leg and
titanium on shared seeds, per convention and contact."""

import pytest

from mat_hopper.core.control_legs import mass_matched
from mat_hopper.core.materials import paper_designs, parse_design
from mat_hopper.experiments.profiles import get_profile
from mat_hopper.experiments.stress_pairs import GRADIENTS, stress_pair_tasks


def test_the_grid_pairs_each_gradient_with_its_controls_on_the_profiles_seeds():
    quick = get_profile("quick")
    tasks = stress_pair_tasks(quick, ("paper",))
    assert len(tasks) == len(GRADIENTS) * 3 * quick.replicates
    ti_keys = {t.key() for t in tasks if t.labels["leg"] == "titanium"}
    assert len(ti_keys) == quick.replicates  # titanium's runs serve every gradient
    rho = paper_designs()["rho-inc"]
    same_mass = [t for t in tasks if t.labels["gradient"] == "rho-inc" and t.labels["leg"] == "mass-matched"]
    assert [t.design.densities_g_cm3 for t in same_mass] == [mass_matched(rho).densities_g_cm3] * quick.replicates
    # the gradient's own runs are experiment 3's forward replicates: one cache key each
    own = quick.sim_settings(quick.replicate(0), design=rho)
    first = next(t for t in tasks if t.labels["gradient"] == "rho-inc" and t.labels["leg"] == "gradient")
    assert first.settings == own
    assert parse_design("Ti").name in {t.design.name for t in tasks}


def test_the_contact_is_in_every_runs_settings_and_key():
    quick = get_profile("quick")
    soft = stress_pair_tasks(quick, ("bending",))
    stiff = stress_pair_tasks(quick, ("bending",), contact="stiff")
    assert {t.settings.contact for t in stiff} == {"stiff"} and {t.labels["contact"] for t in stiff} == {"stiff"}
    assert not {t.key() for t in soft} & {t.key() for t in stiff}
    with pytest.raises(ValueError):
        stress_pair_tasks(quick, ("bending",), contact="rubber")
