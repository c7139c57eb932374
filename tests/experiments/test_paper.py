"""Experiments as data: grid sizes, spec numbers, profiles, bad input."""

import math

import pytest

from mat_hopper.core import reference as ref
from mat_hopper.core.perturbations import Perturbation
from mat_hopper.experiments.paper import (
    EXPERIMENT_NAMES,
    experiment_1,
    experiment_2,
    experiment_3,
    get_experiment,
    parse_experiments,
)
from mat_hopper.experiments.profiles import PROFILE_ENV, Profile, get_profile, resolve_profile
from mat_hopper.physics.stability import stability_grid


def test_experiment_1_is_five_materials_by_four_behaviours():
    e = experiment_1()
    tasks = e.tasks("paper")
    assert len(tasks) == 20 == e.n_runs
    assert {t.labels["design"] for t in tasks} == set(ref.MONO_MATERIALS)
    assert {t.behaviour.name for t in tasks} == {"static", "forward", "ramp", "circle"}
    assert len({t.key() for t in tasks}) == 20


def test_experiment_2_has_the_spec_sweeps_forward_only():
    tasks = experiment_2().tasks("paper")
    assert len(tasks) == 36 == sum(len(v) for s in ref.SWEEPS.values() for v in s.values())
    assert {t.behaviour.name for t in tasks} == {"forward"}
    for base, sweeps in ref.SWEEPS.items():
        rho0, e0 = ref.MONO_MATERIALS[base]
        for prop, values in sweeps.items():
            pts = [t for t in tasks if t.labels["sweep_base"] == base and t.labels["sweep_property"] == prop]
            assert [t.labels["sweep_value"] for t in pts] == list(values)
            for t in pts:  # the design carries the swept value, the other property at the base's
                want_rho = t.labels["sweep_value"] if prop == "density" else rho0
                want_e = t.labels["sweep_value"] if prop == "modulus" else e0
                assert t.design.densities_g_cm3 == (want_rho,) * 3
                assert t.design.moduli_gpa == (want_e,) * 3
            base_pts = [t for t in pts if t.labels["is_base"]]
            assert len(base_pts) == 1 and base_pts[0].labels["design"] == base


def test_experiment_2_base_points_are_experiment_1_runs():
    """Each sweep's base point is the same physics as exp1's forward run of
    that material: one cache entry serves both."""
    exp1 = {(t.labels["design"], t.behaviour.name): t.key() for t in experiment_1().tasks("quick")}
    for t in experiment_2().tasks("quick"):
        if t.labels["is_base"]:
            assert t.key() == exp1[(t.labels["sweep_base"], "forward")]
        else:
            assert t.key() not in exp1.values()


def test_experiment_3_gradients_and_shared_baselines():
    tasks = experiment_3().tasks("paper")
    grads = [t for t in tasks if t.labels["group"] == "gradient"]
    bases = [t for t in tasks if t.labels["group"] == "baseline"]
    assert len(grads) == 16 and len(bases) == 8
    inc = next(t for t in grads if t.labels["design"] == "rho-inc").design
    assert inc.densities_g_cm3 == ref.GRADIENT_DENSITIES
    assert set(inc.moduli_gpa) == {ref.GRADIENT_MODULUS_GPA}
    dec = next(t for t in grads if t.labels["design"] == "rho-dec").design
    assert dec.densities_g_cm3 == ref.GRADIENT_DENSITIES[::-1]
    pts = next(t for t in grads if t.labels["design"] == "PVC-Ti-SS").design
    assert pts.densities_g_cm3 == tuple(ref.MONO_MATERIALS[m][0] for m in ("PVC", "Ti", "SS"))
    exp1_keys = {t.key() for t in experiment_1().tasks("paper")}
    assert {t.key() for t in bases} <= exp1_keys  # reused through the cache
    assert not ({t.key() for t in grads} & exp1_keys)


def test_stability_map_is_the_spec_grid():
    d, e = stability_grid(ref.STABILITY_GRID_SIZE)
    assert len(d) == len(e) == 20
    assert d[0] == round(ref.STABILITY_DENSITY_RANGE[0], 1) and d[-1] == ref.STABILITY_DENSITY_RANGE[1]
    assert e[0] == ref.STABILITY_MODULUS_RANGE[0] and e[-1] == ref.STABILITY_MODULUS_RANGE[1]
    assert all(round(x, 1) == x for x in list(d) + list(e))
    ratios = e[1:] / e[:-1]  # log-spaced (up to the rounding)
    assert max(ratios) / min(ratios) < 1.05
    tasks = get_experiment("stability").tasks("paper")
    assert len(tasks) == 400
    assert tasks[0].duration_s == ref.STABILITY_TEST_DURATION_S
    assert len(get_experiment("stability").tasks("quick")) == get_profile("quick").stability_grid_size ** 2


def test_replicates_add_seeded_runs_beside_the_unperturbed_one():
    tasks = experiment_1().tasks("quick", replicates=3)
    assert len(tasks) == 20 * 4
    reps = sorted({t.labels["replicate"] for t in tasks})
    assert reps == [-1, 0, 1, 2]
    prof = get_profile("quick")
    for t in tasks:
        r = t.labels["replicate"]
        window = (prof.transient_s, prof.duration_s)  # pushes inside the scored window
        assert t.settings.perturbation == (None if r == -1 else Perturbation.replicate(r, window))
    assert len({t.key() for t in tasks}) == 80


def test_profiles_paper_and_quick(monkeypatch):
    paper = get_profile("paper")
    assert (paper.duration_s, paper.transient_s, paper.timestep_s) == (ref.DURATION_S, ref.TRANSIENT_S, ref.TIMESTEP_S)
    assert paper.stability_grid_size == ref.STABILITY_GRID_SIZE
    quick = get_profile("quick")
    assert quick.duration_s < paper.duration_s and quick.stability_grid_size < paper.stability_grid_size
    s = experiment_1().tasks(quick)[0].settings
    assert (s.duration_s, s.transient_s) == (quick.duration_s, quick.transient_s)
    assert {t.labels["profile"] for t in experiment_3().tasks(quick)} == {"quick"}
    monkeypatch.setenv(PROFILE_ENV, "quick")
    assert resolve_profile() is quick
    monkeypatch.setenv(PROFILE_ENV, "bogus")
    with pytest.raises(ValueError, match="MAT_HOPPER_PROFILE"):
        resolve_profile()
    monkeypatch.delenv(PROFILE_ENV)
    assert resolve_profile() is paper


def test_profile_and_experiment_bad_input():
    with pytest.raises(ValueError, match="unknown profile"):
        get_profile("fast")
    with pytest.raises(ValueError, match="duration"):
        Profile("x", 5.0, 10.0, 1e-4, 4, 1.0)
    with pytest.raises(ValueError, match="stability_grid_size"):
        Profile("x", 12.0, 4.0, 1e-4, 0, 1.0)
    with pytest.raises(ValueError, match="unknown experiment"):
        parse_experiments("1,5")
    with pytest.raises(ValueError, match="at least one"):
        parse_experiments(",")
    with pytest.raises(ValueError, match="replicates"):
        experiment_1().tasks("quick", replicates=-1)
    assert parse_experiments("1,2,3,stability,robust,controls,2-gibson-ashby") == list(EXPERIMENT_NAMES)
    assert parse_experiments("stability, exp1, 1") == ["stability", "exp1"]


def test_every_run_label_names_its_settings():
    for t in experiment_2().tasks("quick"):
        assert {"experiment", "profile", "convention", "design", "behaviour", "replicate"} <= set(t.labels)
        assert math.isclose(t.labels["density_g_cm3"], t.design.densities_g_cm3[0])


def test_exp2_under_gibson_ashby_softens_porous_points():
    from mat_hopper.experiments.paper import experiment_2

    plain, porous = experiment_2(), experiment_2("gibson-ashby")
    assert porous.name == "exp2-gibson-ashby" and plain.name == "exp2"
    tags = lambda e: {p.label: dict(p.tags) for p in e.points}
    a, b = tags(plain), tags(porous)
    assert len(a) == len(b)
    # SS at 4.31 g/cm^3 (solid 8.0, 193 GPa): E = 193 x (4.31 / 8)^2 = 56.02 GPa
    (key,) = [k for k in b if k.startswith("SS rho=4.31")]
    assert b[key]["modulus_gpa"] == pytest.approx(56.02, abs=0.01)
    assert b[key]["porosity_model"] == "gibson-ashby"
    assert a["SS rho=4.31"]["modulus_gpa"] == 193.0
    # denser than the solid (SS at 9.28) and every modulus point: unchanged
    assert b["SS rho=9.28"]["modulus_gpa"] == 193.0
    assert {k: v for k, v in b.items() if v["sweep_property"] == "modulus"} == {
        k: {**v, "porosity_model": "gibson-ashby"} for k, v in a.items() if v["sweep_property"] == "modulus"
    }


def test_experiment_2_runs_under_gibson_ashby_porosity_by_name():
    # a porous steel point (density 2 g/cm^3 of the solid's 8) is softer by
    # (2 / 8)^2 = 1/16 under Gibson-Ashby: 193 GPa -> 12.0625 GPa
    exp = get_experiment("2-gibson-ashby")
    assert exp.name == "exp2-gibson-ashby"
    soft = [p for p in exp.points if dict(p.tags)["sweep_base"] == "SS" and dict(p.tags)["sweep_property"] == "density"]
    by_rho = {dict(p.tags)["density_g_cm3"]: dict(p.tags)["modulus_gpa"] for p in soft}
    assert by_rho[8.0] == 193.0 and by_rho[2.0] == pytest.approx(12.0625)


def test_names_any_case_are_stored_canonical():
    exp = experiment_2("Gibson-Ashby")
    assert exp.name == "exp2-gibson-ashby"
    assert {dict(p.tags)["porosity_model"] for p in exp.points} == {"gibson-ashby"}
    p = Profile("x", 12.0, 4.0, convention="Axial", axial_timestep_s="AUTO")
    assert (p.convention, p.axial_timestep_s) == ("axial", "auto")
    assert p.for_convention("AXIAL") is p


def test_every_experiment_has_its_spellings_and_errors_list_them_all():
    from mat_hopper.experiments.paper import EXPERIMENT_SPELLINGS, EXPERIMENTS, experiment_spellings

    assert list(EXPERIMENT_SPELLINGS) == list(EXPERIMENTS)
    for key, spellings in EXPERIMENT_SPELLINGS.items():
        assert key in spellings  # the canonical key is a spelling too
    with pytest.raises(ValueError) as e:
        parse_experiments("5")
    assert experiment_spellings() in str(e.value) and "stability (4, stab)" in str(e.value)
