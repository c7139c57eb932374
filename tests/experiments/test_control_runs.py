"""The controls experiment's run specs."""

import pytest

from mat_hopper.experiments import controls as ce


def test_attribution_tasks_drop_mds_springs_and_match_the_axial_step():
    tasks = ce.attribution_tasks("quick", designs=("MD", "SS"), behaviours=("forward",), replicates=2)
    cells = {(t.labels["mass_of"], t.labels["springs"]) for t in tasks}
    assert cells == {("MD", "rigid"), ("SS", "rigid"), ("SS", "paper"), ("SS", "axial"), ("SS", ce.RIGID_AT_AXIAL_STEP)}
    by = {(t.labels["mass_of"], t.labels["springs"], t.labels["replicate"]): t for t in tasks}
    axial, rigid = by[("SS", "axial", 0)], by[("SS", ce.RIGID_AT_AXIAL_STEP, 0)]
    assert rigid.settings == axial.settings and all(e is None for e in rigid.design.moduli_gpa)


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
