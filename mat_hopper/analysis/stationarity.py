"""Whether a claim's verdict depends on the scoring window.

A claim is judged on the hop cycles scored between the transient and the
end of each run. Where the gait has not settled (the ramp under the
authors' world-frame apex, whose height above the ground shrinks as the
hopper climbs), a verdict can differ between windows, and a claim that
holds in one window only is a claim about the window. So each claim is
judged again on each half of the scored window, and the two verdicts are
reported beside the whole window's: the same verdict in both halves is
``stationary``, a different one ``window-dependent``.

The halves split at the midpoint of the scored window, the mean of the
first scored cycle's start and the last one's end over the whole table:
the runs of one profile share one window, so one midpoint serves them
all. A cycle belongs to the half its start falls in; each run keeps its
replicates and pairing, only its cycles are halved, so a paired claim is
judged on the same seeds in each half.
"""

from __future__ import annotations

import pandas as pd

STATIONARY = "stationary"
WINDOW_DEPENDENT = "window-dependent"
NOT_CHECKED = "not checked"


def window_midpoint_s(hops: pd.DataFrame) -> float | None:
    """The midpoint of the scored window, s.

    Args:
        hops: per-hop rows with ``t_start_s`` and ``t_end_s`` (s).

    Returns:
        The mean of the earliest cycle start and the latest cycle end, s;
        None when the table is empty or lacks those columns.
    """
    if hops is None or len(hops) == 0 or not {"t_start_s", "t_end_s"} <= set(hops.columns):
        return None
    return 0.5 * (float(hops["t_start_s"].min()) + float(hops["t_end_s"].max()))


def window_halves(hops: pd.DataFrame, midpoint_s: float | None = None) -> tuple[pd.DataFrame, pd.DataFrame] | None:
    """(first half, second half) of `hops`' cycles, split by each cycle's
    start at `midpoint_s` (default :func:`window_midpoint_s`); None when
    there is no window to split.

    Args:
        hops: per-hop rows with ``t_start_s`` and ``t_end_s`` (s).
        midpoint_s: where to split, s; None: the scored window's midpoint.

    Returns:
        Two DataFrames with `hops`' columns, or None.
    """
    mid = window_midpoint_s(hops) if midpoint_s is None else float(midpoint_s)
    if mid is None:
        return None
    first = hops["t_start_s"] < mid
    return hops[first], hops[~first]


def stationarity(first_verdict: str, second_verdict: str, first_ours: str = "", second_ours: str = "") -> str:
    """One cell of the claims table's ``stationarity`` column: whether the
    verdicts on the two halves of the scored window agree.

    Args:
        first_verdict, second_verdict: the claim's verdict on each half
            (``holds``, ``partly``, ``does not hold``, ...); an empty one
            means the half was not judged.
        first_ours, second_ours: our number on each half, quoted in a
            window-dependent cell.

    Returns:
        ``"stationary (holds | holds)"``, ``"window-dependent (first half:
        holds, ...; second half: partly, ...)"`` or ``"not checked"``.
    """
    if not first_verdict or not second_verdict:
        return NOT_CHECKED
    if first_verdict == second_verdict:
        return f"{STATIONARY} ({first_verdict} | {second_verdict})"

    def half(name, verdict, ours):
        return f"{name} half: {verdict}" + (f", {ours}" if ours else "")

    return (
        f"{WINDOW_DEPENDENT} ({half('first', first_verdict, first_ours)}; "
        f"{half('second', second_verdict, second_ours)})"
    )


def is_window_dependent(cell: str) -> bool:
    """Whether a ``stationarity`` cell marks its claim window-dependent.

    Args:
        cell: a cell of the claims table's ``stationarity`` column.

    Returns:
        True for a ``window-dependent (...)`` cell.
    """
    return str(cell).startswith(WINDOW_DEPENDENT)
