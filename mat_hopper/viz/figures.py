"""The book's figures, from tidy result tables.

Every ``figure_*`` / ``*_figure`` function takes tables (or, for the time
series, :class:`~mat_hopper.sim.Rollout` objects), returns a
:class:`matplotlib.figure.Figure` and reads no file; :func:`save_figure`
writes one as PNG and SVG, atomically. Figures are built on
``matplotlib.figure.Figure`` directly (no pyplot state), so making many of
them leaks nothing; Jupyter shows a returned figure as usual.

- :func:`figure4_mono`: Fig. 4 A-C, box plots of power, jerk and tracking
  error per behaviour and design, a star where a design differs from MD
  (Holm-adjusted p < alpha; see :mod:`mat_hopper.analysis.stats`).
- :func:`figure4_sweeps`: Fig. 4 D-E, tracking error against density and
  against modulus, one line per base material.
- :func:`figure5_gradients`: Fig. 5 A-B, gradients beside MD and SS.
- :func:`figure5_timeseries`: Fig. 5 C, hop height, tracking error and hip
  power per hop cycle over simulated time.
- :func:`stability_figure`: the measured largest stable time step over
  density and modulus (log colour scale) with the analytic estimate 2 /
  omega_max as contours, and measured against analytic.
- :func:`ashby_figure`: density against modulus (log-log) of the catalogue,
  the paper's two material classes as shaded regions, and the design
  bounds.
- :func:`write_figures`: all of them from a reproduction's tables, into
  ``<out_dir>/figures/``.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pandas as pd
from matplotlib import rc_context
from matplotlib.colors import LogNorm
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Patch, Polygon, Rectangle
from matplotlib.ticker import FuncFormatter, LogLocator, NullFormatter

from ..atomic import atomic_path
from .. import reference as ref
from ..analysis import stats as _stats
from ..behaviours import BEHAVIOUR_NAMES
from ..materials import CATALOGUE, CONVENTIONS
from ..optimize._space import DENSITY_BOUNDS_G_CM3, MODULUS_BOUNDS_GPA

# --- style -------------------------------------------------------------------

STYLE = {
    "font.size": 9,
    "axes.titlesize": 10,
    "axes.labelsize": 9,
    "xtick.labelsize": 8,
    "ytick.labelsize": 8,
    "legend.fontsize": 8,
    "legend.frameon": False,
    "axes.spines.top": False,
    "axes.spines.right": False,
    "axes.grid": True,
    "axes.grid.axis": "y",
    "grid.alpha": 0.3,
    "grid.linewidth": 0.6,
    "svg.fonttype": "none",
    "svg.hashsalt": "mat-hopper",
}
DPI = 200

# Colour-blind-safe (seaborn "colorblind"), one colour per design everywhere.
DESIGN_COLOURS = {
    "MD": "#949494",
    "PVC": "#029e73",
    "Al": "#56b4e9",
    "Ti": "#cc78bc",
    "SS": "#0173b2",
    "rho-inc": "#de8f05",
    "rho-dec": "#d55e00",
    "PVC-Ti-SS": "#9467bd",
    "SS-Ti-PVC": "#8c564b",
}
_FALLBACK = ("#ece133", "#fbafe4", "#1f77b4", "#2ca02c", "#9467bd", "#17becf")
DESIGN_ORDER = tuple(DESIGN_COLOURS)
DESIGN_LABELS = {"rho-inc": "ρ-inc", "rho-dec": "ρ-dec"}
BEHAVIOUR_LABELS = {"static": "Static", "forward": "Forward", "ramp": "Ramp", "circle": "Circle"}
CLASS_COLOURS = {"metal": "#0173b2", "ceramic": "#d55e00", "polymer": "#029e73",
                 "natural": "#de8f05", "composite": "#cc78bc", "reference": "#949494"}

# metric column -> (label, SI unit, allow SI prefixes)
METRIC_INFO = {
    "power_w": ("Hip power", "W", True),
    "power_paper_w": ("Hip power, authors' formula", "W", True),
    "jerk_m_s3": ("Jerk", "m/s³", False),
    "tracking_error_m": ("Tracking error", "m", True),
    "hop_height_m": ("Hop height", "m", False),
    "energy_j": ("Energy per hop", "J", True),
}
_PREFIXES = ((1.0, ""), (1e-3, "m"), (1e-6, "µ"))

# Ashby-chart envelopes of the two material classes the paper uses (g/cm^3,
# GPa), drawn as rounded boxes in log-log space. Approximate extents read
# off Ashby's density-modulus chart (Ashby, "Materials Selection in
# Mechanical Design", 4th ed., 2011, fig. 4.3): metals 1.7-20 g/cm^3 and
# 40-400 GPa, technical ceramics 2.2-16 g/cm^3 and 100-1000 GPa; polymers
# 0.9-2 g/cm^3 and 0.2-10 GPa, natural materials 0.4-2 g/cm^3 and 0.1-30 GPa.
CLASS_REGIONS = {
    "metals and ceramics": {"density_g_cm3": (1.5, 22.0), "modulus_gpa": (30.0, 1200.0),
                            "classes": ("metal", "ceramic"), "colour": "#0173b2"},
    "polymers and natural composites": {"density_g_cm3": (0.4, 2.2), "modulus_gpa": (0.08, 30.0),
                                        "label": "polymers and\nnatural composites",
                                        "classes": ("polymer", "natural"), "colour": "#029e73"},
}
# Design bounds of the material search (paper, Fig. 2 B: about 0.9-20 g/cm^3
# and 0.1-1000 GPa): the optimizer's own (mat_hopper.optimize._space).
DESIGN_BOUNDS = {"density_g_cm3": DENSITY_BOUNDS_G_CM3, "modulus_gpa": MODULUS_BOUNDS_GPA}


def _new_figure(width_in: float, height_in: float) -> Figure:
    return Figure(figsize=(width_in, height_in), dpi=100, layout="constrained")


def design_colour(design: str, i: int = 0) -> str:
    """The design's colour (fixed for the paper's designs)."""
    return DESIGN_COLOURS.get(design, _FALLBACK[i % len(_FALLBACK)])


def design_label(design: str) -> str:
    return DESIGN_LABELS.get(design, design)


def order_designs(designs) -> list[str]:
    """Paper designs in the paper's order, then the rest as first seen."""
    seen = list(dict.fromkeys(designs))
    return [d for d in DESIGN_ORDER if d in seen] + [d for d in seen if d not in DESIGN_ORDER]


def order_behaviours(behaviours) -> list[str]:
    seen = list(dict.fromkeys(behaviours))
    return [b for b in BEHAVIOUR_NAMES if b in seen] + [b for b in seen if b not in BEHAVIOUR_NAMES]


def metric_scale(metric: str, values=None) -> tuple[float, str]:
    """(factor, axis label with unit) for a metric: values times factor are
    in the labelled unit; an SI prefix is chosen so typical values are >= 1."""
    label, unit, prefixes = METRIC_INFO.get(metric, (metric, "", False))
    factor, prefix = 1.0, ""
    if prefixes and values is not None:
        v = np.abs(np.asarray(values, dtype=float))
        v = v[np.isfinite(v) & (v > 0)]
        if len(v):
            typical = float(np.median(v))
            for f, p in _PREFIXES:
                factor, prefix = 1.0 / f, p
                if typical >= f:
                    break
    return factor, (f"{label} ({prefix}{unit})" if unit else label)


def _panel_label(ax, letter: str):
    ax.text(-0.02, 1.02, letter, transform=ax.transAxes, fontsize=12, fontweight="bold",
            ha="right", va="bottom")


def plain_log_ticks(axis) -> None:
    """Plain-number tick labels (0.5, 1, 2, 5, 10, ...) on a log axis
    (an ``ax.xaxis``, ``ax.yaxis`` or a colorbar's ``cb.ax.yaxis``); 1-2-5
    steps when the axis spans fewer than three decades."""
    lo, hi = sorted(abs(v) for v in axis.get_view_interval())
    decades = math.log10(hi / lo) if lo > 0 and hi > 0 else 10.0
    subs = (1.0, 2.0, 5.0) if decades < 3 else (1.0,)
    axis.set_major_locator(LogLocator(base=10, subs=subs))
    axis.set_major_formatter(FuncFormatter(_plain_number))
    axis.set_minor_formatter(NullFormatter())


def _plain_number(x, _pos=None) -> str:
    if x == 0 or not np.isfinite(x):
        return ""
    if 1e-3 <= abs(x) < 1e5:
        return f"{x:g}"
    return f"{x:.0e}".replace("e-0", "e-").replace("e+0", "e")


def _require(table: pd.DataFrame, columns, what: str):
    missing = [c for c in columns if c not in table.columns]
    if missing:
        raise ValueError(f"{what} needs columns {missing}; the table has {list(table.columns)}")


# --- saving --------------------------------------------------------------------


def save_figure(fig: Figure, path_stem, *, formats=("png", "svg"), dpi: int = DPI) -> list[Path]:
    """Write `fig` as ``<path_stem>.png`` and ``<path_stem>.svg`` (folders
    made as needed), each atomically: a temp file in the same folder, then
    ``os.replace``. Metadata carry no date, so the same figure gives the
    same files. Returns the paths written."""
    stem = Path(path_stem)
    if stem.suffix.lower() in (".png", ".svg", ".pdf"):
        stem = stem.with_suffix("")
    stem.parent.mkdir(parents=True, exist_ok=True)
    written = []
    for fmt in formats:
        if fmt not in ("png", "svg", "pdf"):
            raise ValueError(f"formats must be among png, svg, pdf; got {fmt!r}")
        target = stem.parent / f"{stem.name}.{fmt}"
        meta = {"Software": None} if fmt == "png" else {"Date": None} if fmt == "svg" else {"CreationDate": None}
        with atomic_path(target) as tmp, \
                rc_context({"svg.hashsalt": STYLE["svg.hashsalt"], "svg.fonttype": STYLE["svg.fonttype"]}):
            fig.savefig(tmp, format=fmt, dpi=dpi, metadata=meta)
        written.append(target)
    return written


# --- grouped box plots -----------------------------------------------------------


def _grouped_boxes(ax, table, metric, groups, designs, *, group_col="behaviour", factor=1.0,
                   stars=None, width=0.8, points=None):
    """Box plots of `metric` at x = group index, one box per design side by
    side. stars: set of (group, design) to mark; points: a table of values
    to draw as black dots over the boxes (replicate means). Returns the
    tops used."""
    n = max(len(designs), 1)
    w = width / n
    cells = {k: v.to_numpy(float) * factor for k, v in table.groupby([group_col, "design"], sort=False)[metric]}
    pts = ({k: v.to_numpy(float) * factor for k, v in points.groupby([group_col, "design"], sort=False)[metric]}
           if points is not None and len(points) else {})
    tops = []
    for di, d in enumerate(designs):
        colour = design_colour(d, di)
        data, positions, dot_x, dot_y = [], [], [], []
        for gi, g in enumerate(groups):
            v = cells.get((g, d), np.array([]))
            v = v[np.isfinite(v)]
            if len(v) == 0:
                continue
            pos = gi - width / 2 + w * (di + 0.5)
            data.append(v)
            positions.append(pos)
            top = float(v.max())
            p = pts.get((g, d), np.array([]))
            p = p[np.isfinite(p)]
            if len(p):
                dot_x.extend(pos + (np.arange(len(p)) - (len(p) - 1) / 2) * (w * 0.5 / len(p)))
                dot_y.extend(p)
                top = max(top, float(p.max()))
            tops.append(top)
            if stars and (g, d) in stars:
                ax.annotate("*", xy=(pos, top), xytext=(0, 0.5), textcoords="offset points",
                            ha="center", va="bottom", fontsize=11, fontweight="bold")
        if not data:
            continue
        ax.boxplot(data, positions=positions, widths=w * 0.8, patch_artist=True, manage_ticks=False,
                   boxprops=dict(facecolor=colour, edgecolor="#333333", linewidth=0.6),
                   medianprops=dict(color="black", linewidth=1.0),
                   whiskerprops=dict(color="#333333", linewidth=0.6),
                   capprops=dict(color="#333333", linewidth=0.6),
                   flierprops=dict(marker="o", markersize=1.5, markerfacecolor=colour,
                                   markeredgecolor="none", alpha=0.6))
        if dot_x:
            ax.plot(dot_x, dot_y, "o", ms=2.2, color="black", alpha=0.8, zorder=3, gid="replicate-means")
    ax.set_xticks(range(len(groups)))
    ax.set_xticklabels([BEHAVIOUR_LABELS.get(g, g) for g in groups])
    ax.set_xlim(-0.5, len(groups) - 0.5)
    ax.grid(False, axis="x")
    if tops:
        lo, hi = ax.get_ylim()
        ax.set_ylim(lo, hi + 0.08 * (hi - lo))
    return tops


def _stars(comparison: pd.DataFrame | None, metric: str, by: str = "behaviour") -> set:
    if comparison is None or len(comparison) == 0:
        return set()
    c = comparison[(comparison["metric"] == metric) & comparison["significant"].fillna(False).astype(bool)]
    return set(zip(c[by], c["design"]))


def _dropped_note(bad: pd.DataFrame, designs, behaviours) -> str | None:
    """'not shown: SS forward, ramp (unstable at dt=1e-4 s)' for unusable runs."""
    if bad is None or len(bad) == 0:
        return None
    b = bad[bad["design"].isin(designs) & bad["behaviour"].isin(behaviours)]
    if len(b) == 0:
        return None
    parts = []
    for d in order_designs(b["design"].unique()):
        g = b[b["design"] == d]
        why = g["why"].iloc[0].split(",")[0]
        parts.append(f"{design_label(d)} {', '.join(order_behaviours(g['behaviour'].unique()))} ({why})")
    return "not shown: " + "; ".join(parts)


def _legend_designs(fig, designs, note: str | None = None, points: bool = False, dropped: str | None = None):
    handles = [Patch(facecolor=design_colour(d, i), edgecolor="#333333", linewidth=0.6, label=design_label(d))
               for i, d in enumerate(designs)]
    if note:
        handles.append(Line2D([], [], linestyle="none", marker="$*$", markersize=7, color="black", label=note))
    if points:
        handles.append(Line2D([], [], linestyle="none", marker="o", markersize=3, color="black",
                              label="replicate means (boxes: their hop cycles)"))
    if dropped:
        handles.append(Line2D([], [], linestyle="none", marker="x", markersize=5, color="#555555", label=dropped))
    n = len(designs)
    if fig.get_figwidth() < 10.0 and len(handles) > n:     # inches: too narrow for one row
        fig.legend(handles=handles[:n], loc="outside upper center", ncols=n, handlelength=1.2, columnspacing=1.2)
        fig.legend(handles=handles[n:], loc="outside lower center", ncols=len(handles) - n, handlelength=1.2,
                   columnspacing=1.2)
    else:
        fig.legend(handles=handles, loc="outside upper center", ncols=len(handles), handlelength=1.2,
                   columnspacing=1.2)


def _basis_note(comparison, baseline: str, alpha: float) -> str:
    basis = comparison["basis"].iloc[0] if comparison is not None and len(comparison) and "basis" in comparison else "hops"
    what = "hop cycles" if basis == "hops" else "replicate means"
    return f"Holm p < {alpha:g} vs {design_label(baseline)} (Mann-Whitney U, {what})"


def _drawn(table: pd.DataFrame, comparison: pd.DataFrame | None):
    """What the boxes show: the unperturbed run's hop cycles (basis hops),
    or the perturbed replicates' cycles with their means (basis replicates)."""
    basis = comparison["basis"].iloc[0] if comparison is not None and len(comparison) and "basis" in comparison else "hops"
    if basis == "replicates" and "replicate" in table.columns:
        reps = table[table["replicate"] != _stats.UNPERTURBED]
        return reps, _stats.replicate_means(reps)
    drawn = _stats.select_replicates(table, _stats.UNPERTURBED)
    return (drawn if len(drawn) else table), None


def _one_experiment(hops: pd.DataFrame, designs, behaviours) -> pd.DataFrame:
    """The rows of the given designs and behaviours, each design taken from
    the first experiment (sorted) that has it, with the experiment column
    merged so that all of them form one comparison family."""
    t = hops[hops["design"].isin(designs) & hops["behaviour"].isin(behaviours)]
    if "experiment" in t.columns and len(t):
        t = _stats.combine_experiments(t)
    return t


def figure4_mono(hops: pd.DataFrame, comparison: pd.DataFrame | None = None, *,
                 metrics=("power_w", "jerk_m_s3", "tracking_error_m"), designs=None, behaviours=None,
                 baseline: str = "MD", basis: str = "hops", alpha: float = 0.05,
                 log_metrics=("jerk_m_s3",), runs: pd.DataFrame | None = None) -> Figure:
    """Fig. 4 A-C: one box plot panel per metric, behaviours on x, one box
    per design, a star where the design differs from `baseline`.

    hops: per-hop table (design, behaviour, the metrics; replicate, if any,
    -1 = unperturbed). Basis hops: the boxes show the unperturbed run's
    cycles; basis replicates: the perturbed replicates' cycles, with each
    replicate's mean as a dot.
    comparison: from :func:`mat_hopper.analysis.stats.compare_designs`; computed
    here on `basis` when not given. designs default: MD PVC Al Ti SS that
    are present; log_metrics: metrics drawn on a log axis; runs: the run
    summaries: hop cycles of runs that diverged, fell or failed are left
    out (:func:`mat_hopper.analysis.stats.drop_unusable`)."""
    _require(hops, ("design", "behaviour", *metrics), "figure4_mono")
    bad = _stats.unusable_runs(runs)
    designs = order_designs(designs or [d for d in ("MD", "PVC", "Al", "Ti", "SS")
                                        if d in set(hops["design"]) | set(bad["design"])])
    behaviours = order_behaviours(behaviours or hops["behaviour"].unique())
    dropped = _dropped_note(bad, designs, behaviours)
    hops = _stats.drop_unusable(hops, bad)
    table = _one_experiment(hops, designs, behaviours)
    if len(table) == 0:
        raise ValueError("figure4_mono: no rows for the requested designs and behaviours")
    if comparison is None and baseline in set(table["design"]):
        comparison = _stats.compare_designs(table, baseline, basis=basis, metrics=metrics, alpha=alpha)
    drawn, means = _drawn(table, comparison)
    with rc_context(STYLE):
        panel_in = 4.0 if len(behaviours) >= 3 else 2.8     # one or two behaviours: narrower panels
        fig = _new_figure(panel_in * len(metrics), 3.4)
        axes = fig.subplots(1, len(metrics), squeeze=False)[0]
        for i, (ax, m) in enumerate(zip(axes, metrics)):
            factor, ylabel = metric_scale(m, drawn[m])
            if m in log_metrics:
                ax.set_yscale("log")
            _grouped_boxes(ax, drawn, m, behaviours, designs, factor=factor, stars=_stars(comparison, m),
                           points=means)
            if m in log_metrics:
                plain_log_ticks(ax.yaxis)
            ax.set_ylabel(ylabel)
            _panel_label(ax, "ABCDEFGH"[i])
        _legend_designs(fig, [d for d in designs if d in set(drawn["design"])],
                        _basis_note(comparison, baseline, alpha) if comparison is not None else None,
                        points=means is not None, dropped=dropped)
    return fig


def figure5_gradients(hops: pd.DataFrame, comparison: pd.DataFrame | None = None, *,
                      panels=(("MD", "SS", "rho-inc", "rho-dec"), ("MD", "SS", "PVC-Ti-SS", "SS-Ti-PVC")),
                      metrics=("power_w", "jerk_m_s3", "tracking_error_m"), behaviours=None,
                      baseline: str = "MD", basis: str = "hops", alpha: float = 0.05,
                      log_metrics=("jerk_m_s3",), runs: pd.DataFrame | None = None) -> Figure:
    """Fig. 5 A-B: columns A (density gradients) and B (material gradients)
    beside MD and SS; one row per metric; stars vs `baseline`.

    hops: per-hop table holding the gradients (experiment 3) and MD and SS
    (experiment 1); each design is taken from one experiment and all are
    compared as one family. runs: as in :func:`figure4_mono`."""
    _require(hops, ("design", "behaviour", *metrics), "figure5_gradients")
    all_designs = order_designs([d for p in panels for d in p])
    behaviours = order_behaviours(behaviours or hops["behaviour"].unique())
    bad = _stats.unusable_runs(runs)
    dropped = _dropped_note(bad, all_designs, behaviours)
    hops = _stats.drop_unusable(hops, bad)
    table = _one_experiment(hops, all_designs, behaviours)
    if len(table) == 0:
        raise ValueError("figure5_gradients: no rows for the requested designs and behaviours")
    if comparison is None and baseline in set(table["design"]):
        comparison = _stats.compare_designs(table, baseline, basis=basis, metrics=metrics, alpha=alpha)
    drawn, means = _drawn(table, comparison)
    present = set(drawn["design"])
    with rc_context(STYLE):
        fig = _new_figure(5.2 * len(panels), 2.5 * len(metrics) + 0.4)
        axes = fig.subplots(len(metrics), len(panels), squeeze=False, sharey="row")
        for j, panel in enumerate(panels):
            designs = [d for d in panel if d in present]
            for i, m in enumerate(metrics):
                ax = axes[i, j]
                factor, ylabel = metric_scale(m, drawn[m])
                if m in log_metrics:
                    ax.set_yscale("log")
                _grouped_boxes(ax, drawn, m, behaviours, designs, factor=factor, stars=_stars(comparison, m),
                           points=means)
                if m in log_metrics:
                    plain_log_ticks(ax.yaxis)
                if j == 0:
                    ax.set_ylabel(ylabel)
                if i == 0:
                    ax.set_title(" / ".join(design_label(d) for d in panel if d not in ("MD", "SS"))
                                 + " beside MD and SS")
                    _panel_label(ax, "ABCDEFGH"[j])
                if i < len(metrics) - 1:
                    ax.tick_params(labelbottom=False)
        _legend_designs(fig, [d for d in all_designs if d in present],
                        _basis_note(comparison, baseline, alpha) if comparison is not None else None,
                        points=means is not None, dropped=dropped)
    return fig


# --- sweeps ---------------------------------------------------------------------

SWEEP_PROPERTIES = {"density": ("density_g_cm3", "Density (g/cm³)"), "modulus": ("modulus_gpa", "Modulus (GPa)")}


def figure4_sweeps(hops: pd.DataFrame, baseline_hops: pd.DataFrame | None = None, *,
                   metric: str = "tracking_error_m", baseline: str = "MD", alpha: float = 0.05,
                   runs: pd.DataFrame | None = None) -> Figure:
    """Fig. 4 D-E: `metric` against density (D) and against modulus (E),
    one line per base material: mean over hop cycles with the interquartile
    range as bars; the base material's own point has a black edge.

    hops: experiment 2's per-hop table (sweep_base, sweep_property,
    density_g_cm3, modulus_gpa, the metric). baseline_hops: the baseline
    design's forward-hopping cycles (experiment 1): drawn as a dashed line
    with its IQR band, and each sweep point is then tested against it
    (Mann-Whitney U on hop cycles, Holm over all points): filled markers
    differ significantly, open ones do not. runs: the run summaries of
    experiment 2: points whose run diverged, fell or failed are left out of
    the lines and marked with a cross on the axis."""
    _require(hops, ("sweep_base", "sweep_property", "density_g_cm3", "modulus_gpa", metric), "figure4_sweeps")
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
    table = table.assign(_point=table[keys].astype(str).agg("|".join, axis=1),
                         **{c: pd.to_numeric(table[c], errors="coerce") for c in (metric, "density_g_cm3", "modulus_gpa")})
    significant = None
    base = None
    if baseline_hops is not None and len(baseline_hops):
        base = _stats.select_replicates(baseline_hops[baseline_hops["design"] == baseline], _stats.UNPERTURBED)
        if "behaviour" in base.columns and "behaviour" in table.columns:
            base = base[base["behaviour"].isin(set(table["behaviour"]))]
        if len(base):
            joint = pd.concat([table.assign(design=table["_point"])[["design", metric]].assign(behaviour="sweep"),
                               base.assign(design="__baseline__")[["design", metric]].assign(behaviour="sweep")],
                              ignore_index=True)
            from ..metrics import compare
            cmp = compare(joint, "__baseline__", by="behaviour", metrics=(metric,), alpha=alpha)
            significant = set(cmp.loc[cmp["significant"].astype(bool), "design"])
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
                if len(s) == 0:
                    continue
                colour = design_colour(b, i)
                g = s.groupby(["_point", col], sort=False)[metric]
                pts = pd.DataFrame({"mean": g.mean(), "q1": g.quantile(0.25), "q3": g.quantile(0.75)}).reset_index()
                pts = pts.sort_values(col)
                x = pts[col].to_numpy(float)
                y = pts["mean"].to_numpy(float) * factor
                yerr = np.vstack([y - pts["q1"].to_numpy(float) * factor, pts["q3"].to_numpy(float) * factor - y])
                ax.errorbar(x, y, yerr=np.clip(yerr, 0, None), color=colour, lw=1.2, capsize=2, elinewidth=0.8,
                            marker="none", label=b, zorder=2)
                nominal = ref.MONO_MATERIALS.get(b, (None, None))
                for xi, yi, pt in zip(x, y, pts["_point"]):
                    filled = significant is None or pt in significant
                    ax.plot(xi, yi, "o", ms=5, color=colour, zorder=3,
                            markerfacecolor=colour if filled else "white", markeredgewidth=1.0,
                            markeredgecolor=colour)
                nom = s[(np.isclose(s["density_g_cm3"], nominal[0] or -1)) & (np.isclose(s["modulus_gpa"], nominal[1] or -1))]
                if len(nom):
                    ax.plot(float(nom[col].iloc[0]), float(nom[metric].mean()) * factor, "o", ms=10,
                            markerfacecolor="none", markeredgecolor="black", markeredgewidth=1.2, zorder=4)
            lost = bad[bad["sweep_property"] == prop] if len(bad) else bad
            for _, row in lost.iterrows():
                bi = bases.index(row["sweep_base"]) if row["sweep_base"] in bases else 0
                ax.plot(float(row[col]), 0.03 + 0.05 * bi, marker="x", ms=6, mew=1.6, color=design_colour(row["sweep_base"], bi),
                        clip_on=False, zorder=5, transform=ax.get_xaxis_transform())
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
        handles = [Line2D([], [], color=design_colour(b, i), marker="o", lw=1.2, label=b) for i, b in enumerate(bases)]
        handles.append(Line2D([], [], ls="none", marker="o", ms=10, markerfacecolor="none", markeredgecolor="black",
                              markeredgewidth=1.2, label="base material"))
        if len(bad):
            why = "diverged" if bad["why"].str.startswith("unstable").all() else "diverged, fell or failed"
            handles.append(Line2D([], [], ls="none", marker="x", ms=7, mew=1.6, color="#555555",
                                  label=f"run {why}"))
        if base is not None and len(base):
            handles.append(Patch(facecolor=design_colour(baseline), alpha=0.3, edgecolor=design_colour(baseline),
                                 linestyle="--", label=f"{design_label(baseline)} mean, IQR"))
            handles.append(Line2D([], [], ls="none", marker="o", ms=5, markerfacecolor="white",
                                  markeredgecolor="#555555", label=f"open: not significant vs {design_label(baseline)}"))
        fig.legend(handles=handles, loc="outside upper center", ncols=min(len(handles), 5), columnspacing=1.0)
    return fig


# --- time series ------------------------------------------------------------------


def rollout_series(rollout) -> pd.DataFrame:
    """Per hop cycle of one rollout, from its start (no transient cut):
    mid-time (s) and the metrics of :func:`mat_hopper.metrics.hop_table`
    (hop height m, tracking error m, hip power W, ...), one row per cycle."""
    from ..metrics import hop_table
    t = hop_table(rollout, transient_s=0.0)
    return t.assign(t_mid_s=(t["t_start_s"].astype(float) + t["t_end_s"].astype(float)) / 2)


TIMESERIES_METRICS = ("hop_height_m", "tracking_error_m", "power_w")


def figure5_timeseries(rollouts, *, behaviours=None, metrics=TIMESERIES_METRICS,
                       transient_s: float | None = None) -> Figure:
    """Fig. 5 C: hop height, tracking error and hip power against simulated
    time, one point per hop cycle (lift-off to lift-off, the metrics'
    own cycles) at its mid-time, one column per behaviour (forward, then
    ramp), one line per design. The transient (cycles not scored) is shaded.

    rollouts: iterable of :class:`~mat_hopper.sim.Rollout`."""
    rollouts = list(rollouts)
    if not rollouts:
        raise ValueError("figure5_timeseries needs at least one Rollout")
    behaviours = order_behaviours(behaviours or [r.behaviour.name for r in rollouts])
    designs = order_designs([r.design.name for r in rollouts])
    series = [(r, rollout_series(r)) for r in rollouts]
    allrows = pd.concat([s for _, s in series if len(s)], ignore_index=True) if any(len(s) for _, s in series) else None
    scales = [metric_scale(m, None if allrows is None else allrows[m]) for m in metrics]
    transient = rollouts[0].settings.transient_s if transient_s is None else float(transient_s)
    with rc_context(STYLE):
        fig = _new_figure(4.6 * len(behaviours), 2.1 * len(metrics) + 0.6)
        axes = fig.subplots(len(metrics), len(behaviours), squeeze=False, sharex="col", sharey="row")
        for j, b in enumerate(behaviours):
            for r, s in series:
                if r.behaviour.name != b or len(s) == 0:
                    continue
                di = designs.index(r.design.name)
                colour = design_colour(r.design.name, di)
                for i, m in enumerate(metrics):
                    axes[i, j].plot(s["t_mid_s"], s[m].astype(float) * scales[i][0], color=colour, lw=1.1,
                                    marker="o", ms=1.8)
                if not r.stable:
                    axes[0, j].axvline(r.diverged_at_s, color=colour, ls=":", lw=1.0)
            for i in range(len(metrics)):
                ax = axes[i, j]
                if transient > 0:
                    ax.axvspan(0, transient, color="#000000", alpha=0.06, lw=0)
                if j == 0:
                    ax.set_ylabel(scales[i][1])
                ax.grid(True, axis="x", alpha=0.3)
            axes[0, j].set_title(f"{BEHAVIOUR_LABELS.get(b, b)} hopping")
            axes[-1, j].set_xlabel("Simulated time (s)")
            axes[0, j].set_xlim(left=0)
        _panel_label(axes[0, 0], "C")
        handles = [Line2D([], [], color=design_colour(d, i), lw=1.5, marker="o", ms=2.5, label=design_label(d))
                   for i, d in enumerate(designs)]
        if transient > 0:
            handles.append(Patch(facecolor="#000000", alpha=0.1, label=f"transient (< {transient:g} s, not scored)"))
        fig.legend(handles=handles, loc="outside upper center", ncols=min(len(handles), 6), columnspacing=1.0,
                   title="one point per hop cycle (lift-off to lift-off)", title_fontsize=8)
    return fig


# --- stability ---------------------------------------------------------------------


def _edges(centres: np.ndarray) -> np.ndarray:
    """Cell edges (geometric midpoints) around log-spaced centres."""
    c = np.log(np.asarray(centres, dtype=float))
    if len(c) == 1:
        return np.exp(np.array([c[0] - 0.1, c[0] + 0.1]))
    mid = (c[1:] + c[:-1]) / 2
    return np.exp(np.concatenate([[c[0] - (mid[0] - c[0])], mid, [c[-1] + (c[-1] - mid[-1])]]))


MEASURED_COLUMNS = ("max_stable_timestep_s", "dt_stable_s", "spec_timestep_s", "dt_spec_s")
ANALYTIC_COLUMNS = ("analytic_timestep_s", "dt_estimate_s")
ANALYTIC_LABELS = {"analytic_timestep_s": "2/ω_max", "dt_estimate_s": "2/ω_max",
                   "combined_timestep_s": "min(2/ω_max, controller limit)"}


def stability_figure(stab: pd.DataFrame, *, materials=("PVC", "Al", "Ti", "SS"), convention: str | None = None,
                     measured: str | None = None, analytic: str | None = None) -> Figure:
    """The largest stable time step (s) over density and modulus, measured
    (heat map, log colour scale; hatched: no tried step was stable) with
    the analytic estimate 2 / omega_max as labelled contours (left), and
    measured against analytic (right, log-log, the line y = x).

    stab: one row per grid point: density_g_cm3, modulus_gpa, a measured
    step (`measured`, default the first present of
    :data:`MEASURED_COLUMNS`: max_stable_timestep_s, the bisection of
    :mod:`mat_hopper.stability`; pass ``measured="spec_timestep_s"`` for
    the spec's 20-step scan) and the estimate (`analytic`, default
    analytic_timestep_s; ``analytic="combined_timestep_s"`` adds the
    controller limit); materials: catalogue names
    marked on the map; convention: keep the rows of this convention (when
    the table has a convention column) and name it in the title."""
    if "convention" in stab.columns:
        convs = sorted(stab["convention"].dropna().unique())
        if convention is not None:
            stab = stab[stab["convention"] == convention]
        elif len(convs) > 1:
            raise ValueError(f"stability_figure: the table holds conventions {convs}; pass convention=")
        elif convs:
            convention = convs[0]
    measured = measured or next((c for c in MEASURED_COLUMNS if c in stab.columns), MEASURED_COLUMNS[0])
    analytic = analytic or next((c for c in ANALYTIC_COLUMNS if c in stab.columns), ANALYTIC_COLUMNS[0])
    _require(stab, ("density_g_cm3", "modulus_gpa", measured, analytic), "stability_figure")
    an_label = ANALYTIC_LABELS.get(analytic, "")
    stab = stab.rename(columns={measured: "_measured", analytic: "_analytic"})[
        ["density_g_cm3", "modulus_gpa", "_measured", "_analytic"]].rename(
        columns={"_measured": "max_stable_timestep_s", "_analytic": "analytic_timestep_s"})
    stab = stab.apply(pd.to_numeric, errors="coerce")
    cols = ("density_g_cm3", "modulus_gpa", "max_stable_timestep_s", "analytic_timestep_s")
    if len(stab) == 0:
        raise ValueError("stability_figure: the table is empty")
    t = stab.groupby(["modulus_gpa", "density_g_cm3"], as_index=False)[list(cols[2:])].min()
    rho = np.sort(t["density_g_cm3"].unique())
    mod = np.sort(t["modulus_gpa"].unique())
    grid = t.pivot(index="modulus_gpa", columns="density_g_cm3", values="max_stable_timestep_s").reindex(
        index=mod, columns=rho)
    present = t.assign(one=1.0).pivot(index="modulus_gpa", columns="density_g_cm3", values="one").reindex(
        index=mod, columns=rho)
    analytic = t.pivot(index="modulus_gpa", columns="density_g_cm3", values="analytic_timestep_s").reindex(
        index=mod, columns=rho)
    measured = grid.to_numpy(float)
    finite = measured[np.isfinite(measured) & (measured > 0)]
    an = analytic.to_numpy(float)
    an_ok = an[np.isfinite(an) & (an > 0)]
    vals = np.concatenate([finite, an_ok])
    vmin, vmax = (float(vals.min()), float(vals.max())) if len(vals) else (1e-5, 1e-3)
    if vmin == vmax:
        vmin, vmax = vmin / 2, vmax * 2
    norm = LogNorm(vmin=vmin, vmax=vmax)
    with rc_context({**STYLE, "axes.grid": False}):
        fig = _new_figure(10.0, 4.2)
        ax, ax2 = fig.subplots(1, 2, width_ratios=[1.35, 1.0])
        xe, ye = _edges(rho), _edges(mod)
        mesh = ax.pcolormesh(xe, ye, np.ma.masked_invalid(measured), norm=norm, cmap="viridis", shading="flat")
        unstable = np.isfinite(present.to_numpy(float)) & ~np.isfinite(measured)
        if unstable.any():
            ax.pcolormesh(xe, ye, np.ma.masked_where(~unstable, np.ones_like(measured)), cmap="Greys", vmin=0,
                          vmax=4, hatch="///", shading="flat", edgecolor="#777777", linewidth=0)
        cb = fig.colorbar(mesh, ax=ax, pad=0.02)
        cb.set_label("Largest stable time step, measured (s)" + (" (spec scan)" if "spec" in measured else ""))
        plain_log_ticks(cb.ax.yaxis)
        if len(an_ok) and len(rho) > 1 and len(mod) > 1:
            lo, hi = math.floor(math.log10(an_ok.min()) * 2) / 2, math.ceil(math.log10(an_ok.max()) * 2) / 2
            levels = 10 ** np.arange(lo, hi + 0.01, 0.5)
            levels = levels[(levels > an_ok.min()) & (levels < an_ok.max())]
            if len(levels):
                cs = ax.contour(rho, mod, np.ma.masked_invalid(an), levels=levels, colors="white",
                                linewidths=0.9, linestyles="--")
                ax.clabel(cs, fmt=lambda v: f"{v:.0e} s".replace("e-0", "e-"), fontsize=7, inline=True)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlim(xe[0], xe[-1])
        ax.set_ylim(ye[0], ye[-1])
        plain_log_ticks(ax.xaxis)
        plain_log_ticks(ax.yaxis)
        ax.set_xlabel("Density (g/cm³)")
        ax.set_ylabel("Modulus (GPa)")
        for name in materials:
            m = CATALOGUE.get(name.lower())
            if m is None or m.modulus_gpa is None:
                continue
            if not (xe[0] <= m.density_g_cm3 <= xe[-1] and ye[0] <= m.modulus_gpa <= ye[-1]):
                continue
            ax.plot(m.density_g_cm3, m.modulus_gpa, "o", ms=6, markerfacecolor="white", markeredgecolor="black")
            ax.annotate(m.name, (m.density_g_cm3, m.modulus_gpa), xytext=(5, 4), textcoords="offset points",
                        fontsize=8, color="white", fontweight="bold")
        ax.set_title("Largest stable time step" + (f", {convention} convention" if convention else ""))
        _panel_label(ax, "A")
        handles = [Line2D([], [], color="black", ls="--", lw=0.9, label=f"analytic {an_label}")]
        if unstable.any():
            handles.append(Patch(facecolor="#dddddd", hatch="///", edgecolor="#777777", label="no tried step stable"))
        ax.legend(handles=handles, loc="lower right", frameon=True, fontsize=7)

        ok = t[np.isfinite(t["max_stable_timestep_s"]) & np.isfinite(t["analytic_timestep_s"])]
        sc = ax2.scatter(ok["analytic_timestep_s"], ok["max_stable_timestep_s"], c=ok["density_g_cm3"],
                         cmap="cividis", norm=LogNorm(), s=16, edgecolor="none")
        cb2 = fig.colorbar(sc, ax=ax2, pad=0.02)
        cb2.set_label("Density (g/cm³)")
        plain_log_ticks(cb2.ax.yaxis)
        lims = [vmin / 1.5, vmax * 1.5]
        ax2.plot(lims, lims, color="black", lw=0.8, ls=":", label="measured = analytic")
        ax2.set_xscale("log")
        ax2.set_yscale("log")
        ax2.set_xlim(lims)
        ax2.set_ylim(lims)
        ax2.set_aspect("equal")
        ax2.set_xlabel(f"Analytic estimate {an_label} (s)")
        ax2.set_ylabel("Measured largest stable step (s)")
        ax2.grid(True, which="major", alpha=0.3)
        ax2.legend(loc="upper left")
        _panel_label(ax2, "B")
    return fig


# --- Ashby ---------------------------------------------------------------------------


def catalogue_table(catalogue=None) -> pd.DataFrame:
    """The material catalogue as a table: name, density_g_cm3, modulus_gpa
    (nan for rigid), material_class, source."""
    mats = (catalogue or CATALOGUE).values() if isinstance(catalogue or CATALOGUE, dict) else catalogue
    return pd.DataFrame([{"name": m.name, "density_g_cm3": m.density_g_cm3,
                          "modulus_gpa": np.nan if m.modulus_gpa is None else m.modulus_gpa,
                          "material_class": m.material_class, "source": m.source} for m in mats])


def _superellipse(x_range, y_range, n: float = 6.0, points: int = 200) -> np.ndarray:
    """Vertices of a rounded box spanning the ranges in log10 space."""
    lx, ly = np.log10(x_range), np.log10(y_range)
    cx, cy, ax_, ay = lx.mean(), ly.mean(), (lx[1] - lx[0]) / 2, (ly[1] - ly[0]) / 2
    th = np.linspace(0, 2 * np.pi, points, endpoint=False)
    c, s = np.cos(th), np.sin(th)
    x = cx + ax_ * np.sign(c) * np.abs(c) ** (2 / n)
    y = cy + ay * np.sign(s) * np.abs(s) ** (2 / n)
    return 10 ** np.column_stack([x, y])


def ashby_figure(materials: pd.DataFrame | None = None, *, regions=None, bounds=None,
                 highlight=("PVC", "Al", "Ti", "SS")) -> Figure:
    """Density (g/cm^3) against modulus (GPa), log-log: the catalogue's
    materials by class, the paper's two material classes as shaded regions
    (:data:`CLASS_REGIONS`) and the design bounds (:data:`DESIGN_BOUNDS`,
    dashed). materials: a table like :func:`catalogue_table` (the default);
    rigid materials (no modulus) are left out."""
    t = catalogue_table() if materials is None else materials
    _require(t, ("name", "density_g_cm3", "modulus_gpa", "material_class"), "ashby_figure")
    t = t[np.isfinite(t["modulus_gpa"].astype(float))]
    regions = CLASS_REGIONS if regions is None else regions
    bounds = DESIGN_BOUNDS if bounds is None else bounds
    with rc_context({**STYLE, "axes.grid": False}):
        fig = _new_figure(6.0, 4.8)
        ax = fig.subplots()
        for name, r in regions.items():
            verts = _superellipse(r["density_g_cm3"], r["modulus_gpa"])
            ax.add_patch(Polygon(verts, closed=True, facecolor=r["colour"], alpha=0.12, edgecolor=r["colour"],
                                 linewidth=1.0, zorder=0))
            ax.text(math.sqrt(r["density_g_cm3"][0] * r["density_g_cm3"][1]), r["modulus_gpa"][1] * 0.8,
                    r.get("label", name),
                    ha="center", va="top", color=r["colour"], fontsize=8.5, fontweight="bold", zorder=1)
        (r0, r1), (e0, e1) = bounds["density_g_cm3"], bounds["modulus_gpa"]
        ax.add_patch(Rectangle((r0, e0), r1 - r0, e1 - e0, fill=False, ls="--", lw=1.0, edgecolor="black", zorder=1))
        ax.text(r1 * 0.93, e0 * 1.25, "design bounds", ha="right", va="bottom", fontsize=8)
        classes = list(dict.fromkeys(t["material_class"]))
        for cls in classes:
            s = t[t["material_class"] == cls]
            colour = CLASS_COLOURS.get(cls, "#333333")
            big = s["name"].isin(highlight)
            ax.scatter(s["density_g_cm3"][~big], s["modulus_gpa"][~big], s=28, color=colour, edgecolor="white",
                       linewidth=0.6, zorder=3, label=cls)
            ax.scatter(s["density_g_cm3"][big], s["modulus_gpa"][big], s=60, color=colour, edgecolor="black",
                       linewidth=0.9, zorder=4, label=None if (~big).any() else cls)
            for _, row in s.iterrows():
                ax.annotate(row["name"], (row["density_g_cm3"], row["modulus_gpa"]), xytext=(5, -3),
                            textcoords="offset points", fontsize=7.5, zorder=5,
                            fontweight="bold" if row["name"] in highlight else "normal")
        ax.set_xscale("log")
        ax.set_yscale("log")
        xs = [*t["density_g_cm3"], r0, r1] + [v for r in regions.values() for v in r["density_g_cm3"]]
        ys = [*t["modulus_gpa"], e0, e1] + [v for r in regions.values() for v in r["modulus_gpa"]]
        ax.set_xlim(min(xs) / 1.5, max(xs) * 1.5)
        ax.set_ylim(min(ys) / 2.5, max(ys) * 2.5)
        plain_log_ticks(ax.xaxis)
        ax.yaxis.set_major_formatter(FuncFormatter(_plain_number))
        ax.set_xlabel("Density ρ (g/cm³)")
        ax.set_ylabel("Young's modulus E (GPa)")
        ax.grid(True, which="major", alpha=0.25, axis="both")
        handles, labels = ax.get_legend_handles_labels()
        handles.append(Line2D([], [], ls="none", marker="o", ms=8, markerfacecolor="white", markeredgecolor="black",
                              label="the paper's materials"))
        ax.legend(handles=handles, loc="upper left", frameon=True, fontsize=7.5, title="material class",
                  title_fontsize=8)
    return fig


# --- all figures of a reproduction -------------------------------------------------------


def _concat_tables(frames) -> pd.DataFrame | None:
    frames = [f for f in frames if f is not None and len(f)]
    return pd.concat(frames, ignore_index=True) if frames else None


def _of_convention(t: pd.DataFrame | None, convention: str) -> pd.DataFrame | None:
    if t is None or "convention" not in t.columns:
        return t if convention == "paper" else None
    t = t[t["convention"] == convention]
    return t if len(t) else None


def write_figures(tables: dict, out_dir, *, rollouts=None, basis: str = "auto", formats=("png", "svg"),
                  dpi: int = DPI) -> list[Path]:
    """Every figure the tables allow, as PNG and SVG in ``<out_dir>/figures/``.

    tables: a reproduction's tables by name (``exp1_hops``, ``exp1_runs``,
    ``exp2_hops``, ``exp2_runs``, ``exp3_hops``, ``exp3_runs``,
    ``stability``; any may be missing: its figures are skipped). Files:
    ``fig4_mono``, ``fig4_sweeps``, ``fig5_gradients`` (stars on hop
    cycles, the paper's test) and, when the runs have replicates and basis
    is ``auto`` or ``replicates``, ``fig4_mono_replicates`` and
    ``fig5_gradients_replicates`` (basis ``hops`` or ``replicates``: only
    those); ``stability_map``; ``ashby``;
    ``fig5_timeseries`` when `rollouts` (Rollout objects of forward and
    ramp hopping) are given. A convention other than ``paper`` gets its
    name as a suffix (``fig4_mono_axial``). Returns the paths written."""
    if basis not in ("auto", "hops", "replicates"):
        raise ValueError(f"basis must be one of auto, hops, replicates; got {basis!r}")
    fig_dir = Path(out_dir) / "figures"
    written: list[Path] = []

    def save(fig, stem):
        written.extend(save_figure(fig, fig_dir / stem, formats=formats, dpi=dpi))

    get = tables.get
    runs_all = _concat_tables([get("exp1_runs"), get("exp2_runs"), get("exp3_runs")])
    for conv in CONVENTIONS:
        sfx = "" if conv == "paper" else f"_{conv}"
        runs = _of_convention(runs_all, conv)
        e1, e2, e3 = (_of_convention(get(f"exp{i}_hops"), conv) for i in (1, 2, 3))
        reps = any(t is not None and _stats.has_replicates(t) for t in (e1, e3))
        bases = {"hops": ["hops"], "replicates": ["replicates"] if reps else [],
                 "auto": ["hops", "replicates"] if reps else ["hops"]}[basis]
        for b in bases:
            tail = "" if b == "hops" else "_replicates"
            if e1 is not None:
                save(figure4_mono(e1, basis=b, runs=runs), f"fig4_mono{tail}{sfx}")
            grad = _concat_tables([e1, e3])
            if e3 is not None and grad is not None:
                save(figure5_gradients(grad, basis=b, runs=runs), f"fig5_gradients{tail}{sfx}")
        if e2 is not None:
            base = _concat_tables([e1, e3])
            if base is not None:
                base = base[(base["design"] == "MD") & (base["behaviour"] == "forward")]
            save(figure4_sweeps(e2, base if base is not None and len(base) else None, runs=runs),
                 f"fig4_sweeps{sfx}")
        stab = _of_convention(get("stability"), conv)
        if stab is not None:
            save(stability_figure(stab, convention=conv), f"stability_map{sfx}")
    if rollouts:
        save(figure5_timeseries(rollouts), "fig5_timeseries")
    save(ashby_figure(), "ashby")
    return written
