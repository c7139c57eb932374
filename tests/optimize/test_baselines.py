"""A run that fell or diverged is never a baseline nor a comparator: the
report leaves it out and says why (mat_hopper.optimize.report.baseline_runs),
racing never promotes it nor ranks the others against it
(mat_hopper.optimize._racing.promote), and the end-of-study line counts
it. Runs use a 2 s profile (tiny)."""

from __future__ import annotations

import optuna
import pytest

from mat_hopper.cli import main
from mat_hopper.experiments.profiles import Profile
from mat_hopper.optimize import (
    Evaluation,
    Objective,
    RunOptions,
    SearchSpace,
    StudyConfig,
    fall_reason,
    promote,
    run_study,
    write_report,
)

optuna.logging.set_verbosity(optuna.logging.WARNING)
TINY = Profile("tiny", duration_s=2.0, transient_s=0.5)


@pytest.fixture(scope="module")
def five_segments(tmp_path_factory):
    """The newcomer's study, --segments 5: SS and rho-inc diverge within
    5 ms at the 1e-4 s step (their 5-segment springs are too stiff), the
    third paper design, PVC-Ti-SS, hops. (studies dir, name)."""
    root = tmp_path_factory.mktemp("five")
    config = StudyConfig("five", SearchSpace(n_segments=5), Objective(profile=TINY, replicates=0))
    options = RunOptions(trials=3, workers=1, studies_dir=str(root), progress=False, cache_dir=str(root / "cache"))
    res = run_study(config, options)
    assert res.done == 3
    return root, "five", res


def test_a_diverged_baseline_is_left_out_and_named(five_segments):
    root, name, res = five_segments
    storage = optuna.storages.RDBStorage(f"sqlite:///{root}/{name}.db")
    rep = write_report(name, storage, str(root / "report"))
    assert rep["baselines"] == {}  # both diverged: no comparator
    left = rep["baselines_left_out"]
    assert set(left) == {"SS", "rho-inc"}
    assert left["SS"].startswith("diverged at t = 0.00") and left["SS"].endswith("s (ramp)")
    assert not [c for c in rep["pareto"].columns if "_vs_" in c]  # no percent change against them
    assert rep["feasibility"].reasons.get("diverged", 0) >= 2


def test_the_report_says_which_baseline_is_left_out(five_segments, capsys):
    root, name, _ = five_segments
    assert main(["optimize", "--report", name, "--studies-dir", str(root), "--out", str(root / "cli-report")]) == 0
    out = capsys.readouterr().out
    assert "SS left out as a baseline: diverged at t = 0.00" in out
    assert "rho-inc left out as a baseline: diverged at t = " in out
    assert "  SS: tracking error" not in out  # its values are not quoted


def test_the_study_ends_with_its_feasibility(five_segments):
    _, _, res = five_segments
    f = res.feasibility
    assert f.finished == 3 and f.feasible + sum(f.reasons.values()) == 3
    assert f.reasons["diverged"] >= 2
    assert f.text().startswith(f"feasible: {f.feasible} of 3 finished trials; not feasible: ")
    assert f"{f.reasons['diverged']} diverged" in f.text()


def test_fall_reason_words():
    assert fall_reason([{"behaviour": "ramp", "upright": True, "diverged_at_s": None}]) is None
    rows = [
        {"behaviour": "ramp", "upright": False, "diverged_at_s": None, "replicate": 1001},
        {"behaviour": "circle", "upright": False, "diverged_at_s": 0.0043, "replicate": -1},
    ]
    assert fall_reason(rows) == "diverged at t = 0.0043 s (circle)"
    assert fall_reason(rows[:1]) == "fell (ramp, replicate seed 1001: base below 0.1 m at the end)"


def _ev(values, constraints=(0.0, 0.0)):
    return Evaluation(values=tuple(values), constraints=tuple(constraints), hop_height_m=1.0)


def test_racing_never_promotes_a_fallen_run_nor_ranks_against_it():
    """Trial 0 fell (unstable 1) with the lowest values of all: it is not
    promoted, and it does not push the standing trials off the first
    layer: 1 and 2 (a trade-off) stay ahead of 3, which 1 dominates."""
    recs = {
        0: _ev((0.001, 0.001), (0.9, 1.0)),  # diverged: a few ms of a run
        1: _ev((1.0, 2.0)),
        2: _ev((2.0, 1.0)),
        3: _ev((1.5, 2.5)),
        4: _ev((0.5, 0.5), (0.0, 1.0)),  # fell, otherwise feasible
    }
    assert promote(recs, 5) == [1, 2, 3]
    assert promote(recs, 1) == [1]
    assert promote({0: recs[0], 4: recs[4]}, 2) == []  # nothing stood: nothing promoted
    three = Evaluation((0.1, 0.1), (0.0, 1.0, -0.2), 1.0, constraint_names=("hop_height", "unstable", "leg_mass"))
    assert promote({0: three, 1: recs[1]}, 2) == [1]


def test_the_command_ends_with_the_feasibility_line(tmp_path, monkeypatch, capsys):
    """optimize --segments 5: SS and rho-inc (the first two queued) diverge
    within 5 ms, so two quick trials cost next to nothing; the command's
    last lines say how many were feasible and why the others were not."""
    monkeypatch.chdir(tmp_path)
    argv = ["optimize", "--study", "s5", "--segments", "5", "--trials", "2", "--replicates", "0"]
    assert main([*argv, "--profile", "quick", "--workers", "1", "--no-progress", "--cache", "cache"]) == 0
    out = capsys.readouterr().out.splitlines()
    assert out[0].startswith("study s5 (sqlite:///") and out[0].endswith("2/2 trials finished")
    assert out[1] == "feasible: 0 of 2 finished trials; not feasible: 2 diverged"


def test_the_feasibility_line_counts_what_racing_pruned():
    """Racing stops trials at a lower rung: the line says so, and what its
    count counts (trials at full fidelity), rather than "3 of 3" beside a
    study of 9 trials."""
    from mat_hopper.optimize._feasibility import Feasibility

    assert Feasibility(finished=3, feasible=3, pruned=6).text() == (
        "feasible: 3 of 3 trials finished at full fidelity (6 more stopped on a screening rung)"
    )
    assert Feasibility(finished=3, feasible=3).text() == "feasible: 3 of 3 finished trials"
