"""Figures of single chapters drawn from hand-made tables: what they draw."""

import math

import numpy as np
import pandas as pd
from matplotlib.patches import Rectangle

from mat_hopper.viz import chapters


def _bars(ax):
    return sorted(
        (round(p.get_y() + p.get_height() / 2), p.get_width())
        for p in ax.patches
        if isinstance(p, Rectangle) and p.get_height() < 1
    )


def test_agreement_figure_bars_are_the_differences():
    """Row 0 has scored hops (its hop-cycle differences are drawn), row 1 none
    (its whole-run differences are), row 2 diverged on both backends."""
    nan = math.nan
    table = pd.DataFrame(
        {
            "design": ["A", "B", "C"],
            "behaviour": ["forward"] * 3,
            "stable_ref": [True, True, False],
            "stable": [True, True, False],
            "n_hops_ref": [10, 0, 0],
            "n_hops": [10, 0, 0],
            "hop_height_diff_m": [0.001, nan, nan],
            "tracking_error_diff_pct": [3.0, nan, nan],
            "power_diff_pct": [-2.0, nan, nan],
            "run_tracking_error_diff_pct": [9.0, -4.0, nan],
            "run_power_diff_pct": [9.0, 12.0, nan],
            "agrees": [True, False, True],
        }
    )
    fig = chapters.agreement_figure(table)
    tracking, power = fig.axes[:2]
    assert _bars(tracking) == [(0, 3.0), (1, -4.0)]
    assert _bars(power) == [(0, -2.0), (1, 12.0)]
    assert [t.get_text() for t in tracking.texts] == ["diverged"]


def test_codesign_and_convergence_figures_draw_every_design():
    hops = pd.DataFrame(
        [
            {"experiment": e, "design": d, "replicate": r, "tracking_error_m": 0.02 + 0.01 * i, "power_w": 1.0 + i}
            for e in ("authors' gains", "own gains")
            for i, d in enumerate(["MD", "SS"])
            for r in range(2)
        ]
    )
    fig = chapters.codesign_figure(hops, ["MD", "SS"], "authors' gains", "own gains")
    assert len(fig.axes[0].lines) == 4  # two points per design
    metrics = pd.DataFrame(
        [
            {
                "design": "SS",
                "behaviour": b,
                "n_segments": n,
                "tracking_error_m": 0.02,
                "power_w": 2.0,
                "hop_height_m": 1.0,
            }
            for b in ("forward", "ramp")
            for n in (1, 2, 4)
        ]
    )
    fig = chapters.convergence_figure(metrics)
    assert [len(ax.lines) for ax in fig.axes] == [2, 2, 2]
    np.testing.assert_array_equal(fig.axes[0].lines[0].get_xdata(), [1, 2, 4])
