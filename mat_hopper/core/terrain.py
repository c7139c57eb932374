"""The terrain under the hopper: flat ground, or the ramp box of the ramp
behaviour (the authors' box, pitched up by its grade).

:func:`ramp_pose` places the box as the authors' model does
(:data:`mat_hopper.core.reference.RAMP_CENTER_X`, ``RAMP_CENTER_Z``,
``RAMP_HALF_SIZE``; docs/reference-hopper.md), and :func:`terrain_height_m`
gives the height of that terrain under world points, m, for the metrics that
measure a hop above the ground. :func:`terrain_height_at` is the same
height at one point in compiled code, from the numbers of
:func:`terrain_params`: the rollout loop reads it at each lift-off when the
controller regulates the apex above the ground
(``SimSettings.apex_reference = "ground"``, :mod:`mat_hopper.core.controller`).
:mod:`mat_hopper.core.mjcf` adds the box to the model.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from ..util.parsing import is_real
from . import reference as ref

__all__ = [
    "MAX_RAMP_GRADE_DEG",
    "TERRAIN_PARAMS",
    "check_ramp_grade",
    "ramp_pose",
    "terrain_height_at",
    "terrain_height_m",
    "terrain_params",
]

# deg, exclusive: a grade of +-90 deg is a wall (tan is infinite), beyond it
# the ramp is upside down. The paper's ramp is 2 deg; the Behaviour class
# itself accepts [0, 30) deg (a ramp the hopper can climb).
MAX_RAMP_GRADE_DEG = 90.0


def check_ramp_grade(ramp_grade_deg) -> float | None:
    """The ramp's pitch as a float strictly inside (-90, 90) deg, or None
    (flat ground); ValueError naming it otherwise.

    Args:
        ramp_grade_deg: None for flat ground, else the pitch, deg: an int or
            a float.

    Returns:
        None, or the pitch as a float, deg.

    Raises:
        ValueError: a bool, a string or other non-number, nan, inf, or a
            pitch not strictly between -90 and 90 deg (a vertical or
            overhanging ramp).
    """
    if ramp_grade_deg is None:
        return None
    ok = is_real(ramp_grade_deg)
    a = float(ramp_grade_deg) if ok else math.nan
    if not (math.isfinite(a) and -MAX_RAMP_GRADE_DEG < a < MAX_RAMP_GRADE_DEG):
        raise ValueError(
            f"ramp_grade_deg must be None (flat) or a finite number strictly between -{MAX_RAMP_GRADE_DEG:g} and "
            f"{MAX_RAMP_GRADE_DEG:g} deg, got {ramp_grade_deg!r}"
        )
    return a


def ramp_pose(grade_deg: float) -> tuple[np.ndarray, np.ndarray]:
    """Centre (m) and quaternion (w, x, y, z) of the ramp box pitched up by
    grade_deg (deg).

    The centre is the authors' exact (RAMP_CENTER_X, 0, RAMP_CENTER_Z):
    -0.03 m is not a rounding of the height at which the top face would
    meet the ground at x = 0 (-0.0302 m at 2 deg); it leaves a step of about
    0.2 mm there, and ramp results move by 5-15 % if it is "corrected"
    (docs/reference-hopper.md).

    Args:
        grade_deg: the ramp's pitch, deg (the paper's 2), strictly between
            -90 and 90 (:func:`check_ramp_grade`).

    Returns:
        (centre, quat): the box's centre, (3,) array in m, always
        (RAMP_CENTER_X, 0, RAMP_CENTER_Z) = (2, 0, -0.03) m; and its
        orientation, (4,) unit quaternion (w, x, y, z), a rotation by
        -grade about the y axis.

    Raises:
        ValueError: a pitch :func:`check_ramp_grade` refuses (None included:
            a flat ground has no ramp box).
    """
    if grade_deg is None:
        raise ValueError("grade_deg: a ramp needs a pitch in deg (None is flat ground, which has no ramp)")
    a = math.radians(check_ramp_grade(grade_deg))
    quat = np.array([math.cos(-a / 2), 0.0, math.sin(-a / 2), 0.0])
    return np.array([ref.RAMP_CENTER_X, 0.0, ref.RAMP_CENTER_Z]), quat


def terrain_height_m(x_m, y_m, ramp_grade_deg: float | None = None):
    """Height (m) of the terrain under world points (x, y): 0 on the flat
    ground; on the ramp behaviour the higher of the ground and the ramp
    box's top face, z = cz + hz / cos(a) + tan(a) (x - cx) over the box's
    footprint (a the grade angle; the box's far end and sides are not
    modelled: the hopper never reaches them). Arrays broadcast.
    tests/core/test_model.py checks it against MuJoCo's own ray casts.

    Args:
        x_m: world x of the points, m (scalar or array).
        y_m: world y of the points, m (broadcast against `x_m`).
        ramp_grade_deg: None for flat ground (default), else the ramp's
            pitch, deg (as :class:`mat_hopper.core.behaviours.Behaviour` holds
            it), strictly between -90 and 90.

    Returns:
        Float array of the broadcast shape of `x_m` and `y_m` (0-d for
        scalars), m: 0 on flat ground or off the ramp's footprint.

    Raises:
        ValueError: a pitch :func:`check_ramp_grade` refuses.
    """
    ramp_grade_deg = check_ramp_grade(ramp_grade_deg)
    x, y = np.asarray(x_m, dtype=float), np.asarray(y_m, dtype=float)
    ground = np.zeros(np.broadcast(x, y).shape)
    if ramp_grade_deg is None:
        return ground
    a = math.radians(ramp_grade_deg)
    (cx, _, cz), _ = ramp_pose(ramp_grade_deg)
    hx, hy, hz = ref.RAMP_HALF_SIZE
    u = (x - cx + hz * math.sin(a)) / math.cos(a)  # along the top face, from its centre
    top = cz + hz / math.cos(a) + math.tan(a) * (x - cx)
    on = (np.abs(u) <= hx) & (np.abs(y) <= hy)
    return np.where(on, np.maximum(ground, top), ground)


# The numbers terrain_height_at reads, in this order (terrain_params):
# a ramp (1) or flat ground (0), the box's centre x and z (m), its half
# sizes (m), and the sine, cosine and tangent of the grade.
TERRAIN_PARAMS = ("ramp", "cx_m", "cz_m", "hx_m", "hy_m", "hz_m", "sin_a", "cos_a", "tan_a")


def terrain_params(ramp_grade_deg: float | None = None) -> np.ndarray:
    """The terrain as :func:`terrain_height_at` reads it.

    Args:
        ramp_grade_deg: None for flat ground (default), else the ramp's
            pitch, deg, strictly between -90 and 90.

    Returns:
        Float array of the values named by :data:`TERRAIN_PARAMS`: all 0
        on flat ground; on the ramp 1, the box of :func:`ramp_pose` and
        :data:`mat_hopper.core.reference.RAMP_HALF_SIZE`, and the grade's
        sine, cosine and tangent.

    Raises:
        ValueError: a pitch :func:`check_ramp_grade` refuses.
    """
    grade = check_ramp_grade(ramp_grade_deg)
    if grade is None:
        return np.zeros(len(TERRAIN_PARAMS))
    a = math.radians(grade)
    (cx, _, cz), _ = ramp_pose(grade)
    hx, hy, hz = ref.RAMP_HALF_SIZE
    return np.array([1.0, cx, cz, hx, hy, hz, math.sin(a), math.cos(a), math.tan(a)], dtype=float)


@numba.njit(cache=True)
def terrain_height_at(x_m, y_m, params):
    """Height (m) of the terrain under one world point (x, y): the arithmetic
    of :func:`terrain_height_m` for a scalar, compiled (the rollout loop
    calls it); tests/core/test_apex_reference.py checks the two agree.

    Args:
        x_m, y_m: world x and y of the point, m.
        params: :func:`terrain_params` of the terrain.

    Returns:
        float, m: 0 on flat ground or off the ramp's footprint.
    """
    if params[0] == 0.0:
        return 0.0
    cx, cz, hx, hy, hz, sa, ca, ta = (
        params[1],
        params[2],
        params[3],
        params[4],
        params[5],
        params[6],
        params[7],
        params[8],
    )
    u = (x_m - cx + hz * sa) / ca  # along the top face, from its centre
    top = cz + hz / ca + ta * (x_m - cx)
    if abs(u) <= hx and abs(y_m) <= hy:
        return max(0.0, top)
    return 0.0
