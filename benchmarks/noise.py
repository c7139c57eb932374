"""The optimizer's noise study: how many replicates should a trial get?

Six of the paper's designs (SS, rho-inc, PVC-Ti-SS, PVC, Al, Ti) run on
each behaviour, once unperturbed and under --replicates seeded
perturbations (the search's seeds, ``mat_hopper.optimize._robust``:
common random numbers), on a profile (default quick). For each behaviour
and objective it prints

- the replicate spread: the median over designs of the replicates'
  coefficient of variation (sd / mean);
- the unperturbed run's error: the median |nominal - mean of all
  replicates| / mean;
- for K = 1 .. n: the median standard error of a K-replicate mean, as a
  fraction of the between-design sd of the n-replicate means, and
  Kendall's tau between the designs' K-replicate means (first K seeds)
  and their n-replicate means (K = 0: the unperturbed run).

    python benchmarks/noise.py                         # quick, forward and ramp, 6 replicates
    python benchmarks/noise.py --behaviours forward --replicates 8 --csv noise.csv
"""

from __future__ import annotations

import argparse

import numpy as np
import pandas as pd
from scipy import stats

from mat_hopper.experiments.profiles import get_profile
from mat_hopper.materials import paper_designs
from mat_hopper.optimize._objective import OBJECTIVES, Objective, mujoco_warnings_to, run_behaviour
from mat_hopper.optimize._robust import perturbations

DESIGNS = ("SS", "rho-inc", "PVC-Ti-SS", "PVC", "Al", "Ti")


def runs(behaviours, replicates: int, profile) -> pd.DataFrame:
    """One row per (design, behaviour, replicate; -1 unperturbed)."""
    rows = []
    designs = paper_designs()
    for b in behaviours:
        ob = Objective(behaviours=(b,), profile=profile, replicates=0)
        for name in DESIGNS:
            for pert in [None, *perturbations(replicates)]:
                with mujoco_warnings_to([]):
                    r = run_behaviour(designs[name], b, ob, perturbation=pert)
                rows.append({"design": name, **{k: r[k] for k in ("behaviour", "replicate", *OBJECTIVES, "upright")}})
                print(name, b, r["replicate"], *(f"{r[o]:.4g}" for o in OBJECTIVES), flush=True)
    return pd.DataFrame(rows)


def summary(frame: pd.DataFrame) -> pd.DataFrame:
    """The module doc's figures, one row per (behaviour, objective, K)."""
    out = []
    for (b,), g in frame.groupby(["behaviour"]):
        reps = g[g["replicate"] >= 0]
        n = reps["replicate"].nunique()
        seeds = sorted(reps["replicate"].unique())
        for o in OBJECTIVES:
            wide = reps.pivot(index="design", columns="replicate", values=o)[seeds]
            full = wide.mean(axis=1)
            nominal = g[g["replicate"] < 0].set_index("design")[o].reindex(wide.index)
            cv = float(np.median(wide.std(axis=1, ddof=1) / wide.mean(axis=1)))
            nominal_err = float(np.median((nominal - full).abs() / full))
            between = float(full.std(ddof=1))
            for k in range(0, n + 1):
                est = nominal if k == 0 else wide.iloc[:, :k].mean(axis=1)
                se = np.nan if k < 2 else float(np.median(wide.iloc[:, :k].std(axis=1, ddof=1) / np.sqrt(k)))
                out.append(
                    {
                        "behaviour": b,
                        "objective": o,
                        "replicate_cv": cv,
                        "nominal_rel_error": nominal_err,
                        "K": k,
                        "se_over_between_sd": se / between,
                        "kendall_tau_vs_all": float(stats.kendalltau(est, full).statistic),
                    }
                )
    return pd.DataFrame(out)


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--behaviours", default="forward,ramp")
    p.add_argument("--replicates", type=int, default=6)
    p.add_argument("--profile", default="quick")
    p.add_argument("--csv", help="write the runs here")
    a = p.parse_args()
    frame = runs([b.strip() for b in a.behaviours.split(",")], a.replicates, get_profile(a.profile))
    if a.csv:
        frame.to_csv(a.csv, index=False)
    pd.set_option("display.width", 200)
    print(summary(frame).to_string(index=False, float_format=lambda v: f"{v:.3g}"))


if __name__ == "__main__":
    main()
