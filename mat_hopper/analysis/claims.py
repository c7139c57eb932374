"""The paper's quantitative claims beside ours, with a verdict computed
from the results (never typed in).

:func:`claims_table` takes the result tables of a reproduction (per-hop
table, run summaries, stable-time-step map) and returns one row per claim
and stiffness convention: the claim, the paper's figure, ours, a verdict
and the rule that gave it. :func:`write_claims` writes ``claims.md`` and
``claims.csv`` (atomically).

Verdicts:

- ``holds``, ``partly``, ``does not hold``: by the claim's rule (below, and
  in the table's ``rule`` column);
- ``not run``: the convention's results needed for the claim are missing;
- ``not testable``: the runs exist but none of the needed ones is usable:
  they diverged numerically (e.g. the explicit spring limit of stiff
  metals under the ``axial`` convention at dt = 1e-4 s), fell over, or
  failed. Where only some of the needed runs are unusable the claim is
  judged on the others and its verdict is at best ``partly``.

Rules (thresholds are module constants):

- a number of the paper (a percent change) is matched when ours has the
  same sign and lies within ``MATCH_REL_TOL`` (25 %) of it, or within
  ``MATCH_ABS_TOL_PCT`` (10 percentage points), whichever is wider:
  ``holds``; same sign and at least ``PARTLY_MIN_FRACTION`` (a quarter) of
  its size: ``partly``; otherwise ``does not hold``;
- "every ... significantly" claims count the comparisons that go the
  claimed way with Holm-adjusted p < ``ALPHA``: all ``holds``, at least
  half ``partly``, fewer ``does not hold``;
- hop height: every design and behaviour's mean within
  ``HOP_HEIGHT_TOL_M`` (0.05 m) of 1 m ``holds``, at least half ``partly``;
- stable time steps: within ``TIMESTEP_TOL_DECADES`` (0.3 decade, a factor 2) of
  the paper's value for every material ``holds``; for some, or in the
  paper's order (PVC's step the largest), ``partly``;
- the log-linear trend: a least-squares plane log10 dt = a + b log10 rho +
  c log10 E with b > 0 and c < 0 and R^2 >= ``TREND_MIN_R2`` (0.8)
  ``holds``; the right signs with a poorer fit, or one right sign,
  ``partly``.

Comparisons are those of :mod:`mat_hopper.analysis.stats` on the ``basis`` chosen
(``auto``: replicate means where every design and behaviour has
replicates, else the paper's hop cycles of the unperturbed run; the
``basis`` column says which); the Holm family is one metric within one
experiment (experiments 1 and 3 together for the gradient claims). Hop
cycles of runs that diverged, fell over or failed are never used
(:func:`mat_hopper.analysis.stats.drop_unusable`).
"""

from __future__ import annotations

import math
import os
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from .. import reference as ref
from ..atomic import write_text
from ..behaviours import BEHAVIOUR_NAMES
from ..materials import CATALOGUE, CONVENTIONS
from . import stats as _stats
from .stats import seconds

HOLDS, PARTLY, FAILS, NOT_RUN, NOT_TESTABLE = "holds", "partly", "does not hold", "not run", "not testable"
VERDICTS = (HOLDS, PARTLY, FAILS, NOT_RUN, NOT_TESTABLE)

ALPHA = 0.05                 # significance level, Holm-adjusted p
MATCH_REL_TOL = 0.25         # a percent change matches within 25 % of the paper's ...
MATCH_ABS_TOL_PCT = 10.0     # ... or within 10 percentage points
PARTLY_MIN_FRACTION = 0.25   # same sign and at least a quarter of the paper's size
HOP_HEIGHT_TOL_M = 0.05      # m around the 1 m target
TIMESTEP_TOL_DECADES = 0.3   # |log10(ours / paper)|: within a factor 2
TREND_MIN_R2 = 0.8
GRID_FAR_DECADES = 0.15      # a stability grid point this far (log10) from a material is flagged

MONO = ("PVC", "Al", "Ti", "SS")
COLUMNS = ("claim_id", "claim", "paper", "ours", "verdict", "convention", "basis", "detail", "rule")
MEASURED_TIMESTEP_COLUMNS = ("max_stable_timestep_s", "dt_stable_s", "spec_timestep_s", "dt_spec_s")


# --- small helpers ---------------------------------------------------------------


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
    hops: pd.DataFrame              # usable runs only
    runs: pd.DataFrame | None
    stability: pd.DataFrame | None
    basis: str
    alpha: float
    timestep_s: float | None
    bad: pd.DataFrame = field(default_factory=pd.DataFrame)   # unusable runs: design, behaviour, experiment, why
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
        return Outcome("; ".join(probs), NOT_TESTABLE, "no usable comparison"
                       + (f"; not run: {', '.join(missing)}" if missing else ""))
    return Outcome("not run", NOT_RUN, f"no results of {', '.join(designs)} on {', '.join(behaviours)}")


def _claim_hop_height(ctx: _Context) -> Outcome:
    t = ctx.hops
    if len(t) == 0:
        return _missing_or_untestable(ctx, list(ctx.bad["design"].unique()) if len(ctx.bad) else ["any design"],
                                      list(BEHAVIOUR_NAMES), None)
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
    detail = "furthest from 1 m: " + ", ".join(f"{r['design']} {r['behaviour']} {r['hop_height_m']:.3f} m"
                                               for r in worst.to_dict("records"))
    lo, hi = means["hop_height_m"].min(), means["hop_height_m"].max()
    n_bad = len(ctx.bad)
    probs = ctx.problems(list(ctx.bad["design"].unique()) if len(ctx.bad) else [], list(BEHAVIOUR_NAMES))
    if probs:
        verdict = _cap(verdict)
        detail += "; unusable: " + "; ".join(probs)
    return Outcome(f"{k}/{n} design-behaviour means within ±{HOP_HEIGHT_TOL_M:g} m; "
                   f"{lo:.3f}-{hi:.3f} m" + (f"; {n_bad} runs unusable" if n_bad else ""), verdict, detail)


def _comparison_rows(ctx, exps, designs, behaviours, metric, baseline="MD"):
    c, basis = ctx.compare(exps, metric, baseline)
    if len(c) == 0:
        return c, basis
    return c[c["design"].isin(designs) & c["behaviour"].isin(behaviours) & (c["metric"] == metric)], basis


def _claim_count_significant(metric, designs, behaviours, direction, exps=("exp1",)):
    def evaluate(ctx: _Context) -> Outcome:
        rows, basis = _comparison_rows(ctx, exps, designs, behaviours, metric)
        if len(rows) == 0:
            return _missing_or_untestable(ctx, ["MD", *designs], behaviours, exps)
        good = rows["significant"].fillna(False).astype(bool) & (np.sign(rows["pct_change"]) == direction)
        n_needed = len(designs) * len(behaviours)
        k = int(good.sum())
        verdict = fraction_verdict(k, n_needed)
        word = "lower" if direction < 0 else "higher"
        misses = rows[~good.to_numpy()]
        detail = ("not: " + ", ".join(f"{r.behaviour} {r.design} {_pct(r.pct_change)} (p_holm={r.p_holm:.2g})"
                                      for r in misses.itertuples())) if len(misses) else "all"
        probs = ctx.problems(["MD", *designs], behaviours, exps)
        if probs or len(rows) < n_needed:
            verdict = _cap(verdict) if len(rows) else verdict
            if probs:
                detail += "; unusable: " + "; ".join(probs)
        return Outcome(f"{k}/{n_needed} significantly {word} (Holm p < {ctx.alpha:g})", verdict, detail)
    return evaluate


def _claim_ss_tracking(ctx: _Context) -> Outcome:
    rows, basis = _comparison_rows(ctx, ("exp1",), ["SS"], BEHAVIOUR_NAMES, "tracking_error_m")
    if len(rows) == 0:
        return _missing_or_untestable(ctx, ["MD", "SS"], BEHAVIOUR_NAMES, ("exp1",))
    pct = rows.set_index("behaviour")["pct_change"]
    thr = ref.CLAIM_SS_TRACKING_PCT
    ok = pct <= thr
    if ok.all() and len(pct) == len(BEHAVIOUR_NAMES):
        verdict = HOLDS
    elif (pct < 0).all() or ok.sum() >= len(BEHAVIOUR_NAMES) / 2:
        verdict = PARTLY
    else:
        verdict = FAILS
    ours = ", ".join(f"{b} {_pct(pct[b])}" for b in BEHAVIOUR_NAMES if b in pct.index)
    detail = _ci_detail(rows)
    probs = ctx.problems(["MD", "SS"], BEHAVIOUR_NAMES, ("exp1",))
    if probs or len(pct) < len(BEHAVIOUR_NAMES):
        verdict = _cap(verdict)
        detail += ("; unusable: " + "; ".join(probs)) if probs else "; some behaviours missing"
    return Outcome(ours, verdict, detail)


def _ci_detail(rows: pd.DataFrame) -> str:
    parts = []
    for r in rows.to_dict("records"):
        s = f"{r['behaviour']} {r['design']} vs {r['baseline']}: p_holm={r['p_holm']:.2g}"
        if "ci_low" in r and np.isfinite(r.get("ci_low", np.nan)):
            s += f", 95 % CI [{r['ci_low']:+.0f}, {r['ci_high']:+.0f}] %"
        parts.append(s)
    return "; ".join(parts)


def _claim_ss_power(ctx: _Context) -> Outcome:
    rows, basis = _comparison_rows(ctx, ("exp1",), ["SS"], BEHAVIOUR_NAMES, "power_w")
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
        return _missing_or_untestable(ctx, list(ctx.bad["design"].unique()) if len(ctx.bad) else ["sweeps"],
                                      ["forward"], ("exp2",))
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
        f"{b} {sd * 1e3:.1f} vs {sm * 1e3:.1f} mm" for b, sd, sm in spans)
    probs = ctx.problems(list(ctx.bad["design"].unique()) if len(ctx.bad) else [], ["forward"], ("exp2",))
    if probs or len(spans) < len(ref.SWEEPS):
        verdict = _cap(verdict)
        if probs:
            detail += "; unusable: " + "; ".join(probs)
    return Outcome(f"density moves it more for {k}/{len(spans)} base materials", verdict, detail)


def _claim_low_modulus(ctx: _Context) -> Outcome:
    pts, basis = _sweep_points(ctx)
    if pts is None:
        return _missing_or_untestable(ctx, list(ctx.bad["design"].unique()) if len(ctx.bad) else ["sweeps"],
                                      ["forward"], ("exp2",))
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
    ours = (f"median {low.median() * 1e3:.1f} mm (E <= {ref.CLAIM_LOW_MODULUS_GPA:g} GPa, n={len(low)}) vs "
            f"{high.median() * 1e3:.1f} mm (E >= {ref.CLAIM_HIGH_MODULUS_GPA:g} GPa, n={len(high)})")
    detail = (f"low-modulus range {low.min() * 1e3:.1f}-{low.max() * 1e3:.1f} mm, high-modulus range "
              f"{high.min() * 1e3:.1f}-{high.max() * 1e3:.1f} mm (sweep points of experiment 2)")
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
    ordered = all(np.isfinite(v) for v in found.values()) and \
        found["PVC"] > max(v for k, v in found.items() if k != "PVC")
    verdict = HOLDS if all(close) else PARTLY if (any(close) or ordered) else FAILS
    ours = ", ".join(f"{k} {seconds(v)} s" if np.isfinite(v) else f"{k} none stable" for k, v in found.items())
    return Outcome(ours, verdict, f"measured column {col}; nearest grid points: " + "; ".join(notes))


def _claim_timestep_trend(ctx: _Context) -> Outcome:
    s, col = _stability(ctx)
    if s is None:
        return Outcome("not run", NOT_RUN, "no stable-time-step map for this convention")
    ok = s[np.isfinite(s[col].astype(float)) & (s[col].astype(float) > 0)]
    x = np.column_stack([np.ones(len(ok)), np.log10(ok["density_g_cm3"].astype(float)),
                         np.log10(ok["modulus_gpa"].astype(float))])
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


_PCT_RULE = (f"same sign and within max({MATCH_REL_TOL:.0%} of the paper's, {MATCH_ABS_TOL_PCT:g} points): holds; "
             f"same sign and >= {PARTLY_MIN_FRACTION:.0%} of its size: partly")
_COUNT_RULE = f"all comparisons the claimed way with Holm p < {ALPHA:g}: holds; at least half: partly"

CLAIMS: tuple[Claim, ...] = (
    Claim("hop_height", "Every design holds a mean hop height of 1 m",
          f"{ref.CLAIM_HOP_HEIGHT_M:g} m, every design and behaviour",
          f"every design-behaviour mean within {HOP_HEIGHT_TOL_M:g} m of 1 m: holds; at least half: partly",
          _claim_hop_height),
    Claim("tracking_all_beat_md", "Tracking error: every physical material beats MD significantly",
          "PVC, Al, Ti, SS lower than MD, p < 0.05, all four behaviours", _COUNT_RULE,
          _claim_count_significant("tracking_error_m", list(MONO), list(BEHAVIOUR_NAMES), -1)),
    Claim("tracking_ss_55", "Tracking error: SS lower than MD by at least 55 % on every behaviour",
          f"<= {ref.CLAIM_SS_TRACKING_PCT:+.0f} % on every behaviour",
          f"every behaviour <= {ref.CLAIM_SS_TRACKING_PCT:+.0f} %: holds; every behaviour lower, or half of them "
          f"<= {ref.CLAIM_SS_TRACKING_PCT:+.0f} %: partly", _claim_ss_tracking),
    Claim("power_higher_dynamic", "Power: higher for materials than MD on the dynamic behaviours (2-4)",
          "PVC, Al, Ti, SS higher than MD on forward, ramp, circle", _COUNT_RULE,
          _claim_count_significant("power_w", list(MONO), list(ref.DYNAMIC_BEHAVIOURS), +1)),
    Claim("power_ss_max", "Power: up to +193 % for SS against MD",
          f"{ref.CLAIM_SS_POWER_MAX_PCT:+.0f} % (largest, SS)", _PCT_RULE + " (on our largest increase)",
          _claim_ss_power),
    Claim("density_over_modulus", "Density moves tracking error more than modulus",
          "density sweeps change tracking error more than modulus sweeps",
          "span of mean tracking error over the density sweep larger than over the modulus sweep for every "
          "base material: holds; for at least half: partly", _claim_density_over_modulus),
    Claim("low_modulus_tracks_worse", "Moduli <= 9 GPa track worse than moduli >= 20 GPa",
          f"E <= {ref.CLAIM_LOW_MODULUS_GPA:g} GPa much higher tracking error than E >= {ref.CLAIM_HIGH_MODULUS_GPA:g} GPa",
          "every low-modulus sweep point above every high-modulus one: holds; medians in that order: partly",
          _claim_low_modulus),
    Claim("ramp_rho_inc_tracking", "Ramp: rho-inc against MD, tracking error",
          _pct(ref.CLAIM_RAMP_RHO_INC_TRACKING_PCT), _PCT_RULE,
          _claim_pct("rho-inc", "tracking_error_m", ref.CLAIM_RAMP_RHO_INC_TRACKING_PCT)),
    Claim("ramp_rho_inc_power", "Ramp: rho-inc against MD, power",
          _pct(ref.CLAIM_RAMP_RHO_INC_POWER_PCT), _PCT_RULE,
          _claim_pct("rho-inc", "power_w", ref.CLAIM_RAMP_RHO_INC_POWER_PCT)),
    Claim("ramp_ss_tracking", "Ramp: SS against MD, tracking error",
          _pct(ref.CLAIM_RAMP_SS_TRACKING_PCT), _PCT_RULE,
          _claim_pct("SS", "tracking_error_m", ref.CLAIM_RAMP_SS_TRACKING_PCT)),
    Claim("ramp_ss_power", "Ramp: SS against MD, power",
          _pct(ref.CLAIM_RAMP_SS_POWER_PCT), _PCT_RULE,
          _claim_pct("SS", "power_w", ref.CLAIM_RAMP_SS_POWER_PCT)),
    Claim("headline_tracking", "Ramp: rho-inc against SS, tracking error (abstract)",
          _pct(ref.CLAIM_HEADLINE_TRACKING_PCT), _PCT_RULE,
          _claim_pct("rho-inc", "tracking_error_m", ref.CLAIM_HEADLINE_TRACKING_PCT, baseline="SS")),
    Claim("headline_power", "Ramp: rho-inc against SS, power (abstract)",
          _pct(ref.CLAIM_HEADLINE_POWER_PCT), _PCT_RULE,
          _claim_pct("rho-inc", "power_w", ref.CLAIM_HEADLINE_POWER_PCT, baseline="SS")),
    Claim("timestep_materials", "Stable time step: PVC about 1e-3 s, Al and SS about 1e-4 s",
          ", ".join(f"{k} {seconds(v)} s" for k, v in ref.CLAIM_STABLE_TIMESTEP_S.items()),
          f"every material within a factor {10 ** TIMESTEP_TOL_DECADES:.0f} of the paper's: holds; some, or PVC's the largest: "
          "partly", _claim_timestep_materials),
    Claim("timestep_trend", "Stable time step log-linear in density and modulus; light or stiff need smaller steps",
          "log-linear; grows with density, shrinks with modulus",
          f"plane fit in log-log with density slope > 0, modulus slope < 0 and R² >= {TREND_MIN_R2:g}: holds; "
          "right signs with a poorer fit, or one right sign: partly", _claim_timestep_trend),
)


# --- the table -----------------------------------------------------------------------------


def _by_convention(table: pd.DataFrame | None, convention: str) -> pd.DataFrame | None:
    if table is None:
        return None
    if "convention" not in table.columns:
        return table if convention == "paper" else table.iloc[0:0]
    return table[table["convention"] == convention]


def claims_table(hops: pd.DataFrame | None, runs: pd.DataFrame | None = None,
                 stability: pd.DataFrame | None = None, *, conventions=CONVENTIONS, basis: str = "auto",
                 alpha: float = ALPHA, timestep_s: float | None = None) -> pd.DataFrame:
    """Every claim of the paper beside ours, per stiffness convention.

    hops: the per-hop table of experiments 1-3 (all conventions; columns of
    :func:`mat_hopper.metrics.hop_table` plus experiment, convention,
    replicate and the sweep columns); runs: the run summaries (status,
    stable, upright, diverged_at_s, ...; optional, tells unstable runs
    apart from missing ones); stability: the stable-time-step map (one row
    per grid point; a ``convention`` column, else taken as ``paper``);
    basis: ``hops``, ``replicates`` or ``auto``; timestep_s: the runs' time
    step (s), named in "unstable at dt=..." when runs has no timestep_s
    column. Columns: claim_id, claim, paper, ours, verdict, convention,
    basis, detail, rule (and profile, when the tables have one)."""
    if basis not in _stats.BASES + ("auto",):
        raise ValueError(f"basis must be one of hops, replicates, auto; got {basis!r}")
    hops = pd.DataFrame() if hops is None else hops
    profiles = set()
    for t in (hops, runs, stability):
        if t is not None and "profile" in t.columns:
            profiles |= set(t["profile"].dropna().astype(str))
    if len(profiles) > 1:
        raise ValueError(f"the tables hold several profiles {sorted(profiles)}; pass one profile's results")
    rows = []
    for conv in conventions:
        if conv not in CONVENTIONS:
            raise ValueError(f"unknown convention {conv!r}; accepted: {', '.join(CONVENTIONS)}")
        h = _by_convention(hops, conv)
        r = _by_convention(runs, conv)
        bad = _stats.unusable_runs(r, timestep_s)
        h = _stats.drop_unusable(h if h is not None else pd.DataFrame(), bad)
        if len(h) and "design" not in h.columns:
            raise ValueError("hops needs a 'design' column")
        ctx = _Context(conv, h, r, _by_convention(stability, conv), basis, alpha, timestep_s, bad)
        for claim in CLAIMS:
            is_stab = claim.claim_id.startswith("timestep")
            if not is_stab and len(h) == 0 and len(bad) == 0:
                out = Outcome("not run", NOT_RUN, f"no {conv}-convention hopping results")
            else:
                out = claim.evaluate(ctx)
            used = ("" if out.verdict in (NOT_RUN, NOT_TESTABLE) else
                    "stability map" if is_stab else _basis_used(ctx, claim))
            rows.append({"claim_id": claim.claim_id, "claim": claim.claim, "paper": claim.paper, "ours": out.ours,
                         "verdict": out.verdict, "convention": conv, "basis": used, "detail": out.detail,
                         "rule": claim.rule})
    out = pd.DataFrame(rows, columns=list(COLUMNS))
    if len(profiles) == 1:
        out.insert(len(COLUMNS) - 3, "profile", profiles.pop())
    return out


def _basis_used(ctx: _Context, claim: Claim) -> str:
    exps = {"density_over_modulus": ("exp2",), "low_modulus_tracks_worse": ("exp2",),
            "hop_height": None}.get(claim.claim_id, ("exp1", "exp3") if claim.claim_id.startswith(("ramp", "headline"))
                                    else ("exp1",))
    t = ctx.hops if exps is None else ctx.experiment(exps)
    return {"hops": "hop cycles", "replicates": "replicate means"}[ctx.basis_for(t)]


# --- writers ---------------------------------------------------------------------------------


def _md_cell(x) -> str:
    s = "" if x is None or (isinstance(x, float) and math.isnan(x)) else str(x)
    return s.replace("|", "\\|").replace("\n", " ")


def to_markdown(table: pd.DataFrame, columns=("claim", "convention", "paper", "ours", "verdict", "basis")) -> str:
    """The claims as a markdown table (one row per claim and convention),
    the rules listed below it."""
    cols = [c for c in columns if c in table.columns]
    lines = ["| " + " | ".join(cols) + " |", "|" + "|".join("---" for _ in cols) + "|"]
    for r in table.to_dict("records"):
        lines.append("| " + " | ".join(_md_cell(r[c]) for c in cols) + " |")
    if "rule" in table.columns and "claim_id" in table.columns:
        lines += ["", "Verdict rules:", ""]
        for cid, rule in dict(zip(table["claim_id"], table["rule"])).items():
            claim = table.loc[table["claim_id"] == cid, "claim"].iloc[0]
            lines.append(f"- {_md_cell(claim)}: {_md_cell(rule)}.")
    return "\n".join(lines) + "\n"


def write_claims(table: pd.DataFrame, directory) -> tuple[str, str]:
    """Write ``claims.md`` (markdown table) and ``claims.csv`` (every
    column) into `directory`, each atomically. Returns their paths."""
    directory = os.fspath(directory)
    md = os.path.join(directory, "claims.md")
    csv = os.path.join(directory, "claims.csv")
    write_text(to_markdown(table), md)
    write_text(table.to_csv(index=False), csv)
    return md, csv
