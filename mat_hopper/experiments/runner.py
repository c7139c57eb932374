"""Run grids of simulations in parallel, cached on disk, resumable.

A grid is a list of *tasks*. A task is a small frozen dataclass that knows
every setting that changes its result (:meth:`key_dict`), how to compute
that result (:meth:`compute` -> a table and a one-line summary dict), and
how to label it in the output (:attr:`labels`: experiment, profile, design,
behaviour, ...; labels are *not* part of the key, so two experiments that
need the same physics share one cached result). :class:`RunSpec` (one
design on one behaviour, its per-hop table and run summary) is the task of
experiments 1-3; :class:`mat_hopper.physics.stability.StabilitySpec` is the task
of the stable-time-step map.

Cache. One parquet file per result, ``<cache_dir>/<key>.parquet``, named by
a SHA-256 hash of the key dict (every setting: design with per-segment
density and modulus, behaviour, duration, time step, transient, record
rate, stiffness convention, controller gains, perturbation; the versions
of mat-hopper and MuJoCo, and a digest of the source of the modules that
make results, so an edited simulation never reuses old results). The summary and the key dict ride in
the file's metadata, so a result is one file, written atomically (temp
file in the same folder, then ``os.replace``): a reader sees the whole file
or none. Every file carries a SHA-256 content checksum of its columns and
metadata (:func:`content_checksum`), verified on load: a damaged file (a
flipped bit, a truncated write) is logged and recomputed, never loaded. Temp files (``.tmp-*``) are never read. A run killed half-way
keeps every result it finished; the next run loads them and computes only
the missing ones. A diverged simulation is a result (cached); an exception
in a task is not (it becomes a ``failed`` row with the error text, and the
next run tries again).

Parallelism. Local processes (``concurrent.futures.ProcessPoolExecutor``,
forkserver context whose server preloads :mod:`mat_hopper.experiments._warmup`, so
workers start with MuJoCo, numba's compiled loop and pyarrow loaded), all
cores by default; or a Dask cluster (``scheduler``: an address or a
``distributed.Client``). The parent process is the only writer of the
cache. Output tables are in grid order whatever the completion order, and
every result is read back from its stored file, so fresh, cached, local
and Dask runs give identical tables.
"""

from __future__ import annotations

import logging
import math
import multiprocessing
from collections.abc import Iterable, Sequence
from concurrent.futures import ProcessPoolExecutor, as_completed
from concurrent.futures.process import BrokenProcessPool
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import pandas as pd

from ..core.behaviours import Behaviour
from ..core.materials import LegDesign
from ..core.sim import SimSettings
from ..util.keys import design_key, hash_key, settings_key, versions
from ..util.pool import default_workers, stop_pool
from ._grid import FAILED, assemble
from .cache import Cache
from .groups import execute_unit, iter_unit, prefix_units

_log = logging.getLogger("mat_hopper.cache")


# Status of a task's summary row.
# suspect: no divergence, but the numbers are corrupted (core.rollout.Rollout.suspect).
OK, DIVERGED, SUSPECT, FALLEN = "ok", "diverged", "suspect", "fallen"  # and FAILED (._grid)


# ---------------------------------------------------------------------------
# the hop-run task


@dataclass(frozen=True, eq=False)
class RunSpec:
    """One design on one behaviour under one SimSettings.

    labels: output columns (experiment, profile, design label, replicate,
    sweep columns, ...), not part of the cache key."""

    design: LegDesign
    behaviour: Behaviour
    settings: SimSettings
    labels: dict = field(default_factory=dict)

    kind = "run"

    def key_dict(self) -> dict:
        return {
            "kind": self.kind,
            "design": design_key(self.design),
            "behaviour": self.behaviour.key(),
            "settings": settings_key(self.settings),
            "versions": versions(),
        }

    def key(self) -> str:
        return f"{self.kind}-{hash_key(self.key_dict())}"

    def default_labels(self) -> dict:
        return {"design": self.design.name, "behaviour": self.behaviour.name}

    def compute(self) -> tuple[pd.DataFrame, dict]:
        """Simulate; return (per-hop table, run summary). Never raises on
        divergence: an unstable run is a summary with status 'diverged', a
        numerically suspect one (``Rollout.suspect``) status 'suspect'."""
        from ..core.sim import simulate

        return self.summarize(simulate(self.design, self.behaviour, settings=self.settings, warn=False))

    def summarize(self, rollout) -> tuple[pd.DataFrame, dict]:
        """(per-hop table, run summary) of this run's rollout (computed here or
        forked from a shared prefix, :mod:`mat_hopper.experiments.groups`)."""
        from ..core.sim import C
        from ..physics.metrics import hop_table, run_summary

        full = hop_table(rollout, warn=False)  # the summary's status says a divergence
        summary = run_summary(rollout, hops=full)  # one hop table per run
        hops = full.drop(columns=["design", "behaviour"])
        for k in ("design", "behaviour"):
            summary.pop(k, None)
        if summary.get("diverged_at_s") is None:
            summary["diverged_at_s"] = math.nan
        summary["upright"] = bool(rollout.upright)
        summary["final_base_z_m"] = float(rollout.data[-1, C["z"]]) if len(rollout.data) else math.nan
        summary.update(
            duration_s=self.settings.duration_s,
            timestep_s=self.settings.timestep_s,
            transient_s=self.settings.transient_s,
        )
        ok = OK if rollout.upright else FALLEN  # a suspect run's numbers are corrupted: left out as diverged ones
        summary["status"] = DIVERGED if not rollout.stable else (SUSPECT if rollout.suspect else ok)
        return hops, summary


# ---------------------------------------------------------------------------
# execution


def check_workers(workers) -> int | None:
    """Check a count of local worker processes.

    Args:
        workers: processes (an integer >= 1, Python or NumPy), or None for the
            default (every core).

    Returns:
        `workers` as an int, or None when None.

    Raises:
        ValueError: a bool, a non-integer or a value < 1.
    """
    if workers is None:
        return None
    if isinstance(workers, bool) or not isinstance(workers, (int, np.integer)) or workers < 1:
        raise ValueError(f"workers must be an integer >= 1 (processes), got {workers!r}")
    return int(workers)


@dataclass
class GridResult:
    """Concatenated tables of a grid, in grid order.

    tables: every task's table with its labels in front; summary: one row
    per task (labels, summary fields, status, error, key). n_cached,
    n_computed, n_failed count unique keys (bookkeeping, not results)."""

    tables: pd.DataFrame
    summary: pd.DataFrame
    n_tasks: int
    n_unique: int
    n_cached: int
    n_computed: int
    n_failed: int


class Runner:
    """Runs grids of tasks; reusable across grids (keeps its pool warm).

    cache_dir: where results live (default $MAT_HOPPER_CACHE or
    results/cache); workers: local processes (default all cores; 1 runs in
    this process); scheduler: a Dask scheduler address or a
    ``distributed.Client`` (then `workers` must be left unset); progress:
    show a tqdm bar. Use as a context manager, or call :meth:`close`.
    The runs a grid does not find cached are submitted longest first (their
    physics steps, :func:`mat_hopper.util.limits.task_steps`), so no long
    run starts last and finishes alone; ``branch`` replicates of one design
    go to one worker together, which simulates their shared prefix once
    (:mod:`mat_hopper.experiments.groups`), each stored under its own key."""

    def __init__(self, cache_dir=None, *, workers: int | None = None, scheduler=None, progress: bool = True):
        self.workers = check_workers(workers)
        if scheduler is not None and self.workers is not None:
            raise ValueError("give either workers (local processes) or scheduler (Dask), not both")
        if scheduler is not None and not isinstance(scheduler, str) and not hasattr(scheduler, "submit"):
            raise ValueError(
                f"scheduler must be an address like tcp://host:8786 or a distributed.Client, got {scheduler!r}"
            )
        if isinstance(scheduler, str) and not scheduler.strip():
            raise ValueError("scheduler address is empty (e.g. tcp://127.0.0.1:8786)")
        self.cache = Cache(cache_dir)
        self.scheduler = scheduler
        self.progress = progress
        self._pool = None
        self._client = None
        self._own_client = False

    # -- resources --
    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def close(self):
        if self._pool is not None:
            self._pool.shutdown(wait=True, cancel_futures=True)
            self._pool = None
        if self._own_client and self._client is not None:
            self._client.close()
        self._client = None

    @property
    def n_workers(self) -> int:
        return self.workers if self.workers is not None else default_workers()

    def _get_pool(self) -> ProcessPoolExecutor:
        if self._pool is None:
            if "forkserver" in multiprocessing.get_all_start_methods():
                ctx = multiprocessing.get_context("forkserver")
                # workers fork from a server that already loaded everything (no effect
                # if this process's forkserver is already running)
                ctx.set_forkserver_preload(["mat_hopper.experiments._warmup"])
            else:  # pragma: no cover (not Linux)
                ctx = multiprocessing.get_context("spawn")
            self._pool = ProcessPoolExecutor(self.n_workers, mp_context=ctx)
        return self._pool

    def _get_client(self):
        if self._client is None:
            if isinstance(self.scheduler, str):
                from distributed import Client

                try:
                    self._client = Client(self.scheduler, timeout="20s")
                except OSError as e:
                    raise ValueError(f"cannot reach the Dask scheduler at {self.scheduler!r}: {e}") from None
                self._own_client = True
            else:
                self._client = self.scheduler
        return self._client

    # -- the grid --
    def run(self, tasks: Sequence, desc: str = "runs") -> GridResult:
        """Run every task (cached ones are loaded), return the grid's tables."""
        tasks = list(tasks)
        if not tasks:
            raise ValueError("the grid is empty: no tasks to run")
        for t in tasks:
            if not (hasattr(t, "key") and hasattr(t, "compute") and hasattr(t, "labels")):
                raise ValueError(f"grid entries must be tasks (RunSpec, StabilitySpec), got {t!r}")
        keys = [t.key() for t in tasks]
        unique: dict[str, Any] = {}
        for k, t in zip(keys, tasks):
            unique.setdefault(k, t)
        self.cache.clean_temp()
        results: dict[str, tuple[pd.DataFrame, dict]] = {}
        errors: dict[str, str] = {}
        for k in unique:
            got = self.cache.load(k)
            if got is not None:
                results[k] = got
        n_cached = len(results)
        # units of work (a task, or runs sharing a branch prefix), longest first (the pool's makespan)
        workers = None if self.scheduler is not None else self.n_workers
        todo = prefix_units([k for k in unique if k not in results], unique, workers)

        from ..util.progress import progress_bar

        bar = progress_bar(
            total=len(unique),
            initial=n_cached,
            desc=desc,
            unit="run",
            enabled=self.progress,
            dynamic_ncols=True,
            leave=False,
        )
        try:
            for key, table, summary, err in self._compute(todo, unique):
                if err is None:
                    self.cache.store(key, table, summary, unique[key].key_dict())
                    got = self.cache.load(key)  # tables always come from the stored form
                    if got is None:
                        err = "result could not be read back from the cache"
                    else:
                        results[key] = got
                if err is not None:
                    errors[key] = err
                bar.update(1)
        finally:
            bar.close()
        tables, summary = assemble(tasks, keys, results, errors)
        return GridResult(tables, summary, len(tasks), len(unique), n_cached, sum(map(len, todo)), len(errors))

    def _compute(self, todo: list[tuple[str, ...]], unique: dict) -> Iterable:
        """(key, table, summary, error) of every key of the units `todo`, as they finish."""
        if not todo:
            return
        if self.scheduler is not None:
            yield from self._compute_dask(todo, unique)
        elif self.n_workers == 1 or len(todo) == 1:
            for unit in todo:  # each result stored as it comes
                yield from iter_unit([unique[k] for k in unit])
        else:
            yield from self._compute_pool(todo, unique)

    def _compute_pool(self, todo, unique):
        pool = self._get_pool()
        futures = {pool.submit(execute_unit, [unique[k] for k in unit]): unit for unit in todo}
        try:
            for fut in as_completed(futures):
                unit = futures[fut]
                try:
                    yield from fut.result()
                except BrokenProcessPool as e:
                    self._pool = None  # a worker died (killed, out of memory): fresh pool next time
                    died = f"worker process died ({e}); from a script, start the grid under if __name__ == '__main__':"
                    yield from ((k, None, None, died) for k in unit)
                except Exception as e:  # pickling and the like
                    yield from ((k, None, None, f"{type(e).__name__}: {e}") for k in unit)
        except BaseException:  # an interrupt, or the grid's consumer stopped (GeneratorExit)
            # The pool cancels what has not started (stop_pool: Future.cancel() from here races the
            # pool's own thread into an InvalidStateError traceback when a worker dies) and finishes
            # the runs under way; the next grid starts a fresh pool.
            self._pool = None
            stop_pool(pool)
            raise

    def _compute_dask(self, todo, unique):
        from distributed import as_completed as dask_completed

        client = self._get_client()
        futures = {client.submit(execute_unit, [unique[k] for k in unit], pure=False): unit for unit in todo}
        try:
            for fut in dask_completed(list(futures)):
                unit = futures[fut]
                try:
                    yield from fut.result()
                except Exception as e:
                    yield from ((k, None, None, f"{type(e).__name__}: {e}") for k in unit)
        except BaseException:
            for f in futures:
                f.cancel()
            raise


def run_grid(
    tasks: Sequence,
    cache_dir=None,
    *,
    workers: int | None = None,
    scheduler=None,
    progress: bool = True,
    desc: str = "runs",
) -> GridResult:
    """Run a grid once (see :class:`Runner`).

    Args:
        tasks: the grid: runner tasks (:class:`RunSpec`,
            :class:`~mat_hopper.physics.stability.StabilitySpec`, ...), each with
            ``key``, ``compute`` and ``labels``.
        cache_dir: the result cache folder (default: $MAT_HOPPER_CACHE, else
            ``results/cache``).
        workers: local worker processes (an integer >= 1; default: every core;
            1 runs in this process); not with `scheduler`.
        scheduler: a Dask scheduler address or a ``distributed.Client``; None
            runs local processes.
        progress: show a tqdm bar.
        desc: the progress bar's label.

    Returns:
        The :class:`GridResult`, in grid order: ``tables`` every task's table
        with its labels in front and a ``key`` column, ``summary`` one row per
        task (labels, summary fields, status, error, key), and the task,
        unique, cached, computed and failed counts. A task that raised is a
        ``failed`` summary row with its error text, not an exception.

    Raises:
        ValueError: an empty grid, an entry that is not a task, invalid
            `workers`, `workers` together with `scheduler`, an invalid or
            unreachable scheduler, or $MAT_HOPPER_CACHE set but empty.
    """
    with Runner(cache_dir, workers=workers, scheduler=scheduler, progress=progress) as r:
        return r.run(tasks, desc=desc)


# ---------------------------------------------------------------------------
# whole rollouts (time series, gait tiles), through the same cache and pool


@dataclass(frozen=True, eq=False)
class RolloutSpec(RunSpec):
    """A whole rollout of one design on one behaviour (every recorded
    channel, the controller's events, optionally all joint positions): the
    task behind time series and gait tiles. Cached like every task, under
    :class:`RunSpec`'s key plus ``record_qpos``: the table holds the
    recorded channels (and ``qpos_<i>`` columns), the summary the events
    and the model's numbers."""

    record_qpos: bool = False

    kind = "rollout"

    def key_dict(self) -> dict:
        return {**super().key_dict(), "record_qpos": bool(self.record_qpos)}

    def compute(self) -> tuple[pd.DataFrame, dict]:
        from ..core.sim import CHANNELS, simulate

        r = simulate(self.design, self.behaviour, settings=self.settings, record_qpos=self.record_qpos, warn=False)
        table = pd.DataFrame(np.asarray(r.data, dtype=float), columns=list(CHANNELS))
        if self.record_qpos:
            table = pd.concat(
                [
                    table,
                    pd.DataFrame(
                        np.asarray(r.qpos, dtype=float), columns=[f"qpos_{i}" for i in range(r.qpos.shape[1])]
                    ),
                ],
                axis=1,
            )
        ev = np.asarray(r.events, dtype=float)
        summary = {
            "events": ev.ravel().tolist(),
            "events_shape": list(ev.shape),
            "diverged_step": int(r.diverged_step),
            "total_mass_kg": float(r.total_mass_kg),
            "spring_stiffness_n_m": [float(k) for k in r.spring_stiffness_n_m],
        }
        return table, summary

    def rollout(self, table: pd.DataFrame, summary: dict):
        """The :class:`~mat_hopper.core.rollout.Rollout` from this task's stored result."""
        from ..core.rollout import Rollout
        from ..core.sim import CHANNELS

        data = table[list(CHANNELS)].to_numpy(float)
        qcols = [c for c in table.columns if c.startswith("qpos_")]
        qpos = table[qcols].to_numpy(float) if self.record_qpos else None
        events = np.asarray(summary["events"], dtype=float).reshape(summary["events_shape"])
        return Rollout(
            self.design,
            self.behaviour,
            self.settings,
            data,
            events,
            int(summary["diverged_step"]),
            float(summary["total_mass_kg"]),
            tuple(summary["spring_stiffness_n_m"]),
            qpos,
        )


def rollout_specs(
    designs, behaviours, settings: SimSettings, *, record_rate_hz=None, record_qpos: bool = False
) -> list:
    """The tasks of :func:`rollouts` (and of the book's plan, which counts
    them before any run): one :class:`RolloutSpec` per design and behaviour.

    Args:
        designs: design names or LegDesigns.
        behaviours: behaviour names or Behaviours.
        settings: the :class:`~mat_hopper.core.sim.SimSettings` of every rollout.
        record_rate_hz: samples per simulated second, Hz (None: the settings').
        record_qpos: keep every joint position.

    Returns:
        list of :class:`RolloutSpec`, design-major.
    """
    from dataclasses import replace

    from ..core.behaviours import behaviour as get_behaviour
    from ..core.materials import parse_design

    if record_rate_hz is not None:
        settings = replace(settings, record_rate_hz=float(record_rate_hz))
    return [
        RolloutSpec(
            parse_design(d) if isinstance(d, str) else d,
            get_behaviour(b) if isinstance(b, str) else b,
            settings,
            record_qpos=bool(record_qpos),
        )
        for d in designs
        for b in behaviours
    ]


def rollouts(
    designs,
    behaviours,
    settings: SimSettings,
    *,
    record_rate_hz: float | None = None,
    record_qpos: bool = False,
    cache_dir=None,
    workers: int | None = None,
) -> list:
    """Whole rollouts (:class:`~mat_hopper.core.rollout.Rollout`) of every design
    (names or LegDesigns) on every behaviour (names or Behaviours) under
    `settings` (e.g. ``profile.sim_settings()``), for time series and gait
    tiles, in design-major order. record_rate_hz: samples per simulated
    second (default the settings'); record_qpos: keep joint positions (for
    rendering). Through the one cache and pool (:class:`Runner`, tasks
    :class:`RolloutSpec`): missing ones run in parallel, all are read back
    from the cache.

    Args:
        designs: design names or LegDesigns.
        behaviours: behaviour names or Behaviours.
        settings: the :class:`~mat_hopper.core.sim.SimSettings` of every rollout.
        record_rate_hz: samples per simulated second, Hz (None: the settings').
        record_qpos: keep every joint position (``Rollout.qpos``).
        cache_dir: the result cache folder (default: $MAT_HOPPER_CACHE, else
            ``results/cache``).
        workers: local worker processes (default: every core).

    Returns:
        list of :class:`~mat_hopper.core.rollout.Rollout`, one per (design,
        behaviour), design-major.

    Raises:
        ValueError: no design or no behaviour, an unknown design or behaviour
            name, an invalid record rate or `workers`, or $MAT_HOPPER_CACHE set
            but empty.
        RuntimeError: a rollout raised (the errors joined).
    """
    specs = rollout_specs(designs, behaviours, settings, record_rate_hz=record_rate_hz, record_qpos=record_qpos)
    if not specs:
        raise ValueError("rollouts: give at least one design and one behaviour")
    with Runner(cache_dir, workers=workers, progress=False) as runner:
        res = runner.run(specs, desc="rollouts")
        if res.n_failed:
            bad = res.summary[res.summary["status"] == FAILED]
            raise RuntimeError("rollouts failed: " + "; ".join(bad["error"].astype(str)))
        return [s.rollout(*runner.cache.load(s.key())) for s in specs]
