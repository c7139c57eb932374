"""The runner: cache keys, caching, failures as rows, resume after SIGKILL,
Dask equivalence, bad input. Runs are 2.5 s of simulated time."""

import dataclasses
import os
import signal
import subprocess
import sys
import textwrap
import time

import pandas as pd
import pytest

import mat_hopper.util.version
from mat_hopper.core.behaviours import behaviour
from mat_hopper.core.controller import ControllerSettings
from mat_hopper.core.materials import LegDesign, parse_design
from mat_hopper.core.perturbations import Perturbation
from mat_hopper.core.sim import SimSettings
from mat_hopper.experiments.cache import Cache
from mat_hopper.experiments.paper import experiment_1
from mat_hopper.experiments.profiles import Profile
from mat_hopper.experiments.runner import Runner, RunSpec, run_grid
from mat_hopper.util import keys as cache_keys
from mat_hopper.util.atomic import TEMP_PREFIX

SHORT = SimSettings(duration_s=2.5, timestep_s=1e-4, transient_s=0.5)
TINY = Profile("tiny", 2.5, 0.5, 1e-4, 2, 0.5)


def spec(design="SS", beh="forward", settings=SHORT, **labels):  # labels: output columns
    d = parse_design(design) if isinstance(design, str) else design
    return RunSpec(d, behaviour(beh), settings, labels)


def small_grid(n=4):
    return experiment_1().tasks(TINY)[:n]


# --- keys -------------------------------------------------------------------


def test_cache_key_changes_with_every_setting(monkeypatch):
    base = spec()
    variants = {
        "design density": spec(LegDesign.from_properties([8.0, 8.0, 8.1], [193.0])),
        "design modulus": spec(LegDesign.from_properties([8.0], [193.0, 193.0, 190.0])),
        "segments": spec(LegDesign.mono("SS", 4)),
        "behaviour": spec(beh="ramp"),
        "duration": spec(settings=dataclasses.replace(SHORT, duration_s=1.6)),
        "timestep": spec(settings=dataclasses.replace(SHORT, timestep_s=5e-5)),
        "transient": spec(settings=dataclasses.replace(SHORT, transient_s=0.4)),
        "record rate": spec(settings=dataclasses.replace(SHORT, record_rate_hz=500.0)),
        "convention": spec(settings=dataclasses.replace(SHORT, convention="axial")),
        "gain": spec(settings=dataclasses.replace(SHORT, controller=ControllerSettings(flight_kp=11.0))),
        "perturbation": spec(
            settings=dataclasses.replace(
                SHORT, perturbation=Perturbation.replicate(0, (SHORT.transient_s, SHORT.duration_s))
            )
        ),
        "seed": spec(settings=dataclasses.replace(SHORT, perturbation=Perturbation.replicate(1, (0.5, 2.5)))),
        "replicate protocol": spec(settings=dataclasses.replace(SHORT, replicate_protocol="branch")),
    }
    keys = {name: t.key() for name, t in variants.items()}
    assert base.key() not in keys.values()
    assert len(set(keys.values())) == len(keys)
    # labels are not physics: same key
    assert RunSpec(base.design, base.behaviour, SHORT, {"experiment": "x", "design": "renamed"}).key() == base.key()
    assert spec(LegDesign.from_properties([8.0] * 3, [193.0] * 3, name="other")).key() == base.key()
    before = base.key()
    monkeypatch.setattr(cache_keys, "source_digest", lambda: "edited-source")  # where versions() finds it
    edited = base.key()
    monkeypatch.setattr(mat_hopper.util.version, "__version__", "0.0.0-test")  # where versions() reads it
    assert len({before, edited, base.key()}) == 3


# --- caching, failures ----------------------------------------------------------


def test_grid_caches_and_reuses_results(tmp_path):
    tasks = small_grid(3) + [small_grid(1)[0]]  # a duplicate runs once
    first = run_grid(tasks, tmp_path, workers=1, progress=False)
    assert (first.n_tasks, first.n_unique, first.n_computed, first.n_cached, first.n_failed) == (4, 3, 3, 0, 0)
    assert len(Cache(tmp_path).keys()) == 3
    second = run_grid(tasks, tmp_path, workers=1, progress=False)
    assert (second.n_computed, second.n_cached) == (0, 3)
    pd.testing.assert_frame_equal(first.tables, second.tables)
    pd.testing.assert_frame_equal(first.summary, second.summary)
    s = first.summary
    assert list(s["design"]) == ["MD", "MD", "MD", "MD"]
    assert list(s["behaviour"]) == ["static", "forward", "ramp", "static"]
    assert set(s["status"]) == {"ok"} and set(s["profile"]) == {"tiny"}
    h = first.tables
    for col in ("experiment", "profile", "design", "behaviour", "replicate", "hop", "tracking_error_m", "key"):
        assert col in h.columns
    assert set(h["replicate"]) == {-1}


def test_diverged_run_is_a_cached_result(tmp_path):
    bad = spec("SS", "static", dataclasses.replace(SHORT, timestep_s=1e-3))  # beyond SS's stable step
    res = run_grid([bad, spec("MD", "static")], tmp_path, workers=1, progress=False)
    row = res.summary.iloc[0]
    assert row["status"] == "diverged" and not row["stable"] and 0 < row["diverged_at_s"] < 2.5
    assert res.summary.iloc[1]["status"] == "ok"
    again = run_grid([bad], tmp_path, workers=1, progress=False)
    assert again.n_cached == 1 and again.summary.iloc[0]["status"] == "diverged"


@dataclasses.dataclass(frozen=True)
class Exploding:
    """A task whose computation raises (a bug in a design, say)."""

    name: str
    labels: dict = dataclasses.field(default_factory=dict)

    def key_dict(self):
        return {"kind": "explode", "name": self.name}

    def key(self):
        return f"explode-{self.name}"

    def default_labels(self):
        return {"design": self.name}

    def compute(self):
        raise RuntimeError(f"boom in {self.name}")


def test_a_failing_task_is_a_failed_row_not_a_crash(tmp_path):
    tasks = [small_grid(1)[0], Exploding("bad-leg")]
    res = run_grid(tasks, tmp_path, workers=1, progress=False)
    assert res.n_failed == 1
    bad = res.summary.iloc[1]
    assert bad["status"] == "failed" and "boom in bad-leg" in bad["error"]
    assert res.summary.iloc[0]["status"] == "ok"
    assert "explode-bad-leg" not in Cache(tmp_path).keys()  # failures are retried next time
    again = run_grid(tasks, tmp_path, workers=1, progress=False)
    assert again.n_cached == 1 and again.n_computed == 1 and again.n_failed == 1


def test_process_pool_matches_in_process(tmp_path):
    tasks = small_grid(4)
    local = run_grid(tasks, tmp_path / "a", workers=1, progress=False)
    pool = run_grid(tasks, tmp_path / "b", workers=2, progress=False)
    assert pool.n_computed == 4 and pool.n_failed == 0
    pd.testing.assert_frame_equal(local.tables, pool.tables)
    pd.testing.assert_frame_equal(local.summary, pool.summary)


# --- resume after SIGKILL ---------------------------------------------------------

KILL_SCRIPT = textwrap.dedent("""
    import sys
    from mat_hopper.experiments.profiles import Profile
    from mat_hopper.experiments.paper import experiment_1
    from mat_hopper.experiments.runner import run_grid
    if __name__ == "__main__":
        tasks = experiment_1().tasks(Profile("tiny", 2.5, 0.5, 1e-4, 2, 0.5))[:8]
        run_grid(tasks, sys.argv[1], workers=2, progress=False)
        print("finished")
""")


@pytest.mark.slow
def test_resume_after_sigkill_computes_only_what_is_missing(tmp_path):
    cache = tmp_path / "cache"
    script = tmp_path / "grid.py"
    script.write_text(KILL_SCRIPT)
    proc = subprocess.Popen(
        [sys.executable, str(script), str(cache)],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        start_new_session=True,
    )
    deadline = time.monotonic() + 120
    try:
        while time.monotonic() < deadline:
            if cache.exists() and len(Cache(cache).keys()) >= 3:
                break
            if proc.poll() is not None:
                break
            time.sleep(0.02)
    finally:
        os.killpg(proc.pid, signal.SIGKILL)  # the runner and its workers, mid-grid
        proc.wait()
    done = Cache(cache).keys()
    assert 3 <= len(done) < 8, "the grid should have been killed part-way"
    # debris a crash may leave: a temp file, and (paranoia) a damaged result file
    (cache / f"{TEMP_PREFIX}junk.parquet").write_bytes(b"half a file")
    tasks = experiment_1().tasks(TINY)[:8]
    missing = [t.key() for t in tasks if t.key() not in done]
    (cache / f"{missing[0]}.parquet").write_bytes(b"PAR1 damaged")
    resumed = run_grid(tasks, cache, workers=1, progress=False)
    assert resumed.n_cached == len(done)
    assert resumed.n_computed == 8 - len(done) and resumed.n_failed == 0
    fresh = run_grid(tasks, tmp_path / "fresh", workers=1, progress=False)
    pd.testing.assert_frame_equal(resumed.tables, fresh.tables)
    pd.testing.assert_frame_equal(resumed.summary, fresh.summary)


# --- Dask ------------------------------------------------------------------------------


def test_dask_local_cluster_gives_identical_tables(tmp_path):
    distributed = pytest.importorskip("distributed")
    tasks = small_grid(4) + [Exploding("on-dask")]
    local = run_grid(tasks, tmp_path / "local", workers=2, progress=False)
    with distributed.LocalCluster(
        processes=True, n_workers=2, threads_per_worker=1, dashboard_address=None, silence_logs=40
    ) as cluster:
        with distributed.Client(cluster) as client:
            dask = run_grid(tasks, tmp_path / "dask", scheduler=client, progress=False)
        by_address = run_grid(tasks[:1], tmp_path / "addr", scheduler=cluster.scheduler_address, progress=False)
    assert dask.n_computed == 5 and dask.n_failed == 1
    pd.testing.assert_frame_equal(local.tables, dask.tables)
    pd.testing.assert_frame_equal(local.summary, dask.summary)
    pd.testing.assert_frame_equal(
        local.tables[local.tables["key"] == tasks[0].key()].reset_index(drop=True), by_address.tables
    )


# --- bad input ------------------------------------------------------------------------


def test_bad_grid_input_fails_before_any_work(tmp_path):
    with pytest.raises(ValueError, match="empty"):
        run_grid([], tmp_path, progress=False)
    for bad in (0, -2, 1.5, True):
        with pytest.raises(ValueError, match="workers"):
            Runner(tmp_path, workers=bad)
    with pytest.raises(ValueError, match="not both"):
        Runner(tmp_path, workers=2, scheduler="tcp://127.0.0.1:1")
    with pytest.raises(ValueError, match="tasks"):
        run_grid(["SS"], tmp_path, progress=False)
    assert Cache(tmp_path).keys() == set()


def test_replicates_run_with_their_seeded_perturbation(tmp_path):
    tasks = [
        t
        for t in experiment_1().tasks(TINY, replicates=2)
        if t.labels["design"] == "SS" and t.behaviour.name == "forward"
    ]
    res = run_grid(tasks, tmp_path, workers=1, progress=False)
    assert list(res.summary["replicate"]) == [-1, 0, 1] and set(res.summary["status"]) == {"ok"}
    h = res.tables
    assert set(h["replicate"]) == {-1, 0, 1}
    errs = h.groupby("replicate")["tracking_error_m"].mean()
    assert errs[-1] != errs[0] and errs[0] != errs[1]  # perturbed runs differ, seed by seed


# --- stopping a pool: no InvalidStateError traceback -------------------------------


@dataclasses.dataclass(frozen=True, eq=False)
class NapTask:
    """A grid task that sleeps (no physics): a pool's futures are pending,
    running and done at once, at almost no CPU."""

    i: int
    seconds: float = 0.3
    labels: dict = dataclasses.field(default_factory=dict)

    def key_dict(self) -> dict:
        return {"kind": "nap", "i": self.i}

    def key(self) -> str:
        return f"nap-{self.i}"

    def default_labels(self) -> dict:
        return {"nap": self.i}

    def compute(self):
        time.sleep(self.seconds)
        return pd.DataFrame({"i": [self.i]}), {"status": "ok"}


def test_an_interrupt_as_the_workers_die_leaves_no_invalid_state_traceback(tmp_path, monkeypatch):
    """SIGTERM sent to the process group: the grid stops (KeyboardInterrupt,
    as mat_hopper.cli raises it) and the pool's workers die. Were the grid
    to cancel its pending futures itself (Future.cancel()), the pool's
    manager thread would then fail them as a broken pool and raise
    InvalidStateError (CPython < 3.12): a traceback on stderr."""
    import threading

    import mat_hopper.util.progress

    thread_errors = []
    monkeypatch.setattr(threading, "excepthook", lambda args: thread_errors.append(repr(args.exc_value)))
    runner = Runner(tmp_path, workers=2, progress=True)
    workers = []

    class Bar:  # the grid's progress bar: the interrupt lands at the first result
        def update(self, n):
            workers.extend(runner._pool._processes.values())
            raise KeyboardInterrupt

        def close(self):  # the same SIGTERM reaches the workers
            for p in workers:
                p.terminate()
            for p in workers:
                p.join(30)
            time.sleep(1.0)  # the pool's manager thread sees them die

    monkeypatch.setattr(mat_hopper.util.progress, "progress_bar", lambda **kw: Bar())
    with pytest.raises(KeyboardInterrupt):
        runner.run([NapTask(i) for i in range(12)])
    runner.close()
    assert thread_errors == []


def test_stop_pool_cancels_through_the_pool_and_can_stop_its_workers():
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor

    from mat_hopper.util.pool import stop_pool

    ctx = multiprocessing.get_context("forkserver")
    for terminate in (False, True):
        pool = ProcessPoolExecutor(1, mp_context=ctx)
        futures = [pool.submit(time.sleep, 0.2) for _ in range(6)]
        futures[0].result()
        stop_pool(pool, terminate=terminate)
        assert all(f.done() for f in futures)
        assert any(f.cancelled() for f in futures)  # the queued ones never ran
