"""Grouped box plots, the layout of the paper's Fig. 4 and 5: behaviours
along x, one box per design side by side in each, drawn by seaborn's
``boxplot`` (designs as hue), with significance stars and replicate-mean
dots placed at the boxes' centres."""

from __future__ import annotations

import warnings

import numpy as np
import pandas as pd

from .style import BEHAVIOUR_LABELS, design_colour


def _seaborn_boxes(sns, ax, long, groups, designs, width) -> None:
    """The boxes of :func:`_grouped_boxes`: seaborn's boxplot of `long`
    (columns group, design, value), designs as hue, in the given orders."""
    sns.boxplot(
        data=long,
        x="group",
        y="value",
        hue="design",
        order=list(groups),
        hue_order=list(designs),
        palette={d: design_colour(d, di) for di, d in enumerate(designs)},
        width=width,
        gap=0.2,
        dodge=True,
        linewidth=0.6,
        linecolor="#333333",
        fliersize=1.5,
        medianprops=dict(color="black", linewidth=1.0),
        legend=False,
        ax=ax,
    )


def grouped_boxes(
    ax, table, metric, groups, designs, *, group_col="behaviour", factor=1.0, stars=None, width=0.8, points=None
):
    """Box plots of `metric` at x = group index, one box per design side by
    side, drawn by seaborn (``boxplot`` with the designs as hue, the paper's
    layout: behaviours along x, designs side by side in each).

    Args:
        ax: the matplotlib Axes.
        table: per-hop rows with `group_col`, ``design`` and `metric`.
        metric: the column drawn (its unit times `factor`).
        groups: the x groups in order (behaviours).
        designs: the designs in order (hue).
        group_col: the grouping column (default ``behaviour``).
        factor: a unit factor applied to the values (e.g. 1e3 for mm).
        stars: set of (group, design) to mark with a star.
        width: the total width of a group's boxes (x units).
        points: a table of values drawn as black dots over the boxes (replicate means).

    Returns:
        The tops (largest value drawn) of each box, for the axis limits.
    """
    import seaborn as sns

    n = max(len(designs), 1)
    w = width / n
    cells = {k: v.to_numpy(float) * factor for k, v in table.groupby([group_col, "design"], sort=False)[metric]}
    pts = (
        {k: v.to_numpy(float) * factor for k, v in points.groupby([group_col, "design"], sort=False)[metric]}
        if points is not None and len(points)
        else {}
    )
    long = pd.DataFrame(
        [(g, d, x) for (g, d), v in cells.items() if g in groups and d in designs for x in v[np.isfinite(v)]],
        columns=["group", "design", "value"],
    )
    if len(long):
        with warnings.catch_warnings():  # seaborn 0.13.2 passes bxp(vert=), deprecated by matplotlib 3.11
            warnings.filterwarnings("ignore", message="vert: bool was deprecated", category=DeprecationWarning)
            _seaborn_boxes(sns, ax, long, groups, designs, width)
    tops = []
    for di, d in enumerate(designs):
        dot_x, dot_y = [], []
        for gi, g in enumerate(groups):
            v = cells.get((g, d), np.array([]))
            v = v[np.isfinite(v)]
            if len(v) == 0:
                continue
            pos = gi - width / 2 + w * (di + 0.5)
            top = float(v.max())
            p = pts.get((g, d), np.array([]))
            p = p[np.isfinite(p)]
            if len(p):
                dot_x.extend(pos + (np.arange(len(p)) - (len(p) - 1) / 2) * (w * 0.5 / len(p)))
                dot_y.extend(p)
                top = max(top, float(p.max()))
            tops.append(top)
            if stars and (g, d) in stars:
                ax.annotate(
                    "*",
                    xy=(pos, top),
                    xytext=(0, 0.5),
                    textcoords="offset points",
                    ha="center",
                    va="bottom",
                    fontsize=11,
                    fontweight="bold",
                )
        if dot_x:
            ax.plot(dot_x, dot_y, "o", ms=2.2, color="black", alpha=0.8, zorder=3, gid="replicate-means")
    ax.set_xticks(range(len(groups)))
    ax.set_xticklabels([BEHAVIOUR_LABELS.get(g, g) for g in groups])
    ax.set_xlim(-0.5, len(groups) - 0.5)
    ax.set_xlabel("")
    ax.grid(False, axis="x")
    if tops:
        lo, hi = ax.get_ylim()
        ax.set_ylim(lo, hi + 0.08 * (hi - lo))
    return tops
