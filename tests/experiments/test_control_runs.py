"""The controls experiment's run specs."""

import pytest

from mat_hopper.experiments import controls as ce


def test_attribution_tasks_drop_mds_springs_and_match_the_axial_step():
    tasks = ce.attribution_tasks("paper", designs=("MD", "SS"), behaviours=("forward",), replicates=2)
    cells = {(t.labels["mass_of"], t.labels["springs"]) for t in tasks}
    assert cells == {("MD", "rigid"), ("SS", "rigid"), ("SS", "paper"), ("SS", "axial"), ("SS", ce.RIGID_AT_AXIAL_STEP)}
    by = {(t.labels["mass_of"], t.labels["springs"], t.labels["replicate"]): t for t in tasks}
    axial, rigid = by[("SS", "axial", 0)], by[("SS", ce.RIGID_AT_AXIAL_STEP, 0)]
    assert rigid.settings == axial.settings and all(e is None for e in rigid.design.moduli_gpa)


def test_a_profile_without_substep_studies_runs_no_axial_arms():
    """The quick profile (CI's book): rigid and paper springs only; the
    robustness study drops its axial and 2e-5 s variants the same way."""
    from mat_hopper.experiments.paper import get_experiment
    from mat_hopper.experiments.profiles import PROFILES

    assert PROFILES["paper"].substep_studies and not PROFILES["quick"].substep_studies
    tasks = ce.attribution_tasks("quick", designs=("MD", "SS"), behaviours=("forward",), replicates=2)
    assert {(t.labels["mass_of"], t.labels["springs"]) for t in tasks} == {
        ("MD", "rigid"),
        ("SS", "rigid"),
        ("SS", "paper"),
    }
    assert all(t.settings.substeps == 1 for t in tasks)
    study = get_experiment("robustness")
    quick = {t.labels["variant"] for t in study.tasks("quick", 2)}
    paper = {t.labels["variant"] for t in study.tasks("paper", 2)}
    assert paper - quick == {"axial", "2e-5 s physics", "2e-5 s step"}
    assert {t.labels["substeps"] for t in study.tasks("quick", 2)} == {1}


def test_substep_studies_must_be_a_bool():
    from mat_hopper.experiments.profiles import Profile

    with pytest.raises(ValueError, match="substep_studies must be True or False"):
        Profile("p", 12.0, 4.0, substep_studies="False")


def test_push_scale_is_a_profile_setting_that_reaches_every_replicate():
    from dataclasses import replace

    from mat_hopper.experiments.profiles import PROFILES

    quick = PROFILES["quick"]
    assert quick.push_scale == 1.0 and quick.replicate(2).push_force_n == 5.0
    doubled = replace(quick, push_scale=2.0)
    assert doubled.replicate(2).push_force_n == 10.0
    # the same seed draws the same push time: only the force moves
    assert doubled.replicate(2).push_window_s == quick.replicate(2).push_window_s
    tasks = ce.push_scale_tasks(quick, designs=("SS",), scales=(0.0, 2.0), replicates=2)
    assert sorted({t.settings.perturbation.push_force_n for t in tasks}) == [0.0, 10.0]
    with pytest.raises(ValueError, match="push_scale"):
        replace(quick, push_scale=-1.0)


def test_control_tables_record_names_not_latencies():
    """The sensor timing column holds its name (as SimSettings.columns does),
    never the int-like SensorTiming; control kinds are read any case."""
    specs = {
        "controls": ce.control_tasks("quick", designs=("SS",), behaviours=("static",), kinds=("Mass",), replicates=2),
        "attribution": ce.attribution_tasks("quick", designs=("MD",), behaviours=("static",), replicates=2),
        "push_scale": ce.push_scale_tasks("quick", designs=("SS",), scales=(1.0,), replicates=2),
    }
    for name, tasks in specs.items():
        timings = [t.labels["sensor_timing"] for t in tasks]
        assert timings and all(type(v) is str and v == "authors" for v in timings), name
    controls = specs["controls"]
    assert {t.labels["control"] for t in controls} == {"none", "mass"}
    assert {t.labels["design"] for t in controls} >= {"SS~mass"}
    with pytest.raises(ValueError, match="unknown control 'stiff'"):
        ce.control_tasks("quick", designs=("SS",), kinds=("stiff",), replicates=2)
