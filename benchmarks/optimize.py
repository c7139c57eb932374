"""Optimizer throughput: trials per hour of 60 s ramp trials on this machine.

Runs a fresh study (SQLite in a temporary folder, the default storage)
with --workers processes and the paper profile (60 s runs, 1e-4 s step),
then prints

- trials/hour end to end (study creation and worker start included);
- full-run trials/hour: simulated seconds per wall hour / 60, which does
  not flatter the figure when some designs diverge early (cheap trials);
- the simulator's own limit on this machine: one 60 s SS ramp rollout
  timed in this process (CPU time), times the worker count;
- the optimizer's efficiency: full-run trials/hour over that limit.

By default the space is the paper's catalogue materials (PVC, Al, Ti, SS
per segment), whose designs all run the full minute, so the figure is the
cost of real 60 s trials.

    python benchmarks/optimize.py [--trials 8] [--workers 2] [--space catalogue]
"""

from __future__ import annotations

import argparse
import os
import tempfile
import time

import optuna
from optuna.trial import TrialState

from mat_hopper.optimize import RunOptions, StudyConfig, run_study
from mat_hopper.optimize_objective import PROFILES, Objective
from mat_hopper.optimize_space import SearchSpace
from mat_hopper.optimize_storage import open_storage
from mat_hopper.sim import simulate


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--trials", type=int, default=8)
    p.add_argument("--workers", type=int, default=2)
    p.add_argument("--space", default="catalogue", help="catalogue (PVC, Al, Ti, SS) or continuous")
    p.add_argument("--profile", default="paper")
    p.add_argument("--no-limit", action="store_true", help="skip timing the bare simulator")
    a = p.parse_args(argv)
    prof = PROFILES[a.profile]
    space = SearchSpace(kinds=a.space, materials=("PVC", "Al", "Ti", "SS"))
    config = StudyConfig("bench", space, Objective(behaviours=("ramp",), profile=prof))
    with tempfile.TemporaryDirectory() as tmp:
        opts = RunOptions(trials=a.trials, workers=a.workers, studies_dir=tmp, progress=False)
        t0 = time.perf_counter()
        res = run_study(config, opts)
        wall = time.perf_counter() - t0
        study = optuna.load_study(study_name="bench", storage=open_storage(opts.storage_url("bench")))
        done = study.get_trials(deepcopy=False, states=(TrialState.COMPLETE,))
        sim_s = sum(t.user_attrs["result"]["simulated_s"] for t in done)
        del study
    print(f"{len(done)} trials ({a.space} space, {prof.name} profile: {prof.duration_s:g} s ramp runs at "
          f"{prof.timestep_s:g} s), {a.workers} workers, {os.cpu_count()} CPUs: {wall:.1f} s wall")
    print(f"trials/hour end to end: {len(done) / wall * 3600:.0f}")
    full = sim_s / prof.duration_s / wall * 3600
    print(f"full-run trials/hour (simulated s / {prof.duration_s:g} per wall hour): {full:.0f}")
    if not res.finished:
        print("warning: the study did not reach its target")
    if not a.no_limit:
        simulate("SS", "ramp", duration=0.05, transient=0.0)          # compiled code loaded
        c0 = time.process_time()
        simulate("SS", "ramp", duration=prof.duration_s, timestep=prof.timestep_s, transient=prof.transient_s)
        cpu = time.process_time() - c0
        limit = a.workers * 3600 / cpu
        print(f"simulator limit: one {prof.duration_s:g} s rollout = {cpu:.2f} s CPU -> "
              f"{limit:.0f} trials/hour on {a.workers} cores")
        print(f"optimizer efficiency: {full / limit:.0%} of the simulator's limit")


if __name__ == "__main__":
    main()
