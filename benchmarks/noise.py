"""The optimizer's noise study: how many replicates should a trial get?

Six of the paper's designs (SS, rho-inc, PVC-Ti-SS, PVC, Al, Ti) run on
each behaviour, once unperturbed and under --replicates seeded
perturbations (the search's seeds, ``mat_hopper.optimize._scoring``:
common random numbers), on a profile (default quick). For each behaviour
and objective it prints

- the replicate spread: the median over designs of the replicates'
  coefficient of variation (sd / mean);
- the unperturbed run's error: the median |nominal - mean of all
  replicates| / mean;
- the variance of a paired difference between two designs on the same
  seeds (common random numbers) over the unpaired variance (median over
  pairs);
- for K = 0 .. n/2 (K = 0: the unperturbed run): the relative standard
  error of a K-replicate mean, and, judged on the held-out second half of
  the seeds, the fraction of design pairs that the K-replicate means (of
  every K-subset of the first half) order as the held-out means do, and
  Kendall's tau.

    python benchmarks/noise.py                         # quick, forward and ramp, 6 replicates
    python benchmarks/noise.py --behaviours forward --replicates 8 --csv noise.csv
"""

from __future__ import annotations

import argparse
import itertools

import numpy as np
import pandas as pd
from scipy import stats

from mat_hopper.core.materials import paper_designs
from mat_hopper.experiments.profiles import get_profile
from mat_hopper.optimize._objective import OBJECTIVES, Objective, mujoco_warnings_to, run_behaviour
from mat_hopper.optimize._scoring import perturbations

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
        seeds = sorted(reps["replicate"].unique())
        n = len(seeds)
        for o in OBJECTIVES:
            wide = reps.pivot(index="design", columns="replicate", values=o)[seeds].to_numpy(float)
            full = wide.mean(axis=1)
            nominal = (
                g[g["replicate"] < 0]
                .set_index("design")[o]
                .reindex(reps.pivot(index="design", columns="replicate", values=o).index)
                .to_numpy(float)
            )
            cv = wide.std(axis=1, ddof=1) / wide.mean(axis=1)
            pairs = list(itertools.combinations(range(len(wide)), 2))
            # common random numbers: variance of a paired difference against unpaired
            paired = [np.var(wide[i] - wide[j], ddof=1) for i, j in pairs]
            unpaired = [np.var(wide[i], ddof=1) + np.var(wide[j], ddof=1) for i, j in pairs]
            crn_ratio = float(np.median(np.array(paired) / np.array(unpaired)))
            # the first half of the seeds is the search's pool, the second half held out
            half = n // 2
            held = wide[:, half:].mean(axis=1)
            for k in range(0, half + 1):
                subsets = [None] if k == 0 else list(itertools.combinations(range(half), k))
                agree, taus = [], []
                for sub in subsets:
                    # K = 0: the unperturbed run; else the mean of K pool seeds, judged on the held-out seeds
                    est = nominal if sub is None else wide[:, list(sub)].mean(axis=1)
                    rest = held
                    agree += [np.sign(est[i] - est[j]) == np.sign(rest[i] - rest[j]) for i, j in pairs]
                    taus.append(stats.kendalltau(est, rest).statistic)
                out.append(
                    {
                        "behaviour": b,
                        "objective": o,
                        "K": k,
                        "replicate_cv": float(np.median(cv)),
                        "rel_se_of_mean": np.nan if k == 0 else float(np.median(cv) / np.sqrt(k)),
                        "nominal_bias": float(np.median((nominal - full) / full)),
                        "crn_variance_ratio": crn_ratio,
                        "pair_order_agreement": float(np.mean(agree)),
                        "kendall_tau": float(np.mean(taus)),
                    }
                )
    return pd.DataFrame(out)


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--behaviours", default="forward,ramp")
    p.add_argument("--replicates", type=int, default=6)
    p.add_argument("--profile", default="quick")
    p.add_argument("--csv", help="write the runs here")
    p.add_argument("--from-csv", help="summarize the runs of an earlier --csv instead of running")
    a = p.parse_args()
    if a.from_csv:
        frame = pd.read_csv(a.from_csv)
    else:
        frame = runs([b.strip() for b in a.behaviours.split(",")], a.replicates, get_profile(a.profile))
    if a.csv:
        frame.to_csv(a.csv, index=False)
    pd.set_option("display.width", 200)
    print(summary(frame).to_string(index=False, float_format=lambda v: f"{v:.3g}"))


if __name__ == "__main__":
    main()
