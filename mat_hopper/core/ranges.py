"""The ranges a design may take: accepted physical ranges of density,
modulus and segment count, and the design space the paper's sweeps span.

The accepted ranges (:data:`DENSITY_RANGE_G_CM3`, :data:`MODULUS_RANGE_GPA`,
:data:`MAX_SEGMENTS`) bound what a design may ask for; values outside raise
ValueError naming the range. The design space (:data:`DENSITY_BOUNDS_G_CM3`,
:data:`MODULUS_BOUNDS_GPA`) is the optimizer's and the Ashby chart's box,
inside the accepted ranges. One module for the checks that
:mod:`mat_hopper.core.catalogue`, :mod:`mat_hopper.core.conventions` and
:mod:`mat_hopper.core.materials` share.
"""

from __future__ import annotations

import math

from ..util.parsing import is_decimal
from . import reference as ref

__all__ = [
    "DENSITY_BOUNDS_G_CM3",
    "DENSITY_RANGE_G_CM3",
    "MAX_SEGMENTS",
    "MODULUS_BOUNDS_GPA",
    "MODULUS_RANGE_GPA",
    "POLYMER_DENSITY_FLOOR_G_CM3",
    "check_n_segments",
]

# Accepted physical ranges. Densities: from aerogels (about 0.001 g/cm^3) to
# beyond osmium (22.6 g/cm^3); moduli: from soft gels (kPa, 1e-6 GPa) to
# beyond diamond (about 1200 GPa). Segments: a cap on model size (the
# convergence study goes to 24).
DENSITY_RANGE_G_CM3 = (0.001, 30.0)
MODULUS_RANGE_GPA = (1e-6, 2000.0)
MAX_SEGMENTS = 64

# The design space: the property ranges the paper's sweeps span, with the
# density floor of engineering polymers (the optimizer's box, the Ashby
# chart's). Not the accepted input range (DENSITY_RANGE_G_CM3 above).
_SWEEP_DENSITIES = [v for s in ref.SWEEPS.values() for v in s["density"]]
_SWEEP_MODULI = [v for s in ref.SWEEPS.values() for v in s["modulus"]]
POLYMER_DENSITY_FLOOR_G_CM3 = 0.9  # polyolefins (Ashby 2011, app. C)
DENSITY_BOUNDS_G_CM3 = (POLYMER_DENSITY_FLOOR_G_CM3, float(max(_SWEEP_DENSITIES)))  # (0.9, 20)
MODULUS_BOUNDS_GPA = (float(min(_SWEEP_MODULI)), float(max(_SWEEP_MODULI)))  # (0.1, 1000)


def _check_number(
    value, field: str, accepted: str, *, allow_zero: bool = False, bounds: tuple[float, float] | None = None
) -> float:
    """A finite number > 0 (>= 0 with allow_zero), inside bounds if given.
    Numeric strings ("8", " 1e3 ") are parsed as ASCII decimals only
    (:func:`mat_hopper.util.parsing.is_decimal`: not "inf", "1_0" or "٨");
    anything else is refused."""
    if isinstance(value, bool) or (isinstance(value, str) and not is_decimal(value)):
        raise ValueError(f"{field} must be a number {accepted}, got {value!r}")
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{field} must be a number {accepted}, got {value!r}") from None
    if not math.isfinite(x) or x < 0 or (x == 0 and not allow_zero):
        raise ValueError(f"{field} must be {accepted}, got {value!r}")
    if bounds is not None and not bounds[0] <= x <= bounds[1]:
        raise ValueError(f"{field} must be {accepted}, got {value!r}")
    return x


def check_n_segments(n_segments) -> int:
    """An integer number of segments in [1, MAX_SEGMENTS] (no bools, no 2.5).

    Args:
        n_segments: the count asked for: an int, or any value that
            ``float()`` and ``int()`` both read to the same integer (3.0,
            ``"3"``).

    Returns:
        The count as an int.

    Raises:
        ValueError: a bool, a value that is not an integer (2.5, ``"3.0"``,
            nan, inf, None), a string of non-ASCII digits (``"٣"``) or one
            outside [1, :data:`MAX_SEGMENTS`] (64).
    """
    try:
        ok = (not isinstance(n_segments, bool)) and float(n_segments) == int(n_segments)
        ok = ok and (is_decimal(n_segments) if isinstance(n_segments, str) else True)  # ASCII only: not "٣"
    except (TypeError, ValueError, OverflowError):
        ok = False
    if not ok or not 1 <= int(n_segments) <= MAX_SEGMENTS:
        raise ValueError(f"n_segments must be an integer in [1, {MAX_SEGMENTS}], got {n_segments!r}")
    return int(n_segments)
