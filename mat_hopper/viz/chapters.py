"""Figures of single chapters of the book: the two stiffness conventions
(:func:`convention_figure`), one rollout's controller signals
(:func:`controller_figure`), the authors' code defects, measured
(:func:`defects_figure`), tracking against leg mass
(:func:`leg_mass_figure`), materials at the authors' and at their own
gains (:func:`codesign_figure`), metrics against the number of segments
(:func:`convergence_figure`) and the warp backend against the CPU
rollouts (:func:`agreement_figure`). Each returns a
``matplotlib.figure.Figure``.
"""

from __future__ import annotations

import numpy as np
import pandas as pd
from matplotlib import rc_context
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Patch

from ..core import reference as ref
from ..core.behaviours import order_behaviours
from ..core.materials import CONVENTIONS
from .style import STYLE, design_colour


def convention_figure(table: pd.DataFrame):
    """Two panels per material, both conventions side by side: the material
    spring's stiffness (N/m) and the largest stable time step (s; bar:
    measured, with its bracket; marker: the estimate 2 / w_max), log
    scales. table: from :func:`convention_stability`.

    Args:
        table: one row per design and convention (:func:`convention_stability`,
            :mod:`mat_hopper.experiments.paper`), columns ``design``,
            ``convention``, ``material_spring_n_m`` (N/m; nan for a rigid
            leg), ``analytic_timestep_s``, ``max_stable_timestep_s``,
            ``unstable_timestep_s`` (s) and, optionally,
            ``controller_timestep_s`` (s, drawn as the controller limit).

    Returns:
        The ``matplotlib.figure.Figure``.

    Raises:
        ValueError: a required column is missing (named).
    """
    need = (
        "design",
        "convention",
        "material_spring_n_m",
        "analytic_timestep_s",
        "max_stable_timestep_s",
        "unstable_timestep_s",
    )
    missing = [c for c in need if c not in table.columns]
    if missing:
        raise ValueError(f"convention_figure needs columns {missing}")
    designs = list(dict.fromkeys(table["design"]))
    convs = [c for c in CONVENTIONS if c in set(table["convention"])]
    colours = {"paper": "#0173b2", "axial": "#de8f05"}
    w = 0.8 / max(len(convs), 1)
    with rc_context(STYLE):
        fig = Figure(figsize=(9.0, 3.4), layout="constrained")
        ax_k, ax_dt = fig.subplots(1, 2)
        for ci, conv in enumerate(convs):
            sub = table[table["convention"] == conv].set_index("design").reindex(designs)
            x = np.arange(len(designs)) - 0.4 + w * (ci + 0.5)
            _draw_convention_bars(ax_k, ax_dt, sub, x, w * 0.9, colours.get(conv), conv)
        for ax in (ax_k, ax_dt):
            ax.set_yscale("log")
            ax.set_xticks(np.arange(len(designs)))
            ax.set_xticklabels(designs)
            ax.grid(False, axis="x")
        _mark_rigid(ax_k, table, designs)
        k_all = table["material_spring_n_m"].to_numpy(float)
        if np.isfinite(k_all).any():
            ax_k.set_ylim(np.nanmin(k_all) / 5, np.nanmax(k_all) * 2)
        dt_all = table[
            [c for c in ("max_stable_timestep_s", "analytic_timestep_s", "controller_timestep_s") if c in table.columns]
        ].to_numpy(float)
        if np.isfinite(dt_all).any():
            ax_dt.set_ylim(np.nanmin(dt_all) / 3, np.nanmax(dt_all) * 3)
        ax_k.set_ylabel("Material spring stiffness (N/m)")
        ax_dt.set_ylabel("Largest stable time step (s)")
        _timestep_line(ax_dt, ref.TIMESTEP_S, " paper's dt", "#555555", ":")
        if "controller_timestep_s" in table.columns and np.isfinite(table["controller_timestep_s"]).any():
            ctrl = float(np.nanmin(table["controller_timestep_s"].to_numpy(float)))
            _timestep_line(ax_dt, ctrl, " controller limit", "#d55e00", "--")
        handles = [Patch(color=colours.get(c), label=f"{c} convention") for c in convs]
        handles += [
            Line2D([], [], color="black", lw=1.0, label="measured bracket (stable to unstable)"),
            Line2D(
                [], [], ls="none", marker="D", ms=4.5, color="black", markerfacecolor="white", label="estimate 2/ω_max"
            ),
        ]
        fig.legend(handles=handles, loc="outside upper center", ncols=len(handles))
    return fig


def _draw_convention_bars(ax_k, ax_dt, sub, x, width, colour, conv) -> None:
    """One convention's bars: spring stiffness; measured step with its bracket and the estimate."""
    k = sub["material_spring_n_m"].to_numpy(float)
    ok = np.isfinite(k)
    ax_k.bar(x[ok], k[ok], width, color=colour, label=conv)
    lo = sub["max_stable_timestep_s"].to_numpy(float)
    hi = sub["unstable_timestep_s"].to_numpy(float)
    ok = np.isfinite(lo)
    ax_dt.bar(x[ok], lo[ok], width, color=colour, alpha=0.85)
    both = ok & np.isfinite(hi)
    ax_dt.vlines(x[both], lo[both], hi[both], color="black", lw=1.0)
    ax_dt.plot(
        x, sub["analytic_timestep_s"].to_numpy(float), "D", ms=4.5, color="black", markerfacecolor="white", zorder=4
    )


def _mark_rigid(ax_k, table, designs) -> None:
    """'rigid: no spring' under the designs without a material spring."""
    for i, d in enumerate(designs):
        if d in table["design"].values and table.loc[table["design"] == d, "material_spring_n_m"].isna().all():
            ax_k.text(
                i,
                0.02,
                "rigid:\nno spring",
                transform=ax_k.get_xaxis_transform(),
                ha="center",
                va="bottom",
                fontsize=7,
                color="#555555",
            )


def _timestep_line(ax, dt_s: float, label: str, colour: str, ls: str) -> None:
    """A horizontal reference step (s), named at the right edge."""
    ax.axhline(dt_s, color=colour, lw=0.8, ls=ls)
    ax.text(1.0, dt_s, label, transform=ax.get_yaxis_transform(), va="center", ha="left", fontsize=7, color=colour)


def controller_figure(rollout, window_s: tuple[float, float] | None = None):
    """The controller at work in one rollout: left, the whole run (hop
    apex heights against the 1 m target, the adaptive thrust setting F,
    tracking error); right, a short window (default: 1.5 s after the
    transient) with stance shaded: base height, thrust force on the foot
    spring, hip pitch angle against its target, base x against the
    desired x. Times are simulated seconds.

    Args:
        rollout: the :class:`~mat_hopper.core.rollout.Rollout` to show.
        window_s: (start, end) of the close-up, simulated s; None: 1.5 s
            starting at the transient (or 1.5 s before the run's end, if
            earlier, but not before 0).

    Returns:
        The ``matplotlib.figure.Figure`` (4 x 2 panels).

    Raises:
        ValueError: a rollout with fewer than 2 recorded samples, or a window
            whose end is not after its start.
    """
    from ..core.sim import C

    d = rollout.data
    if len(d) < 2:
        raise ValueError("controller_figure: the rollout recorded fewer than 2 samples")
    t = d[:, C["t"]]
    if window_s is None:
        t0 = min(rollout.settings.transient_s, max(float(t[-1]) - 1.5, 0.0))
        window_s = (t0, t0 + 1.5)
    w0, w1 = float(window_s[0]), float(window_s[1])
    if not w1 > w0:
        raise ValueError(f"window_s must be (start, end) with end > start s, got {window_s!r}")
    sel = (t >= w0) & (t <= w1)
    err = np.hypot(d[:, C["x"]] - d[:, C["x_des"]], d[:, C["y"]] - d[:, C["y_des"]])
    from ..core.controller import TOUCHDOWN

    ev = rollout.events[rollout.events[:, 1] == TOUCHDOWN]
    apex_t, apex_h = ev[:, 0], ev[:, 2]  # the controller's hop height, logged at each touchdown
    ok = np.isfinite(apex_h)
    stance = d[:, C["phase"]] > 0.5
    transient = rollout.settings.transient_s
    with rc_context(STYLE):
        fig = Figure(figsize=(10.0, 7.0), layout="constrained")
        axes = fig.subplots(4, 2, sharex="col")
        # left: whole run
        a = axes[0, 0]
        a.plot(apex_t[ok], apex_h[ok], ".", ms=3, color="#0173b2")
        a.axhline(ref.HOP_HEIGHT_TARGET, color="black", lw=0.8, ls="--")
        a.set_ylabel("Hop apex (m)")
        a.set_title(f"{rollout.design.name}, {rollout.behaviour.name} hopping: the whole run")
        axes[1, 0].plot(t, d[:, C["thrust_setting"]], color="#d55e00", lw=1.0)
        axes[1, 0].set_ylabel("Thrust setting F (N)")
        axes[2, 0].plot(t, np.degrees(d[:, C["hip_y"]]), color="#029e73", lw=0.6)
        axes[2, 0].set_ylabel("Hip pitch (deg)")
        axes[3, 0].plot(t, err * 1e3, color="#cc78bc", lw=0.8)
        axes[3, 0].set_ylabel("Tracking error (mm)")
        axes[3, 0].set_xlabel("Simulated time (s)")
        for a in axes[:, 0]:
            if transient > 0:
                a.axvspan(0, transient, color="black", alpha=0.06, lw=0)
            a.axvspan(w0, w1, color="#de8f05", alpha=0.25, lw=0)
        # right: the window
        tw = t[sel]
        axes[0, 1].plot(tw, d[sel, C["z"]], color="#0173b2", lw=1.2, label="base z")
        axes[0, 1].axhline(ref.HOP_HEIGHT_TARGET, color="black", lw=0.8, ls="--", label="target apex")
        axes[0, 1].set_ylabel("Base height (m)")
        axes[0, 1].set_title(f"{w1 - w0:g} s up close (stance shaded)")
        axes[0, 1].legend(loc="lower right")
        axes[1, 1].plot(tw, d[sel, C["force_thrust"]], color="#d55e00", lw=1.2)
        axes[1, 1].set_ylabel("Thrust force (N)")
        axes[2, 1].plot(tw, np.degrees(d[sel, C["hip_y"]]), color="#029e73", lw=1.2, label="angle")
        axes[2, 1].plot(
            tw, np.degrees(d[sel, C["hip_y_target"]]), color="black", lw=0.9, ls="--", label="flight target"
        )
        axes[2, 1].set_ylabel("Hip pitch (deg)")
        axes[2, 1].legend(loc="lower right")
        axes[3, 1].plot(tw, d[sel, C["x"]], color="#cc78bc", lw=1.2, label="base x")
        axes[3, 1].plot(tw, d[sel, C["x_des"]], color="black", lw=0.9, ls="--", label="desired x")
        axes[3, 1].set_ylabel("x (m)")
        axes[3, 1].set_xlabel("Simulated time (s)")
        axes[3, 1].legend(loc="lower right")
        st = stance[sel]
        edges = np.flatnonzero(np.diff(np.concatenate([[0], st.astype(int), [0]])))
        for a in axes[:, 1]:
            for s0, s1 in zip(edges[::2], edges[1::2]):
                a.axvspan(tw[s0], tw[min(s1, len(tw) - 1)], color="black", alpha=0.08, lw=0)
            a.set_xlim(w0, w1)
    return fig


def jerk_rate_panel(ax, jerk: dict) -> None:
    """Mean |jerk| against the record rate on `ax`, per design ({design:
    table from :func:`mat_hopper.analysis.tables.jerk_by_rate`}, log-log):
    solid, the plain finite difference of the recorded acceleration (aliased
    leg ringing, labelled as such); dashed, the book's metric (50 Hz
    low-pass at the physics rate), flat in the rate.

    Args:
        ax: the matplotlib ``Axes`` drawn on (scales, labels, title and legend
            set).
        jerk: {design name: table} with columns ``rate_hz`` and
            ``raw_jerk_m_s3`` (or ``mean_jerk_m_s3``), m/s^3,
            and optionally ``metric_jerk_m_s3`` (the dashed line).
    """
    for i, (d, t) in enumerate(jerk.items()):
        colour = design_colour(d, i)
        raw = t["raw_jerk_m_s3"] if "raw_jerk_m_s3" in t else t["mean_jerk_m_s3"]
        ax.plot(t["rate_hz"], raw, "o-", color=colour, label=f"{d}, finite difference (authors')")
        if "metric_jerk_m_s3" in t:
            ax.plot(t["rate_hz"], t["metric_jerk_m_s3"], "s--", color=colour, label=f"{d}, 50 Hz low-pass (metric)")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("Record rate (Hz)")
    ax.set_ylabel("Mean |jerk| (m/s³)")
    ax.set_title("Jerk against the record rate")
    ax.legend(fontsize="small")


def jerk_rate_figure(jerk: dict):
    """One panel: :func:`jerk_rate_panel`.

    Args:
        jerk: {design name: :func:`mat_hopper.analysis.tables.jerk_by_rate`
            table}, as for :func:`jerk_rate_panel`.

    Returns:
        The ``matplotlib.figure.Figure``.
    """
    with rc_context(STYLE):
        fig = Figure(figsize=(5.2, 3.6), layout="constrained")
        jerk_rate_panel(fig.subplots(), jerk)
    return fig


def defects_figure(clock: pd.DataFrame, power: pd.DataFrame):
    """Two of the authors' code defects, measured: (A) tracking error
    against the wall-clock factor of the desired path (table from
    :func:`clock_drift`); (B) the percent change of power of one design
    against another, real hip power beside the authors' formula (table
    from :func:`power_formula_table`). The jerk's sampling defect has a
    figure of its own, :func:`jerk_rate_figure`.

    Args:
        clock: :func:`mat_hopper.experiments.paper.clock_drift` rows, columns
            ``design``, ``clock_factor`` and ``mean_tracking_error_m`` (m, drawn
            in mm).
        power: :func:`mat_hopper.analysis.tables.power_formula_table`: one row
            per measure (bars, legend label = index), one column per behaviour
            (%); its ``columns.name`` labels the y axis.

    Returns:
        The ``matplotlib.figure.Figure`` (panels A, B).
    """
    with rc_context(STYLE):
        fig = Figure(figsize=(8.0, 3.4), layout="constrained")
        a, c = fig.subplots(1, 2)
        for i, (d, g) in enumerate(clock.groupby("design", sort=False)):
            g = g.sort_values("clock_factor")
            a.plot(g["clock_factor"], g["mean_tracking_error_m"] * 1e3, "o-", color=design_colour(d, i), label=d)
        a.set_xlabel("Wall clock / simulated clock")
        a.set_ylabel("Tracking error (mm)")
        a.set_title("Desired path on the wall clock")
        a.legend()
        behs = order_behaviours(power.columns)
        x = np.arange(len(behs))
        for i, (label, row) in enumerate(power.iterrows()):
            c.bar(x - 0.2 + 0.4 * i, row[behs].to_numpy(float), 0.38, label=label, color=("#0173b2", "#de8f05")[i % 2])
        c.axhline(0, color="black", lw=0.8)
        vals = power[behs].to_numpy(float)
        vals = vals[np.isfinite(vals)]
        if len(vals):  # head room for the legend above the bars
            lo, hi = min(0.0, float(vals.min())), max(0.0, float(vals.max()))
            c.set_ylim(lo - 0.05 * (hi - lo), hi + 0.45 * (hi - lo))
        c.set_xticks(x)
        c.set_xticklabels(behs)
        c.set_ylabel(power.columns.name or "% change")
        c.set_title("Power: real or the authors' formula")
        c.legend(loc="upper left")
        c.grid(False, axis="x")
        for ax, letter in zip((a, c), "AB"):
            ax.text(
                -0.02, 1.02, letter, transform=ax.transAxes, fontsize=12, fontweight="bold", ha="right", va="bottom"
            )
    return fig


def leg_mass_figure(table: pd.DataFrame, md_tracking_m: float | None = None):
    """Mean tracking error (mm) of every sweep point that ended upright
    against the mass of its leg's material (kg), from
    :func:`mat_hopper.analysis.tables.leg_mass_table` of experiment 2's
    runs: density sweeps filled and joined per base material, modulus
    sweeps (which leave the mass alone) hollow; `md_tracking_m`, the rigid
    MD leg's forward tracking error, as a dashed line.

    Args:
        table: :func:`mat_hopper.analysis.tables.leg_mass_table` rows, columns
            ``sweep_base``, ``sweep_property`` (``"density"`` or
            ``"modulus"``), ``sweep_value``, ``leg_mass_kg`` (kg) and
            ``mean_tracking_error_m`` (m, drawn in mm); where an ``upright``
            column is present, only its true rows are drawn.
        md_tracking_m: the MD leg's tracking error, m; None or nan: no line.

    Returns:
        The ``matplotlib.figure.Figure``.

    Raises:
        ValueError: a required column is missing (named).
    """
    need = ("sweep_base", "sweep_property", "sweep_value", "leg_mass_kg", "mean_tracking_error_m")
    missing = [c for c in need if c not in table.columns]
    if missing:
        raise ValueError(f"leg_mass_figure needs columns {missing}")
    t = table[table["upright"].astype(bool)] if "upright" in table.columns else table
    with rc_context(STYLE):
        fig = Figure(figsize=(6.4, 4.0), layout="constrained")
        ax = fig.subplots()
        for i, (base, g) in enumerate(t.groupby("sweep_base", sort=False)):
            colour = design_colour(base, i)
            dens = g[g["sweep_property"] == "density"].sort_values("leg_mass_kg")
            ax.plot(
                dens["leg_mass_kg"], dens["mean_tracking_error_m"] * 1e3, "o-", color=colour, label=f"{base}: density"
            )
            mod = g[g["sweep_property"] == "modulus"]
            ax.plot(
                mod["leg_mass_kg"],
                mod["mean_tracking_error_m"] * 1e3,
                "o",
                mfc="none",
                color=colour,
                label=f"{base}: modulus",
            )
        if md_tracking_m is not None and np.isfinite(md_tracking_m):
            ax.axhline(md_tracking_m * 1e3, color="black", ls="--", lw=0.8, label="MD")
        ax.set_xlabel("Mass of the leg's material (kg)")
        ax.set_ylabel("Tracking error (mm)")
        ax.set_title("Experiment 2: tracking error against leg mass")
        ax.legend(fontsize="small", ncol=2)
    return fig


def codesign_figure(hops: pd.DataFrame, designs, default: str, tuned: str, *, title: str = ""):
    """Chapter 9c (gains tuned per material): each material's replicate mean of tracking error (mm)
    against hip power (W), at the authors' gains (open circle, experiment
    ``default``) and at its own tuned gains (filled, experiment ``tuned``),
    an arrow from one to the other.

    hops: per-hop rows with experiment, design, replicate, tracking_error_m
    and power_w (:func:`mat_hopper.optimize.codesign.codesign`'s ``hops``);
    designs: the materials, in legend order. Each point is the mean over
    replicates of the per-replicate means.

    Args:
        hops: per-hop rows, columns ``experiment``, ``design``, ``replicate``,
            ``tracking_error_m`` (m, drawn in mm) and ``power_w`` (W).
        designs: the design names drawn, in legend order; each must have rows
            in both experiments.
        default: the ``experiment`` value of the runs at the authors' gains.
        tuned: the ``experiment`` value of the runs at each material's tuned
            gains.
        title: the axes' title; empty: none.

    Returns:
        The ``matplotlib.figure.Figure``.
    """
    means = (
        hops.groupby(["experiment", "design", "replicate"])[["tracking_error_m", "power_w"]]
        .mean()
        .groupby(["experiment", "design"])
        .mean()
    )
    with rc_context(STYLE):
        fig = Figure(figsize=(6.4, 4.4), layout="constrained")
        ax = fig.subplots()
        for i, design in enumerate(designs):
            a, o = means.loc[(default, design)], means.loc[(tuned, design)]
            colour = design_colour(design, i)
            ax.plot(a["tracking_error_m"] * 1e3, a["power_w"], "o", mfc="none", mec=colour, ms=9)
            ax.plot(o["tracking_error_m"] * 1e3, o["power_w"], "o", color=colour, ms=9, label=design)
            ax.annotate(
                "",
                (o["tracking_error_m"] * 1e3, o["power_w"]),
                (a["tracking_error_m"] * 1e3, a["power_w"]),
                arrowprops={"arrowstyle": "->", "color": colour},
            )
        ax.set_xlabel("tracking error (mm, mean over replicates)")
        ax.set_ylabel("hip power (W, mean over replicates)")
        if title:
            ax.set_title(title, fontsize=10)
        ax.legend(fontsize=8)
    return fig


def convergence_figure(metrics: pd.DataFrame):
    """Chapter 12: tracking error (mm), hip power (W) and hop height (m)
    against the number of segments N (log 2 axis), one line per design and
    behaviour (solid: forward, dashed: the others).

    metrics: one row per design, behaviour and N with n_segments,
    tracking_error_m, power_w, hop_height_m
    (:func:`mat_hopper.experiments.convergence.metrics_table`).

    Args:
        metrics: columns ``design``, ``behaviour``, ``n_segments``,
            ``tracking_error_m`` (m, drawn in mm), ``power_w`` (W) and
            ``hop_height_m`` (m).

    Returns:
        The ``matplotlib.figure.Figure`` (three panels, one legend below).
    """
    with rc_context(STYLE):
        fig = Figure(figsize=(9, 3.2), layout="constrained")
        axes = fig.subplots(1, 3)
        for (d, beh), g in metrics.groupby(["design", "behaviour"], sort=False):
            g = g.sort_values("n_segments")
            style = "-" if beh == "forward" else "--"
            axes[0].plot(g["n_segments"], 1e3 * g["tracking_error_m"], style, marker="o", label=f"{d}, {beh}")
            axes[1].plot(g["n_segments"], g["power_w"], style, marker="o")
            axes[2].plot(g["n_segments"], g["hop_height_m"], style, marker="o")
        for ax, label in zip(axes, ("tracking error (mm)", "hip power (W)", "hop height (m)")):
            ax.set_xscale("log", base=2)
            ax.set_xlabel("segments N")
            ax.set_ylabel(label)
        fig.legend(loc="outside lower center", ncols=6, fontsize=7, frameon=False)
    return fig


def agreement_figure(table: pd.DataFrame):
    """Chapter 13: the warp backend against the CPU rollouts, per design and
    behaviour: tracking error and hip power differences (% of the CPU's),
    the acceptance band (:data:`mat_hopper.batch.RELATIVE_TOLERANCE`)
    shaded; runs that diverged on both backends marked "diverged". A run
    without scored hop cycles shows its whole-run means' differences.

    table: :func:`mat_hopper.batch.agreement` rows (behaviour may be nan).

    Args:
        table: one row per run, columns ``design``, ``behaviour`` (a string,
            or nan for none), ``tracking_error_diff_pct``, ``power_diff_pct``
            (%), ``agrees`` (bar colour), ``stable_ref`` and ``stable``
            (both false: "diverged"); ``run_tracking_error_diff_pct`` and
            ``run_power_diff_pct``, where present, fill the non-finite values.

    Returns:
        The ``matplotlib.figure.Figure`` (two panels sharing the rows).
    """
    from ..batch import RELATIVE_TOLERANCE

    band = 100 * RELATIVE_TOLERANCE
    labels = [d if not isinstance(b, str) else f"{d}, {b}" for d, b in zip(table["design"], table["behaviour"])]
    y = np.arange(len(table))
    with rc_context(STYLE):
        fig = Figure(figsize=(9, 0.35 * len(table) + 1.4), layout="constrained")
        axes = fig.subplots(1, 2, sharey=True)
        for ax, col, title in zip(
            axes,
            ("tracking_error_diff_pct", "power_diff_pct"),
            ("tracking error, warp vs CPU (%)", "hip power, warp vs CPU (%)"),
        ):
            # over scored hop cycles, else over the whole run (as the verdict)
            values = table[col].astype(float).to_numpy()
            if f"run_{col}" in table.columns:
                values = np.where(np.isfinite(values), values, table[f"run_{col}"].astype(float).to_numpy())
            ok = table["agrees"].to_numpy(bool)
            ax.axvspan(-band, band, color="#2a9d8f", alpha=0.12, lw=0)
            ax.axvline(0, color="#555555", lw=0.8)
            ax.barh(
                y[np.isfinite(values)],
                values[np.isfinite(values)],
                color=np.where(ok, "#2a9d8f", "#e76f51")[np.isfinite(values)],
            )
            for i in np.flatnonzero(~np.isfinite(values)):
                both = not table["stable_ref"].iloc[i] and not table["stable"].iloc[i]
                ax.text(0, y[i], "diverged" if both else "no value", va="center", ha="center", fontsize=7)
            ax.set_xlabel(title)
            lim = max(2 * band, float(np.nanmax(np.abs(values))) * 1.15 if np.isfinite(values).any() else 0)
            ax.set_xlim(-lim, lim)
        axes[0].set_yticks(y, labels)
        axes[0].invert_yaxis()
    return fig
