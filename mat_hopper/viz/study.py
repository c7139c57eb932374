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


def pareto_figure(frame: pd.DataFrame, front: pd.DataFrame, base: dict, title: str) -> Figure:
    """Power against tracking error of every complete trial (feasible,
    infeasible), the Pareto front, the paper's designs (gold stars) and
    baseline runs made outside the study (white stars)."""
    fig = Figure(figsize=(6.4, 4.8), layout="constrained")
    ax = fig.subplots()
    done = frame[frame["state"] == "COMPLETE"] if not frame.empty else frame
    ok = _feasible_complete(frame)
    bad = done[~done["feasible"].astype(bool)] if not done.empty else done
    shown = pd.concat([ok, done[done["paper_design"] != ""]]) if not done.empty else done
    if not ok.empty:
        ax.scatter(ok["tracking_error_m"], ok["power_w"], s=14, c="tab:blue", alpha=0.6, label=f"feasible ({len(ok)})")
    if not bad.empty:
        ax.scatter(
            bad["tracking_error_m"],
            bad["power_w"],
            s=14,
            c="0.6",
            marker="x",
            alpha=0.6,
            label=f"infeasible ({len(bad)})",
        )
    if not front.empty:
        ax.plot(
            front["tracking_error_m"],
            front["power_w"],
            "-o",
            c="tab:red",
            ms=5,
            drawstyle="steps-post",
            label=f"Pareto front ({len(front)})",
        )
    for _, r in done[done["paper_design"] != ""].iterrows() if not done.empty else ():
        ax.scatter([r["tracking_error_m"]], [r["power_w"]], marker="*", s=160, c="gold", edgecolors="k", zorder=5)
        ax.annotate(
            r["paper_design"] + ("" if r["feasible"] else " (infeasible)"),
            (r["tracking_error_m"], r["power_w"]),
            textcoords="offset points",
            xytext=(6, 6),
            fontsize=8,
        )
    for name, (te, pw) in base.items():
        if done.empty or name not in set(done["paper_design"]):
            ax.scatter([te], [pw], marker="*", s=160, c="white", edgecolors="k", zorder=5)
            ax.annotate(f"{name} (baseline run)", (te, pw), textcoords="offset points", xytext=(6, 6), fontsize=8)
            shown = pd.concat([shown, pd.DataFrame({"tracking_error_m": [te], "power_w": [pw]})])
    if len(shown):
        for col, setter in (("tracking_error_m", ax.set_xlim), ("power_w", ax.set_ylim)):
            lo, hi = float(shown[col].min()), float(shown[col].max())
            pad = 0.08 * (hi - lo) if hi > lo else 0.1 * abs(hi) + 1e-12
            setter(lo - pad, hi + pad)
    ax.set_xlabel("tracking error (m, mean over hop cycles)")
    ax.set_ylabel("hip power (W, mean over hop cycles)")
    ax.set_title(title, fontsize=10)
    ax.legend(fontsize=8, loc="best")
    return fig


def _optuna_axes_figure(ax) -> Figure:
    """The Figure of an Axes made by optuna.visualization.matplotlib (which
    draws through pyplot), detached from pyplot so it does not pile up."""
    import matplotlib.pyplot as plt

    fig = ax.figure
    plt.close(fig)
    return fig


def hypervolume_figure(study, reference_point, title: str) -> Figure:
    """Hypervolume of the feasible front after each trial (Optuna's plot),
    against `reference_point` (both objectives minimized)."""
    from optuna.visualization.matplotlib import plot_hypervolume_history

    if not reference_point:  # no feasible trial yet: an empty plot with the title
        fig = Figure(figsize=(6.4, 3.6), layout="constrained")
        ax = fig.subplots()
        ax.set_xlabel("trial")
        ax.set_ylabel("hypervolume (m W)")
        ax.set_title(title, fontsize=10)
        return fig
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # ExperimentalWarning
        ax = plot_hypervolume_history(study, list(reference_point))
    ax.set_ylabel("hypervolume (m W)")
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


def importances_figure(study, title: str) -> Figure:
    """Optuna's parameter importances (PED-ANOVA), every objective in one
    plot (an empty plot with the title, and a note, until the sampler has
    chosen enough trials: :func:`mat_hopper.optimize.report.enough_for_importances`)."""
    from optuna.visualization.matplotlib import plot_param_importances

    from ..optimize.report import MIN_SAMPLED_TRIALS, enough_for_importances

    if enough_for_importances(study):
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
        f"no importances: fewer than {MIN_SAMPLED_TRIALS} finished trials chosen by the sampler\n"
        "(the enqueued paper designs are not samples)",
        ha="center",
        va="center",
        transform=ax.transAxes,
        fontsize=9,
    )
    return fig
