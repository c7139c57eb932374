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


def test_a_gradient_and_its_controls_share_one_step_where_the_step_is_auto():
    """Under bending (timestep auto) a gradient, its mass-matched leg and
    titanium run at the step the finest of them needs, so a pair differs in
    the leg alone; under paper all run at the profile's 1e-4 s."""
    from mat_hopper.core.timestep import auto_timestep
    from mat_hopper.experiments.common_step import common_step

    for contact in ("authors", "stiff"):
        tasks = stress_pair_tasks("paper", ("bending",), contact=contact)
        by_gradient = {}
        for t in tasks:
            by_gradient.setdefault(t.labels["gradient"], set()).add((t.settings.timestep_s, t.settings.substeps))
        assert all(len(steps) == 1 for steps in by_gradient.values()), by_gradient
        legs = {}
        for t in tasks:
            legs.setdefault(t.labels["gradient"], {})[t.labels["leg"]] = t.design
        for name, steps in by_gradient.items():
            period, k = common_step(legs[name].values(), "bending", contact)
            assert steps == {(period / k, k)}
            # independently of common_step: no leg of the trio runs coarser than its own auto step needs
            ((dt, substeps),) = steps
            for leg in legs[name].values():
                own_k, own_dt = auto_timestep(leg, "bending", contact=contact)
                assert dt <= own_dt * (1 + 1e-12) and dt * substeps <= own_k * own_dt * (1 + 1e-12)
        # the shared step is not every leg's own: some leg would run at another alone
        own = {auto_timestep(leg, "bending", contact=contact)[1] for trio in legs.values() for leg in trio.values()}
        shared = {dt for steps in by_gradient.values() for dt, _ in steps}
        assert own - shared
    paper = stress_pair_tasks("paper", ("paper",))
    assert {t.settings.timestep_s for t in paper} == {1e-4}
    # one_step=False (chapter 8b, which reads only whether each bending leg stayed up): each leg's own step
    own = stress_pair_tasks("paper", ("bending",), one_step=False)
    assert {t.settings.timestep_s for t in own} == {auto_timestep(t.design, "bending")[1] for t in own}


def test_the_bending_shares_take_the_figure_seeds_and_bad_counts_are_refused():
    """The share that stayed up is read by no test: its runs take the
    profile's figure_replicates (3 at paper), seeds 0-2 of the paired runs'."""
    paper = get_profile("paper")
    full = stress_pair_tasks(paper, ("bending",), one_step=False)
    few = stress_pair_tasks(paper, ("bending",), one_step=False, replicates=paper.figure_replicates)
    assert paper.figure_replicates == 3 and len(full) == 10 * len(few) // 3
    assert {t.labels["replicate"] for t in few} == {0, 1, 2}
    assert {t.key() for t in few} <= {t.key() for t in full}
    for bad in (0, -1, 2.5, "3", True, float("nan")):
        with pytest.raises(ValueError, match="replicates"):
            stress_pair_tasks(paper, ("bending",), replicates=bad)
    # one convention named as a string is that convention, not its letters; none is refused
    assert [t.key() for t in stress_pair_tasks("quick", "bending")] == [
        t.key() for t in stress_pair_tasks("quick", ("bending",))
    ]
    with pytest.raises(ValueError, match="conventions"):
        stress_pair_tasks("quick", ())
