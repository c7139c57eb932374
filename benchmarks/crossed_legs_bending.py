"""The modulus question where a leg can bend: chapter 9c's crossed legs
(rho-inc's densities at SS's 193 GPa, SS's densities at rho-inc's 70 GPa,
beside rho-inc and SS) on the ramp under a bending convention and a named
contact, on paired replicate seeds of a profile. Does the modulus change
tracking error or power beyond the ±10 % margin when the leg bends?

Every leg runs at one physics step and one control period, the finest any
of the four needs under ``timestep_s="auto"`` (so they are compared alike).
The legs, the timing rule (:func:`mat_hopper.experiments.crossed_legs.common_step_tasks`),
the contrasts, paired intervals, Holm families and verdicts
(:func:`mat_hopper.analysis.factorial.factorial_effects`) are those of chapter 9c.

    python benchmarks/crossed_legs_bending.py [--profile paper] [--convention bending]
        [--contact stiff] [--csv out.csv]
"""

from __future__ import annotations

import argparse
import time

from mat_hopper.analysis.factorial import factorial_effects
from mat_hopper.analysis.stats import drop_unusable, unusable_runs
from mat_hopper.experiments import crossed_legs
from mat_hopper.experiments.profiles import get_profile
from mat_hopper.experiments.runner import run_grid

METRICS = ("tracking_error_m", "power_w", "power_total_w")


def factorial(grid):
    usable = drop_unusable(grid.tables, unusable_runs(grid.summary))
    means = usable.groupby(["leg", "replicate"])[list(METRICS)].mean()
    return factorial_effects(means, crossed_legs.CONTRASTS, metrics=METRICS, alone=(crossed_legs.CLAIM,))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--profile", default="paper")
    ap.add_argument("--convention", default="bending")
    ap.add_argument("--contact", default="stiff")
    ap.add_argument("--cache", default="results/cache")
    ap.add_argument("--csv")
    args = ap.parse_args()
    profile = get_profile(args.profile)
    period, substeps = crossed_legs.common_step(args.convention, args.contact)
    specs = crossed_legs.common_step_tasks(profile, args.convention, args.contact)
    print(f"{len(specs)} runs, {args.convention}, {args.contact} contact, control period {period:.3g} s, "
          f"{substeps} substeps, {profile.name} profile", flush=True)  # fmt: skip
    t0 = time.perf_counter()
    grid = run_grid(specs, args.cache, desc="crossed legs")
    bad = unusable_runs(grid.summary)
    print(f"{grid.n_computed} computed, {grid.n_cached} cached, {len(bad)} unusable, {time.perf_counter() - t0:.0f} s")
    table = factorial(grid)
    cols = ["contrast", "metric", "n_pairs", "pct_change", "ci_low", "ci_high", "p_holm", "conclusion"]
    print(table[cols].to_string(index=False))
    if args.csv:
        table.to_csv(args.csv, index=False)


if __name__ == "__main__":
    main()
