"""Which sampler finds the front fastest? Hypervolume after every trial, side by side.

Every sampler gets the same study: the same objective (tracking error and
hip power on the ramp, the book's constraints), the same space
(continuous density and modulus per segment, 3 segments; optionally
restricted to Ashby classes), the same enqueued paper designs first, the
same seed, batch size and trial budget, run by the optimizer's loop
(:func:`mat_hopper.optimize.run_loop` with the CPU pool evaluator, as the
book runs its study: rounds of trials through the result runner, so the
paper designs' runs, shared by every sampler, are simulated once). Then it prints the hypervolume of
each sampler's feasible trials after every ``--every`` trials, side by
side, and the mean over the budget (the area under the curve: which
sampler got there first), the final value and the number of feasible
trials, for two reference points, one for all samplers each: the worst
feasible value of each objective over every sampler's trials, and over
the paper's designs only (plus 10 % of the range): the second measures
only the region that competes with the paper, where a few extreme
feasible trials (tens of W) cannot swamp the differences.

Samplers: Optuna's multi-objective TPE (``tpe``, the book's: multivariate,
constant liar), NSGA-II (``nsga2``), random search (``random``, the floor
any sampler must beat) and the GP sampler (``gp``, when PyTorch is
installed).

    python benchmarks/sampler.py [--profile quick] [--duration 12] [--trials 48] [--batch 8]
        [--samplers tpe,nsga2,random] [--seed 0] [--ashby-classes metal,polymer] [--workers 2]
"""

from __future__ import annotations

import argparse
import dataclasses
import importlib.util
import tempfile
import time

import numpy as np
import optuna
import pandas as pd

from mat_hopper.experiments.profiles import get_profile
from mat_hopper.optimize import (
    Objective,
    PoolEvaluator,
    RunOptions,
    SearchSpace,
    StudyConfig,
    create_or_load,
    run_loop,
    trials_frame,
)
from mat_hopper.optimize._samplers import make_sampler, sampler_seed
from mat_hopper.optimize.report import HV_MARGIN, feasible_complete, hypervolume_2d


def sampler_for(name: str, seed: int):
    if name == "random":
        return optuna.samplers.RandomSampler(seed=sampler_seed(seed, 0))
    return make_sampler(name, sampler_seed(seed, 0))


def hv_table(frames: dict, reference, trials: int) -> pd.DataFrame:
    """Hypervolume of each sampler's feasible trials after each trial."""
    rows = []
    for n in range(1, trials + 1):
        row = {"trials": n}
        for name, f in frames.items():
            good = feasible_complete(f[f["trial"] < n])
            row[name] = hypervolume_2d(good[["tracking_error_m", "power_w"]].to_numpy(float), reference)
        rows.append(row)
    return pd.DataFrame(rows)


def main(argv=None) -> pd.DataFrame:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--profile", default="quick")
    ap.add_argument("--duration", type=float, help="run length (s), shorter than the profile's for a first look")
    ap.add_argument("--trials", type=int, default=48)
    ap.add_argument("--batch", type=int, default=8)
    ap.add_argument("--every", type=int, default=4, help="print a row every N trials")
    ap.add_argument("--samplers", default="tpe,nsga2,random" + (",gp" if importlib.util.find_spec("torch") else ""))
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--ashby-classes", default="")
    ap.add_argument("--workers", type=int)
    ap.add_argument("--cache", help="result cache folder (default: a temporary one)")
    args = ap.parse_args(argv)

    profile = get_profile(args.profile)
    if args.duration:
        profile = dataclasses.replace(
            profile,
            name=f"{profile.name}-{args.duration:g}s",
            duration_s=args.duration,
            transient_s=min(profile.transient_s, args.duration / 3),
        )
    objective = Objective(profile=profile, replicates=0)  # single draws, as its recorded comparison was run
    config = StudyConfig("bench", SearchSpace(ashby_classes=args.ashby_classes), objective)
    tmp = tempfile.mkdtemp(prefix="mat-hopper-sampler-")
    frames, walls = {}, {}
    for name in [s.strip() for s in args.samplers.split(",") if s.strip()]:
        t0 = time.perf_counter()
        storage = optuna.storages.InMemoryStorage()
        study = create_or_load(config, storage, sampler=sampler_for(name, args.seed))
        options = RunOptions(trials=args.trials, batch_size=args.batch, progress=False)
        with PoolEvaluator(args.cache or f"{tmp}/cache", workers=args.workers) as evaluator:
            run_loop(study, storage, config, evaluator, options)
        walls[name] = time.perf_counter() - t0
        frames[name] = trials_frame(study, config)
        print(f"{name}: {args.trials} trials in {walls[name]:.0f} s", flush=True)

    ok = pd.concat([feasible_complete(f) for f in frames.values()])
    paper = ok[ok["paper_design"].fillna("") != ""]
    tables = {}
    for what, pts in (("every sampler's feasible trials", ok), ("the paper's feasible designs", paper)):
        vals = pts[["tracking_error_m", "power_w"]].to_numpy(float)
        lo, hi = vals.min(axis=0), vals.max(axis=0)
        reference = hi + HV_MARGIN * np.where(hi > lo, hi - lo, np.abs(hi))
        tables[what] = table = hv_table(frames, reference, args.trials)
        print(
            f"\nhypervolume (m W) after each trial, reference point from the worst of {what} "
            f"({reference[0]:.4g} m, {reference[1]:.4g} W); {config.objective.behaviours[0]}, {profile.name} "
            f"profile ({profile.duration_s:g} s runs), seed {args.seed}, batch {args.batch}; trials "
            f"1-{len(config.space.seeds())} are the paper's designs"
        )
        shown = table[(table["trials"] % args.every == 0) | (table["trials"] == args.trials)]
        print(shown.to_string(index=False, float_format=lambda v: f"{v:.4g}"))
        summary = pd.DataFrame(
            {
                "sampler": list(frames),
                "mean hypervolume": [table[s].mean() for s in frames],
                "final hypervolume": [table[s].iloc[-1] for s in frames],
                "feasible": [len(feasible_complete(f)) for f in frames.values()],
                "wall s": [walls[s] for s in frames],
            }
        ).sort_values("mean hypervolume", ascending=False)
        print(summary.to_string(index=False, float_format=lambda v: f"{v:.4g}"))
        print(f"best by mean hypervolume (area under the curve): {summary.iloc[0]['sampler']}")
    table = tables["the paper's feasible designs"]
    return table


if __name__ == "__main__":
    main()
