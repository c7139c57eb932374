"""The body's mean |jerk| (m/s^3) as a run would report it at lower record
rates (Hz), emulated by keeping every k-th recorded sample: the raw finite
difference of the acceleration, which measures the sampling of the leg's
kHz ringing, beside the book's filtered ``jerk_z`` metric
(:mod:`mat_hopper.physics.metrics`).
"""

from __future__ import annotations

import numpy as np
import pandas as pd


def _subsampling_steps(rates_hz, record_hz: float, n_samples: int) -> list[int]:
    """Every-k-th-sample steps k that emulate `rates_hz` from a record at
    `record_hz` (:func:`jerk_by_rate`), all checked before any is used."""
    try:
        rates = [float(r) for r in rates_hz]
    except (TypeError, ValueError):
        raise ValueError(f"rates_hz must be numbers (Hz), got {rates_hz!r}") from None
    if not rates:
        raise ValueError("jerk_by_rate needs at least one rate")
    possible = f"possible rates: {record_hz:g} Hz divided by a whole number ({record_hz:g}, {record_hz / 2:g}, ...)"
    steps = []
    for rate in rates:
        if not (np.isfinite(rate) and rate > 0):
            raise ValueError(f"rate {rate} Hz must be a finite number > 0; {possible}")
        if rate > record_hz * (1 + 1e-6):  # 1e-6: the record rate is read off the samples' times
            raise ValueError(f"rate {rate:g} Hz exceeds the record rate {record_hz:g} Hz; {possible}")
        ratio = record_hz / rate
        k = max(1, int(round(ratio))) if ratio < n_samples else n_samples
        if (n_samples - 1) // k + 1 < 3:
            raise ValueError(f"rate {rate:g} Hz leaves fewer than 3 samples")
        steps.append(k)
    return steps


def jerk_by_rate(rollout, rates_hz=(1000.0, 100.0, 10.0)) -> pd.DataFrame:
    """Mean |jerk| (m/s^3) of the body's vertical motion after the
    transient, as it would be recorded at each rate (every k-th recorded
    sample), two ways:

    - ``raw_jerk_m_s3``: the vertical acceleration at that rate
      differentiated by finite differences (``np.gradient``), the
      authors' way (they logged at about 10 Hz of wall
      time). The leg's axial modes (kHz, barely damped) lie above the
      Nyquist frequency of any record rate, so this number measures the
      sampling (aliased ringing), not the hop: kept as an illustration.
    - ``metric_jerk_m_s3``: the book's metric, :mod:`mat_hopper.physics.metrics`'
      ``jerk_z`` channel (computed at the physics rate from the
      acceleration low-passed at 50 Hz) averaged over the samples at that
      rate: what ``hop_table`` reports for a run recorded at that rate.

    ``mean_jerk_m_s3`` repeats ``raw_jerk_m_s3`` (an alias of the same
    values). Columns rate_hz, raw_jerk_m_s3, metric_jerk_m_s3,
    mean_jerk_m_s3.

    Args:
        rollout: a :class:`mat_hopper.core.rollout.Rollout`; averaged from ``rollout.settings.transient_s`` on.
        rates_hz: the record rates to emulate, Hz (one or more, each finite and > 0). Subsampling can
            only emulate the record rate R divided by a whole number k (R, R/2, R/3, ...): a rate at or
            below R is rounded to the nearest of these (the ``rate_hz`` column says which); a rate above
            R cannot be honoured and is refused, never lowered to R.

    Returns:
        DataFrame, one row per rate: rate_hz (the emulated rate, Hz), raw_jerk_m_s3, metric_jerk_m_s3,
        mean_jerk_m_s3 (m/s^3).

    Raises:
        ValueError: no rate; a rate that is not a finite number > 0; a rate above the record rate (the
            message gives the record rate and the possible rates); fewer than 4 recorded samples; a
            rate that leaves fewer than 3 samples. Every rate is checked before any is computed.
    """
    from ..core.sim import C

    d = rollout.data
    t, az, jz = d[:, C["t"]], d[:, C["az"]], d[:, C["jerk_z"]]
    if len(t) < 4:
        raise ValueError("jerk_by_rate: the rollout recorded fewer than 4 samples")
    dt = float(np.median(np.diff(t)))
    steps = _subsampling_steps(rates_hz, 1.0 / dt, len(t))
    rows = []
    for k in steps:
        ts, a, j = t[::k], az[::k], jz[::k]
        raw = np.abs(np.gradient(a, ts))
        keep = ts >= rollout.settings.transient_s
        rows.append(
            {
                "rate_hz": 1.0 / (k * dt),
                "raw_jerk_m_s3": float(raw[keep].mean()),
                "metric_jerk_m_s3": float(np.abs(j[keep]).mean()),
            }
        )
    out = pd.DataFrame(rows)
    out["mean_jerk_m_s3"] = out["raw_jerk_m_s3"]
    return out
