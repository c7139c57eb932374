"""Plots of an optimizer study (:mod:`mat_hopper.optimize.report`).

The hypervolume history and the parameter importances are Optuna's own
(``optuna.visualization.matplotlib``). The Pareto plot is ours: Optuna's
``plot_pareto_front`` cannot mark the paper's designs, their baseline runs
made outside the study, or say which of them are infeasible.

Every function returns a ``matplotlib.figure.Figure`` and never switches
the backend; save with :func:`mat_hopper.viz.style.save_figure`.
"""

from __future__ import annotations

import warnings

import pandas as pd
from matplotlib.figure import Figure


def _feasible_complete(frame: pd.DataFrame) -> pd.DataFrame:
    if frame.empty:
        return frame
    return frame[(frame["state"] == "COMPLETE") & frame["feasible"].astype(bool)]


DEFAULT_AXES = (("tracking_error_m", "tracking error (m, mean over hop cycles)"),
                ("power_w", "hip power (W, mean over hop cycles)"))  # fmt: skip


def pareto_figure(frame: pd.DataFrame, front: pd.DataFrame, base: dict, title: str, *, axes=DEFAULT_AXES) -> Figure:
    """Every complete trial (feasible, infeasible), the Pareto front, the
    paper's designs (gold stars) and baseline runs made outside the study
    (white stars), in the objectives' plane: one panel for two objectives,
    one per pair for three (the front's projections, no staircase).

    Args:
        frame: the trials table (:func:`mat_hopper.optimize.report.trials_frame`).
        front: the Pareto table (:func:`mat_hopper.optimize.report.pareto_frame`).
        base: {name: objective values, in `axes` order} of the baselines.
        title: the figure's title.
        axes: ((column, axis label), ...) of the objectives, two or three.

    Returns:
        A matplotlib Figure.
    """
    pairs = [(0, 1)] if len(axes) == 2 else [(i, j) for i in range(len(axes)) for j in range(i + 1, len(axes))]
    fig = Figure(figsize=(6.4 if len(pairs) == 1 else 4.6 * len(pairs), 4.8), layout="constrained")
    panels = fig.subplots(1, len(pairs), squeeze=False)[0]
    for ax, (i, j) in zip(panels, pairs):
        _pareto_panel(ax, frame, front, base, axes, (i, j), staircase=len(pairs) == 1)
    if len(pairs) == 1:
        panels[0].set_title(title, fontsize=10)
    else:
        fig.suptitle(title, fontsize=10)
    return fig


def _pareto_panel(ax, frame, front, base: dict, axes, ij, staircase: bool) -> None:
    """One panel of :func:`pareto_figure`: objective ij[1] against ij[0]."""
    (x, xlabel), (y, ylabel) = axes[ij[0]], axes[ij[1]]
    done = frame[frame["state"] == "COMPLETE"] if not frame.empty else frame
    ok = _feasible_complete(frame)
    bad = done[~done["feasible"].astype(bool)] if not done.empty else done
    shown = pd.concat([ok, done[done["paper_design"] != ""]]) if not done.empty else done
    if not ok.empty:
        ax.scatter(ok[x], ok[y], s=14, c="tab:blue", alpha=0.6, label=f"feasible ({len(ok)})")
    if not bad.empty:
        ax.scatter(bad[x], bad[y], s=14, c="0.6", marker="x", alpha=0.6, label=f"infeasible ({len(bad)})")
    if not front.empty:
        f = front.sort_values(x, kind="stable")
        style = {"drawstyle": "steps-post"} if staircase else {}
        fmt = "-o" if staircase else "o"
        ax.plot(f[x], f[y], fmt, c="tab:red", ms=5, label=f"Pareto front ({len(front)})", **style)
    for _, r in done[done["paper_design"] != ""].iterrows() if not done.empty else ():
        ax.scatter([r[x]], [r[y]], marker="*", s=160, c="gold", edgecolors="k", zorder=5)
        ax.annotate(
            r["paper_design"] + ("" if r["feasible"] else " (infeasible)"),
            (r[x], r[y]),
            textcoords="offset points",
            xytext=(6, 6),
            fontsize=8,
        )
    for name, values in base.items():
        if done.empty or name not in set(done["paper_design"]):
            bx, by = values[ij[0]], values[ij[1]]
            ax.scatter([bx], [by], marker="*", s=160, c="white", edgecolors="k", zorder=5)
            ax.annotate(f"{name} (baseline run)", (bx, by), textcoords="offset points", xytext=(6, 6), fontsize=8)
            shown = pd.concat([shown, pd.DataFrame({x: [bx], y: [by]})])
    if len(shown):
        for col, setter in ((x, ax.set_xlim), (y, ax.set_ylim)):
            lo, hi = float(shown[col].min()), float(shown[col].max())
            pad = 0.08 * (hi - lo) if hi > lo else 0.1 * abs(hi) + 1e-12
            setter(lo - pad, hi + pad)
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.legend(fontsize=8, loc="best")


def _optuna_axes_figure(ax) -> Figure:
    """The Figure of an Axes made by optuna.visualization.matplotlib (which
    draws through pyplot), detached from pyplot so it does not pile up."""
    import matplotlib.pyplot as plt

    fig = ax.figure
    plt.close(fig)
    return fig


def hypervolume_figure(study, reference_point, title: str, *, unit: str = "m W") -> Figure:
    """Hypervolume of the feasible front after each trial (Optuna's plot,
    any number of objectives; every objective minimized).

    Args:
        study: an optuna.Study.
        reference_point: one value per objective (empty: no feasible trial
            yet, an empty plot).
        title: the plot's title.
        unit: the product of the objectives' units, for the axis.

    Returns:
        A matplotlib Figure.
    """
    from optuna.visualization.matplotlib import plot_hypervolume_history

    if not reference_point:  # no feasible trial yet: an empty plot with the title
        fig = Figure(figsize=(6.4, 3.6), layout="constrained")
        ax = fig.subplots()
        ax.set_xlabel("trial")
        ax.set_ylabel(f"hypervolume ({unit})")
        ax.set_title(title, fontsize=10)
        return fig
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # ExperimentalWarning
        ax = plot_hypervolume_history(study, list(reference_point))
    ax.set_ylabel(f"hypervolume ({unit})")
    ax.set_title(title, fontsize=10)
    return _optuna_axes_figure(ax)


def _margins_for_labels(fig, ax, pad_px: float = 12.0) -> None:
    """Margins measured from the drawn tick labels, x label and title, so
    that none is cut."""
    fig.draw_without_rendering()  # the figure left pyplot: its own canvas does not draw
    w, h = fig.bbox.width, fig.bbox.height
    left = max((t.get_window_extent().width for t in ax.get_yticklabels()), default=0.0) + 2 * pad_px
    below = ax.xaxis.label.get_window_extent().height + max(
        (t.get_window_extent().height for t in ax.get_xticklabels()), default=0.0
    )
    above = ax.title.get_window_extent().height + pad_px
    fig.subplots_adjust(
        left=left / w, right=1 - pad_px / w, bottom=(below + 3 * pad_px) / h, top=1 - (above + pad_px) / h
    )


def importances_figure(study, title: str, *, note: str | None = None) -> Figure:
    """Optuna's parameter importances (PED-ANOVA), every objective in one plot.

    Args:
        study: an optuna.Study.
        title: the plot's title.
        note: when given, no importances are computed: an empty plot with
            the title and this note (the report passes one until the sampler
            has chosen enough trials:
            :func:`mat_hopper.optimize.report.enough_for_importances`).

    Returns:
        A matplotlib Figure.
    """
    from optuna.visualization.matplotlib import plot_param_importances

    if note is None:
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")  # ExperimentalWarning
                ax = plot_param_importances(study)
            ax.set_title(title, fontsize=10)
            fig = _optuna_axes_figure(ax)
            # Optuna's default size cuts long parameter names (seg1_density_g_cm3) and the
            # legend: size by the rows, and let the layout make room for every label
            fig.set_size_inches(8.0, max(3.8, 1.6 + 0.32 * len(ax.get_yticklabels())))
            _margins_for_labels(fig, ax)
            return fig
        except (ValueError, RuntimeError, ZeroDivisionError):
            pass
    fig = Figure(figsize=(6.4, 3.8), layout="constrained")
    ax = fig.subplots()
    ax.set_xlabel("importance")
    ax.set_title(title, fontsize=10)
    ax.text(
        0.5,
        0.5,
        note or "no importances: Optuna could not compute them",
        ha="center",
        va="center",
        transform=ax.transAxes,
        fontsize=9,
    )
    return fig
