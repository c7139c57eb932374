"""The coordinator of a study run (:func:`run_study`): worker processes
started against one storage with a shared budget of trials, dead workers'
trials failed and re-queued, Ctrl-C and signals handled (the module doc of
:mod:`mat_hopper.optimize._study` describes the whole)."""

from __future__ import annotations

import multiprocessing as mp
import os
import sys
import time
import warnings
from dataclasses import dataclass, field

import optuna
from tqdm.std import tqdm

from ..progress import progress_bar
from ._processes import _signals_ignored, _start_method, _warm_up, stop_signals
from ._samplers import check_sampler, worker_seed
from ._storage import dispose, recover_dead, redact, storage_errors
from ._study import RunOptions, StudyConfig, _Job, _worker_main, check_objectives_vary, counts, create_or_load

POLL_S = 1.0  # s between the coordinator's looks at its workers

# --- the coordinator ---------------------------------------------------------


class _Bar(tqdm):
    monitor_interval = 0  # no monitor thread: we refresh it ourselves, and fork stays safe


@dataclass
class RunResult:
    """What a run did.

    Args:
        study: the study's name.
        url: its storage URL, password hidden.
        target: the trials the study was to hold.
        done, running: finished and running trials at the end.
        worker_reports: one dict per worker that exited normally (pid, seed,
            told = [(trial number, state)]).
        dead_workers: (pid, exit code) of the others.
        recovered: trials failed and re-enqueued because their worker died.
        start_method: how workers were started (``"fork"``, ``"forkserver"``; ``"warp:DEVICE"``).
    """

    study: str
    url: str
    target: int
    done: int
    running: int
    worker_reports: list = field(default_factory=list)
    dead_workers: list = field(default_factory=list)
    recovered: list = field(default_factory=list)
    start_method: str = ""

    @property
    def finished(self) -> bool:
        return self.done >= self.target


def run_study(config: StudyConfig, options: RunOptions = RunOptions()) -> RunResult:
    """Run `config`'s study until it holds options.trials finished trials.

    Args:
        config: the study (name, search space, objective).
        options: how to run it: trials, local worker processes, sampler and
            seed, storage (see the module doc).

    Returns:
        A :class:`RunResult`: trials done and running, worker reports, dead
        workers and the trials re-queued after them.

    Raises:
        ValueError: bad settings or an unreachable storage, before any work; a
            database error later, as one line naming the storage and its cause
            (e.g. "database is locked").
        KeyboardInterrupt: Ctrl-C (:class:`Interrupted` for SIGTERM and SIGHUP),
            after the workers are stopped and their running trials failed and re-queued.
    """
    check_sampler(options.sampler)
    check_objectives_vary(config.objective)
    url = options.storage_url(config.name)
    with stop_signals(), storage_errors(url):
        return _run(config, options, url)


def _run(config: StudyConfig, options: RunOptions, url: str) -> RunResult:
    storage = options.open(config.name)
    study = create_or_load(config, storage)
    if "mat_hopper_racing" in study.user_attrs:  # _racing.RACING_ATTR: its open bracket's trials stay RUNNING
        raise ValueError(f"study {config.name!r} is a racing study (mat_hopper.optimize.run_racing): resume it there")
    recovered = recover_dead(study, max_retry=options.max_retry, reason="worker of an earlier run died")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", optuna.exceptions.ExperimentalWarning)
        optuna.storages.fail_stale_trials(study)
    done, running = counts(study)
    result = RunResult(config.name, redact(url), options.trials, done, running, recovered=recovered)
    budget = options.trials - done - running
    if budget <= 0:
        return result

    result.start_method = _start_method()
    if result.start_method == "fork":
        _warm_up()
    pool = _Workers(config, options, url, storage, study, result, budget)
    pool.spawn(min(options.workers, budget))
    bar = progress_bar(
        tqdm_class=_Bar,
        total=options.trials,
        initial=min(done, options.trials),
        unit="trial",
        desc=config.name,
        enabled=options.progress,
        dynamic_ncols=True,
        file=sys.stderr,
        mininterval=1.0,
    )
    try:
        _supervise(pool, bar)
    except KeyboardInterrupt as e:
        with _signals_ignored():  # a second Ctrl-C or SIGTERM does not cut the clean-up short
            pool.stop(f"interrupted ({getattr(e, 'signal_name', 'SIGINT')})")
        raise
    except BaseException:
        if pool.live:
            pool.stop("stopped by an error in the coordinator")
        raise
    finally:
        bar.close()
    result.done, result.running = counts(study)
    return result


def _supervise(pool: _Workers, bar) -> None:
    """Poll the workers until the budget is spent or no worker makes progress:
    reap the dead (their trials failed, tickets returned), respawn while
    trials remain, raise a worker's storage error."""
    options, result, study = pool.options, pool.result, pool.study
    max_spawn = options.workers + options.workers * (options.max_retry + 1)
    told_before, recovered_before = 0, len(result.recovered)
    while True:
        pool.reap()
        if pool.errors:  # a storage failure in a worker: the others would meet it too
            pool.stop("stopped after a storage error")
            raise ValueError(pool.errors[0])
        done, running = counts(study)
        bar.n = min(done, options.trials)
        bar.set_postfix(running=running, dead=len(result.dead_workers), refresh=False)
        bar.refresh()
        if not pool.live:
            told = sum(len(r["told"]) for r in result.worker_reports)
            progress = told > told_before or len(result.recovered) > recovered_before
            told_before, recovered_before = told, len(result.recovered)
            if done < options.trials and pool.tickets.value > 0 and pool.spawned < max_spawn and progress:
                pool.spawn(min(options.workers, pool.tickets.value))
                continue
            return
        time.sleep(POLL_S)


class _Workers:
    """The worker processes of one run: spawned with a shared ticket count
    (trials left), each reporting through a pipe; a dead one's trials are
    failed (retried) and its ticket returned."""

    def __init__(self, config, options, url, storage, study, result, budget: int):
        self.config, self.options, self.url = config, options, url
        self.storage, self.study, self.result = storage, study, result
        self.ctx = mp.get_context(result.start_method)
        self.tickets = self.ctx.Value("i", budget)
        self.n_existing = len(study.get_trials(deepcopy=False))
        self.live: dict[int, tuple] = {}
        self.errors: list[str] = []
        self.spawned = 0

    def spawn(self, n: int) -> None:
        config, options = self.config, self.options
        dispose(self.storage)  # no pooled connection crosses the fork (reopened on next use)
        for _ in range(n):
            seed = worker_seed(options.seed, self.n_existing, self.spawned)
            job = _Job(config.name, config.key(), options, self.url, seed, options.trials)
            parent_end, child_end = self.ctx.Pipe(duplex=False)
            p = self.ctx.Process(
                target=_worker_main,
                args=(job, self.tickets, child_end, os.getpid()),
                daemon=True,
                name=f"mat-hopper-worker-{self.spawned}",
            )
            p.start()
            child_end.close()
            self.live[p.pid] = (p, parent_end)
            self.spawned += 1

    def receive(self, conn) -> None:
        while conn.poll():
            try:
                rep = conn.recv()
            except (EOFError, OSError):
                return
            if "error" in rep:
                self.errors.append(rep["error"])
            self.result.worker_reports.append(rep)

    def reap(self) -> None:
        for pid, (p, conn) in list(self.live.items()):
            self.receive(conn)
            if p.is_alive():
                continue
            p.join()
            self.receive(conn)
            conn.close()
            del self.live[pid]
            if p.exitcode != 0:
                self.result.dead_workers.append((pid, p.exitcode))
                lost = recover_dead(
                    self.study,
                    pids={pid},
                    max_retry=self.options.max_retry,
                    reason=f"worker exited with code {p.exitcode}",
                )
                self.result.recovered += lost
                with self.tickets.get_lock():  # its ticket back (the storage check in _claim still caps the total)
                    self.tickets.value += max(1, len(lost))

    def stop(self, reason: str) -> None:
        for p, _ in self.live.values():
            p.terminate()
        for p, conn in self.live.values():
            p.join(10)
            conn.close()
        with storage_errors(self.url):
            recover_dead(self.study, pids=set(self.live), max_retry=self.options.max_retry, reason=reason)
        self.live.clear()
