"""The controls experiment's run specs."""

from mat_hopper.experiments import controls as ce


def test_attribution_tasks_drop_mds_springs_and_match_the_axial_step():
    tasks = ce.attribution_tasks("quick", designs=("MD", "SS"), behaviours=("forward",), replicates=2)
    cells = {(t.labels["mass_of"], t.labels["springs"]) for t in tasks}
    assert cells == {("MD", "rigid"), ("SS", "rigid"), ("SS", "paper"), ("SS", "axial"), ("SS", ce.RIGID_AT_AXIAL_STEP)}
    by = {(t.labels["mass_of"], t.labels["springs"], t.labels["replicate"]): t for t in tasks}
    axial, rigid = by[("SS", "axial", 0)], by[("SS", ce.RIGID_AT_AXIAL_STEP, 0)]
    assert rigid.settings == axial.settings and all(e is None for e in rigid.design.moduli_gpa)
