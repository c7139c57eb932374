"""Hypervolume of a front, exact in any number of minimized objectives, and its history over a study.

The hypervolume is bounded by a reference point; :func:`hypervolume_history`
takes it :data:`HV_MARGIN` (10 %) of each objective's feasible range beyond
its worst feasible value. Units: the product of the objectives' units.
Re-exported by :mod:`mat_hopper.optimize.report`.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ._objective import OBJECTIVES
from ._report_tables import feasible_complete

HV_MARGIN = 0.1


def hypervolume(points, reference) -> float:
    """Volume dominated by `points` (n x d, every objective minimized) and
    bounded by `reference` (d values), exact, for any d >= 1.

    Ours because Optuna's public API only plots the hypervolume history
    (``optuna.visualization.matplotlib.plot_hypervolume_history``, used for
    the figure; its computation is private) and no hypervolume package is
    installed. Slicing (Zitzler's HSO): sort by the last objective; between
    one point's value and the next, the dominated region's cross-section is
    the (d - 1)-dimensional hypervolume of the points seen so far. d = 2 is
    the usual staircase sweep. Cost O(n^(d-1) log n): fronts of tens of
    points in 2 or 3 objectives take milliseconds.

    Args:
        points: (n, d) array-like (n may be 0).
        reference: (d,) the bounding point; points not strictly below it in
            every objective add nothing.

    Returns:
        float, in the product of the objectives' units.
    """
    r = np.asarray(reference, float).ravel()
    p = np.asarray(points, float).reshape(-1, len(r))
    p = p[np.all(p < r, axis=1)]
    if len(p) == 0:
        return 0.0
    if len(r) == 1:
        return float(r[0] - p[:, 0].min())
    if len(r) == 2:  # staircase: by x, add each point's strip below the best y so far
        p = p[np.lexsort((p[:, 1], p[:, 0]))]
        area, best_y = 0.0, r[1]
        for x, y in p:
            if y < best_y:
                area += (r[0] - x) * (best_y - y)
                best_y = y
        return float(area)
    p = p[np.argsort(p[:, -1], kind="stable")]
    volume = 0.0
    for i in range(len(p)):  # the slab from this point's last value to the next one's (or the reference)
        top = p[i + 1, -1] if i + 1 < len(p) else r[-1]
        if top > p[i, -1]:
            volume += hypervolume(p[: i + 1, :-1], r[:-1]) * (top - p[i, -1])
    return float(volume)


def hypervolume_2d(points: np.ndarray, reference) -> float:
    """:func:`hypervolume` in two objectives.

    Args:
        points: (n, 2) minimized objective values.
        reference: (2,) the bounding point.

    Returns:
        The area dominated by `points` and bounded by `reference`.
    """
    return hypervolume(np.asarray(points, float).reshape(-1, 2), reference)


def hypervolume_history(frame: pd.DataFrame, reference=None, objectives=OBJECTIVES) -> tuple[pd.DataFrame, tuple]:
    """Hypervolume of the feasible complete trials up to each trial number.

    Args:
        frame: :func:`trials_frame`'s table.
        reference: the reference point (None: the worst feasible value of
            each objective plus HV_MARGIN of its range).
        objectives: the study's objectives (the table's columns used).

    Returns:
        (a table of trial, hypervolume; the reference point as a tuple, ()
        without a feasible trial).
    """
    ok = feasible_complete(frame)
    if ok.empty:
        return pd.DataFrame(columns=["trial", "hypervolume"]), ()
    vals = ok[list(objectives)].to_numpy(float)
    if reference is None:
        lo, hi = vals.min(axis=0), vals.max(axis=0)
        span = np.where(hi > lo, hi - lo, np.maximum(np.abs(hi), 1e-12))
        reference = tuple(float(v) for v in hi + HV_MARGIN * span)
    trials = frame.sort_values("trial")["trial"].to_numpy()
    ok_trials = ok["trial"].to_numpy()
    out = []
    for n in trials:
        out.append({"trial": int(n), "hypervolume": hypervolume(vals[ok_trials <= n], reference)})
    return pd.DataFrame(out), tuple(reference)
