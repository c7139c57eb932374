"""The modulus question where a leg can bend: chapter 9c's crossed legs
(rho-inc's densities at SS's 193 GPa, SS's densities at rho-inc's 70 GPa,
beside rho-inc and SS) on the ramp under a bending convention and a named
contact, on paired replicate seeds of a profile. Does the modulus change
tracking error or power beyond the ±10 % margin when the leg bends?

Every leg runs at one physics step and one control period, the finest any
of the four needs under ``timestep_s="auto"`` (so they are compared alike).
The contrasts, paired intervals, Holm families and verdicts are those of
chapter 9c (:mod:`mat_hopper.analysis.paired`).

    python benchmarks/crossed_legs_bending.py [--profile paper] [--convention bending]
        [--contact stiff] [--csv out.csv]
"""

from __future__ import annotations

import argparse
import time
from dataclasses import replace

import pandas as pd

from mat_hopper.analysis import paired
from mat_hopper.analysis.stats import drop_unusable, unusable_runs
from mat_hopper.core.behaviours import behaviour
from mat_hopper.core.materials import LegDesign, parse_design
from mat_hopper.core.timestep import auto_timestep
from mat_hopper.experiments.profiles import get_profile
from mat_hopper.experiments.runner import RunSpec, run_grid
from mat_hopper.physics.metrics import holm

METRICS = ("tracking_error_m", "power_w", "power_total_w")


def crossed_legs() -> dict[str, LegDesign]:
    rho, ss = parse_design("rho-inc"), parse_design("SS")
    return {
        "rho-inc": rho,
        "rho-inc at 193 GPa": LegDesign.from_properties(rho.densities_g_cm3, ss.moduli_gpa, name="rho-inc-at-193GPa"),
        "SS at 70 GPa": LegDesign.from_properties(ss.densities_g_cm3, rho.moduli_gpa, name="SS-at-70GPa"),
        "SS": ss,
    }


CONTRASTS = {  # label: (design, against)
    "claim: rho-inc against SS": ("rho-inc", "SS"),
    "modulus 70 vs 193 GPa, at rho-inc's densities": ("rho-inc", "rho-inc at 193 GPa"),
    "modulus 70 vs 193 GPa, at SS's densities": ("SS at 70 GPa", "SS"),
    "densities rho-inc vs SS, at 70 GPa": ("rho-inc", "SS at 70 GPa"),
    "densities rho-inc vs SS, at 193 GPa": ("rho-inc at 193 GPa", "SS"),
}


def tasks(profile, convention: str, contact: str):
    legs = crossed_legs()
    autos = [auto_timestep(leg, convention, contact=contact) for leg in legs.values()]
    period = min(k * dt for k, dt in autos)
    dt = min(dt for _, dt in autos)
    substeps = max(1, round(period / dt))
    out = []
    for name, leg in legs.items():
        for seed in range(profile.replicates):
            s = profile.sim_settings(profile.replicate(seed), design=leg)
            s = replace(s, convention=convention, contact=contact, timestep_s=period / substeps, substeps=substeps)
            out.append(RunSpec(leg, behaviour("ramp"), s, {"leg": name, "replicate": seed}))
    return out, period, substeps


def factorial(grid) -> pd.DataFrame:
    usable = drop_unusable(grid.tables, unusable_runs(grid.summary))
    means = usable.groupby(["leg", "replicate"])[list(METRICS)].mean()
    rows = []
    for label, (a, c) in CONTRASTS.items():
        for m in METRICS:
            rows.append({"contrast": label, "metric": m, **paired.paired_effect(means.xs(a)[m], means.xs(c)[m])})
    table = pd.DataFrame(rows)
    claim = table["contrast"].str.startswith("claim")
    table.loc[claim, "p_holm"] = table.loc[claim, "p"]
    for _, g in table[~claim].groupby("metric"):
        table.loc[g.index, "p_holm"] = holm(g["p"].to_numpy(float))
    table["conclusion"] = [paired.conclusion(p, lo, hi) for p, lo, hi in zip(table.p_holm, table.ci_low, table.ci_high)]
    return table


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--profile", default="paper")
    ap.add_argument("--convention", default="bending")
    ap.add_argument("--contact", default="stiff")
    ap.add_argument("--cache", default="results/cache")
    ap.add_argument("--csv")
    args = ap.parse_args()
    profile = get_profile(args.profile)
    specs, period, substeps = tasks(profile, args.convention, args.contact)
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
