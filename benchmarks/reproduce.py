"""Wall time of ``mat-hopper reproduce``, per experiment and in total.

Full mode (default): runs :func:`mat_hopper.experiments.reproduce.reproduce` from
a fresh, empty cache (a temporary folder unless --cache is given) and
prints the wall seconds of each experiment, of the figures and claims, and
the total.

Sampled mode (``--sample K``): an estimate without the full cost. For each
experiment it takes the runs that would really be computed (unique keys
not already done by an earlier experiment, e.g. exp3's MD and SS
baselines come from exp1), times every K-th of them one by one in this
process, and extrapolates: estimated wall = mean seconds per run x runs to
compute / workers. Pool start-up and the figures are not included.

    python benchmarks/reproduce.py [--profile paper] [--experiments 1,2,3,stability]
                                   [--workers 2] [--sample K] [--cache DIR]
"""

from __future__ import annotations

import argparse
import os
import tempfile
import time

from mat_hopper.experiments.paper import get_experiment, parse_experiments
from mat_hopper.experiments.profiles import get_profile
from mat_hopper.experiments.reproduce import reproduce
from mat_hopper.experiments.runner import default_workers


def sampled(profile, names, workers: int, k: int) -> None:
    done: set[str] = set()
    total = 0.0
    print(f"sampled estimate: every {k}th run to compute, timed alone, / {workers} workers")
    for name in names:
        tasks = get_experiment(name).tasks(profile)
        unique = {}
        for t in tasks:
            key = t.key()
            if key not in done:
                unique.setdefault(key, t)
        done |= set(unique)
        todo = list(unique.values())
        sample = todo[::k]
        times = []
        for t in sample:
            t0 = time.perf_counter()
            t.compute()
            times.append(time.perf_counter() - t0)
        mean = sum(times) / len(times) if times else 0.0
        est = mean * len(todo) / workers
        total += est
        print(
            f"{name:10s} {len(tasks):4d} tasks, {len(todo):4d} to compute; sampled {len(sample):3d}: "
            f"{mean:6.2f} s/run (min {min(times, default=0):.2f}, max {max(times, default=0):.2f}) "
            f"-> estimated {est:7.1f} s wall"
        )
    print(f"{'total':10s} estimated {total:7.1f} s wall ({total / 60:.1f} min) on {workers} workers")


def full(profile, names, workers: int, cache: str | None) -> None:
    with tempfile.TemporaryDirectory(prefix="mat-hopper-bench-") as tmp:
        cache = cache or os.path.join(tmp, "cache")
        out = os.path.join(tmp, "out")
        t0 = time.perf_counter()
        rep = reproduce(profile, names, out, workers=workers, cache_dir=cache, progress=False, log=print)
        total = time.perf_counter() - t0
    for name, s in rep.wall_s.items():
        print(f"{name:10s} {s:7.1f} s wall" + (f"  ({rep.computed[name]} computed)" if name in rep.computed else ""))
    print(f"{'total':10s} {total:7.1f} s wall ({total / 60:.1f} min) on {workers} workers")


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--profile", default="paper")
    p.add_argument("--experiments", default="1,2,3,stability")
    p.add_argument("--workers", type=int, default=None, help="default: all cores")
    p.add_argument("--sample", type=int, default=1, help="time every K-th run only and extrapolate (K > 1)")
    p.add_argument("--cache", default=None, help="cache folder for full mode (default: fresh temporary)")
    a = p.parse_args(argv)
    profile = get_profile(a.profile)
    names = parse_experiments(a.experiments)
    workers = a.workers or default_workers()
    print(
        f"profile={profile.name} experiments={','.join(names)} workers={workers} "
        f"load average={' '.join(f'{x:.2f}' for x in os.getloadavg())}"
    )
    if a.sample > 1:
        sampled(profile, names, workers, a.sample)
    else:
        full(profile, names, workers, a.cache)


if __name__ == "__main__":
    main()
