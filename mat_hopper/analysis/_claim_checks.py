"""The claims' checks: verdict helpers, thresholds and one function per
claim of the paper (private; the table and its rules are
:mod:`mat_hopper.analysis.claims`, whose docstring states the rules)."""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from ..core import reference as ref
from ..core.behaviours import BEHAVIOUR_NAMES
from ..core.materials import CATALOGUE
from . import stats as _stats
from .stats import seconds

HOLDS, PARTLY, FAILS, NOT_RUN, NOT_TESTABLE = "holds", "partly", "does not hold", "not run", "not testable"
VERDICTS = (HOLDS, PARTLY, FAILS, NOT_RUN, NOT_TESTABLE)

ALPHA = 0.05  # significance level, Holm-adjusted p
MATCH_REL_TOL = 0.25  # a percent change matches within 25 % of the paper's ...
MATCH_ABS_TOL_PCT = 10.0  # ... or within 10 percentage points
PARTLY_MIN_FRACTION = 0.25  # same sign and at least a quarter of the paper's size
HOP_HEIGHT_TOL_M = 0.05  # m around the 1 m target
TIMESTEP_TOL_DECADES = 0.3  # |log10(ours / paper)|: within a factor 2
TREND_MIN_R2 = 0.8
GRID_FAR_DECADES = 0.15  # a stability grid point this far (log10) from a material is flagged

MONO = ("PVC", "Al", "Ti", "SS")
COLUMNS = (
    "claim_id",
    "claim",
    "paper",
    "ours",
    "verdict",
    "convention",
    "sensor_timing",
    "replicate_protocol",
    "basis",
    "n_replicates",
    "timestep_check",
    "stationarity",
    "detail",
    "rule",
)
TIMESTEP_MOVE_TOL = 0.10  # a run "moves" when a metric's mean changes by more than 10 % at the finer step
MEASURED_TIMESTEP_COLUMNS = ("max_stable_timestep_s", "dt_stable_s", "spec_timestep_s", "dt_spec_s")


# --- small helpers ---------------------------------------------------------------


# Why a percent change against MD has no value: its tracking error is zero
# where nothing perturbs it (hopping in place, round-off only).
UNDEFINED_WHY = (
    "undefined: MD tracks exactly in place without a perturbation (its tracking error is round-off); "
    "run perturbed replicates (--replicates 2 or more) for a ratio"
)


def _pct(x: float) -> str:
    return "nan" if x is None or not np.isfinite(x) else f"{x:+.0f} %"


def _exp(name) -> str:
    s = str(name).strip().lower()
    return s if s.startswith("exp") or s == "stability" else f"exp{s}"


def match_percent(ours: float, paper: float) -> str:
    """Verdict for a percent change of ours against the paper's (module doc)."""
    if ours is None or not np.isfinite(ours):
        return NOT_TESTABLE
    if np.sign(ours) != np.sign(paper) or ours == 0:
        return FAILS
    if abs(ours - paper) <= max(MATCH_REL_TOL * abs(paper), MATCH_ABS_TOL_PCT):
        return HOLDS
    if abs(ours) >= PARTLY_MIN_FRACTION * abs(paper):
        return PARTLY
    return FAILS


def fraction_verdict(k: int, n: int) -> str:
    """All of n: holds; at least half: partly; fewer: does not hold."""
    if n == 0:
        return NOT_TESTABLE
    if k == n:
        return HOLDS
    return PARTLY if k >= n / 2 else FAILS


def _cap(verdict: str) -> str:
    return PARTLY if verdict == HOLDS else verdict


@dataclass
class Outcome:
    ours: str
    verdict: str
    detail: str = ""


@dataclass
class Claim:
    claim_id: str
    claim: str
    paper: str
    rule: str
    evaluate: Callable[[_Context], Outcome]


# --- the results of one convention -----------------------------------------------------


@dataclass
class _Context:
    convention: str
    hops: pd.DataFrame  # usable runs only
    runs: pd.DataFrame | None
    stability: pd.DataFrame | None
    basis: str
    alpha: float
    timestep_s: float | None
    bad: pd.DataFrame = field(default_factory=pd.DataFrame)  # unusable runs: design, behaviour, experiment, why
    _cache: dict = field(default_factory=dict)

    def experiment(self, exps) -> pd.DataFrame:
        """This convention's usable hop rows of these experiments, as one family."""
        key = ("experiment", tuple(exps))
        if key not in self._cache:
            self._cache[key] = self._experiment(exps)
        return self._cache[key]

    def _experiment(self, exps) -> pd.DataFrame:
        exps = [_exp(e) for e in exps]
        t = self.hops
        if "experiment" in t.columns:
            t = t[t["experiment"].astype(str).map(_exp).isin(exps)]
            t = t.assign(experiment=t["experiment"].astype(str).map(_exp))
            t = _stats.combine_experiments(t, exps)
        return t

    def basis_for(self, table: pd.DataFrame) -> str:
        if self.basis != "auto":
            return self.basis
        return "replicates" if _stats.has_replicates(table) else "hops"

    def sample(self, table: pd.DataFrame, basis: str) -> pd.DataFrame:
        """One value per run (replicates) or the unperturbed run's cycles (hops)."""
        if basis == "replicates":
            return _stats.replicate_means(table)
        return _stats.select_replicates(table, _stats.UNPERTURBED)

    def compare(self, exps, metric: str, baseline: str = "MD"):
        """(comparison table, basis) of every design against the baseline on
        one metric: one Holm family (designs x behaviours)."""
        key = (tuple(exps), metric, baseline)
        if key not in self._cache:
            t = self.experiment(exps)
            if len(t) == 0 or baseline not in set(t["design"]):
                self._cache[key] = (pd.DataFrame(), self.basis_for(t))
            else:
                basis = self.basis_for(t)
                c = _stats.compare_designs(t, baseline, basis=basis, alpha=self.alpha, metrics=(metric,))
                self._cache[key] = (c, basis)
        return self._cache[key]

    def missing(self, designs, behaviours, exps=None) -> list[str]:
        """Needed designs with neither a usable nor an unusable run."""
        t = self.hops if exps is None else self.experiment(exps)
        have = set(t["design"]) if len(t) else set()
        if len(self.bad):
            b = self.bad[self.bad["behaviour"].isin(behaviours)]
            have |= set(b["design"])
        return [d for d in designs if d not in have]

    def problems(self, designs, behaviours, exps=None) -> list[str]:
        """Why needed runs are unusable, one text per design (behaviours listed)."""
        if len(self.bad) == 0:
            return []
        b = self.bad[self.bad["design"].isin(designs) & self.bad["behaviour"].isin(behaviours)]
        if exps is not None and "experiment" in b.columns:
            b = b[b["experiment"].astype(str).map(_exp).isin([_exp(e) for e in exps])]
        out = []
        for (d, why), g in b.groupby(["design", "why"], sort=False):
            out.append(f"{d} {why} ({', '.join(dict.fromkeys(g['behaviour']))})")
        return out

    def has_any(self, exps=None) -> bool:
        """Whether this convention has any run (usable or not) of these experiments."""
        n = len(self.experiment(exps)) if exps else len(self.hops)
        if n:
            return True
        if len(self.bad) == 0:
            return False
        if exps is None or "experiment" not in self.bad.columns:
            return True
        return bool(self.bad["experiment"].astype(str).map(_exp).isin([_exp(e) for e in exps]).any())


# --- the claims -------------------------------------------------------------------------


def _missing_or_untestable(ctx, designs, behaviours, exps) -> Outcome:
    probs = ctx.problems(designs, behaviours, exps)
    missing = ctx.missing(designs, behaviours, exps)
    if probs:
        return Outcome(
            "; ".join(probs),
            NOT_TESTABLE,
            "no usable comparison" + (f"; not run: {', '.join(missing)}" if missing else ""),
        )
    return Outcome("not run", NOT_RUN, f"no results of {', '.join(designs)} on {', '.join(behaviours)}")


def _claim_hop_height(ctx: _Context) -> Outcome:
    t = ctx.hops
    if len(t) == 0:
        return _missing_or_untestable(
            ctx, list(ctx.bad["design"].unique()) if len(ctx.bad) else ["any design"], list(BEHAVIOUR_NAMES), None
        )
    basis = ctx.basis_for(t)
    s = ctx.sample(t, basis)
    keys = [c for c in ("design", "behaviour") if c in s.columns]
    if "sweep_base" in s.columns:
        keys += ["density_g_cm3", "modulus_gpa"]
    means = s.groupby(keys, dropna=False)["hop_height_m"].mean().reset_index().dropna(subset=["hop_height_m"])
    if len(means) == 0:
        return Outcome("no scored hops", NOT_TESTABLE)
    means["err"] = (means["hop_height_m"] - ref.CLAIM_HOP_HEIGHT_M).abs()
    k, n = int((means["err"] <= HOP_HEIGHT_TOL_M).sum()), len(means)
    verdict = HOLDS if k == n else PARTLY if k >= n / 2 else FAILS
    worst = means.sort_values("err", ascending=False).head(3)
    detail = "furthest from 1 m: " + ", ".join(
        f"{r['design']} {r['behaviour']} {r['hop_height_m']:.3f} m" for r in worst.to_dict("records")
    )
    lo, hi = means["hop_height_m"].min(), means["hop_height_m"].max()
    n_bad = len(ctx.bad)
    probs = ctx.problems(list(ctx.bad["design"].unique()) if len(ctx.bad) else [], list(BEHAVIOUR_NAMES))
    if probs:
        verdict = _cap(verdict)
        detail += "; unusable: " + "; ".join(probs)
    return Outcome(
        f"{k}/{n} design-behaviour means within ±{HOP_HEIGHT_TOL_M:g} m; "
        f"{lo:.3f}-{hi:.3f} m" + (f"; {n_bad} runs unusable" if n_bad else ""),
        verdict,
        detail,
    )


def _comparison_rows(ctx, exps, designs, behaviours, metric, baseline="MD"):
    """The claim's own comparisons, Holm-corrected among themselves (each
    claim is its own family) with the paired conclusion re-drawn. Paired
    comparisons whose family an exact sign-flip test cannot bring under
    Holm's threshold at their n (:func:`mat_hopper.analysis.paired.reachable`)
    are never significant: a "difference" there is "not enough evidence"."""
    from ..physics.metrics import holm
    from .paired import DIFFERENCE, NOT_ENOUGH, conclusion, reachable

    c, basis = ctx.compare(exps, metric, baseline)
    if len(c) == 0:
        return c, basis
    rows = c[c["design"].isin(designs) & c["behaviour"].isin(behaviours) & (c["metric"] == metric)].copy()
    if len(rows):
        rows["p_holm"] = holm(rows["p"].to_numpy(float))
        rows["significant"] = rows["p_holm"] < ctx.alpha
        if "conclusion" in rows.columns:
            rows["conclusion"] = [
                conclusion(p, lo, hi, alpha=ctx.alpha) for p, lo, hi in zip(rows.p_holm, rows.ci_low, rows.ci_high)
            ]
        if "n_pairs" in rows.columns and rows.get("paired", pd.Series(False, index=rows.index)).all():
            if not reachable(int(rows["n_pairs"].min()), len(rows), ctx.alpha):
                rows["significant"] = False
                if "conclusion" in rows.columns:
                    rows.loc[rows["conclusion"] == DIFFERENCE, "conclusion"] = NOT_ENOUGH
    return rows, basis


def smallest_p(n_replicates: int, family_size: int = 1) -> float:
    """The smallest Holm-adjusted p a family of `family_size` two-sided
    Mann-Whitney U tests of n against n replicates can reach: the exact
    two-sided minimum 2 / C(2n, n), times the family size (Holm's first
    step). n = 6 and 16 comparisons (4 materials x 4 behaviours): 0.035."""
    if n_replicates < 1:
        return math.nan
    return min(1.0, family_size * 2.0 / math.comb(2 * n_replicates, n_replicates))


# A count over hop cycles of one run (basis hops): its p-values describe the
# run (the cycles are not independent samples, mat_hopper.analysis.stats),
# so the count is labelled descriptive and never called significant.
HOPS_WORDS = "descriptive: Holm p < {alpha:g} over hop cycles, not independent samples"


def _claim_count_significant(metric, designs, behaviours, direction, exps=("exp1",), baseline="MD"):
    def evaluate(ctx: _Context) -> Outcome:
        rows, basis = _comparison_rows(ctx, exps, designs, behaviours, metric, baseline)
        if len(rows) == 0:
            return _missing_or_untestable(ctx, [baseline, *designs], behaviours, exps)
        good = rows["significant"].fillna(False).astype(bool) & (np.sign(rows["pct_change"]) == direction)
        n_needed = len(designs) * len(behaviours)
        k = int(good.sum())
        verdict = fraction_verdict(k, n_needed)
        word = "lower" if direction < 0 else "higher"
        family = len(rows)  # the claim's own comparisons
        n_min = int(min(rows["n"].min(), rows["n_baseline"].min())) if basis == "replicates" else 0
        paired = bool(rows["paired"].all()) if "paired" in rows.columns else False
        # Paired: the exact sign-flip test's smallest p (2 / 2^n) must reach Holm's threshold
        # (a t test can reach any p at n = 3 only through its normality assumption).
        p_floor = (
            family * float(rows["p_min"].max()) if paired and "p_min" in rows.columns else smallest_p(n_min, family)
        )
        if basis == "replicates" and p_floor >= ctx.alpha:
            same_way = int((np.sign(rows["pct_change"]) == direction).sum())
            n_show = int(rows["n_pairs"].min()) if paired else n_min
            test = "an exact sign-flip test of" if paired else "Mann-Whitney with"
            return Outcome(
                f"{same_way}/{n_needed} {word}; significance untestable: {test} n = {n_show} reaches Holm p "
                f">= {min(1.0, p_floor):.2g} at best in this family of {family}",
                NOT_TESTABLE,
                "more replicates are needed",
            )
        misses = rows[~good.to_numpy()]
        detail = (
            (
                "not: "
                + ", ".join(
                    f"{r.behaviour} {r.design} {_pct(r.pct_change)} (p_holm={r.p_holm:.2g})"
                    for r in misses.itertuples()
                )
            )
            if len(misses)
            else "all"
        )
        probs = ctx.problems([baseline, *designs], behaviours, exps)
        if probs or len(rows) < n_needed:
            verdict = _cap(verdict) if len(rows) else verdict
            if probs:
                detail += "; unusable: " + "; ".join(probs)
        if paired:
            n_pairs = int(rows["n_pairs"].min())
            detail += (
                f"; paired t on log ratios, n = {n_pairs} seeds, Holm over this claim's {family}; "
                f"exact sign-flip smallest p at n = {n_pairs}: {rows['p_min'].max():.2g} "
                f"(x {family} for Holm: {min(1.0, family * rows['p_min'].max()):.2g}); "
                + ", ".join(f"{r.behaviour} {r.design}: {r.conclusion}" for r in rows.itertuples())
            )
            missed = misses["conclusion"] if "conclusion" in misses else pd.Series(dtype=str)
            if verdict == FAILS and len(missed) and (missed == "not enough evidence").all():
                # no comparison speaks against the claim: the evidence is missing, not contrary
                same_way = int((np.sign(rows["pct_change"]) == direction).sum())
                return Outcome(
                    f"{k}/{n_needed} significantly {word}, {same_way}/{n_needed} {word}; the others: not enough "
                    f"evidence at n = {n_pairs}",
                    NOT_TESTABLE,
                    detail,
                )
        if basis != "replicates":  # p over the cycles of one run describes it: no inference, no significance
            return Outcome(f"{k}/{n_needed} {word}, {HOPS_WORDS.format(alpha=ctx.alpha)}", verdict, detail)
        return Outcome(f"{k}/{n_needed} significantly {word} (Holm p < {ctx.alpha:g})", verdict, detail)

    return evaluate


def _claim_ss_tracking(ctx: _Context) -> Outcome:
    rows, basis = _comparison_rows(ctx, ("exp1",), ["SS"], BEHAVIOUR_NAMES, "tracking_error_m")
    if len(rows) == 0:
        return _missing_or_untestable(ctx, ["MD", "SS"], BEHAVIOUR_NAMES, ("exp1",))
    pct = rows.set_index("behaviour")["pct_change"]
    undefined = [b for b in BEHAVIOUR_NAMES if b in pct.index and not np.isfinite(pct[b])]
    if len(undefined) == len(pct):
        return Outcome(", ".join(f"{b} undefined" for b in undefined), NOT_TESTABLE, UNDEFINED_WHY)
    pct = pct.drop(undefined)  # no ratio to MD's zero: judged on the others
    thr = ref.CLAIM_SS_TRACKING_PCT
    ok = pct <= thr
    if ok.all() and len(pct) == len(BEHAVIOUR_NAMES):
        verdict = HOLDS
    elif (pct < 0).all() or ok.sum() >= len(BEHAVIOUR_NAMES) / 2:
        verdict = PARTLY
    else:
        verdict = FAILS
    ours = ", ".join(
        f"{b} {'undefined (MD tracks exactly in place, unperturbed)' if b in undefined else _pct(pct[b])}"
        for b in BEHAVIOUR_NAMES
        if b in pct.index or b in undefined
    )
    detail = _ci_detail(rows)
    probs = ctx.problems(["MD", "SS"], BEHAVIOUR_NAMES, ("exp1",))
    if probs or len(pct) < len(BEHAVIOUR_NAMES):
        verdict = _cap(verdict)
        detail += ("; unusable: " + "; ".join(probs)) if probs else ""
        detail += f"; {', '.join(undefined)}: {UNDEFINED_WHY}" if undefined else ""
        detail += "; some behaviours missing" if not probs and len(pct) + len(undefined) < len(BEHAVIOUR_NAMES) else ""
    return Outcome(ours, verdict, detail)


def _ci_detail(rows: pd.DataFrame) -> str:
    parts = []
    for r in rows.to_dict("records"):
        s = f"{r['behaviour']} {r['design']} vs {r['baseline']}: p_holm={r['p_holm']:.2g}"
        if "ci_low" in r and np.isfinite(r.get("ci_low", np.nan)):
            s += f", 95 % CI [{r['ci_low']:+.0f}, {r['ci_high']:+.0f}] %"
        if r.get("paired") is True:
            s += f" (paired, n = {r['n_pairs']}: {r['conclusion']})"
        parts.append(s)
    return "; ".join(parts)


def _claim_ss_power_for(metric: str = "power_w"):
    def evaluate(ctx: _Context) -> Outcome:
        return _claim_ss_power_metric(ctx, metric)

    return evaluate


def _claim_ss_power(ctx: _Context) -> Outcome:
    return _claim_ss_power_metric(ctx, "power_w")


def _claim_ss_power_metric(ctx: _Context, metric: str) -> Outcome:
    rows, basis = _comparison_rows(ctx, ("exp1",), ["SS"], BEHAVIOUR_NAMES, metric)
    if len(rows) == 0:
        return _missing_or_untestable(ctx, ["MD", "SS"], BEHAVIOUR_NAMES, ("exp1",))
    best = rows.loc[rows["pct_change"].idxmax()] if rows["pct_change"].notna().any() else None
    if best is None:
        return Outcome("no finite percent change", NOT_TESTABLE)
    verdict = match_percent(float(best["pct_change"]), ref.CLAIM_SS_POWER_MAX_PCT)
    probs = ctx.problems(["MD", "SS"], BEHAVIOUR_NAMES, ("exp1",))
    detail = "per behaviour: " + ", ".join(f"{r.behaviour} {_pct(r.pct_change)}" for r in rows.itertuples())
    if probs:
        verdict = _cap(verdict)
        detail += "; unusable: " + "; ".join(probs)
    return Outcome(f"{_pct(best['pct_change'])} (max, {best['behaviour']})", verdict, detail)


def _claim_pct(design, metric, paper_pct, baseline="MD", behaviour="ramp", exps=("exp1", "exp3")):
    def evaluate(ctx: _Context) -> Outcome:
        rows, basis = _comparison_rows(ctx, exps, [design], [behaviour], metric, baseline)
        if len(rows) == 0:
            return _missing_or_untestable(ctx, [baseline, design], [behaviour], exps)
        r = rows.iloc[0]
        verdict = match_percent(float(r["pct_change"]), paper_pct)
        ours = _pct(r["pct_change"])
        if np.isfinite(r.get("ci_low", np.nan)):
            ours += f" (95 % CI {r['ci_low']:+.0f} to {r['ci_high']:+.0f} %)"
        return Outcome(ours, verdict, _ci_detail(rows))

    return evaluate


def _sweep_points(ctx: _Context):
    t = ctx.experiment(("exp2",))
    if len(t) == 0 or "sweep_property" not in t.columns:
        return None, None
    basis = ctx.basis_for(t)
    s = ctx.sample(t, basis)
    keys = ["sweep_base", "sweep_property", "density_g_cm3", "modulus_gpa"]
    pts = s.groupby(keys, dropna=False)["tracking_error_m"].mean().reset_index()
    return pts, basis


def _claim_density_over_modulus(ctx: _Context) -> Outcome:
    pts, basis = _sweep_points(ctx)
    if pts is None:
        return _missing_or_untestable(
            ctx, list(ctx.bad["design"].unique()) if len(ctx.bad) else ["sweeps"], ["forward"], ("exp2",)
        )
    spans = []
    order = {b: i for i, b in enumerate(ref.SWEEPS)}
    pts = pts.sort_values("sweep_base", key=lambda c: c.map(lambda b: order.get(b, len(order))), kind="stable")
    for base, g in pts.groupby("sweep_base", sort=False):
        d = g.loc[g["sweep_property"] == "density", "tracking_error_m"]
        m = g.loc[g["sweep_property"] == "modulus", "tracking_error_m"]
        if len(d) >= 2 and len(m) >= 2:
            spans.append((base, float(np.ptp(d)), float(np.ptp(m))))
    if not spans:
        return Outcome("too few sweep points", NOT_TESTABLE)
    k = sum(sd > sm for _, sd, sm in spans)
    verdict = fraction_verdict(k, len(spans))
    detail = "span of mean tracking error, density vs modulus sweep: " + ", ".join(
        f"{b} {sd * 1e3:.1f} vs {sm * 1e3:.1f} mm" for b, sd, sm in spans
    )
    probs = ctx.problems(list(ctx.bad["design"].unique()) if len(ctx.bad) else [], ["forward"], ("exp2",))
    if probs or len(spans) < len(ref.SWEEPS):
        verdict = _cap(verdict)
        if probs:
            detail += "; unusable: " + "; ".join(probs)
    return Outcome(f"density moves it more for {k}/{len(spans)} base materials", verdict, detail)


def _claim_low_modulus(ctx: _Context) -> Outcome:
    pts, basis = _sweep_points(ctx)
    if pts is None:
        return _missing_or_untestable(
            ctx, list(ctx.bad["design"].unique()) if len(ctx.bad) else ["sweeps"], ["forward"], ("exp2",)
        )
    pts = pts.drop_duplicates(["density_g_cm3", "modulus_gpa"])
    low = pts.loc[pts["modulus_gpa"] <= ref.CLAIM_LOW_MODULUS_GPA, "tracking_error_m"].dropna()
    high = pts.loc[pts["modulus_gpa"] >= ref.CLAIM_HIGH_MODULUS_GPA, "tracking_error_m"].dropna()
    if len(low) == 0 or len(high) == 0:
        return Outcome("no points on one side", NOT_TESTABLE)
    if low.min() > high.max():
        verdict = HOLDS
    elif low.median() > high.median():
        verdict = PARTLY
    else:
        verdict = FAILS
    ours = (
        f"median {low.median() * 1e3:.1f} mm (E <= {ref.CLAIM_LOW_MODULUS_GPA:g} GPa, n={len(low)}) vs "
        f"{high.median() * 1e3:.1f} mm (E >= {ref.CLAIM_HIGH_MODULUS_GPA:g} GPa, n={len(high)})"
    )
    detail = (
        f"low-modulus range {low.min() * 1e3:.1f}-{low.max() * 1e3:.1f} mm, high-modulus range "
        f"{high.min() * 1e3:.1f}-{high.max() * 1e3:.1f} mm (sweep points of experiment 2)"
    )
    probs = ctx.problems(list(ctx.bad["design"].unique()) if len(ctx.bad) else [], ["forward"], ("exp2",))
    if probs:
        verdict = _cap(verdict)
        detail += "; unusable: " + "; ".join(probs)
    return Outcome(ours, verdict, detail)


def _stability(ctx: _Context):
    s = ctx.stability
    if s is None or len(s) == 0:
        return None, None
    if "convention" in s.columns:
        s = s[s["convention"] == ctx.convention]
    elif ctx.convention != "paper":
        return None, None
    col = next((c for c in MEASURED_TIMESTEP_COLUMNS if c in s.columns), None)
    if len(s) == 0 or col is None:
        return None, None
    return s, col


def _claim_timestep_materials(ctx: _Context) -> Outcome:
    s, col = _stability(ctx)
    if s is None:
        return Outcome("not run", NOT_RUN, "no stable-time-step map for this convention")
    lr, le = np.log10(s["density_g_cm3"].to_numpy(float)), np.log10(s["modulus_gpa"].to_numpy(float))
    found, notes, close = {}, [], []
    for name, paper_dt in ref.CLAIM_STABLE_TIMESTEP_S.items():
        m = CATALOGUE[name.lower()]
        dist = np.maximum(np.abs(lr - math.log10(m.density_g_cm3)), np.abs(le - math.log10(m.modulus_gpa)))
        i = int(np.argmin(dist))
        dt = float(s[col].iloc[i])
        found[name] = dt
        where = f"{s['density_g_cm3'].iloc[i]:g} g/cm³, {s['modulus_gpa'].iloc[i]:g} GPa"
        notes.append(f"{name} at {where}" + (" (far from the material)" if dist[i] > GRID_FAR_DECADES else ""))
        close.append(np.isfinite(dt) and abs(math.log10(dt / paper_dt)) <= TIMESTEP_TOL_DECADES)
    ordered = all(np.isfinite(v) for v in found.values()) and found["PVC"] > max(
        v for k, v in found.items() if k != "PVC"
    )
    verdict = HOLDS if all(close) else PARTLY if (any(close) or ordered) else FAILS
    ours = ", ".join(f"{k} {seconds(v)} s" if np.isfinite(v) else f"{k} none stable" for k, v in found.items())
    return Outcome(ours, verdict, f"measured column {col}; nearest grid points: " + "; ".join(notes))


def _claim_timestep_trend(ctx: _Context) -> Outcome:
    s, col = _stability(ctx)
    if s is None:
        return Outcome("not run", NOT_RUN, "no stable-time-step map for this convention")
    ok = s[np.isfinite(s[col].astype(float)) & (s[col].astype(float) > 0)]
    x = np.column_stack(
        [np.ones(len(ok)), np.log10(ok["density_g_cm3"].astype(float)), np.log10(ok["modulus_gpa"].astype(float))]
    )
    y = np.log10(ok[col].astype(float).to_numpy())
    if len(ok) < 4 or np.ptp(x[:, 1]) == 0 or np.ptp(x[:, 2]) == 0:
        return Outcome(f"{len(ok)} stable grid points: too few for a fit", NOT_TESTABLE)
    coef, *_ = np.linalg.lstsq(x, y, rcond=None)
    resid = y - x @ coef
    r2 = 1.0 - float(resid @ resid) / float(((y - y.mean()) ** 2).sum()) if np.ptp(y) > 0 else 0.0
    b, c = float(coef[1]), float(coef[2])
    signs = (b > 0) + (c < 0)
    verdict = HOLDS if signs == 2 and r2 >= TREND_MIN_R2 else PARTLY if signs >= 1 else FAILS
    ours = f"log10 dt = {coef[0]:.2f} {b:+.2f} log10 ρ {c:+.2f} log10 E, R² = {r2:.2f}"
    detail = f"{len(ok)} of {len(s)} grid points stable (column {col}); ρ in g/cm³, E in GPa"
    return Outcome(ours, verdict, detail)
