"""Optimizer throughput: trials per hour of 60 s ramp trials on this machine.

Runs a fresh study (SQLite in a temporary folder, the default storage)
with --workers processes and the paper profile (60 s runs, 1e-4 s step),
then prints

- trials/hour end to end, wall clock (study creation and the start of the
  evaluation processes included): what this machine gave, other load included;
- full-run trials/hour: simulated seconds per wall hour / 60, which does
  not flatter the figure when some designs diverge early (cheap trials);
- CPU seconds per trial (the command's and its evaluation processes' CPU
  time, every overhead of Optuna, the database and the run cache included)
  and what that gives on --workers idle cores: the figure to compare across
  machines when the cores are shared;
- the simulator's own limit: one bare 60 s SS ramp rollout (CPU time);
- the optimizer's own overhead (sampler, storage, heartbeat, run cache,
  metrics): a few trials of the optimizer's loop in this process (one
  evaluation process: this one), CPU inside the simulation against CPU of
  the whole loop. Measured in one process at one moment, so it
  holds when the host's speed drifts (on a shared VM the same rollout takes
  anywhere from 4 to 7 s of CPU from one minute to the next).

By default the space is the paper's catalogue materials (PVC, Al, Ti, SS
per segment), whose designs all run the full minute, so the figure is the
cost of real 60 s trials.

    python benchmarks/optimize.py [--trials 8] [--workers 2] [--space catalogue]
"""

from __future__ import annotations

import argparse
import multiprocessing
import os
import tempfile
import threading
import time
from concurrent.futures import ProcessPoolExecutor

import optuna
from optuna.trial import TrialState

import mat_hopper.optimize._evaluators as evaluators_module
from mat_hopper.core.sim import simulate
from mat_hopper.experiments.profiles import PROFILES
from mat_hopper.optimize._driver import run_loop, run_study
from mat_hopper.optimize._evaluators import PoolEvaluator
from mat_hopper.optimize._objective import Objective
from mat_hopper.optimize._samplers import make_sampler
from mat_hopper.optimize._space import SearchSpace
from mat_hopper.optimize._study import RunOptions, StudyConfig, create_or_load


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--trials", type=int, default=8)
    p.add_argument("--workers", type=int, default=2)
    p.add_argument("--space", default="catalogue", help="catalogue (PVC, Al, Ti, SS) or continuous")
    p.add_argument("--profile", default="paper")
    p.add_argument("--no-limit", action="store_true", help="skip timing the bare simulator")
    p.add_argument(
        "--overhead-trials",
        type=int,
        default=4,
        help="trials run in this process to measure the optimizer's own overhead (0: skip)",
    )
    a = p.parse_args(argv)
    prof = PROFILES[a.profile]
    space = SearchSpace(kinds=a.space, materials=("PVC", "Al", "Ti", "SS"))
    # single draws (replicates=0): a trial is one rollout, the unit the simulator-alone rate is measured in
    config = StudyConfig("bench", space, Objective(behaviours=("ramp",), profile=prof, replicates=0))
    # The simulator alone on every core, right before and right after the
    # study: the host's speed drifts, so the study is set against both.
    before = None if a.no_limit else bare_parallel_wall(prof, a.workers)
    with tempfile.TemporaryDirectory() as tmp:
        opts = RunOptions(trials=a.trials, workers=a.workers, studies_dir=tmp, progress=False, cache_dir=f"{tmp}/cache")
        with CpuMeter() as cpu:
            t0 = time.perf_counter()
            res = run_study(config, opts)
            wall = time.perf_counter() - t0
        worker_cpu = cpu.seconds
        study = optuna.load_study(study_name="bench", storage=opts.open("bench"))
        done = study.get_trials(deepcopy=False, states=(TrialState.COMPLETE,))
        sim_s = sum(t.user_attrs["result"]["simulated_s"] for t in done)
        del study
    print(
        f"{len(done)} trials ({a.space} space, {prof.name} profile: {prof.duration_s:g} s ramp runs at "
        f"{prof.timestep_s:g} s), {a.workers} workers, {os.cpu_count()} CPUs: {wall:.1f} s wall"
    )
    print(f"trials/hour end to end: {len(done) / wall * 3600:.0f}")
    full = sim_s / prof.duration_s / wall * 3600
    print(f"full-run trials/hour (simulated s / {prof.duration_s:g} per wall hour): {full:.0f}")
    per_trial = worker_cpu / max(1, len(done))
    print(
        f"CPU per trial (command and evaluation processes): {per_trial:.2f} s -> "
        f"{a.workers * 3600 / per_trial:.0f} trials/hour on {a.workers} idle cores"
    )
    if not res.finished:
        print("warning: the study did not reach its target")
    if not a.no_limit:
        after = bare_parallel_wall(prof, a.workers)
        cpu = bare_cpu(prof)
        wall_each = (before + after) / 2
        limit = a.workers * 3600 / wall_each
        print(
            f"simulator alone: {a.workers} bare {prof.duration_s:g} s SS ramp rollouts at once (one per core) = "
            f"{before:.2f} s wall before the study, {after:.2f} s after -> {limit:.0f} trials/hour "
            f"(one alone, the other core idle: {cpu:.2f} s CPU)"
        )
        print(
            f"optimizer end to end / simulator alone: {full / limit:.2f} (the catalogue's designs differ "
            f"from SS in cost; the overhead line below is the like-for-like figure)"
        )
    if a.overhead_trials > 0:
        total, inside = overhead(config, a.overhead_trials)
        print(
            f"optimizer overhead, {a.overhead_trials} trials in one process: "
            f"{(total - inside) / a.overhead_trials * 1000:.0f} ms CPU per trial "
            f"(whole trial / simulation alone: {total / inside:.3f})"
        )


def _bare(prof) -> float:
    c0 = time.process_time()
    simulate("SS", "ramp", duration_s=prof.duration_s, timestep_s=prof.timestep_s, transient_s=prof.transient_s)
    return time.process_time() - c0


def _warm(_=None) -> None:
    simulate("SS", "ramp", duration_s=0.05, transient_s=0.0)  # compiled code loaded


def bare_cpu(prof) -> float:
    """CPU seconds of one bare SS ramp rollout of the profile in this process."""
    _warm()
    return _bare(prof)


def bare_parallel_wall(prof, workers: int) -> float:
    """Wall seconds of `workers` bare rollouts started together, one per
    process: the simulator's own limit when every core is busy."""
    with ProcessPoolExecutor(workers, mp_context=multiprocessing.get_context("fork")) as pool:
        list(pool.map(_warm, range(workers)))
        t0 = time.perf_counter()
        list(pool.map(_bare, [prof] * workers))
        return time.perf_counter() - t0


class CpuMeter:
    """CPU seconds of this process and every process below it while the
    block runs: /proc sampled every 0.2 s from a thread (the evaluation
    processes are the fork server's children, which RUSAGE_CHILDREN never
    sees). Linux only."""

    def __init__(self):
        self.last: dict[int, float] = {}
        self._stop = threading.Event()

    @staticmethod
    def _cpu(pid: int) -> tuple[int, float] | None:
        try:
            with open(f"/proc/{pid}/stat") as f:
                fields = f.read().rsplit(")", 1)[1].split()
        except OSError:
            return None
        return int(fields[1]), (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")

    def _sample(self) -> None:
        stats = {int(p): self._cpu(int(p)) for p in os.listdir("/proc") if p.isdigit()}
        stats = {p: v for p, v in stats.items() if v is not None}
        mine, grew = {os.getpid()}, True
        while grew:  # this process's descendants
            new = {p for p, (pp, _) in stats.items() if pp in mine} - mine
            grew, mine = bool(new), mine | new
        for p in mine:
            self.last[p] = max(self.last.get(p, 0.0), stats[p][1])

    def _run(self) -> None:
        while not self._stop.wait(0.2):
            self._sample()

    def __enter__(self) -> CpuMeter:
        self.start = self._cpu(os.getpid())[1]
        self._thread = threading.Thread(target=self._run, daemon=True)
        self._thread.start()
        return self

    def __exit__(self, *exc) -> None:
        self._sample()
        self._stop.set()
        self._thread.join()
        self.seconds = sum(self.last.values()) - self.start


def overhead(config: StudyConfig, n: int) -> tuple[float, float]:
    """CPU seconds of n trials of the optimizer's loop in this process (one
    evaluation process: this one), and of the simulation inside them
    (run_behaviour, timed by wrapping it)."""
    inside = [0.0]
    run_behaviour = evaluators_module.run_behaviour

    def timed(*args, **kwargs):
        c0 = time.process_time()
        try:
            return run_behaviour(*args, **kwargs)
        finally:
            inside[0] += time.process_time() - c0

    with tempfile.TemporaryDirectory() as tmp:
        opts = RunOptions(trials=n, workers=1, studies_dir=tmp, progress=False)
        storage = opts.open(config.name)
        study = create_or_load(config, storage, make_sampler(opts.sampler, opts.seed))
        evaluators_module.run_behaviour = timed
        try:
            with PoolEvaluator(f"{tmp}/cache", workers=1) as evaluator:
                c0 = time.process_time()
                run_loop(study, storage, config, evaluator, opts)
                total = time.process_time() - c0
        finally:
            evaluators_module.run_behaviour = run_behaviour
        del study
    return total, inside[0]


if __name__ == "__main__":
    main()
