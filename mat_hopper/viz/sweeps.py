"""Fig. 4 D-E of the paper: tracking error against density and against
modulus, one line per base material (experiment 2's one-property sweeps),
from tidy result tables (:mod:`mat_hopper.experiments.paper`).
:mod:`mat_hopper.viz.figures` re-exports :func:`figure4_sweeps`.
"""

from __future__ import annotations

import numpy as np
import pandas as pd
from matplotlib import rc_context
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Patch

from ..analysis import stats as _stats
from ..core import reference as ref
from .style import (
    STYLE,
    _new_figure,
    _panel_label,
    _require,
    design_colour,
    design_label,
    metric_scale,
    plain_log_ticks,
)

SWEEP_PROPERTIES = {"density": ("density_g_cm3", "Density (g/cm³)"), "modulus": ("modulus_gpa", "Modulus (GPa)")}


def figure4_sweeps(
    hops: pd.DataFrame,
    baseline_hops: pd.DataFrame | None = None,
    *,
    metric: str = "tracking_error_m",
    baseline: str = "MD",
    alpha: float = 0.05,
    runs: pd.DataFrame | None = None,
) -> Figure:
    """Fig. 4 D-E: `metric` against density (D) and against modulus (E),
    one line per base material: mean over hop cycles with the interquartile
    range as bars; the base material's own point has a black edge.

    hops: experiment 2's per-hop table (sweep_base, sweep_property,
    density_g_cm3, modulus_gpa, the metric). baseline_hops: the baseline
    design's forward-hopping cycles (experiment 1): drawn as a dashed line
    with its IQR band, and each sweep point is then tested against it
    (Mann-Whitney U on hop cycles, Holm over all points; descriptive, as
    the cycles of one run are not independent): filled markers differ at
    Holm p < alpha, open ones do not. runs: the run summaries of
    experiment 2: points whose run diverged, fell or failed are left out of
    the lines and marked with a cross on the axis.

    Args:
        hops: per-hop table with columns ``sweep_base``, ``sweep_property``
            (``"density"`` or ``"modulus"``), ``density_g_cm3``,
            ``modulus_gpa`` and `metric` (optionally ``replicate``: only the
            unperturbed run's cycles are drawn where present).
        baseline_hops: per-hop rows holding the `baseline` design (column
            ``design``); None: no baseline line and no test (every marker
            filled).
        metric: the metric column drawn (SI; scaled by :func:`metric_scale`).
        baseline: the design name taken from `baseline_hops`.
        alpha: significance level of the Holm-adjusted p.
        runs: run summaries of experiment 2; None: no run is left out.

    Returns:
        The ``matplotlib.figure.Figure`` (panels D and E).

    Raises:
        ValueError: `hops` lacks a required column, or (with baseline hops)
            `alpha` not in (0, 1) (:func:`mat_hopper.physics.metrics.compare_independent`).
    """
    _require(hops, ("sweep_base", "sweep_property", "density_g_cm3", "modulus_gpa", metric), "figure4_sweeps")
    table, bad, baseline_hops = _sweep_table(hops, baseline_hops, runs, metric)
    base, significant = _against_baseline(table, baseline_hops, baseline, metric, alpha)
    factor, ylabel = metric_scale(metric, table[metric])
    seen = list(table["sweep_base"].unique()) + (list(bad["sweep_base"].unique()) if len(bad) else [])
    bases = [b for b in ("PVC", "Al", "Ti", "SS") if b in seen]
    bases += [b for b in dict.fromkeys(seen) if b not in bases]
    with rc_context(STYLE):
        fig = _new_figure(9.0, 3.4)
        axes = fig.subplots(1, 2, sharey=True)
        for ax, (prop, letter) in zip(axes, (("density", "D"), ("modulus", "E"))):
            col, xlabel = SWEEP_PROPERTIES[prop]
            sub = table[table["sweep_property"] == prop]
            for i, b in enumerate(bases):
                s = sub[sub["sweep_base"] == b]
                if len(s):
                    _draw_sweep_line(ax, s, b, design_colour(b, i), col, metric, factor, significant)
            _draw_lost_runs(ax, bad[bad["sweep_property"] == prop] if len(bad) else bad, bases, col)
            if base is not None and len(base):
                v = base[metric].to_numpy(float) * factor
                ax.axhline(np.mean(v), color=design_colour(baseline), ls="--", lw=1.0, zorder=1)
                ax.axhspan(*np.percentile(v, [25, 75]), color=design_colour(baseline), alpha=0.15, lw=0, zorder=0)
            ax.set_xscale("log")
            plain_log_ticks(ax.xaxis)
            ax.set_xlabel(xlabel)
            ax.grid(True, axis="x", which="major", alpha=0.3)
            _panel_label(ax, letter)
        axes[0].set_ylabel(ylabel)
        handles = _sweep_legend(bases, bad, base, baseline, alpha)
        fig.legend(handles=handles, loc="outside upper center", ncols=min(len(handles), 5), columnspacing=1.0)
    return fig


def _sweep_table(hops, baseline_hops, runs, metric):
    """(the sweep's unperturbed hop cycles with a point id and numeric columns,
    the unusable runs of the sweep, the baseline's usable hop cycles)."""
    bad = _stats.unusable_runs(runs)
    if len(bad) and "sweep_property" in bad.columns:
        bad = bad[bad["sweep_property"].notna()]
        if "replicate" in bad.columns and bad["replicate"].notna().any():
            bad = bad[bad["replicate"] == _stats.UNPERTURBED]
    hops = _stats.drop_unusable(hops, bad)
    if baseline_hops is not None:
        baseline_hops = _stats.drop_unusable(baseline_hops, _stats.unusable_runs(runs))
    table = _stats.select_replicates(hops, _stats.UNPERTURBED)
    if len(table) == 0:
        table = hops
    keys = ["sweep_base", "sweep_property", "density_g_cm3", "modulus_gpa"]
    table = table.assign(
        _point=table[keys].astype(str).agg("|".join, axis=1),
        **{c: pd.to_numeric(table[c], errors="coerce") for c in (metric, "density_g_cm3", "modulus_gpa")},
    )
    return table, bad, baseline_hops


def _against_baseline(table, baseline_hops, baseline, metric, alpha):
    """(the baseline's hop cycles or None, the set of sweep points that differ
    from it significantly, Mann-Whitney U with Holm over all points, or None)."""
    significant = None
    base = None
    if baseline_hops is not None and len(baseline_hops):
        base = _stats.select_replicates(baseline_hops[baseline_hops["design"] == baseline], _stats.UNPERTURBED)
        if "behaviour" in base.columns and "behaviour" in table.columns:
            base = base[base["behaviour"].isin(set(table["behaviour"]))]
        if len(base):
            joint = pd.concat(
                [
                    table.assign(design=table["_point"])[["design", metric]].assign(behaviour="sweep"),
                    base.assign(design="__baseline__")[["design", metric]].assign(behaviour="sweep"),
                ],
                ignore_index=True,
            )
            from ..physics.metrics import compare_independent

            cmp = compare_independent(joint, "__baseline__", by="behaviour", metrics=(metric,), alpha=alpha)
            significant = set(cmp.loc[cmp["significant"].astype(bool), "design"])
    return base, significant


def _draw_sweep_line(ax, s, b, colour, col, metric, factor, significant) -> None:
    """One base material's sweep: mean and IQR bars, markers filled where
    significant, and a black ring on the base material's own point."""
    g = s.groupby(["_point", col], sort=False)[metric]
    pts = pd.DataFrame({"mean": g.mean(), "q1": g.quantile(0.25), "q3": g.quantile(0.75)}).reset_index()
    pts = pts.sort_values(col)
    x = pts[col].to_numpy(float)
    y = pts["mean"].to_numpy(float) * factor
    yerr = np.vstack([y - pts["q1"].to_numpy(float) * factor, pts["q3"].to_numpy(float) * factor - y])
    ax.errorbar(
        x,
        y,
        yerr=np.clip(yerr, 0, None),
        color=colour,
        lw=1.2,
        capsize=2,
        elinewidth=0.8,
        marker="none",
        label=b,
        zorder=2,
    )
    nominal = ref.MONO_MATERIALS.get(b, (None, None))
    for xi, yi, pt in zip(x, y, pts["_point"]):
        filled = significant is None or pt in significant
        ax.plot(
            xi,
            yi,
            "o",
            ms=5,
            color=colour,
            zorder=3,
            markerfacecolor=colour if filled else "white",
            markeredgewidth=1.0,
            markeredgecolor=colour,
        )
    nom = s[(np.isclose(s["density_g_cm3"], nominal[0] or -1)) & (np.isclose(s["modulus_gpa"], nominal[1] or -1))]
    if len(nom):
        ax.plot(
            float(nom[col].iloc[0]),
            float(nom[metric].mean()) * factor,
            "o",
            ms=10,
            markerfacecolor="none",
            markeredgecolor="black",
            markeredgewidth=1.2,
            zorder=4,
        )


def _draw_lost_runs(ax, lost, bases, col) -> None:
    """A cross on the axis for each sweep point whose run diverged, fell or failed."""
    for _, row in lost.iterrows():
        bi = bases.index(row["sweep_base"]) if row["sweep_base"] in bases else 0
        ax.plot(
            float(row[col]),
            0.03 + 0.05 * bi,
            marker="x",
            ms=6,
            mew=1.6,
            color=design_colour(row["sweep_base"], bi),
            clip_on=False,
            zorder=5,
            transform=ax.get_xaxis_transform(),
        )


def _sweep_legend(bases, bad, base, baseline, alpha: float = 0.05) -> list:
    """The legend's handles: materials, the base-material ring, lost runs,
    the baseline; open markers are points whose hop cycles do not differ
    from the baseline's at Holm p < `alpha`, a description of one run each
    (hop cycles are not independent samples), not a significance."""
    handles = [Line2D([], [], color=design_colour(b, i), marker="o", lw=1.2, label=b) for i, b in enumerate(bases)]
    ring = dict(ms=10, markerfacecolor="none", markeredgecolor="black", markeredgewidth=1.2)
    handles.append(Line2D([], [], ls="none", marker="o", label="base material", **ring))
    if len(bad):
        why = "diverged" if bad["why"].str.startswith("unstable").all() else "diverged, fell or failed"
        handles.append(Line2D([], [], ls="none", marker="x", ms=7, mew=1.6, color="#555555", label=f"run {why}"))
    if base is not None and len(base):
        colour = design_colour(baseline)
        label = f"{design_label(baseline)} mean, IQR"
        handles.append(Patch(facecolor=colour, alpha=0.3, edgecolor=colour, linestyle="--", label=label))
        open_marker = dict(ms=5, markerfacecolor="white", markeredgecolor="#555555")
        label = f"open: hop-cycle Holm p >= {alpha:g} vs {design_label(baseline)} (descriptive)"
        handles.append(Line2D([], [], ls="none", marker="o", label=label, **open_marker))
    return handles
