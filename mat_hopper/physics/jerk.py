"""Jerk that measures the body, not the leg's ringing.

The loop's ``jerk_z`` (:data:`mat_hopper.core.sim.JERK_CUTOFF_HZ`) is the base's
z acceleration through a *causal* 2nd-order 50 Hz Butterworth at the
physics rate, differentiated step by step. A 2nd-order section passes the
leg's barely damped axial modes (2.5-4 kHz) at a level that the
differentiation then amplifies by 2 pi f, so the jerk it gives carries
the leg's ringing as well as the body's motion.

:func:`body_jerk` is the zero-phase alternative, computed after the run:

1. anti-aliasing: the loop records ``az_mean``, the mean of the physics-rate
   acceleration over each record interval (a box filter; at the default
   1 kHz record rate of a 10 kHz physics step it attenuates a 2.5 kHz mode
   to 13 % before the sample aliases it to 500 Hz). One addition per
   physics step;
2. a 4th-order Butterworth low-pass at 20 Hz run forwards and backwards
   (:func:`scipy.signal.sosfiltfilt`: zero phase, effective order 8), at the
   record rate; the choice of Winter for body-segment kinematics (D. A.
   Winter, *Biomechanics and Motor Control of Human Movement*, 4th ed.,
   Wiley 2009, sec. 2.2.4.4-2.2.4.5: 4th-order zero-lag Butterworth, cut-offs of
   a few Hz to tens of Hz for body motion). The cut-off is a named
   setting: :data:`BODY_JERK_CUTOFF_HZ` (default 20 Hz; the hop's stance
   lasts about 0.1 s, its body content lies below 20 Hz) and
   :data:`BODY_JERK_ORDER`; :func:`jerk_sensitivity` recomputes a jerk at
   other cut-offs (20-100 Hz) and orders;
3. the derivative by central differences (:func:`numpy.gradient`), its
   absolute value averaged over each hop cycle: ``jerk_body_m_s3``.

Why not filter at the physics rate inside the loop: a zero-phase filter
needs the whole signal (it runs backwards), and recording at 10 kHz
multiplies the records by ten; the box mean costs nothing and keeps the
record rate.
"""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
import scipy.signal

from ..core.rollout import hop_cycles
from ..util.parsing import is_real

BODY_JERK_CUTOFF_HZ = 20.0  # Winter 2009, sec. 2.2.4.4-2.2.4.5 (body kinematics)
BODY_JERK_ORDER = 4  # per pass; sosfiltfilt doubles it
SENSITIVITY_CUTOFFS_HZ = (20.0, 30.0, 50.0, 70.0, 100.0)
SENSITIVITY_ORDERS = (2, 4)


def _check_filter(rollout, cutoff_hz, order) -> float:
    """The record rate fs (Hz) of `rollout`, after checking a Butterworth
    cut-off in (0, fs / 2) Hz and an integer order >= 1 (a bool, nan or inf
    refused as ValueError: int(inf) raised OverflowError)."""
    t = rollout.time
    if len(t) < 2:
        raise ValueError("the rollout has fewer than 2 samples")
    fs = 1.0 / float(np.median(np.diff(t)))
    if not (is_real(cutoff_hz) and 0 < cutoff_hz < fs / 2):
        raise ValueError(f"cutoff_hz must be in (0, {fs / 2:g}) Hz (the record Nyquist), got {cutoff_hz!r}")
    if not (is_real(order) and math.isfinite(order) and float(order).is_integer() and order >= 1):
        raise ValueError(f"order must be an integer >= 1, got {order!r}")
    return fs


def body_acceleration(rollout, cutoff_hz: float = BODY_JERK_CUTOFF_HZ, order: int = BODY_JERK_ORDER) -> np.ndarray:
    """The base's z acceleration (m/s^2) at the record rate, low-passed with zero phase.

    Args:
        rollout: a :class:`mat_hopper.core.sim.Rollout` (its ``az_mean`` channel).
        cutoff_hz: the Butterworth cut-off (Hz), below the record Nyquist.
        order: the Butterworth order of one pass (>= 1).

    Returns:
        (n,) array, m/s^2.

    Raises:
        ValueError: a cut-off at or above the record Nyquist, an order < 1,
            or too few samples for the filter.
    """
    fs = _check_filter(rollout, cutoff_hz, order)
    sos = scipy.signal.butter(int(order), cutoff_hz, fs=fs, output="sos")
    az = rollout["az_mean"]
    pad = 3 * (2 * len(sos) + 1)
    if len(az) <= pad:
        raise ValueError(f"the rollout has {len(az)} samples; the filter needs more than {pad}")
    return scipy.signal.sosfiltfilt(sos, az)


def body_jerk(rollout, cutoff_hz: float = BODY_JERK_CUTOFF_HZ, order: int = BODY_JERK_ORDER) -> np.ndarray:
    """|d az / dt| of :func:`body_acceleration` (m/s^3), per recorded sample.

    Args:
        rollout: a :class:`mat_hopper.core.sim.Rollout` (its ``az_mean`` channel
            and ``time``, s).
        cutoff_hz: the Butterworth cut-off (Hz), below the record Nyquist
            (default :data:`BODY_JERK_CUTOFF_HZ`, 20 Hz).
        order: the Butterworth order of one pass, >= 1 (default
            :data:`BODY_JERK_ORDER`, 4).

    Returns:
        (n,) array, m/s^3, one value per recorded sample (central
        differences of the filtered acceleration against ``rollout.time``).

    Raises:
        ValueError: as :func:`body_acceleration`: fewer than 2 samples, a
            cut-off at or above the record Nyquist, an order that is not an
            integer >= 1, or too few samples for the filter.
    """
    a = body_acceleration(rollout, cutoff_hz, order)
    return np.abs(np.gradient(a, rollout.time))


def hop_body_jerk(rollout, i0, i1, cutoff_hz: float = BODY_JERK_CUTOFF_HZ, order: int = BODY_JERK_ORDER):
    """Mean body jerk (m/s^3) of each cycle of samples [i0, i1).

    Args:
        rollout: a Rollout.
        i0, i1: (k,) sample indices of each cycle's start and end.
        cutoff_hz, order: as :func:`body_acceleration`.

    Returns:
        (k,) array, m/s^3.
    """
    j = body_jerk(rollout, cutoff_hz, order)
    csum = np.concatenate([[0.0], np.cumsum(j)])
    i0, i1 = np.asarray(i0), np.asarray(i1)
    return (csum[i1] - csum[i0]) / np.maximum(i1 - i0, 1)


def jerk_sensitivity(rollout, cutoffs_hz=SENSITIVITY_CUTOFFS_HZ, orders=SENSITIVITY_ORDERS, transient_s=None):
    """The run's mean body jerk over its scored hops at each cut-off and order.

    Args:
        rollout: a Rollout.
        cutoffs_hz: cut-offs (Hz).
        orders: Butterworth orders of one pass.
        transient_s: hop cycles before it are not scored, a finite number
            >= 0 s (default None: the run's).

    Returns:
        tidy DataFrame: design, behaviour, cutoff_hz, order, jerk_body_m_s3,
        and the loop's causal ``jerk_m_s3`` for reference.

    Raises:
        ValueError: a cut-off not in (0, record Nyquist) Hz or an order that
            is not an integer >= 1 (every one checked before any filtering,
            with or without scored hops), or `transient_s` not None nor a
            finite number >= 0 s.
    """
    for order in orders:
        for fc in cutoffs_hz:
            _check_filter(rollout, fc, order)
    cyc = hop_cycles(rollout, transient_s)
    t = rollout.time
    i0, i1 = np.searchsorted(t, cyc[:, 0]), np.searchsorted(t, cyc[:, 1])
    causal = np.abs(rollout["jerk_z"])
    ref = float(np.mean([causal[a:b].mean() for a, b in zip(i0, i1) if b > a])) if len(cyc) else np.nan
    rows = []
    for order in orders:
        for fc in cutoffs_hz:
            v = hop_body_jerk(rollout, i0, i1, fc, order) if len(cyc) else np.array([np.nan])
            rows.append(
                {
                    "design": rollout.design.name,
                    "behaviour": rollout.behaviour.name,
                    "cutoff_hz": float(fc),
                    "order": int(order),
                    "jerk_body_m_s3": float(np.mean(v)),
                    "jerk_m_s3": ref,
                }
            )
    return pd.DataFrame(rows)
