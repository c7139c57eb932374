"""The growth rate of an oscillation's envelope: how fast a mode grows.

A leg that bends can carry a lateral mode that grows from
round-off until the body rolls over. Its rate is the slope of the log of
the signal's envelope: the largest |value| in each window (half a hop),
fitted by a straight line from where the envelope first rises above a
floor to where it first passes a ceiling (past that the motion is no
longer small, and a line no longer describes it). Chapter 8b and
``benchmarks/bending_mode.py`` both measure it with this one function.

Ours rather than a library's: scipy's Hilbert envelope assumes one
narrow-band carrier, while a hopping body's tilt carries the hop cycle's
harmonics and contact impulses; the per-window maximum needs no such
assumption.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["GrowthFit", "envelope_growth"]

MIN_WINDOWS = 4  # fewer windows below the ceiling: a jump, not a growth a line describes


@dataclass(frozen=True)
class GrowthFit:
    """An envelope's exponential fit.

    Args:
        rate_per_s: slope of the natural log of the envelope, 1/s (> 0:
            growing, e-folding time 1 / rate; < 0: decaying); nan when
            fewer than :data:`MIN_WINDOWS` windows lie between the floor
            and the ceiling.
        decades: how far the envelope moved over the fitted windows,
            decades (log10 of last over first); nan as the rate.
        passed_s: the start of the first window whose envelope passes the
            ceiling, s; nan when none does.
    """

    rate_per_s: float
    decades: float
    passed_s: float


def envelope_growth(
    time_s, signal, window_s: float, *, start_s: float | None = None, floor: float = 0.0, ceiling: float = 1e-2
) -> GrowthFit:
    """Fit the growth of `signal`'s envelope (module doc).

    Args:
        time_s: (T,) sample times, s, increasing.
        signal: (T,) the oscillating quantity (e.g. the base's roll, rad);
            non-finite samples are skipped.
        window_s: the envelope's window, s (finite, at least the largest
            sample spacing so that every window holds a sample; e.g. half
            a hop, 0.31 s).
        start_s: where the windows begin, s (finite; default: the first sample).
        floor: the fit starts at the first window whose envelope exceeds
            this (default 0: the first window; 1e-12 rad skips the exact
            zeros and round-off before a mode is seeded).
        ceiling: the fit stops before the first window whose envelope
            exceeds this (default 1e-2, in the signal's units).

    Returns:
        A :class:`GrowthFit`. The windows are ``[start_s + k window_s,
        start_s + (k + 1) window_s)``, the last one whole to within half a
        window; each is fitted at its centre.

    Raises:
        ValueError: `time_s` and `signal` not 1-D of one length of at
            least 2 samples, `time_s` not finite and increasing, `window_s`
            not finite or shorter than a sample spacing, `start_s` not
            finite, or not 0 <= `floor` < `ceiling` (both finite).
    """
    t, x = np.asarray(time_s, float), np.asarray(signal, float)
    if t.shape != x.shape or t.ndim != 1 or t.size < 2:
        raise ValueError(f"time_s and signal must be 1-D of one length >= 2, got {t.shape} and {x.shape}")
    if not np.all(np.isfinite(t)) or np.any(np.diff(t) <= 0):
        raise ValueError("time_s must be finite and increasing")
    if not (np.isfinite(window_s) and window_s >= np.max(np.diff(t))):
        raise ValueError(f"window_s must be finite and at least the largest sample spacing, got {window_s!r}")
    if start_s is not None and not np.isfinite(start_s):
        raise ValueError(f"start_s must be finite, got {start_s!r}")
    if not (np.isfinite(floor) and np.isfinite(ceiling) and 0 <= floor < ceiling):
        raise ValueError(f"need finite 0 <= floor < ceiling, got floor {floor!r}, ceiling {ceiling!r}")
    edges = np.arange(t[0] if start_s is None else start_s, t[-1] - window_s / 2, window_s)
    ax, ok = np.abs(x), np.isfinite(x)  # a NaN sample (none in a rollout's record) is skipped, not propagated
    env = np.array([ax.max(initial=0.0, where=ok & (t >= e) & (t < e + window_s)) for e in edges])
    big = np.flatnonzero(env > ceiling)
    stop = int(big[0]) if big.size else len(env)
    passed = float(edges[stop]) if big.size else float("nan")
    above = np.flatnonzero(env[:stop] > floor)
    start = int(above[0]) if above.size else stop
    if stop - start < MIN_WINDOWS:
        return GrowthFit(float("nan"), float("nan"), passed)
    centres, log_env = edges[start:stop] + window_s / 2, np.log(env[start:stop])
    rate = float(np.polyfit(centres, log_env, 1)[0])
    return GrowthFit(rate, float((log_env[-1] - log_env[0]) / np.log(10)), passed)
