"""Chapter 8b's stress pairs under a bending convention on a named contact:
each paper gradient beside its mass-matched leg and titanium, paired on
the profile's seeds (:func:`mat_hopper.experiments.stress_pairs.stress_pair_tasks`),
judged as the chapter judges them
(:func:`mat_hopper.analysis.stress_pairs.stress_verdicts`). On the soft
default contact most bending legs fall; on the stiff one they stand, so
the stress and fatigue verdicts can be read where the leg bends.

    python benchmarks/stress_pairs_contact.py [--profile paper] [--conventions bending] [--contact stiff]
        [--cache results/cache] [--runs-csv runs.csv] [--csv verdicts.csv]
"""

from __future__ import annotations

import argparse
import time

import pandas as pd
from _inputs import outputs, settings  # benchmarks/, on the path of a script run from there

from mat_hopper.analysis.stress_pairs import stress_verdicts, usable_pairs
from mat_hopper.experiments.runner import run_grid
from mat_hopper.experiments.stress_pairs import stress_pair_tasks


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--profile", default="paper", help="run profile: paper or quick (default paper)")
    ap.add_argument("--conventions", default="bending", help="comma-separated stiffness conventions (default bending)")
    ap.add_argument("--contact", default="stiff", help="the foot's contact: authors or stiff (default stiff)")
    ap.add_argument("--cache", default="results/cache", help="result cache folder (default results/cache)")
    ap.add_argument("--runs-csv", help="write the run summaries here")
    ap.add_argument("--csv", help="write the verdicts here")
    args = ap.parse_args()
    names = [c.strip() for c in args.conventions.split(",") if c.strip()]
    if not names:
        ap.error(f"--conventions names none, got {args.conventions!r}; e.g. bending")
    profile, conventions, contact = settings(ap, args.profile, names, args.contact)
    outputs(ap, args.cache, csv=args.csv, runs_csv=args.runs_csv)
    tasks = stress_pair_tasks(profile, conventions, contact=contact)
    print(f"{len(tasks)} runs, {', '.join(conventions)}, {contact} contact, {profile.name} profile", flush=True)
    t0 = time.perf_counter()
    grid = run_grid(tasks, args.cache, desc="stress pairs")
    runs = grid.summary
    print(f"{grid.n_computed} computed, {grid.n_cached} cached, {time.perf_counter() - t0:.0f} s")
    up = runs.assign(stayed_up=runs["status"] == "ok").groupby(["convention", "leg"])["stayed_up"].mean()
    print("stayed up:", up.to_dict())
    verdicts = stress_verdicts(usable_pairs(runs), profile.replicates)
    cols = ["convention", "gradient", "metric", "against", "n_pairs", "pct_change", "ci_low", "ci_high", "conclusion"]
    with pd.option_context("display.width", 200):
        print(verdicts[cols].to_string(index=False, float_format=lambda v: f"{v:.3g}"))
    if args.runs_csv:
        runs.to_csv(args.runs_csv, index=False)
    if args.csv:
        verdicts.to_csv(args.csv, index=False)


if __name__ == "__main__":
    main()
