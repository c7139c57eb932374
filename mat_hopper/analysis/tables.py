"""Small tables of results, for reading: one call per question a chapter
asks (how did each run end, percent change against a baseline, what
claims hold), from the tidy tables of :mod:`mat_hopper.experiments`.
Every percent change is :func:`mat_hopper.util.change.percent_change`.

Units: SI in the column names (``_m``, ``_w``, ``_s``); densities g/cm^3,
moduli GPa.

Every table is importable from here; some live in package-private modules,
one concept each: the model's designs and joints (``_model_tables``), how
the runs ended (``_outcomes``), the claims per chapter (``_claim_tables``)
and jerk by record rate (``_jerk_rates``).
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ..core.behaviours import order_behaviours
from ..core.materials import order_designs
from ..util.change import percent_change
from ._claim_tables import CHAPTER_CLAIMS, claim_rules, claims_for
from ._columns import need_columns as _need
from ._jerk_rates import jerk_by_rate
from ._model_tables import design_table, joint_table
from ._outcomes import failure_table, outcome_summary, outcome_table

__all__ = [
    "CHAPTER_CLAIMS",
    "ORDER_PAIRS",
    "claim_rules",
    "claims_for",
    "design_table",
    "failure_table",
    "jerk_by_rate",
    "joint_table",
    "leg_mass_table",
    "metric_table",
    "order_effect",
    "outcome_summary",
    "outcome_table",
    "pct_change_table",
    "power_formula_table",
    "replicate_table",
    "setting_comparison",
    "starred",
    "sweep_spans",
]


def replicate_table(comparison: pd.DataFrame, metrics=("tracking_error_m", "power_w")) -> pd.DataFrame:
    """A compare_replicates table for reading: one row per design and
    metric, percent change of the mean with its 95 % bootstrap interval,
    the Holm-adjusted p and a star where p < 0.05.

    Args:
        comparison: :func:`mat_hopper.analysis.stats.compare_replicates`'s table (design, metric, n,
            pct_change, ci_low, ci_high, p_holm, significant).
        metrics: the metrics kept.

    Returns:
        DataFrame, one row per row of `comparison` with a kept metric (no behaviour column). Columns:
        design, metric, n, change ("+12 % [+3, +20]": pct_change with ci_low, ci_high), "p (Holm)"
        (three significant digits), "" ("*" where the ``significant`` column is true).

    Raises:
        ValueError: `comparison` lacks one of the columns above.
    """
    need = ("design", "metric", "n", "pct_change", "ci_low", "ci_high", "p_holm", "significant")
    _need(comparison, need, "replicate_table")
    c = comparison[comparison["metric"].isin(metrics)]
    return pd.DataFrame(
        {
            "design": c["design"],
            "metric": c["metric"],
            "n": c["n"],
            "change": [
                f"{p:+.0f} % [{lo:+.0f}, {hi:+.0f}]" for p, lo, hi in zip(c["pct_change"], c["ci_low"], c["ci_high"])
            ],
            "p (Holm)": c["p_holm"].map(lambda p: f"{p:.3g}"),
            "": np.where(c["significant"], "*", ""),
        }
    ).reset_index(drop=True)


def pct_change_table(
    hops: pd.DataFrame, metric: str, baseline: str = "MD", *, designs=None, behaviours=None
) -> pd.DataFrame:
    """Percent change of the mean of `metric` against `baseline` (same
    behaviour, unperturbed runs), designs as rows and behaviours as
    columns (from :func:`mat_hopper.analysis.stats.summary_table`). Where the
    baseline's mean is round-off (:func:`~mat_hopper.util.change.percent_change`;
    e.g. the tracking error of hopping in place) the change is nan: a
    percentage of nothing means nothing.

    Args:
        hops: a per-hop table (design, behaviour, `metric`; the unperturbed run, replicate -1, is used).
        metric: the metric column.
        baseline: the baseline design.
        designs: the designs shown (rows, in the paper's order); None: those of the table.
        behaviours: the behaviours shown (columns, in the paper's order); None: those of the table.

    Returns:
        DataFrame of percent changes (%), designs as index (the baseline left out unless named in
        `designs`, then all nan), behaviours as columns; the columns' name is "<metric>: % vs <baseline>".

    Raises:
        ValueError: `metric` is not a column of `hops` (:func:`mat_hopper.analysis.stats.summary_table`).
    """
    from . import stats

    s = stats.summary_table(hops, metrics=(metric,), baseline=baseline)
    if designs is not None:
        s = s[s["design"].isin(designs)]
    if behaviours is not None:
        s = s[s["behaviour"].isin(behaviours)]
    s = s[s["design"] != baseline]
    t = s.pivot_table(index="design", columns="behaviour", values="pct_change_mean", aggfunc="first")
    t = t.reindex(index=order_designs(designs or t.index), columns=order_behaviours(behaviours or t.columns))
    t.columns.name = f"{metric}: % vs {baseline}"
    return t


def metric_table(hops: pd.DataFrame, metric: str, stat: str = "mean", *, scale: float = 1.0) -> pd.DataFrame:
    """`stat` (mean or median) of `metric` over the scored hop cycles of
    the unperturbed runs, times `scale` (e.g. 1e3 for mm), designs as rows
    and behaviours as columns.

    Args:
        hops: a per-hop table (design, behaviour, `metric`).
        metric: the metric column.
        stat: ``mean`` or ``median``.
        scale: factor on every value.

    Returns:
        DataFrame, designs as index and behaviours as columns, each in the paper's order.

    Raises:
        ValueError: `stat` not mean or median; `metric` not a column of `hops`.
    """
    from . import stats

    if stat not in ("mean", "median"):
        raise ValueError(f"stat must be mean or median, got {stat!r}")
    s = stats.summary_table(hops, metrics=(metric,), baseline=None)
    t = s.pivot_table(index="design", columns="behaviour", values=stat, aggfunc="first") * scale
    t = t.reindex(index=order_designs(t.index), columns=order_behaviours(t.columns))
    t.columns.name = None
    return t


def sweep_spans(hops: pd.DataFrame, metric: str = "tracking_error_m") -> pd.DataFrame:
    """Experiment 2, one row per base material and swept property: the
    smallest and largest mean of `metric` over the sweep's points (mean
    over each point's scored hop cycles, unperturbed runs), their span,
    and the property values where they occur. Columns sweep_base,
    sweep_property, n_points, min, at_min, max, at_max, span.

    Args:
        hops: experiment 2's per-hop rows (sweep_base, sweep_property, density_g_cm3, modulus_gpa,
            `metric`; replicate -1 only where a ``replicate`` column exists).
        metric: the metric column.

    Returns:
        DataFrame, one row per (sweep_base, sweep_property) in order of appearance. min, max and span
        in the metric's unit; at_min, at_max the swept property's value (density_g_cm3 in g/cm^3 for a
        ``density`` sweep, else modulus_gpa in GPa).

    Raises:
        ValueError: `hops` lacks one of the needed columns.
    """
    need = ("sweep_base", "sweep_property", "density_g_cm3", "modulus_gpa", metric)
    missing = [c for c in need if c not in hops.columns]
    if missing:
        raise ValueError(f"sweep_spans needs columns {missing}")
    h = hops[hops["replicate"] == -1] if "replicate" in hops.columns else hops
    rows = []
    for (base, prop), g in h.groupby(["sweep_base", "sweep_property"], sort=False):
        col = "density_g_cm3" if prop == "density" else "modulus_gpa"
        means = g.groupby(col)[metric].mean()
        rows.append(
            {
                "sweep_base": base,
                "sweep_property": prop,
                "n_points": len(means),
                "min": means.min(),
                "at_min": means.idxmin(),
                "max": means.max(),
                "at_max": means.idxmax(),
                "span": means.max() - means.min(),
            }
        )
    return pd.DataFrame(rows)


ORDER_PAIRS = (("rho-inc", "rho-dec"), ("PVC-Ti-SS", "SS-Ti-PVC"))


def order_effect(
    hops: pd.DataFrame, pairs=ORDER_PAIRS, metrics=("tracking_error_m", "power_w", "jerk_m_s3"), alpha: float = 0.05
) -> pd.DataFrame:
    """Does segment order matter? For each pair of designs made of the same
    segments in opposite orders: the percent change of the second's mean
    against the first's, per behaviour and metric, with the Mann-Whitney U
    test on hop cycles (unperturbed runs; Holm over each pair's
    behaviours and metrics). Columns pair, behaviour, metric, pct_change,
    p_holm, significant.

    Args:
        hops: a per-hop table holding both designs of every pair (their experiments are merged into
            one family).
        pairs: (first, second) design names; the second is compared against the first.
        metrics: metric columns.
        alpha: significance level.

    Returns:
        DataFrame, one row per pair, behaviour and metric; pair is "<second> vs <first>", pct_change in
        %. The Holm correction is :func:`mat_hopper.analysis.stats.compare_hops`'s: one family per metric
        (and profile and convention) within each pair.

    Raises:
        ValueError: a pair's design missing from `hops`; a metric not a column of `hops`.
    """
    from . import stats

    frames = []
    for first, second in pairs:
        sub = hops[hops["design"].isin([first, second])]
        if not {first, second} <= set(sub["design"]):
            raise ValueError(f"order_effect: designs {first} and {second} must both be in the table")
        if "experiment" in sub.columns:
            sub = sub.assign(experiment="+".join(sorted(set(sub["experiment"].astype(str)))))
        res = stats.compare_hops(sub, baseline=first, metrics=metrics, alpha=alpha)
        res = res[res["design"] == second].assign(pair=f"{second} vs {first}")
        frames.append(res[["pair", "behaviour", "metric", "pct_change", "p_holm", "significant"]])
    return pd.concat(frames, ignore_index=True)


def starred(
    table: pd.DataFrame,
    rows=("pair", "metric"),
    column: str = "behaviour",
    value: str = "pct_change",
    flag: str = "significant",
) -> pd.DataFrame:
    """A tidy comparison as a wide table for the page: `value` (a percent
    change) as "+12 %" with a star where `flag` is true, `rows` as the
    index and `column` values as columns ("–" where nan).

    Args:
        table: a tidy comparison (e.g. :func:`order_effect`'s).
        rows: the columns that make the index.
        column: the column whose values become columns (behaviours in the paper's order).
        value: the percent-change column.
        flag: the boolean column that earns a star.

    Returns:
        DataFrame of str: "+12 %", "+12 % *" where `flag` is true, "–" where `value` is not finite.

    Raises:
        ValueError: `table` lacks one of the columns `rows`, `column`, `value`, `flag`.
    """
    _need(table, (*rows, column, value, flag), "starred")

    def cell(r) -> str:
        v = r[value]
        if not np.isfinite(v):
            return "–"
        return f"{v:+.0f} %" + (" *" if bool(r[flag]) else "")

    t = table.assign(_cell=table.apply(cell, axis=1))
    out = t.pivot_table(index=list(rows), columns=column, values="_cell", aggfunc="first", sort=False)
    if column == "behaviour":
        out = out[order_behaviours(out.columns)]
    out.columns.name = None
    return out


def setting_comparison(
    hops: pd.DataFrame,
    pairs=(("rho-inc", "MD"), ("SS", "MD"), ("rho-inc", "SS")),
    metrics=("tracking_error_m", "power_w"),
) -> pd.DataFrame:
    """Percent change of the mean of each metric for each (design,
    baseline) pair, per ``setting`` of the table (e.g. from
    :func:`axial_check`): rows setting, columns "<metric>: <design> vs
    <baseline>"; nan where either is missing or the baseline's mean is
    round-off (:func:`~mat_hopper.util.change.percent_change`).

    Args:
        hops: a per-hop table with columns setting, design and the metrics.
        pairs: (design, baseline) names.
        metrics: metric columns.

    Returns:
        DataFrame, one row per setting (in order of appearance, index named ``setting``), percent
        changes (%) of the means over all rows of each design and setting.

    Raises:
        ValueError: `hops` lacks the ``setting`` or ``design`` column or a metric's (the message names
            them).
    """
    _need(hops, ("setting", "design", *metrics), "setting_comparison")
    means = hops.groupby(["setting", "design"])[list(metrics)].mean()
    rows = {}
    for setting in dict.fromkeys(hops["setting"]):
        row = {}
        for design, baseline in pairs:
            for m in metrics:
                try:
                    a, b = means.loc[(setting, design), m], means.loc[(setting, baseline), m]
                except KeyError:
                    a, b = np.nan, np.nan
                row[f"{m}: {design} vs {baseline}"] = percent_change(a, b)
        rows[setting] = row
    out = pd.DataFrame.from_dict(rows, orient="index")
    out.index.name = "setting"
    return out


def power_formula_table(hops: pd.DataFrame, design: str = "SS", baseline: str = "MD") -> pd.DataFrame:
    """Percent change of `design`'s mean hip power against `baseline`'s, per
    behaviour, measured two ways: the real mechanical power of the hip
    motors (``power_w``, ours) and the authors' formula
    (``power_paper_w``). Rows: the two measures; columns: behaviours.

    Args:
        hops: a per-hop table (design, behaviour, power_w, power_paper_w; the unperturbed run is used,
            :func:`pct_change_table`).
        design: the design.
        baseline: the baseline design.

    Returns:
        DataFrame of percent changes (%): rows "real hip power (ours)" and "the authors' formula",
        behaviours as columns (nan where `design` has no value); the columns' name is
        "power: <design> vs <baseline> (%)".

    Raises:
        ValueError: `hops` lacks power_w or power_paper_w.
    """
    rows = {}
    for metric, label in (("power_w", "real hip power (ours)"), ("power_paper_w", "the authors' formula")):
        t = pct_change_table(hops, metric, baseline, designs=[baseline, design])
        rows[label] = t.loc[design] if design in t.index else pd.Series(dtype=float)
    out = pd.DataFrame(rows).T
    out.columns.name = f"power: {design} vs {baseline} (%)"
    return out


def leg_mass_table(runs: pd.DataFrame) -> pd.DataFrame:
    """The runs of a sweep with the mass of the leg's material (the sum of
    :func:`mat_hopper.core.materials.segment_masses`, kg, from the runs'
    per-segment ``densities_g_cm3`` "a/b/c" and ``segment_mass``
    convention) as ``leg_mass_kg``; unperturbed runs only. Columns: those of
    `runs` plus leg_mass_kg.

    Args:
        runs: a run-summary table with ``densities_g_cm3`` ("a/b/c", g/cm^3 per segment, hip to foot)
            and, optionally, ``segment_mass`` (default ``leg``) and ``replicate`` (-1 kept).

    Returns:
        DataFrame: the kept rows, index reset, with leg_mass_kg (kg).

    Raises:
        ValueError: no ``densities_g_cm3`` column; a density out of range
            (:meth:`mat_hopper.core.materials.LegDesign.from_properties`); an unknown segment-mass convention
            (:func:`mat_hopper.core.materials.segment_masses`).
    """
    from ..core.materials import LegDesign, segment_masses

    _need(runs, ("densities_g_cm3",), "leg_mass_table")
    r = runs[runs["replicate"] == -1] if "replicate" in runs.columns else runs
    masses = []
    for text, conv in zip(r["densities_g_cm3"].astype(str), r.get("segment_mass", pd.Series("leg", index=r.index))):
        rho = [float(x) for x in text.split("/")]
        d = LegDesign.from_properties(rho, [None] * len(rho))
        masses.append(sum(segment_masses(d, conv)))
    return r.assign(leg_mass_kg=masses).reset_index(drop=True)
