"""The modulus question where a leg can bend: experiment 2's modulus
sweeps (ref.SWEEPS) under a bending convention and a named contact, on
paired replicate seeds. Does the modulus change tracking error or power
beyond the ±10 % margin when the leg bends?

Per base material (PVC, Al, Ti, SS, each at its own density), its softest
and stiffest swept modulus against its own (the base material), and its
rigid twin (no springs: the limit of an infinite modulus, ``inf`` in the
table; ``--no-rigid`` leaves it out), forward hopping. A base's legs all run at one physics step and control period,
the finest any of them needs under ``timestep_s="auto"`` (so they are
compared alike, at the step the stiffest needs). Paired % differences on
the seeds, their 95 % t intervals, Holm over each metric's contrasts, and
the book's verdicts with the ±10 % margin (:mod:`mat_hopper.analysis.paired`),
and each contrast again on each half of the scored window (``stationarity``).

    python benchmarks/modulus_sweeps_bending.py [--profile paper] [--replicates 10] [--convention bending]
        [--contact stiff] [--no-rigid] [--only SS=15,193 ...] [--step-divisor 2] [--cache results/cache]
        [--runs-csv runs.csv] [--csv out.csv]
"""

from __future__ import annotations

import argparse
import math
import time
from dataclasses import replace

import pandas as pd
from _inputs import outputs, settings  # benchmarks/, on the path of a script run from there

from mat_hopper.analysis import paired
from mat_hopper.analysis.stationarity import stationarity, window_halves
from mat_hopper.analysis.stats import drop_unusable, unusable_runs
from mat_hopper.core import reference as ref
from mat_hopper.core.behaviours import behaviour
from mat_hopper.core.control_legs import rigid_twin
from mat_hopper.core.materials import LegDesign
from mat_hopper.experiments.common_step import at_common_step, common_step
from mat_hopper.experiments.runner import RunSpec, run_grid
from mat_hopper.physics.metrics import holm

METRICS = ("tracking_error_m", "power_w")
CONTACT = ("touch_toggles_per_switch", "peak_penetration_m")  # the hop table's contact columns, per leg
MARGIN_PCT = 100 * paired.EQUIVALENCE_MARGIN  # the book's ±10 %


def legs(rigid: bool = True) -> dict[str, dict[float, LegDesign]]:
    """{base: {modulus GPa: leg}}: the base's own modulus and its sweep's
    extremes, at the base's density; with `rigid`, its rigid twin (no
    springs, the limit of an infinite modulus) under the key ``inf``."""
    out = {}
    for base, sweeps in ref.SWEEPS.items():
        rho, e0 = ref.MONO_MATERIALS[base]
        sweep = sweeps["modulus"]
        out[base] = {
            e: LegDesign.from_properties([rho] * 3, [e] * 3, name=f"{base} E={e:g}")
            for e in sorted({e0, min(sweep), max(sweep)})
        }
        if rigid:
            out[base][math.inf] = rigid_twin(out[base][e0])
    return out


def tasks(
    profile, replicates: int, convention: str, contact: str, rigid: bool = True, only=None, step_divisor: int = 1
) -> list:
    """The runs: every leg of :func:`legs` at its base's common step, or,
    with `only` ({base: moduli}), those legs alone (still at the step all
    of the base's legs need), the step divided by `step_divisor` (a
    time-step check: more substeps of the same control period)."""
    out = []
    for base, by_modulus in legs(rigid).items():
        period, substeps = common_step(by_modulus.values(), convention, contact)
        substeps *= step_divisor
        for e, leg in by_modulus.items():
            if only is not None and e not in only.get(base, ()):
                continue
            for seed in range(replicates):
                s = profile.sim_settings(profile.replicate(seed), design=leg)
                s = at_common_step(replace(s, convention=convention, contact=contact), period, substeps)
                labels = {"base": base, "modulus_gpa": e, "replicate": seed, "timestep_s": s.timestep_s}
                out.append(RunSpec(leg, behaviour("forward"), s, labels))
    return out


def contrasts(hops) -> pd.DataFrame:
    """Each swept modulus against the base's own, per metric, from usable runs' hops."""
    means = hops.groupby(["base", "modulus_gpa", "replicate"])[list(METRICS)].mean()
    rows = []
    for base in [b for b in ref.SWEEPS if b in means.index.get_level_values("base")]:
        e0 = ref.MONO_MATERIALS[base][1]
        for e in sorted(set(means.index.get_level_values("modulus_gpa")[means.index.get_level_values("base") == base])):
            if e == e0:
                continue
            for m in METRICS:
                eff = paired.paired_effect(means.xs((base, e))[m], means.xs((base, e0))[m])
                rows.append({"base": base, "modulus_gpa": e, "against_gpa": e0, "metric": m, **eff})
    table = pd.DataFrame(rows)
    for _, g in table.groupby("metric"):
        table.loc[g.index, "p_holm"] = holm(g["p"].to_numpy(float))
    table["conclusion"] = [paired.conclusion(p, lo, hi) for p, lo, hi in zip(table.p_holm, table.ci_low, table.ci_high)]
    # the whole interval past the margin, one side or the other
    table["beyond_margin"] = (table["ci_low"] > MARGIN_PCT) | (table["ci_high"] < -MARGIN_PCT)
    return table


def contact_columns(hops, table) -> pd.DataFrame:
    """`table` with each leg's and its comparator's mean touch toggles per
    phase switch (chatter) and peak foot penetration (mm) over their hops."""
    legs = hops.groupby(["base", "modulus_gpa"])[list(CONTACT)].mean()
    legs["peak_penetration_m"] *= 1e3
    legs = legs.rename(columns={"peak_penetration_m": "peak_penetration_mm"})
    own = legs.add_prefix("leg_").reset_index()
    ref_ = legs.add_prefix("against_").reset_index().rename(columns={"modulus_gpa": "against_gpa"})
    return table.merge(own, on=["base", "modulus_gpa"]).merge(ref_, on=["base", "against_gpa"])


def with_halves(hops) -> pd.DataFrame:
    """:func:`contrasts` over the whole scored window, beside the same on
    each half of it (:func:`mat_hopper.analysis.stationarity.window_halves`):
    ``first_half_pct``, ``second_half_pct``, their conclusions, and
    ``stationarity`` (:func:`mat_hopper.analysis.stationarity.stationarity`);
    then :func:`contact_columns`."""
    table = contrasts(hops)
    first, second = window_halves(hops)
    key = ["base", "modulus_gpa", "metric"]
    for name, half in (("first_half", first), ("second_half", second)):
        h = contrasts(half)[[*key, "pct_change", "conclusion"]]
        table = table.merge(h.rename(columns={"pct_change": f"{name}_pct", "conclusion": f"{name}_conclusion"}), on=key)
    # a difference in opposite directions in the two halves is window-dependent too
    signed = {
        half: [
            f"{c} ({'up' if x > 0 else 'down'})" if c == "difference" else c
            for c, x in zip(table[f"{half}_conclusion"], table[f"{half}_pct"])
        ]
        for half in ("first_half", "second_half")
    }
    table["stationarity"] = [stationarity(a, b) for a, b in zip(signed["first_half"], signed["second_half"])]
    return contact_columns(hops, table)


def parse_only(ap, items, all_legs) -> dict[str, set[float]]:
    """--only's {base: moduli}: each BASE=E,E... once, its moduli among the
    base's legs (its own, the sweep's extremes, inf for the rigid twin); the
    base's own modulus, every contrast's comparator, is added."""
    only = {}
    for item in items:
        base, sep, values = item.partition("=")
        if not sep or base not in all_legs:
            ap.error(f"--only takes BASE=E,E,... with BASE one of {', '.join(all_legs)}, got {item!r}")
        if base in only:
            ap.error(f"--only names {base} twice; give its moduli once, e.g. {base}=E,E")
        try:
            moduli = {float(e) for e in values.split(",")}
        except ValueError:
            ap.error(f"--only {item}: the moduli must be numbers in GPa (or inf), got {values!r}")
        own = ref.MONO_MATERIALS[base][1]
        unknown = sorted(moduli - set(all_legs[base]))
        if unknown:
            choices = ", ".join(f"{e:g}" for e in sorted(all_legs[base]))
            ap.error(f"--only {item}: {base} has no leg at {unknown} GPa; its legs: {choices}")
        only[base] = moduli | {own}
    return only


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--profile", default="paper")
    ap.add_argument("--replicates", type=int, default=None, help="paired seeds (default: the profile's)")
    ap.add_argument("--convention", default="bending")
    ap.add_argument("--contact", default="stiff")
    ap.add_argument("--cache", default="results/cache")
    ap.add_argument("--no-rigid", action="store_true", help="leave out each base's rigid twin")
    ap.add_argument(
        "--only",
        nargs="+",
        metavar="BASE=E,E",
        help="these legs only, e.g. SS=15,193 Ti=18,120 (GPa; inf: the rigid twin), at their base's step",
    )
    ap.add_argument("--step-divisor", type=int, default=1, help="divide each base's physics step by this (a check)")
    ap.add_argument("--runs-csv", help="write the run summaries here")
    ap.add_argument("--csv")
    args = ap.parse_args()
    profile, (convention,), contact = settings(ap, args.profile, [args.convention], args.contact)
    outputs(ap, args.cache, csv=args.csv, runs_csv=args.runs_csv)
    only = parse_only(ap, args.only, legs(not args.no_rigid)) if args.only else None
    if args.step_divisor < 1:
        ap.error(f"--step-divisor must be >= 1, got {args.step_divisor}")
    n = profile.replicates if args.replicates is None else args.replicates
    if n < 2:
        ap.error(f"--replicates must be >= 2 (paired seeds), got {n}")
    specs = tasks(profile, n, convention, contact, not args.no_rigid, only, args.step_divisor)
    print(f"{len(specs)} runs, {convention}, {contact} contact, {n} seeds, {profile.name} profile", flush=True)
    t0 = time.perf_counter()
    grid = run_grid(specs, args.cache, desc="modulus sweeps")
    bad = unusable_runs(grid.summary)
    print(f"{grid.n_computed} computed, {grid.n_cached} cached, {len(bad)} unusable, {time.perf_counter() - t0:.0f} s")
    if len(bad):
        print(bad.to_string(index=False))
    table = with_halves(drop_unusable(grid.tables, bad))
    cols = ["base", "modulus_gpa", "against_gpa", "metric", "n_pairs", "pct_change", "ci_low", "ci_high", "p_holm"]
    with pd.option_context("display.width", 200):
        print(
            table[
                [*cols, "conclusion", "beyond_margin", "first_half_pct", "second_half_pct", "stationarity"]
            ].to_string(index=False, float_format=lambda v: f"{v:.3g}")
        )
    if args.csv:
        table.to_csv(args.csv, index=False)
    if args.runs_csv:
        grid.summary.to_csv(args.runs_csv, index=False)


if __name__ == "__main__":
    main()
