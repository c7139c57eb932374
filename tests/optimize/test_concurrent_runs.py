"""Several runs on one study evaluate each design once: each claims a worker
index in the storage (mat_hopper.optimize._workers) that seeds its sampler
apart from the others', and the paper designs are queued once. Runs use a
2 s profile (tiny)."""

from __future__ import annotations

import collections
import json
import os
import subprocess
import sys
import textwrap
import time

import optuna
import pytest
from optuna.trial import TrialState
from pg_server import new_database

from mat_hopper.optimize import open_storage
from mat_hopper.optimize._samplers import sampler_seed
from mat_hopper.optimize._workers import RUN_ATTR, claim_worker, release_worker

optuna.logging.set_verbosity(optuna.logging.WARNING)
REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
ENV = {**os.environ, "PYTHONPATH": REPO + os.pathsep + os.environ.get("PYTHONPATH", "")}
ENV.pop("MAT_HOPPER_PROFILE", None)
ENV.pop("MAT_HOPPER_CACHE", None)


def test_runs_on_one_study_claim_different_indices(tmp_path):
    storage = open_storage(f"sqlite:///{tmp_path}/w.db")
    optuna.create_study(study_name="w", storage=storage)
    sid = storage.get_study_id_from_name("w")
    a, ia = claim_worker(storage, sid)
    b, ib = claim_worker(storage, sid)
    assert (ia, ib) == (0, 1)  # two live runs (here: of one process)
    release_worker(storage, sid, a, ia)
    c, ic = claim_worker(storage, sid)
    assert ic == 0  # an index given back is taken again: one run at a time is always 0
    # a claim of a process of this machine that is gone is not live
    dead = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"], capture_output=True, text=True)
    me = storage.get_study_user_attrs(sid)[c]
    storage.set_study_user_attr(sid, f"{RUN_ATTR}dead", {**me, "index": 1, "pid": int(dead.stdout)})
    release_worker(storage, sid, b, ib)
    d, id_ = claim_worker(storage, sid)
    assert id_ == 1  # 0 is c's; 1 is free (b gave it back, the dead claim is not live)
    assert sampler_seed(0, 8, 0) == sampler_seed(0, 8) != sampler_seed(0, 8, 1)  # worker 0: the seeds of before


RUN = textwrap.dedent(
    """
    import sys, time
    from mat_hopper.experiments.profiles import Profile
    from mat_hopper.optimize import Objective, RunOptions, SearchSpace, StudyConfig, run_study
    url, start, cache = sys.argv[1], float(sys.argv[2]), sys.argv[3]
    config = StudyConfig("both", SearchSpace(), Objective(replicates=0, profile=Profile("tiny", 2.0, 0.5)))
    options = RunOptions(trials=24, workers=1, storage=url, progress=False, cache_dir=cache, batch_size=4)
    time.sleep(max(0.0, start - time.time()))  # both at the same moment
    print(run_study(config, options).worker)
    """
)


def _two_runs_evaluate_each_design_once(url, tmp_path):
    """Two commands started together on one fresh study of 24 trials (8
    paper designs, then sampled ones), 4 per round: both sample while TPE
    still draws at random (its first 10 trials), so samplers of one seed
    repeat each other's draws (4 of the 24 trials, in 5 of 5 tries with
    the worker index left out of the seed); with it, none is repeated."""
    start = time.time() + 3.0
    procs = [
        subprocess.Popen(
            [sys.executable, "-c", RUN, url, str(start), str(tmp_path / f"cache{i}")],
            env=ENV,
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
        )
        for i in range(2)
    ]
    outs = [p.communicate(timeout=600) for p in procs]
    for p, (_, err) in zip(procs, outs):
        assert p.returncode == 0, err
    assert sorted(int(o.split()[-1]) for o, _ in outs) == [0, 1]  # two indices, two seeds
    study = optuna.load_study(study_name="both", storage=open_storage(url))
    done = [t for t in study.trials if t.state == TrialState.COMPLETE]
    assert len(done) >= 24 and not [t for t in study.trials if t.state == TrialState.RUNNING]
    sampled = [t for t in study.trials[:16] if "paper_design" not in t.user_attrs]
    # both runs sampled before TPE left its random start: otherwise one seed for both could not show
    assert len({t.user_attrs["worker"]["pid"] for t in sampled}) == 2
    params = collections.Counter(json.dumps(t.params, sort_keys=True) for t in done)
    assert max(params.values()) == 1, [p for p, n in params.items() if n > 1]
    seeds = [t.user_attrs.get("paper_design") for t in study.trials if t.user_attrs.get("paper_design")]
    assert len(seeds) == len(set(seeds)) == 8  # the paper designs queued once


@pytest.mark.slow
def test_two_runs_on_one_fresh_sqlite_study_evaluate_each_design_once(tmp_path):
    _two_runs_evaluate_each_design_once(f"sqlite:///{tmp_path}/both.db", tmp_path)


@pytest.mark.slow
def test_two_runs_on_one_fresh_postgresql_study_evaluate_each_design_once(pg_server, tmp_path):
    _two_runs_evaluate_each_design_once(new_database(pg_server), tmp_path)
