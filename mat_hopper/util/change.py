"""The one percent change against a baseline, and the one round-off floor.

Every percent change in the package (metrics.compare, the statistics, the
book's tables, the optimizer's report) is :func:`percent_change`, with one
rule for a baseline that is nothing: where ``|baseline| < ROUNDOFF`` (SI
units, e.g. the tracking error of hopping in place, zero up to round-off)
or the baseline is not finite, the change is nan. A percentage of nothing
means nothing.

A core leaf module (imports numpy only): the core's
:mod:`mat_hopper.physics.metrics` can use it without an import cycle.
"""

from __future__ import annotations

import numpy as np

ROUNDOFF = 1e-9  # SI units: a magnitude below this is round-off, not a value


def percent_change(value, baseline, *, floor: float = ROUNDOFF):
    """100 (value - baseline) / |baseline| in %, nan where |baseline| <
    `floor` or the baseline is not finite. Elementwise on arrays; a float
    for scalars.

    Args:
        value: the new value(s), a scalar or array-like (broadcast against
            `baseline`).
        baseline: the reference value(s), same units as `value`.
        floor: the least |baseline| that gives a change, in the values' units
            (default :data:`ROUNDOFF`, 1e-9).

    Returns:
        The change in %: a float when both inputs are scalars, else a float
        array of the broadcast shape; nan where |baseline| < `floor` or the
        baseline is not finite.
    """
    v = np.asarray(value, dtype=float)
    b = np.asarray(baseline, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        out = np.where(np.isfinite(b) & (np.abs(b) >= floor), 100.0 * (v - b) / np.abs(b), np.nan)
    return float(out) if out.ndim == 0 else out
