"""A study's Pareto table for the page (mat_hopper.optimize.report), a study run in
rounds, a round left running by a dead run recovered, and chapter 9's study
(mat_hopper.optimize.book_study) and its record read from a finished build."""

from __future__ import annotations

import optuna
import pandas as pd
import pytest

from mat_hopper import optimize


def test_front_table_and_designs():
    front = pd.DataFrame(
        {
            "trial": [0, 7],
            "paper_design": ["SS", ""],
            "tracking_error_m": [0.01, 0.02],
            "power_w": [0.008, 0.005],
            "hop_height_m": [0.96, 0.98],
            "tracking_error_vs_SS_pct": [0.0, 100.0],
            "power_vs_SS_pct": [0.0, -37.5],
            "leg_mass_kg": [8.772, 8.2],
            "seg1_rho_g_cm3": [8.0, 13.4],
            "seg1_e_gpa": [193.0, 4.4],
            "seg2_rho_g_cm3": [8.0, 2.0],
            "seg2_e_gpa": [193.0, 2.4],
        }
    )
    t = optimize.front_table(front)
    assert list(t.columns) == [
        "trial",
        "paper design",
        "tracking error (mm)",
        "hip power (mW)",
        "hop height (m)",
        "tracking vs SS (%)",
        "power vs SS (%)",
        "leg mass (kg)",
        "seg 1 density (g/cm^3)",
        "seg 1 modulus (GPa)",
        "seg 2 density (g/cm^3)",
        "seg 2 modulus (GPa)",
    ]
    assert t.loc[1, "tracking error (mm)"] == 20.0
    assert t.loc[1, "leg mass (kg)"] == 8.2
    assert t.loc[1, "seg 2 density (g/cm^3)"] == 2.0 and t.loc[1, "seg 1 modulus (GPa)"] == 4.4
    noisy = optimize.front_table(front.assign(tracking_error_m_se=[0.001, 0.002], power_w_se=[0.0004, 0.0001]))
    assert list(noisy.columns[3:7]) == ["hip power (mW)", "tracking SE (mm)", "power SE (mW)", "hop height (m)"]
    assert noisy.loc[1, "tracking SE (mm)"] == 2.0
    legs = optimize.front_designs(front)
    assert list(legs) == ["#7"] and legs["#7"].densities_g_cm3 == (13.4, 2.0)
    assert list(optimize.front_designs(front, skip_paper=False, k=1)) == ["#0"]


def test_study_in_rounds_is_the_same_with_one_or_two_processes(tmp_path):
    """Ask a batch, run it as one grid, tell in order: the trials do not
    depend on the number of processes (nor on the cache)."""
    from mat_hopper.experiments.profiles import Profile

    tiny = Profile("tiny", duration_s=2.0, transient_s=0.5)
    config = optimize.StudyConfig("det", optimize.SearchSpace(), optimize.Objective(replicates=0, profile=tiny))
    frames = []
    for workers in (1, 2):
        url = f"sqlite:///{tmp_path}/det{workers}.db"
        opts = optimize.RunOptions(
            trials=11, workers=workers, storage=url, batch_size=3, cache_dir=str(tmp_path / f"cache{workers}")
        )
        optimize.run_study(config, opts)
        study = optuna.load_study(study_name="det", storage=optimize.open_storage(url))
        frames.append(optimize.trials_frame(study, config).drop(columns="worker"))
    assert len(frames[0]) == 11 and (frames[0]["state"] == "COMPLETE").all()
    assert frames[0]["paper_design"].tolist()[:8] == [
        "SS",
        "rho-inc",
        "PVC-Ti-SS",
        "SS-Ti-PVC",
        "rho-dec",
        "PVC",
        "Al",
        "Ti",
    ]
    pd.testing.assert_frame_equal(frames[0], frames[1])


def test_a_round_left_running_by_a_dead_run_is_recovered(tmp_path):
    """A round asked by a run that died (SIGKILL, its trials RUNNING under
    its name): the next run on this machine fails them, re-queues their
    parameters and finishes the study."""
    import subprocess
    import sys

    from mat_hopper.experiments.profiles import Profile
    from mat_hopper.optimize._recovery import worker_identity
    from mat_hopper.optimize._storage import FAIL_REASON_ATTR, WORKER_ATTR

    tiny = Profile("tiny", duration_s=2.0, transient_s=0.5)
    config = optimize.StudyConfig("resume", optimize.SearchSpace(), optimize.Objective(replicates=0, profile=tiny))
    url = f"sqlite:///{tmp_path}/r.db"
    study = optimize.create_or_load(config, optimize.open_storage(url))
    dead = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"], capture_output=True, text=True)
    gone = worker_identity(int(dead.stdout))  # this machine, a process that has ended
    for _ in range(2):
        trial = study.ask()
        trial.set_user_attr(WORKER_ATTR, gone)
        config.space.suggest(trial)
    res = optimize.run_study(config, optimize.RunOptions(trials=3, storage=url, cache_dir=str(tmp_path / "cache")))
    assert res.recovered == [0, 1] and res.finished
    ts = study.get_trials()
    assert [t.state for t in ts[:2]] == [optuna.trial.TrialState.FAIL] * 2
    assert ts[0].user_attrs[FAIL_REASON_ATTR] == f"process of an earlier run died (pid {gone['pid']})"
    retries = {t.system_attrs.get("failed_trial"): t for t in ts if "failed_trial" in t.system_attrs}
    assert sorted(retries) == [0, 1] and [retries[n].params for n in (0, 1)] == [ts[0].params, ts[1].params]
    assert [t.state for t in ts].count(optuna.trial.TrialState.COMPLETE) == 3
    assert not [t for t in ts if t.state == optuna.trial.TrialState.RUNNING]


def _notebook_study_name(profile) -> str:
    """Chapter 9's study name as its notebook built it inline (commit 496aaba), for comparison."""
    import hashlib
    import json

    space = optimize.SearchSpace()
    objective = optimize.Objective(behaviours=("ramp",), profile=profile, replicates=optimize.DEFAULT_REPLICATES,
                                   risk="mean", leg_mass="rho-inc")  # fmt: skip
    racing = optimize.default_racing(objective)
    config_key = {
        "space": space.key(),
        "objective": objective.key(),
        "racing": racing.key(),
        "sampler": "tpe",
        "seed": 0,
    }
    digest = hashlib.sha256(json.dumps(config_key, sort_keys=True, default=str).encode()).hexdigest()[:8]
    return f"book-racing-ramp-{profile.name}-{digest}"


def test_the_book_study_keeps_the_notebooks_study_name_and_brackets():
    from mat_hopper.experiments.profiles import get_profile

    for name, brackets in (("paper", 20), ("quick", 3)):
        profile = get_profile(name)
        book = optimize.book_study(profile)
        assert book.config.name == _notebook_study_name(profile)
        assert (book.screened, book.brackets, book.racing.screen) == (9 * brackets, brackets, 9)
        assert (book.sampler, book.seed, book.objective.behaviours, book.objective.leg_mass) == (
            "tpe",
            0,
            ("ramp",),
            "rho-inc",
        )


def test_the_book_record_refuses_a_missing_or_unfinished_study(tmp_path):
    from mat_hopper.experiments.profiles import get_profile

    profile = get_profile("quick")
    book = optimize.book_study(profile)
    with pytest.raises(ValueError, match=rf"no study '{book.config.name}': .* does not exist"):
        optimize.book_record_tables(tmp_path, tmp_path / "cache", profile)
    storage = optimize.RunOptions(studies_dir=str(tmp_path)).open(book.config.name)
    optimize.create_or_load(book.config, storage)  # made, the paper's designs queued, no trial run
    optimize.dispose(storage)
    with pytest.raises(ValueError, match=r"is not finished: 0 of 3 brackets \(27 trials screened\), 0 complete"):
        optimize.book_record_tables(tmp_path, tmp_path / "cache", profile)


def _finished_by_hand(book, studies_dir, n: int = 10) -> None:
    """The book's study with `n` complete, feasible, mutually non-dominated
    trials (the paper's five queued designs first) and its brackets closed,
    told by hand: no run."""
    from mat_hopper.optimize._objective import RESULT_ATTR
    from mat_hopper.optimize._racing import BRACKET_ATTR

    storage = optimize.RunOptions(studies_dir=str(studies_dir)).open(book.config.name)
    study = optimize.create_or_load(book.config, storage)
    for k in range(n):
        t = study.ask()
        book.config.space.suggest(t)
        for name in book.objective.constraint_names:
            t.set_constraint(name, -1.0)
        t.set_user_attr(RESULT_ATTR, {"feasible": True})
        study.tell(t, [0.01 + 0.001 * k, 0.02 - 0.001 * k])
    study.set_user_attr(BRACKET_ATTR, {"index": book.brackets - 1, "trials": [], "closed": True})
    optimize.dispose(storage)


def test_the_book_record_validates_the_finished_fronts_new_designs_and_the_gradients(tmp_path, monkeypatch):
    import warnings

    from mat_hopper.experiments.profiles import get_profile
    from mat_hopper.optimize import validate

    profile = get_profile("quick")
    book = optimize.book_study(profile)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)  # Optuna: a heartbeat outside Study.optimize
        _finished_by_hand(book, tmp_path)
    with pytest.raises(ValueError, match=r"(\d+) of \1 validation runs are not in the cache"):
        optimize.book_record_tables(tmp_path, tmp_path / "cache", profile)
    seen = {}
    monkeypatch.setattr(validate, "validate_front", lambda legs, objective, **kw: seen.update(legs=legs, ob=objective))
    monkeypatch.setattr(validate, "record_tables", lambda checked, legs, objective, searched: (list(legs), searched))
    names, searched = optimize.book_record_tables(tmp_path, tmp_path / "cache", profile, allow_runs=True)
    new = ["#5", "#6", "#7", "#8", "#9"]  # trials 0-4 are the paper's queued designs: comparators, not new
    assert list(searched) == new and names == [*new, "rho-inc", "rho-dec", "PVC-Ti-SS", "SS-Ti-PVC"]
    assert list(seen["legs"]) == names and seen["ob"] == book.objective
