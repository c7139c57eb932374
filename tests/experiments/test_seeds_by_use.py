"""Seeds where a test needs them: the paired claims' grids run the
profile's replicates, the attribution factorial, the inertia-matched
controls and chapter 8b's bending shares (no paired test reads their
seeds) at most FIGURE_REPLICATES (three), and codesign's tuning screens on
short runs."""

import pytest

from mat_hopper.core.behaviours import behaviour
from mat_hopper.core.materials import parse_design
from mat_hopper.experiments import controls
from mat_hopper.experiments.profiles import FIGURE_REPLICATES, get_profile
from mat_hopper.experiments.reproduce import experiment_tasks
from mat_hopper.optimize import codesign


def _seeds(tasks) -> set:
    return {t.labels["replicate"] for t in tasks}


def test_paired_grids_keep_the_profiles_seeds():
    """Experiment 2's sweeps are tested per seed (their equal-mass slopes,
    Holm), so they keep the profile's 10 like experiments 1 and 3; its
    Gibson-Ashby variant, read only as a figure's means, the figure's 3."""
    paper = get_profile("paper")
    tasks = experiment_tasks(paper, ["exp1", "exp2", "exp2-gibson-ashby", "exp3"])
    # -1 is the unperturbed run every experiment keeps
    for name in ("exp1", "exp2", "exp3"):
        assert _seeds(tasks[name]) == {-1, *range(10)}, name
    # the softened sweeps feed a figure of means only (chapter 7): the figure's seeds, the same first three
    assert _seeds(tasks["exp2-gibson-ashby"]) == {-1, 0, 1, 2}
    assert _seeds(experiment_tasks(get_profile("quick"), ["exp2-gibson-ashby"])["exp2-gibson-ashby"]) == {-1, 0, 1}
    assert FIGURE_REPLICATES == 3 and paper.figure_replicates == 3
    assert get_profile("quick").figure_replicates == 2


def test_the_attribution_factorial_runs_three_seeds_and_the_controls_ten():
    paper = get_profile("paper")
    assert _seeds(controls.attribution_tasks(paper, behaviours=("ramp",))) == {0, 1, 2}
    tasks = controls.control_tasks(paper, behaviours=("ramp",))
    # the rigid twins and mass-matched legs feed the claims' paired verdicts: 10 seeds
    assert _seeds(t for t in tasks if t.labels["control"] != "inertia") == set(range(10))
    # the inertia-matched legs feed none (an interval shown beside them): the figure seeds, 0-2 of the same
    assert _seeds(t for t in tasks if t.labels["control"] == "inertia") == {0, 1, 2}
    assert controls.FIGURE_KINDS == ("inertia",)
    # fewer seeds asked for than the figure's: every kind takes them; figure_seeds=False: every kind all of them
    few = controls.control_tasks(paper, behaviours=("ramp",), replicates=2)
    assert _seeds(t for t in few if t.labels["control"] == "inertia") == {0, 1}
    asked = controls.control_tasks(paper, behaviours=("ramp",), kinds=("inertia",), replicates=10)
    assert _seeds(t for t in asked if t.labels["control"] == "inertia") == {0, 1, 2}
    every = controls.control_tasks(paper, behaviours=("ramp",), kinds=("inertia",), replicates=10, figure_seeds=False)
    assert _seeds(t for t in every if t.labels["control"] == "inertia") == set(range(10))
    assert _seeds(controls.attribution_tasks(paper, behaviours=("ramp",), replicates=5)) == set(range(5))


@pytest.mark.parametrize("bad", [2.5, "3", True, float("nan"), float("inf"), -1, 1])
def test_a_seed_count_that_is_no_whole_number_of_at_least_two_is_refused(bad):
    with pytest.raises(ValueError, match="replicates"):
        controls.control_tasks("quick", replicates=bad)
    with pytest.raises(ValueError, match="replicates"):
        controls.attribution_tasks("quick", replicates=bad)


def test_codesign_tunes_on_screening_runs_and_compares_at_full_length():
    paper, quick = get_profile("paper"), get_profile("quick")
    leg = parse_design("Ti")
    beh = behaviour("forward")
    tune = codesign.tuning_task(leg, beh, paper, codesign.authors_gains(), 0).settings
    assert (tune.duration_s, tune.transient_s) == (12.0, 4.0) == (quick.duration_s, quick.transient_s)
    assert (tune.timestep_s, tune.convention) == (paper.timestep_s, paper.convention)
    full = codesign.comparison_tasks({"Ti": leg}, paper, beh, 2)[0].settings
    assert (full.duration_s, full.transient_s) == (60.0, 20.0)
    assert codesign.screen_profile(quick) is quick  # already short: unchanged
