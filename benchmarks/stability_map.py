"""The stable-time-step map with its two brackets, side by side in one run.

``analytic`` (the default since issue 13) starts each design's search at its
analytic bound (the smaller of the spring chain's 2 / w_max and the
controller's delayed-damping limit) and steps by 1.5; ``ladder`` (the first
release) starts at 1e-2 s and steps down by sqrt(10). Both run the same
profile's grid through the runner with fresh temporary caches and the same
workers, alternating (ladder, analytic, ladder, analytic, ...) over
--repeats rounds; the last line is the ratio of the medians.

    python benchmarks/stability_map.py [--profile paper] [--workers 2] [--repeats 1] [--grid N]
"""

from __future__ import annotations

import argparse
import statistics
import tempfile
import time
from dataclasses import replace

from mat_hopper.experiments.paper import StabilityMap
from mat_hopper.experiments.profiles import get_profile
from mat_hopper.experiments.runner import default_workers, run_grid


def run_map(profile, bracket: str, workers: int) -> tuple[float, int, float]:
    """(wall s, tries in all, median measured step s) of one map."""
    tasks = [replace(t, bracket=bracket) for t in StabilityMap().tasks(profile)]
    with tempfile.TemporaryDirectory() as cache:
        t0 = time.perf_counter()
        res = run_grid(tasks, cache, workers=workers, progress=False, desc=bracket)
        wall = time.perf_counter() - t0
    s = res.summary
    return wall, int(s["n_tries"].sum()), float(s["max_stable_timestep_s"].median())


def main(argv=None) -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--profile", default="paper")
    p.add_argument("--workers", type=int, default=default_workers())
    p.add_argument("--repeats", type=int, default=1)
    p.add_argument("--grid", type=int, help="override the profile's grid size (designs per axis)")
    a = p.parse_args(argv)
    prof = get_profile(a.profile)
    if a.grid:
        prof = replace(prof, stability_grid_size=a.grid)
    n = prof.stability_grid_size**2
    print(f"profile {prof.name}: {n} designs, {prof.stability_duration_s:g} s per try, {a.workers} workers")
    walls = {"ladder": [], "analytic": []}
    for _ in range(a.repeats):
        for bracket in ("ladder", "analytic"):
            wall, tries, med = run_map(prof, bracket, a.workers)
            walls[bracket].append(wall)
            print(
                f"{bracket:8s} wall {wall:7.1f} s  tries {tries:5d} ({tries / n:.1f} per design)  median step {med:.3g} s"
            )
    lad, ana = statistics.median(walls["ladder"]), statistics.median(walls["analytic"])
    print(f"ratio analytic/ladder={ana / lad:.2f}")


if __name__ == "__main__":
    main()
