"""The design optimizer: search space, constraints, samplers, storages
(SQLite and a real PostgreSQL server), the one loop and its evaluation
processes, dead processes, reports. Runs use a 2 s profile (tiny) so the
file stays short."""

from __future__ import annotations

import json
import math
import os
import signal
import subprocess
import sys
import time
import warnings

import numpy as np
import optuna
import pandas as pd
import pytest
from optuna.trial import TrialState
from running_trials import (
    descendants,
    stop_a_running_trial,
    stop_an_evaluation_process,
    wait_for_evaluation_processes,
)

from mat_hopper.cli import main
from mat_hopper.core.materials import LegDesign, paper_designs
from mat_hopper.experiments.profiles import Profile
from mat_hopper.optimize import (
    DENSITY_BOUNDS_G_CM3,
    MODULUS_BOUNDS_GPA,
    Evaluator,
    Lost,
    Objective,
    RunOptions,
    SearchSpace,
    StudyConfig,
    check_sampler,
    create_or_load,
    evaluate,
    open_storage,
    resample,
    run_loop,
    run_study,
)
from mat_hopper.optimize._samplers import make_sampler, sampler_seed
from mat_hopper.optimize._storage import ERROR_ATTR, FAIL_REASON_ATTR, PAPER_ATTR, WORKER_ATTR
from mat_hopper.optimize._study import counts
from mat_hopper.optimize.report import hypervolume_2d, pareto_frame, replay, write_report

optuna.logging.set_verbosity(optuna.logging.WARNING)
TINY = Profile("tiny", duration_s=2.0, transient_s=0.5)
TINY_OBJ = Objective(replicates=0, profile=TINY)
REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def _env():
    """This interpreter's environment (the test's cache included) with the repository importable."""
    return {**os.environ, "PYTHONPATH": REPO + os.pathsep + os.environ.get("PYTHONPATH", "")}


def tiny_config(name, **space):
    return StudyConfig(name, SearchSpace(**space), TINY_OBJ)


@pytest.fixture(autouse=True)
def own_cache(tmp_path, monkeypatch):
    """Every test's runs in a cache of its own (a run cached by another
    test would finish at once)."""
    monkeypatch.setenv("MAT_HOPPER_CACHE", str(tmp_path / "cache"))


def _trials(url, name):
    """A study's trials by number; paper designs still queued (WAITING: a
    study smaller than the nine seeds) left out."""
    study = optuna.load_study(study_name=name, storage=open_storage(url))
    ts = [t for t in study.get_trials() if not (t.state == TrialState.WAITING and PAPER_ATTR in t.user_attrs)]
    return sorted(ts, key=lambda t: t.number), study


# --- a real PostgreSQL server: tests/pg_server.py ----------------------------


# --- search space -----------------------------------------------------------


@pytest.mark.parametrize(
    "kwargs, field",
    [
        ({"density_g_cm3": (5.0, 5.0)}, "density_g_cm3"),
        ({"density_g_cm3": (10.0, 1.0)}, "density_g_cm3"),
        ({"modulus_gpa": (100.0, 10.0)}, "modulus_gpa"),
        ({"modulus_gpa": (0.0, 10.0)}, "modulus_gpa"),
        ({"n_segments": 0}, "n_segments"),
        ({"kinds": ("continuous", "catalogue")}, "kinds"),
        ({"kinds": "grid"}, "kinds"),
        ({"kinds": "catalogue", "materials": ("Unobtainium",)}, "unknown material"),
        ({"kinds": "catalogue", "materials": ("MD",)}, "rigid"),
    ],
)
def test_space_rejects_bad_bounds_and_kinds(kwargs, field):
    with pytest.raises(ValueError, match=field):
        SearchSpace(**kwargs)


def test_default_bounds_span_the_paper_classes():
    assert DENSITY_BOUNDS_G_CM3 == (0.9, 20.0)
    assert MODULUS_BOUNDS_GPA == (0.1, 1000.0)
    for mat in ("PVC", "Al", "Ti", "SS"):
        m = paper_designs()[mat].segments[0]
        assert DENSITY_BOUNDS_G_CM3[0] <= m.density_g_cm3 <= DENSITY_BOUNDS_G_CM3[1]
        assert MODULUS_BOUNDS_GPA[0] <= m.modulus_gpa <= MODULUS_BOUNDS_GPA[1]


@pytest.mark.parametrize("sampler", ["tpe", "nsga2"])
def test_suggested_designs_respect_bounds(sampler):
    space = SearchSpace(
        n_segments=4,
        kinds=("continuous", "catalogue", "continuous", "continuous"),
        density_g_cm3=(2.0, 3.0),
        modulus_gpa=(50.0, 60.0),
        materials=("PVC", "Ti"),
    )
    study = optuna.create_study(directions=["minimize"] * 2, sampler=make_sampler(sampler, 1))
    seen = set()
    for i in range(60):
        t = study.ask()
        d = space.suggest(t)
        assert d.n_segments == 4
        for k, m in enumerate(d.segments):
            if k == 1:
                assert m.name in ("PVC", "Ti")
                seen.add(m.name)
            else:
                assert 2.0 <= m.density_g_cm3 <= 3.0 and 50.0 <= m.modulus_gpa <= 60.0
        assert space.design(t.params).segments == d.segments
        study.tell(t, [float(i % 7), float(i % 5)])
    assert seen == {"PVC", "Ti"}


def test_paper_designs_seed_every_space():
    seeds = dict(SearchSpace().seeds())
    # all nine paper designs but the rigid MD, which a continuous segment cannot express
    assert list(seeds) == ["SS", "rho-inc", "PVC-Ti-SS", "SS-Ti-PVC", "rho-dec", "PVC", "Al", "Ti"]
    assert seeds["SS-Ti-PVC"]["seg1_modulus_gpa"] == 193.0 and seeds["SS-Ti-PVC"]["seg3_density_g_cm3"] == 1.39
    assert seeds["rho-inc"] == {
        "seg1_density_g_cm3": 1.39,
        "seg1_modulus_gpa": 70.0,
        "seg2_density_g_cm3": 4.43,
        "seg2_modulus_gpa": 70.0,
        "seg3_density_g_cm3": 8.0,
        "seg3_modulus_gpa": 70.0,
    }
    cat = dict(SearchSpace(kinds="catalogue").seeds())
    assert cat == {
        "SS": {f"seg{i}_material": "SS" for i in (1, 2, 3)},
        "PVC-Ti-SS": {"seg1_material": "PVC", "seg2_material": "Ti", "seg3_material": "SS"},
        "SS-Ti-PVC": {"seg1_material": "SS", "seg2_material": "Ti", "seg3_material": "PVC"},
        "PVC": {f"seg{i}_material": "PVC" for i in (1, 2, 3)},
        "Al": {f"seg{i}_material": "Al" for i in (1, 2, 3)},
        "Ti": {f"seg{i}_material": "Ti" for i in (1, 2, 3)},
    }
    six = SearchSpace(n_segments=6).seeds()
    rho = dict(six)["rho-inc"]
    assert [rho[f"seg{i}_density_g_cm3"] for i in range(1, 7)] == [1.39, 1.39, 4.43, 4.43, 8.0, 8.0]
    assert [m.name for m in resample(paper_designs()["PVC-Ti-SS"], 2)] == ["PVC", "SS"]
    # bounds that exclude SS's 193 GPa leave it out
    assert [n for n, _ in SearchSpace(modulus_gpa=(1.0, 150.0)).seeds()] == ["rho-inc", "rho-dec", "PVC", "Al", "Ti"]


# --- objective and constraints ---------------------------------------------


def test_constraints_feasible_design_and_diverging_design():
    quick = Objective(replicates=0, profile=Profile("quick", 8.0, 3.0))
    ev = evaluate(paper_designs()["SS"], quick)
    h = ev.per_behaviour[0]["hop_height_m"]
    assert ev.constraints == (pytest.approx(abs(h - 1.0) - 0.05), 0.0)
    assert ev.feasible and ev.per_behaviour[0]["n_hops"] >= 3
    strict = evaluate(
        paper_designs()["SS"], Objective(replicates=0, profile=quick.profile, hop_height_tolerance_m=abs(h - 1.0) / 2)
    )
    assert strict.constraints[0] == pytest.approx(abs(h - 1.0) / 2) and strict.constraints[1] == 0.0
    assert not strict.feasible and strict.values == ev.values
    # light and very stiff: diverges at the paper's step; infeasible, finite values, no exception
    bad = evaluate(LegDesign.from_properties([0.9] * 3, [1000.0] * 3), TINY_OBJ)
    assert bad.constraints[1] == 1.0 and not bad.feasible
    assert all(np.isfinite(bad.values)) and bad.per_behaviour[0]["diverged_at_s"] is not None


def test_behaviour_sets_average_and_bad_names():
    obj = Objective(replicates=0, behaviours="static,ramp", profile=TINY)
    ev = evaluate(paper_designs()["SS"], obj)
    rows = ev.per_behaviour
    assert [r["behaviour"] for r in rows] == ["static", "ramp"]
    assert ev.values[0] == pytest.approx((rows[0]["tracking_error_m"] + rows[1]["tracking_error_m"]) / 2)
    with pytest.raises(ValueError, match="unknown behaviour"):
        Objective(replicates=0, behaviours=("hover",))


# --- helpers of the report --------------------------------------------------


def test_pareto_frame_keeps_optunas_front_once_with_percent_changes():
    # trials 0-2 are Optuna's best_trials; trial 3 repeats trial 0's values (a retried design)
    frame = pd.DataFrame(
        {
            "trial": [0, 1, 2, 3, 4],
            "state": ["COMPLETE"] * 5,
            "feasible": [True] * 4 + [False],
            "design": list("abcde"),
            "paper_design": [""] * 5,
            "tracking_error_m": [1.0, 2.0, 3.0, 1.0, 0.5],
            "power_w": [3.0, 2.0, 1.0, 3.0, 0.5],
            "hop_height_m": [1.0] * 5,
        }
    )
    front = pareto_frame(frame, {"SS": (2.0, 4.0)}, best=[0, 1, 2, 3])
    assert front["trial"].tolist() == [0, 1, 2]
    assert front["tracking_error_vs_SS_pct"].tolist() == [-50.0, 0.0, 50.0]  # (1-2)/2, (2-2)/2, (3-2)/2
    assert front["power_vs_SS_pct"].tolist() == [-25.0, -50.0, -75.0]  # (3-4)/4, (2-4)/4, (1-4)/4
    assert pareto_frame(frame, best=[]).empty


def test_hypervolume():
    pts = np.array([[1.0, 3.0], [2.0, 2.0], [3.0, 1.0], [2.5, 2.5], [1.0, 3.0]])
    # staircase 1x3, 2x2, 3x1 against (4, 4): 3*1 + 2*1 + 1*1 (+ strips) = 6
    assert hypervolume_2d(pts, (4.0, 4.0)) == pytest.approx(6.0)
    assert hypervolume_2d([[5.0, 5.0]], (4.0, 4.0)) == 0.0


# --- bad input: one line, exit 2, before any work ---------------------------


@pytest.mark.parametrize(
    "argv, text",
    [
        (["--sampler", "cmaes"], "unknown sampler"),
        (["--behaviour", "moonwalk"], "unknown behaviour"),
        (["--storage", "foo://bar/baz"], "unknown storage scheme"),
        (["--density-bounds", "5,1"], "min must be < max"),
        (["--modulus-bounds", "10,10"], "min must be < max"),
        (["--trials", "0"], "trials must be"),
        (["--workers", "0"], "workers must be"),
        (["--profile", "slow"], "unknown profile"),
        (["--ashby-classes", "metal,plastics"], "unknown Ashby class 'plastics'"),
        (["--ashby-classes", "metal", "--density-bounds", "1,9"], "give either bounds or --ashby-classes"),
        (["--segment-mass", "per-capsule"], "unknown segment mass convention"),
        (["--storage", "postgresql+psycopg://nobody@127.0.0.1:1/none"], "cannot reach storage"),
    ],
)
def test_bad_input_is_one_line_exit_2(argv, text, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    trials = [] if "--trials" in argv else ["--trials", "5"]  # an option given twice is refused on its own
    code = main(["optimize", "--study", "bad", *trials, *argv])
    err = capsys.readouterr().err.strip()
    assert code == 2
    assert text in err and len(err.splitlines()) == 1
    assert not (tmp_path / "studies").exists()  # nothing was made


def test_gp_sampler_needs_torch_or_builds():
    try:
        import torch  # noqa: F401
    except ImportError:
        with pytest.raises(ValueError, match="PyTorch"):
            check_sampler("gp")
    else:
        assert type(make_sampler("gp", 0)).__name__ == "GPSampler"


# --- studies on SQLite ------------------------------------------------------


def _check_run(res, trials, url, name):
    """Every trial recorded once: COMPLETE trials = what the run told, in
    trial order, no trial told twice, none left running, each named by
    this process (the one that asked it)."""
    ts, _ = _trials(url, name)
    assert res.lost == []
    told = [n for n, state in res.told]
    assert told == sorted(set(told))
    complete = [t.number for t in ts if t.state == TrialState.COMPLETE]
    assert told == complete and len(complete) == trials
    assert not [t for t in ts if t.state in (TrialState.RUNNING, TrialState.WAITING)]
    params = [json.dumps(t.params, sort_keys=True) for t in ts if t.state == TrialState.COMPLETE]
    assert len(set(params)) == len(params)
    assert {t.user_attrs[WORKER_ATTR]["pid"] for t in ts} == {os.getpid()}
    return ts


def test_sqlite_study_two_workers_paper_designs_first_report_replay(tmp_path, monkeypatch, capsys):
    name = "sq"
    opts = RunOptions(trials=7, workers=2, studies_dir=str(tmp_path / "studies"), progress=False)
    res = run_study(tiny_config(name), opts)
    url = opts.storage_url(name)
    assert url == f"sqlite:///{tmp_path}/studies/sq.db" and res.finished
    ts = _check_run(res, 7, url, name)
    assert [t.user_attrs.get(PAPER_ATTR) for t in ts[:3]] == ["SS", "rho-inc", "PVC-Ti-SS"]
    assert ts[1].params["seg1_density_g_cm3"] == 1.39 and ts[0].params["seg3_modulus_gpa"] == 193.0
    for t in ts:
        assert set(t.constraints) == {"hop_height", "unstable"}
        assert t.user_attrs["result"]["feasible"] == all(v <= 0 for v in t.constraints.values())
    # running again with the same target does nothing; a larger one resumes
    again = run_study(tiny_config(name), opts)
    assert again.told == [] and again.evaluator == "" and again.done == 7

    rep = write_report(name, open_storage(url), str(tmp_path / "report"))
    for p in rep["paths"].values():
        assert os.path.getsize(p) > 0
    assert len(rep["trials"]) == 7 and set(rep["baselines"]) == {"SS", "rho-inc"}
    front = rep["pareto"]
    ok = rep["trials"][(rep["trials"].state == "COMPLETE") & rep["trials"].feasible]
    for _, r in front.iterrows():  # nothing feasible dominates a front member
        dom = (
            (ok.tracking_error_m <= r.tracking_error_m)
            & (ok.power_w <= r.power_w)
            & ((ok.tracking_error_m < r.tracking_error_m) | (ok.power_w < r.power_w))
        )
        assert not dom.any()
    if "SS" in set(front.paper_design):
        assert front.loc[front.paper_design == "SS", "tracking_error_vs_SS_pct"].iloc[0] == 0.0
    hv = rep["hypervolume"]["hypervolume"].to_numpy()
    assert np.all(np.diff(hv) >= 0)
    t, design, ev, _ = replay(name, open_storage(url), 4)
    assert tuple(ev.values) == tuple(t.values)  # bit-identical
    monkeypatch.chdir(tmp_path)
    assert main(["optimize", "--study", name, "--replay", "1"]) == 0
    assert "matches the stored values exactly" in capsys.readouterr().out
    assert main(["optimize", "--report", name, "--out", str(tmp_path / "r2")]) == 0
    assert (tmp_path / "r2" / "pareto.png").exists()


TWO_COMMANDS = """
import sys
from mat_hopper.experiments.profiles import Profile
from mat_hopper.optimize import Objective, RunOptions, SearchSpace, StudyConfig, run_study
config = StudyConfig(sys.argv[1], SearchSpace(), Objective(replicates=0, profile=Profile("blink", 0.2, 0.1)))
if __name__ == "__main__":
    res = run_study(config, RunOptions(trials=25, workers=1, storage=sys.argv[2], seed=int(sys.argv[3]), progress=False))
    print(len(res.told), res.finished or res.running > 0)  # the other's last round may still run
"""


@pytest.mark.parametrize("kind", ["sqlite", "journal"])
def test_each_enqueued_trial_is_taken_by_one_command(kind, tmp_path):
    """Two commands popping queued (WAITING) trials at once, rounds of 8
    asked in a row: SQLite has no row locks (we begin transactions
    IMMEDIATE), the journal appends under a file lock. A trial taken by both
    would be told twice (Optuna refuses the second tell: that command fails)
    or show up twice among the complete trials."""
    name = f"race-{kind}"
    url = f"sqlite:///{tmp_path}/{name}.db" if kind == "sqlite" else f"journal:///{tmp_path}/{name}.log"
    config = StudyConfig(
        name, SearchSpace(), Objective(replicates=0, profile=Profile("blink", duration_s=0.2, transient_s=0.1))
    )
    study = create_or_load(config, open_storage(url))
    rng = np.random.default_rng(0)
    enqueued = [
        {f"seg{i}_{p}": float(rng.uniform(1.0, 9.0)) for i in (1, 2, 3) for p in ("density_g_cm3", "modulus_gpa")}
        for _ in range(17)
    ]
    for params in enqueued:
        study.enqueue_trial(params)
    procs = [
        subprocess.Popen(
            [sys.executable, "-c", TWO_COMMANDS, name, url, str(seed)],
            env=_env(),
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
        )
        for seed in (1, 2)
    ]
    outs = [p.communicate(timeout=300) for p in procs]
    for p, (out, err) in zip(procs, outs):
        assert p.returncode == 0 and out.split()[1] == "True", err
    ts, _ = _trials(url, name)
    complete = [t for t in ts if t.state == TrialState.COMPLETE]
    assert sum(int(out.split()[0]) for out, _ in outs) == len(complete) >= 25  # each told what it asked, once
    assert [t.state for t in ts if t.state != TrialState.COMPLETE] == []
    params = [json.dumps(t.params, sort_keys=True) for t in complete]
    assert len(set(params)) == len(params)
    taken = {json.dumps(p, sort_keys=True) for p in enqueued}
    assert taken <= set(params)  # every queued design ran, once


def test_seeded_study_is_deterministic_with_any_number_of_processes(tmp_path):
    """A fresh study is fixed by its seed and batch size: the same trials
    (parameters and values, bit for bit) with one process or two, with the
    default batch of 8 and with a batch of 3."""
    runs = []
    for name, seed, workers, batch in (("d1", 3, 1, None), ("d2", 3, 2, None), ("d3", 4, 1, None), ("b1", 3, 1, 3)):
        opts = RunOptions(
            trials=10,
            workers=workers,
            seed=seed,
            studies_dir=str(tmp_path),
            progress=False,
            batch_size=batch,
            cache_dir=str(tmp_path / f"cache-{name}"),  # each computes its own runs
        )
        run_study(tiny_config(name), opts)
        ts, _ = _trials(opts.storage_url(name), name)
        runs.append([(t.params, t.values) for t in ts])
    assert runs[0] == runs[1]
    assert runs[0][:8] == runs[2][:8] and runs[0][8:] != runs[2][8:]  # the eight seeds, then the sampler
    assert [p for p, _ in runs[3]] == [p for p, _ in runs[0]]  # TPE's first 10 are random: any batch
    opts = RunOptions(trials=10, workers=2, seed=3, studies_dir=str(tmp_path), progress=False, batch_size=3)
    run_study(tiny_config("b2"), opts)
    assert [(t.params, t.values) for t in _trials(opts.storage_url("b2"), "b2")[0]] == runs[3]
    assert sampler_seed(3, 0) != sampler_seed(3, 5) != sampler_seed(4, 5)


def test_diverging_and_failing_designs_never_crash_the_study(tmp_path):
    coarse = Objective(replicates=0, profile=Profile("coarse", duration_s=2.0, transient_s=0.5, timestep_s=0.02))
    config = StudyConfig("div", SearchSpace(), coarse)
    opts = RunOptions(trials=10, workers=1, studies_dir=str(tmp_path), progress=False)
    storage = open_storage(opts.storage_url("div"))
    study = create_or_load(config, storage)
    bad = {f"seg{i}_{p}": v for i in (1, 2, 3) for p, v in (("density_g_cm3", -1.0), ("modulus_gpa", 10.0))}
    study.enqueue_trial(bad)
    res = run_study(config, opts)
    assert res.finished
    ts, _ = _trials(opts.storage_url("div"), "div")
    assert ts[8].state == TrialState.FAIL and "invalid" in ts[8].user_attrs[ERROR_ATTR]  # after the 8 seeds
    done = [t for t in ts if t.state == TrialState.COMPLETE]
    assert len(done) == 9
    for t in done:  # a 20 ms step diverges for every design: infeasible, finite, recorded
        assert t.constraints["unstable"] == 1.0 and not t.user_attrs["result"]["feasible"]
        assert all(np.isfinite(t.values))
    with pytest.raises(ValueError, match="exists with other settings"):
        create_or_load(StudyConfig("div", SearchSpace(), TINY_OBJ), storage)


class _Losing(Evaluator):
    """An evaluator whose processes always die (or that raises `error`)."""

    name = "losing"

    def __init__(self, error=None):
        self.error, self.rounds = error, []

    def evaluate(self, designs, objective, desc="trials"):
        self.rounds.append(len(designs))
        if self.error:
            raise self.error
        return [Lost("evaluation process died (test)") for _ in designs]


def test_rounds_lost_whole_stop_the_loop_and_errors_fail_the_round():
    """Evaluation processes that die round after round: each round's trials
    are failed and re-queued, and the loop stops after max_retry + 1 such
    rounds (it would ask forever). An evaluator that raises: its round's
    trials fail with the error, which reaches the caller. Nothing is left
    running either way."""
    config = tiny_config("lose")
    for evaluator, raised in ((_Losing(), ValueError), (_Losing(RuntimeError("device lost")), RuntimeError)):
        storage = optuna.storages.InMemoryStorage()
        study = create_or_load(config, storage)
        with pytest.raises(raised) as e:
            run_loop(study, storage, config, evaluator, RunOptions(trials=4, max_retry=1, progress=False))
        ts = study.get_trials()
        assert not [t for t in ts if t.state == TrialState.RUNNING]
        if raised is ValueError:
            assert "died in 2 rounds in a row" in str(e.value) and evaluator.rounds == [4, 4]
            failed = [t for t in ts if t.state == TrialState.FAIL]
            assert len(failed) == 8 and all(t.user_attrs[FAIL_REASON_ATTR].startswith("evaluation") for t in failed)
            assert len([t for t in ts if "failed_trial" in t.system_attrs]) == 8  # each re-queued
        else:
            assert evaluator.rounds == [4]
            assert [t.user_attrs[ERROR_ATTR] for t in ts[:4]] == ["RuntimeError: device lost"] * 4


# --- PostgreSQL: workers, resume by a third process, dead workers ------------


def _cli(*args, **kw):
    return subprocess.run(
        [sys.executable, "-m", "mat_hopper", "optimize", *args],
        env=_env(),
        capture_output=True,
        text=True,
        timeout=120,
        **kw,
    )


@pytest.mark.slow
def test_postgres_two_workers_then_a_third_process_resumes(pg_url):
    name = "pg"
    res = run_study(tiny_config(name), RunOptions(trials=6, workers=2, storage=pg_url, progress=False))
    first = _check_run(res, 6, pg_url, name)
    out = _cli("--study", name, "--trials", "8", "--workers", "1", "--storage", pg_url, "--no-progress")
    assert out.returncode == 0, out.stderr
    assert "8/8 trials finished" in out.stdout
    ts, _ = _trials(pg_url, name)
    assert [(t.params, t.values) for t in ts[:6]] == [(t.params, t.values) for t in first]
    assert [t.state for t in ts] == [TrialState.COMPLETE] * 8
    new_pids = {t.user_attrs[WORKER_ATTR]["pid"] for t in ts[6:]}
    assert len(new_pids) == 1 and not new_pids & {t.user_attrs[WORKER_ATTR]["pid"] for t in first}


@pytest.mark.slow
def test_sigkilled_evaluation_process_loses_only_its_round_which_is_retried(pg_url):
    """An evaluation process SIGKILLed while it simulates: the trials of its
    round that were running are failed (fail_reason) and re-queued, each
    retried once with its parameters, and the command finishes the study."""
    name = "kill"
    # bounds that hold no paper design: nothing enqueued ahead of the re-queued trials
    space = SearchSpace(n_segments=3, density_g_cm3=(1.5, 2.5), modulus_gpa=(0.45, 9.0))
    assert space.seeds() == []
    config = StudyConfig(name, space, Objective(replicates=0, profile=Profile("k", duration_s=3.0, transient_s=0.5)))
    create_or_load(config, open_storage(pg_url))
    proc = subprocess.Popen(
        [
            sys.executable,
            "-m",
            "mat_hopper",
            "optimize",
            "--study",
            name,
            "--trials",
            "6",
            "--workers",
            "2",
            "--batch-size",
            "4",
            "--storage",
            pg_url,
            "--no-progress",
        ],
        env=_env(),
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        running, pid = stop_an_evaluation_process(pg_url, name, proc.pid)
        os.kill(pid, signal.SIGKILL)
        out, err = proc.communicate(timeout=120)
    finally:
        if proc.poll() is None:
            proc.kill()
    assert proc.returncode == 0, err
    assert "an evaluation process died" in out
    ts, _ = _trials(pg_url, name)
    failed = [t for t in ts if t.state == TrialState.FAIL]
    assert failed and {t.number for t in failed} <= running  # the round killed mid-way, no other
    for dead in failed:
        assert dead.user_attrs[FAIL_REASON_ATTR].startswith("evaluation process died")
        retries = [t for t in ts if t.system_attrs.get("failed_trial") == dead.number]
        assert len(retries) == 1 and retries[0].state == TrialState.COMPLETE and retries[0].params == dead.params
    assert sum(t.state == TrialState.COMPLETE for t in ts) == 6
    assert not [t for t in ts if t.state in (TrialState.RUNNING, TrialState.WAITING)]


@pytest.mark.slow
def test_heartbeat_fails_and_retries_the_trial_of_a_dead_machine(pg_url):
    """The command SIGKILLed (as by the OOM killer; a machine lost alike): its
    processes end with it, its heartbeat goes silent, Optuna's
    fail_stale_trials marks the trial failed and our callback enqueues it
    again; a new run finishes the study."""
    name = "hb"
    # bounds that hold no paper design: nothing enqueued ahead of the re-queued trial
    space = SearchSpace(n_segments=3, density_g_cm3=(1.5, 2.5), modulus_gpa=(0.45, 9.0))
    assert space.seeds() == []
    config = StudyConfig(name, space, Objective(replicates=0, profile=Profile("k", duration_s=3.0, transient_s=0.5)))
    create_or_load(config, open_storage(pg_url))
    proc = subprocess.Popen(
        [
            sys.executable,
            "-m",
            "mat_hopper",
            "optimize",
            "--study",
            name,
            "--trials",
            "3",
            "--workers",
            "2",
            "--storage",
            pg_url,
            "--no-progress",
        ],
        env=_env(),
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    try:
        wait_for_evaluation_processes(proc.pid)
        victim, _ = stop_a_running_trial(pg_url, name)
        below = descendants(proc.pid)  # its fork server, resource tracker, evaluation processes
        assert len(below) >= 3
        proc.kill()  # the command alone: its processes end with it
        proc.wait(30)
        deadline = time.monotonic() + 20
        while [q for q in below if os.path.exists(f"/proc/{q}")] and time.monotonic() < deadline:
            time.sleep(0.1)
        assert [q for q in below if os.path.exists(f"/proc/{q}")] == []  # no orphaned process
    finally:
        if proc.poll() is None:
            proc.kill()
    storage = open_storage(pg_url, heartbeat_s=1, grace_s=2)
    study = optuna.load_study(study_name=name, storage=storage)
    assert study.trials[victim].state == TrialState.RUNNING
    time.sleep(2.5)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        optuna.storages.fail_stale_trials(study)
    ts = sorted(study.get_trials(), key=lambda t: t.number)
    assert ts[victim].state == TrialState.FAIL
    waiting = [t for t in ts if t.state == TrialState.WAITING and t.system_attrs.get("failed_trial") == victim]
    assert len(waiting) == 1 and waiting[0].params == ts[victim].params
    res = run_study(config, RunOptions(trials=3, workers=1, storage=pg_url, progress=False))
    assert res.finished and counts(study)[0] == 3
    assert study.trials[waiting[0].number].state == TrialState.COMPLETE


def test_stress_constraints_peak_stress_and_fatigue_life():
    # peak stress <= yield / 2 and a fatigue life, as constraints asked for by name
    prof = Profile("tiny", 3.0, 1.0, 1e-4, 2, 1.0)
    plain = Objective(behaviours=("forward",), profile=prof, convention="bending", replicates=0)
    assert plain.constraint_names == ("hop_height", "unstable")
    assert "max_yield_fraction" not in plain.key()
    ob = Objective(
        behaviours=("forward",),
        profile=prof,
        convention="bending",
        replicates=0,
        max_yield_fraction=0.5,
        min_hops_to_failure=1e6,
    )
    assert ob.constraint_names == ("hop_height", "unstable", "peak_stress", "fatigue_life")
    assert Objective.from_key(ob.key()) == ob
    ev = evaluate(LegDesign.mono("SS"), ob)
    row = ev.per_behaviour[0]
    assert ev.constraint_names == ob.constraint_names and len(ev.constraints) == 4
    assert ev.constraints[2] == pytest.approx(row["yield_ratio"] - 0.5)
    assert ev.constraints[3] == pytest.approx(6.0 - math.log10(row["hops_to_failure"]))
    # SS under bending: tens of MPa against 215 MPa: both feasible
    assert ev.constraints[2] < 0 and ev.constraints[3] < 0
    # a limit no leg meets makes it infeasible
    strict = Objective(
        behaviours=("forward",), profile=prof, convention="bending", replicates=0, max_yield_fraction=1e-6
    )
    assert evaluate(LegDesign.mono("SS"), strict).constraints[2] > 0
    with pytest.raises(ValueError, match="max_yield_fraction"):
        Objective(max_yield_fraction=-1.0)


def test_report_functions_refuse_a_study_the_storage_does_not_hold(tmp_path):
    # a name not in the storage: ValueError naming it and the studies present
    # (not Optuna's KeyError), before anything is written
    from mat_hopper.optimize.report import load, trial_design

    storage = optuna.storages.InMemoryStorage()
    optuna.create_study(study_name="other", storage=storage)
    msg = r"no study 'missing'.*studies present: 'other'"
    with pytest.raises(ValueError, match=msg):
        load("missing", storage)
    with pytest.raises(ValueError, match=msg):
        write_report("missing", storage, str(tmp_path / "report"))
    assert not (tmp_path / "report").exists()
    with pytest.raises(ValueError, match=msg):
        replay("missing", storage, 0)
    with pytest.raises(ValueError, match=msg):
        trial_design("missing", storage, 0)
    with pytest.raises(ValueError, match=r"no study 'missing'.*studies present: none"):
        load("missing", optuna.storages.InMemoryStorage())
    # a SQLite URL of a file that does not exist: refused, and no empty database left behind
    url = f"sqlite:///{tmp_path / 'nosuch.db'}"
    with pytest.raises(ValueError, match="no SQLite file"):
        load("missing", url)
    assert not (tmp_path / "nosuch.db").exists()
