"""The book's figures, from tidy result tables.

Every ``figure_*`` / ``*_figure`` function takes tables (or, for the time
series, :class:`~mat_hopper.core.rollout.Rollout` objects), returns a
:class:`matplotlib.figure.Figure` and reads no file; :func:`save_figure`
writes one as PNG and SVG, atomically. Figures are built on
``matplotlib.figure.Figure`` directly (no pyplot state), so making many of
them leaks nothing; Jupyter shows a returned figure as usual.

- :func:`figure4_mono`: Fig. 4 A-C, box plots of power, jerk and tracking
  error per behaviour and design, a star where a design differs from MD
  (Holm-adjusted p < alpha; see :mod:`mat_hopper.analysis.stats`).
- :func:`figure4_sweeps` (:mod:`~mat_hopper.viz.sweeps`): Fig. 4 D-E,
  tracking error against density and against modulus, one line per base
  material.
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

from pathlib import Path

import pandas as pd
from matplotlib import rc_context
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Patch

from ..analysis import stats as _stats
from ..core.behaviours import order_behaviours
from ..core.materials import CONVENTIONS, order_designs
from ._boxes import grouped_boxes as _grouped_boxes
from .maps import ashby_figure, stability_figure
from .style import (
    BEHAVIOUR_LABELS,
    DPI,
    STYLE,
    _new_figure,
    _panel_label,
    _require,
    design_colour,
    design_label,
    metric_scale,
    plain_log_ticks,
    save_figure,
)
from .sweeps import SWEEP_PROPERTIES, figure4_sweeps  # noqa: F401 (re-exported)


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
    handles = [
        Patch(facecolor=design_colour(d, i), edgecolor="#333333", linewidth=0.6, label=design_label(d))
        for i, d in enumerate(designs)
    ]
    if note:
        handles.append(Line2D([], [], linestyle="none", marker="$*$", markersize=7, color="black", label=note))
    if points:
        handles.append(
            Line2D(
                [],
                [],
                linestyle="none",
                marker="o",
                markersize=3,
                color="black",
                label="replicate means (boxes: their hop cycles)",
            )
        )
    if dropped:
        handles.append(Line2D([], [], linestyle="none", marker="x", markersize=5, color="#555555", label=dropped))
    n = len(designs)
    if fig.get_figwidth() < 10.0 and len(handles) > n:  # inches: too narrow for one row
        fig.legend(handles=handles[:n], loc="outside upper center", ncols=n, handlelength=1.2, columnspacing=1.2)
        fig.legend(
            handles=handles[n:], loc="outside lower center", ncols=len(handles) - n, handlelength=1.2, columnspacing=1.2
        )
    else:
        fig.legend(handles=handles, loc="outside upper center", ncols=len(handles), handlelength=1.2, columnspacing=1.2)


def _basis_note(comparison, baseline: str, alpha: float) -> str:
    basis = (
        comparison["basis"].iloc[0] if comparison is not None and len(comparison) and "basis" in comparison else "hops"
    )
    what = "hop cycles: descriptive, they are not independent samples" if basis == "hops" else "replicate means"
    return f"Holm p < {alpha:g} vs {design_label(baseline)} (Mann-Whitney U, {what})"


def _drawn(table: pd.DataFrame, comparison: pd.DataFrame | None):
    """What the boxes show: the unperturbed run's hop cycles (basis hops),
    or the perturbed replicates' cycles with their means (basis replicates)."""
    basis = (
        comparison["basis"].iloc[0] if comparison is not None and len(comparison) and "basis" in comparison else "hops"
    )
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


def figure4_mono(
    hops: pd.DataFrame,
    comparison: pd.DataFrame | None = None,
    *,
    metrics=("power_w", "jerk_m_s3", "tracking_error_m"),
    designs=None,
    behaviours=None,
    baseline: str = "MD",
    basis: str = "hops",
    alpha: float = 0.05,
    log_metrics=("jerk_m_s3",),
    runs: pd.DataFrame | None = None,
) -> Figure:
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
    out (:func:`mat_hopper.analysis.stats.drop_unusable`).

    Args:
        hops: per-hop table with columns ``design``, ``behaviour`` and every
            metric (optionally ``replicate``, ``experiment``).
        comparison: design comparison table (columns ``metric``, ``design``,
            ``behaviour``, ``significant``, optionally ``basis``); None:
            computed here when `baseline` is among the drawn designs.
        metrics: the metric columns, one panel each, in order.
        designs: the designs drawn, in the paper's order; None: those of MD,
            PVC, Al, Ti, SS present in `hops` or among the unusable runs.
        behaviours: the behaviours on x; None: those in `hops`.
        baseline: the design the stars compare against.
        basis: ``"hops"``, ``"replicates"`` or ``"auto"``, passed to
            :func:`mat_hopper.analysis.stats.compare_designs` when the
            comparison is computed here.
        alpha: significance level of the Holm-adjusted p.
        log_metrics: the metrics drawn on a log axis.
        runs: run summaries; None: no run is left out.

    Returns:
        The ``matplotlib.figure.Figure`` (one panel per metric).

    Raises:
        ValueError: `hops` lacks a required column, has no rows for the
            requested designs and behaviours, or (when the comparison is
            computed here) `basis` is not one of the accepted values.
    """
    _require(hops, ("design", "behaviour", *metrics), "figure4_mono")
    bad = _stats.unusable_runs(runs)
    designs = order_designs(
        designs or [d for d in ("MD", "PVC", "Al", "Ti", "SS") if d in set(hops["design"]) | set(bad["design"])]
    )
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
        panel_in = 4.0 if len(behaviours) >= 3 else 2.8  # one or two behaviours: narrower panels
        fig = _new_figure(panel_in * len(metrics), 3.4)
        axes = fig.subplots(1, len(metrics), squeeze=False)[0]
        for i, (ax, m) in enumerate(zip(axes, metrics)):
            factor, ylabel = metric_scale(m, drawn[m])
            if m in log_metrics:
                ax.set_yscale("log")
            _grouped_boxes(ax, drawn, m, behaviours, designs, factor=factor, stars=_stars(comparison, m), points=means)
            if m in log_metrics:
                plain_log_ticks(ax.yaxis)
            ax.set_ylabel(ylabel)
            _panel_label(ax, "ABCDEFGH"[i])
        _legend_designs(
            fig,
            [d for d in designs if d in set(drawn["design"])],
            _basis_note(comparison, baseline, alpha) if comparison is not None else None,
            points=means is not None,
            dropped=dropped,
        )
    return fig


def figure5_gradients(
    hops: pd.DataFrame,
    comparison: pd.DataFrame | None = None,
    *,
    panels=(("MD", "SS", "rho-inc", "rho-dec"), ("MD", "SS", "PVC-Ti-SS", "SS-Ti-PVC")),
    metrics=("power_w", "jerk_m_s3", "tracking_error_m"),
    behaviours=None,
    baseline: str = "MD",
    basis: str = "hops",
    alpha: float = 0.05,
    log_metrics=("jerk_m_s3",),
    runs: pd.DataFrame | None = None,
) -> Figure:
    """Fig. 5 A-B: columns A (density gradients) and B (material gradients)
    beside MD and SS; one row per metric; stars vs `baseline`.

    hops: per-hop table holding the gradients (experiment 3) and MD and SS
    (experiment 1); each design is taken from one experiment and all are
    compared as one family. runs: as in :func:`figure4_mono`.

    Args:
        hops: per-hop table with columns ``design``, ``behaviour`` and every
            metric (optionally ``replicate``, ``experiment``).
        comparison: design comparison table, as for :func:`figure4_mono`;
            None: computed here when `baseline` is among the designs.
        panels: one tuple of design names per column (panel A, B, ...);
            designs absent from `hops` are skipped.
        metrics: the metric columns, one row of panels each.
        behaviours: the behaviours on x; None: those in `hops`.
        baseline: the design the stars compare against.
        basis: ``"hops"``, ``"replicates"`` or ``"auto"``, as for
            :func:`figure4_mono`.
        alpha: significance level of the Holm-adjusted p.
        log_metrics: the metrics drawn on a log axis.
        runs: run summaries; None: no run is left out.

    Returns:
        The ``matplotlib.figure.Figure`` (metrics x panels).

    Raises:
        ValueError: `hops` lacks a required column, has no rows for the
            panels' designs and the behaviours, or (when the comparison is
            computed here) `basis` is not one of the accepted values.
    """
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
                _grouped_boxes(
                    ax, drawn, m, behaviours, designs, factor=factor, stars=_stars(comparison, m), points=means
                )
                if m in log_metrics:
                    plain_log_ticks(ax.yaxis)
                if j == 0:
                    ax.set_ylabel(ylabel)
                if i == 0:
                    ax.set_title(
                        " / ".join(design_label(d) for d in panel if d not in ("MD", "SS")) + " beside MD and SS"
                    )
                    _panel_label(ax, "ABCDEFGH"[j])
                if i < len(metrics) - 1:
                    ax.tick_params(labelbottom=False)
        _legend_designs(
            fig,
            [d for d in all_designs if d in present],
            _basis_note(comparison, baseline, alpha) if comparison is not None else None,
            points=means is not None,
            dropped=dropped,
        )
    return fig


# --- time series ------------------------------------------------------------------


def rollout_series(rollout) -> pd.DataFrame:
    """Per hop cycle of one rollout, from its start (no transient cut):
    mid-time (s) and the metrics of :func:`mat_hopper.physics.metrics.hop_table`
    (hop height m, tracking error m, hip power W, ...), one row per cycle.

    Args:
        rollout: the :class:`~mat_hopper.core.rollout.Rollout`.

    Returns:
        DataFrame: :func:`mat_hopper.physics.metrics.hop_table` at ``transient_s=0``
        plus ``t_mid_s``, the cycle's mid-time (s).

    Raises:
        ValueError: `rollout` is not a Rollout.
    """
    from ..physics.metrics import hop_table

    t = hop_table(rollout, transient_s=0.0)
    return t.assign(t_mid_s=(t["t_start_s"].astype(float) + t["t_end_s"].astype(float)) / 2)


TIMESERIES_METRICS = ("hop_height_m", "tracking_error_m", "power_w")


def figure5_timeseries(
    rollouts, *, behaviours=None, metrics=TIMESERIES_METRICS, transient_s: float | None = None
) -> Figure:
    """Fig. 5 C: hop height, tracking error and hip power against simulated
    time, one point per hop cycle (lift-off to lift-off, the metrics'
    own cycles) at its mid-time, one column per behaviour (forward, then
    ramp), one line per design. The transient (cycles not scored) is shaded.

    rollouts: iterable of :class:`~mat_hopper.core.rollout.Rollout`.

    Args:
        rollouts: the Rollouts, any designs and behaviours.
        behaviours: the behaviour columns, in the paper's order; None: those
            of the rollouts.
        metrics: :func:`mat_hopper.physics.metrics.hop_table` columns, one row of
            panels each (default :data:`TIMESERIES_METRICS`).
        transient_s: the shaded transient, s; None: the first rollout's
            ``settings.transient_s``. It only changes the shading.

    Returns:
        The ``matplotlib.figure.Figure`` (metrics x behaviours); a dotted
        vertical line marks where an unstable rollout diverged.

    Raises:
        ValueError: no rollouts.
    """
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
                    axes[i, j].plot(
                        s["t_mid_s"], s[m].astype(float) * scales[i][0], color=colour, lw=1.1, marker="o", ms=1.8
                    )
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
        handles = [
            Line2D([], [], color=design_colour(d, i), lw=1.5, marker="o", ms=2.5, label=design_label(d))
            for i, d in enumerate(designs)
        ]
        if transient > 0:
            handles.append(Patch(facecolor="#000000", alpha=0.1, label=f"transient (< {transient:g} s, not scored)"))
        fig.legend(
            handles=handles,
            loc="outside upper center",
            ncols=min(len(handles), 6),
            columnspacing=1.0,
            title="one point per hop cycle (lift-off to lift-off)",
            title_fontsize=8,
        )
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


def write_figures(
    tables: dict, out_dir, *, rollouts=None, basis: str = "auto", formats=("png", "svg"), dpi: int = DPI
) -> list[Path]:
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
    name as a suffix (``fig4_mono_axial``). Returns the paths written.

    Args:
        tables: {name: DataFrame}, the names above; others are ignored.
        out_dir: the output folder (str or path); files go to its
            ``figures/`` subfolder, made as needed.
        rollouts: Rollouts for ``fig5_timeseries``; None or empty: skipped.
        basis: ``"auto"``, ``"hops"`` or ``"replicates"`` (see above).
        formats: file formats of each figure, among ``"png"``, ``"svg"``,
            ``"pdf"``.
        dpi: resolution of raster formats, dots per inch.

    Returns:
        The paths written, one per figure and format, in writing order.

    Raises:
        ValueError: an unknown `basis` or format, or a figure function's
            own ValueError (e.g. a table without its required columns).
    """
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
        bases = {
            "hops": ["hops"],
            "replicates": ["replicates"] if reps else [],
            "auto": ["hops", "replicates"] if reps else ["hops"],
        }[basis]
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
            save(figure4_sweeps(e2, base if base is not None and len(base) else None, runs=runs), f"fig4_sweeps{sfx}")
        stab = _of_convention(get("stability"), conv)
        if stab is not None:
            save(stability_figure(stab, convention=conv), f"stability_map{sfx}")
    if rollouts:
        save(figure5_timeseries(rollouts), "fig5_timeseries")
    save(ashby_figure(), "ashby")
    return written
