"""The four behaviours as desired paths of simulated time, plus your own.

A :class:`Behaviour` is a desired planar path of the base, x(t), y(t) in m,
with its velocity, on flat ground or on a ramp. The paths are evaluated in
the compiled rollout loop, so they are encoded as a kind and a few numbers:

- ``line``: x = x0 + v t cos(h), y = y0 + v t sin(h) (static: v = 0);
- ``circle``: radius r about the origin at speed v, x = r cos(v t / r),
  y = r sin(v t / r);
- ``table``: your own path, sampled on a uniform time grid and interpolated
  linearly (hold the last point after the end). Build it with
  :meth:`Behaviour.from_function` (any Python callable t -> (x, y)) or
  :meth:`Behaviour.from_samples`.

Example, a figure-eight of your own::

    fig8 = Behaviour.from_function(
        "figure8", lambda t: (0.3 * np.sin(0.1 * t), 0.15 * np.sin(0.2 * t)),
        duration_s=60.0)
    simulate(design, fig8)
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numba
import numpy as np

from ..util.limits import MAX_PATH_SAMPLES
from ..util.parsing import check_positive
from . import reference as ref

PATH_LINE, PATH_CIRCLE, PATH_TABLE = 0, 1, 2
_PATH_CODES = {"line": PATH_LINE, "circle": PATH_CIRCLE, "table": PATH_TABLE}
BEHAVIOUR_NAMES = ("static", "forward", "ramp", "circle")
DEFAULT_BEHAVIOUR = "forward"  # the CLI's simulate, render and batch


def order_behaviours(behaviours) -> list[str]:
    """Behaviour names in the paper's order (:data:`BEHAVIOUR_NAMES`), then
    the others as first seen; each once.

    Args:
        behaviours: an iterable of behaviour names (str), repeats allowed.

    Returns:
        A list of the distinct names: those of :data:`BEHAVIOUR_NAMES` in
        that order, then the rest in order of first appearance.

    >>> order_behaviours(["circle", "static", "circle"])
    ['static', 'circle']
    """
    seen = list(dict.fromkeys(behaviours))
    return [b for b in BEHAVIOUR_NAMES if b in seen] + [b for b in seen if b not in BEHAVIOUR_NAMES]


@dataclass(frozen=True, eq=False)
class Behaviour:
    """A desired path and the terrain it is hopped on.

    Args:
        name: the behaviour's name (recorded in results).
        path: ``"line"``, ``"circle"`` or ``"table"`` (your own path).
        speed_m_s: commanded speed along the path, m/s.
        radius_m: circle radius, m.
        heading_rad: direction of a line path, rad from +x.
        ramp_grade_deg: None for flat ground, else the ramp's pitch in
            degrees (2 deg = 3.5 % grade).
        start_xy_m: where the base starts, (x, y) m.
        table_dt_s: time between the rows of a table path, s (finite,
            > 0 for a table path).
        table_xy_m: a table path's desired positions, (n, 2) m, at most
            :data:`mat_hopper.util.limits.MAX_PATH_SAMPLES` rows.

    Raises:
        ValueError: an unknown path or a value out of range (a speed,
            radius, heading or start not finite; a table not finite, not
            (n, 2) or over MAX_PATH_SAMPLES rows; a table time step not
            finite and > 0).
    """

    name: str
    path: str = "line"
    speed_m_s: float = 0.0
    radius_m: float = ref.CIRCLE_RADIUS
    heading_rad: float = 0.0
    ramp_grade_deg: float | None = None
    start_xy_m: tuple[float, float] = (0.0, 0.0)
    table_dt_s: float = 0.0
    table_xy_m: np.ndarray = field(default_factory=lambda: np.zeros((1, 2)))

    def __post_init__(self):
        if self.path not in _PATH_CODES:
            raise ValueError(f"path must be one of {', '.join(_PATH_CODES)}, got {self.path!r}")
        for fname in ("speed_m_s", "radius_m", "heading_rad", "table_dt_s"):
            if not math.isfinite(float(getattr(self, fname))):
                raise ValueError(f"{fname} must be finite, got {getattr(self, fname)!r}")
        if self.speed_m_s < 0:
            raise ValueError(f"speed_m_s must be >= 0 m/s, got {self.speed_m_s!r}")
        if self.path == "circle" and not self.radius_m > 0:
            raise ValueError(f"radius_m must be > 0 m, got {self.radius_m!r}")
        if self.ramp_grade_deg is not None and not (0.0 <= float(self.ramp_grade_deg) < 30.0):
            raise ValueError(f"ramp_grade_deg must be in [0, 30) deg, got {self.ramp_grade_deg!r}")
        rows = (np.shape(self.table_xy_m) or (0,))[0]  # before any copy of the table
        if rows > MAX_PATH_SAMPLES:
            raise ValueError(f"table_xy_m has {rows} rows, over the limit of {MAX_PATH_SAMPLES} (MAX_PATH_SAMPLES)")
        table = np.ascontiguousarray(self.table_xy_m, dtype=np.float64)
        if table.ndim != 2 or table.shape[1] != 2 or not np.all(np.isfinite(table)):
            raise ValueError("table_xy_m must be a finite (n, 2) array of x, y in m")
        object.__setattr__(self, "table_xy_m", table)
        start = np.asarray(self.start_xy_m, dtype=np.float64)
        if start.shape != (2,) or not np.all(np.isfinite(start)):
            raise ValueError(f"start_xy_m must be a finite (x, y) in m, got {self.start_xy_m!r}")
        if self.path == "table" and not self.table_dt_s > 0:
            raise ValueError(f"table_dt_s must be > 0 s, got {self.table_dt_s!r}")

    # -- encoding for the compiled loop --
    @property
    def path_code(self) -> int:
        return _PATH_CODES[self.path]

    @property
    def path_params(self) -> np.ndarray:
        return np.array(
            [self.speed_m_s, self.radius_m, self.heading_rad, self.start_xy_m[0], self.start_xy_m[1], self.table_dt_s]
        )

    def desired(self, t: float) -> tuple[float, float, float, float]:
        """Desired (x, y, vx, vy) in m and m/s at simulated time t (s)."""
        return desired_state(float(t), self.path_code, self.path_params, self.table_xy_m)

    def key(self) -> dict:
        """Every setting that changes a result, for cache keys and tables."""
        d = {
            "name": self.name,
            "path": self.path,
            "speed_m_s": self.speed_m_s,
            "radius_m": self.radius_m,
            "heading_rad": self.heading_rad,
            "ramp_grade_deg": self.ramp_grade_deg,
            "start_xy_m": list(self.start_xy_m),
        }
        if self.path == "table":
            d["table_dt_s"] = self.table_dt_s
            d["table_sha"] = __import__("hashlib").sha256(self.table_xy_m.tobytes()).hexdigest()[:16]
        return d

    # -- constructors --
    @classmethod
    def from_samples(cls, name: str, dt_s: float, xy_m, *, ramp_grade_deg: float | None = None) -> Behaviour:
        """Your own path from positions (n, 2) in m sampled every dt_s seconds from t = 0.

        Args:
            name: the behaviour's name.
            dt_s: time between samples, s (finite, > 0).
            xy_m: the positions, (n, 2) m, finite, n at most
                :data:`mat_hopper.util.limits.MAX_PATH_SAMPLES`.
            ramp_grade_deg: None (flat) or the ramp's pitch, deg, in [0, 30).

        Returns:
            The table :class:`Behaviour`, starting at the first sample.

        Raises:
            ValueError: `dt_s` not a finite number > 0, `xy_m` not a finite
                (n, 2) array or over MAX_PATH_SAMPLES rows, or a grade out
                of range.
        """
        dt_s = check_positive(dt_s, "dt_s", unit="s")
        xy = np.asarray(xy_m, dtype=np.float64)
        start = (float(xy[0, 0]), float(xy[0, 1])) if xy.ndim == 2 and len(xy) else (0.0, 0.0)
        return cls(
            name, "table", ramp_grade_deg=ramp_grade_deg, start_xy_m=start, table_dt_s=float(dt_s), table_xy_m=xy
        )

    @classmethod
    def from_function(
        cls,
        name: str,
        fn: Callable[[float], tuple[float, float]],
        duration_s: float,
        dt_s: float = 1e-3,
        *,
        ramp_grade_deg: float | None = None,
    ) -> Behaviour:
        """Your own path from a Python function t (s) -> (x, y) (m), sampled every dt_s.

        Args:
            name: the behaviour's name.
            fn: called once per sample with t (s, a float), returns (x, y) in m.
            duration_s: how long the path lasts, s (finite, > 0); it holds
                its last point after.
            dt_s: time between samples, s (finite, > 0; default 1 ms).
            ramp_grade_deg: None (flat) or the ramp's pitch, deg, in [0, 30).

        Returns:
            The table :class:`Behaviour` of ceil(duration_s / dt_s) + 1
            samples from t = 0.

        Raises:
            ValueError: an empty or blank `name`, `fn` not callable,
                `duration_s` or `dt_s` not a finite number > 0, more
                samples than :data:`mat_hopper.util.limits.MAX_PATH_SAMPLES`
                (checked before `fn` is called), `fn` returning anything
                but two finite numbers (naming `fn`, the time and what it
                returned), or what :meth:`from_samples` refuses.
        """
        if not isinstance(name, str) or not name.strip():
            raise ValueError(f"name must be a non-empty string, got {name!r}")
        if not callable(fn):
            raise ValueError(f"fn must be callable t (s) -> (x, y) (m), got {type(fn).__name__} {fn!r:.60}")
        duration_s = check_positive(duration_s, "duration_s", unit="s")
        dt_s = check_positive(dt_s, "dt_s", unit="s")
        n = math.ceil(duration_s / dt_s) + 1
        if n > MAX_PATH_SAMPLES:
            raise ValueError(
                f"duration_s / dt_s = {duration_s:g} s / {dt_s:g} s is {n:.3g} samples, over the limit of "
                f"{MAX_PATH_SAMPLES} (MAX_PATH_SAMPLES); sample coarser or shorter"
            )
        ts = np.arange(n) * dt_s
        xy = np.array([_point(fn, float(t)) for t in ts], dtype=np.float64).reshape(len(ts), 2)
        return cls.from_samples(name, dt_s, xy, ramp_grade_deg=ramp_grade_deg)


def _point(fn, t: float) -> tuple[float, float]:
    """fn(t) as two finite floats (x, y); ValueError naming `fn` and what it returned."""
    got = fn(t)
    try:
        xy = np.asarray(got, dtype=np.float64)
    except (TypeError, ValueError):
        xy = None
    if xy is None or xy.shape != (2,) or not np.isfinite(xy).all():
        raise ValueError(f"fn must return two finite numbers (x, y) in m; fn({t:g}) returned {got!r:.80}")
    return float(xy[0]), float(xy[1])


def behaviour(
    name: str,
    *,
    speed_m_s: float = ref.SPEED_M_S,
    radius_m: float = ref.CIRCLE_RADIUS,
    grade_deg: float = ref.RAMP_GRADE_DEG,
) -> Behaviour:
    """One of the paper's behaviours by name.

    Args:
        name: ``"static"``, ``"forward"``, ``"ramp"`` or ``"circle"`` (any
            case); a Behaviour is returned as is.
        speed_m_s: commanded speed, m/s (the paper's 0.05).
        radius_m: the circle's radius, m (0.5).
        grade_deg: the ramp's pitch, deg (2).

    Returns:
        The :class:`Behaviour`.

    Raises:
        ValueError: an unknown name.
    """
    if isinstance(name, Behaviour):
        return name
    key = str(name).strip().lower()
    if key == "static":
        return Behaviour("static", "line", 0.0)
    if key == "forward":
        return Behaviour("forward", "line", speed_m_s)
    if key == "ramp":
        return Behaviour("ramp", "line", speed_m_s, ramp_grade_deg=grade_deg)
    if key == "circle":
        return Behaviour("circle", "circle", speed_m_s, radius_m=radius_m, start_xy_m=(radius_m, 0.0))
    from ..util.parsing import did_you_mean

    hint = f"; {did_you_mean(name, BEHAVIOUR_NAMES)}" if did_you_mean(name, BEHAVIOUR_NAMES) else ""
    raise ValueError(f"unknown behaviour {name!r}; accepted: {', '.join(BEHAVIOUR_NAMES)}{hint}")


@numba.njit(cache=True)
def desired_state(t, kind, params, table):
    """Desired base (x, y, vx, vy) in m, m/s at time t (s); compiled and plain."""
    speed, radius, heading, x0, y0, table_dt = params[0], params[1], params[2], params[3], params[4], params[5]
    if kind == PATH_CIRCLE:
        w = speed / radius
        c, s = math.cos(w * t), math.sin(w * t)
        return radius * c, radius * s, -speed * s, speed * c
    if kind == PATH_TABLE:
        n = table.shape[0]
        u = t / table_dt
        i = int(math.floor(u))
        if i >= n - 1:
            return table[n - 1, 0], table[n - 1, 1], 0.0, 0.0
        if i < 0:
            return table[0, 0], table[0, 1], 0.0, 0.0
        f = u - i
        dx = table[i + 1, 0] - table[i, 0]
        dy = table[i + 1, 1] - table[i, 1]
        return table[i, 0] + f * dx, table[i, 1] + f * dy, dx / table_dt, dy / table_dt
    vx, vy = speed * math.cos(heading), speed * math.sin(heading)
    return x0 + vx * t, y0 + vy * t, vx, vy
