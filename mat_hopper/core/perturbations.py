"""Seeded small perturbations, for true replicates of a deterministic run.

A perfectly symmetric deterministic simulation repeats itself: hop cycles of
one run are not independent samples, and in-place hopping has no lateral
motion at all (tracking error exactly zero for every design). Replicates
break the symmetry with small, documented, seeded disturbances:

- start: the base starts offset in x and y (normal, std ``start_offset_m``)
  and tilted in roll and pitch (normal, std ``start_tilt_rad``);
- push: one horizontal force of ``push_force_n`` newtons on the base for
  ``push_duration_s`` seconds, in a random direction, at a random time in
  ``push_window_s``;
- sensor noise: the controller's reading of base position (m) and velocity
  (m/s) gets Gaussian noise of std ``noise_pos_m`` / ``noise_vel_m_s``,
  redrawn every ``noise_period_s`` (a 1 kHz sensor by default).

The controller is not robust to large pushes: 20 N for 0.1 s (2 N s) topples
the stainless-steel hopper; the replicate default of 5 N for 0.1 s does not.

Every draw comes from ``numpy.random.default_rng(seed)``: the same seed gives
the same replicate, bit for bit.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..util.parsing import is_real

# The book's replicate (Perturbation.replicate). The push falls inside the
# scored window of every profile: between PUSH_WINDOW_FRACTION of the way
# from the transient's end to the run's end (quick, 4-12 s: 4.8-8 s; paper,
# 20-60 s: 24-40 s), leaving the second half of the window to recover.
REPLICATE_PUSH_FORCE_N = 5.0  # N, times push_scale
# The largest push_scale accepted: 100 x 5 N = 500 N for 0.1 s, an impulse of
# 50 N s, 2 to 3 m/s to the 17-24 kg hopper (MD to SS), 40 to 60 times its
# 0.05 m/s commanded speed: far past any push a robustness study asks of a
# hopping robot (mat_hopper.experiments.controls.PUSH_SCALES runs 0, 1, 2).
MAX_PUSH_SCALE = 100.0
REPLICATE_PUSH_DURATION_S = 0.1
PUSH_WINDOW_FRACTION = (0.1, 0.5)


def check_push_scale(push_scale, flag: str = "push_scale") -> float:
    """A push scale (the factor on the replicates' 5 N push) as a float in
    [0, :data:`MAX_PUSH_SCALE`].

    Args:
        push_scale: the factor, an int or a float (0: no push).
        flag: the argument or option named in errors (``--push-scale``).

    Returns:
        `push_scale` as a float.

    Raises:
        ValueError: a bool, a non-number, nan, inf, or a value outside
            [0, 100], naming `flag`.
    """
    ok = is_real(push_scale)
    x = float(push_scale) if ok else math.nan
    if not (math.isfinite(x) and 0 <= x <= MAX_PUSH_SCALE):
        raise ValueError(
            f"{flag} must be a finite number in [0, {MAX_PUSH_SCALE:g}] (x {REPLICATE_PUSH_FORCE_N:g} N; 0: no push), "
            f"got {push_scale!r}"
        )
    return x


@dataclass(frozen=True)
class Perturbation:
    """Small seeded disturbances (units in the names). All zero: none."""

    seed: int = 0
    start_offset_m: float = 0.0
    start_tilt_rad: float = 0.0
    push_force_n: float = 0.0
    push_duration_s: float = 0.1
    push_window_s: tuple[float, float] = (5.0, 15.0)
    noise_pos_m: float = 0.0
    noise_vel_m_s: float = 0.0
    noise_period_s: float = 1e-3

    def __post_init__(self):
        if not isinstance(self.seed, (int, np.integer)) or self.seed < 0:
            raise ValueError(f"seed must be an integer >= 0, got {self.seed!r}")
        for name in ("start_offset_m", "start_tilt_rad", "push_force_n", "noise_pos_m", "noise_vel_m_s"):
            v = getattr(self, name)
            if not (is_real(v) and math.isfinite(v) and v >= 0):
                raise ValueError(f"{name} must be a finite number >= 0, got {v!r}")
        if not self.push_duration_s > 0 or not self.noise_period_s > 0:
            raise ValueError("push_duration_s and noise_period_s must be > 0 s")
        a, b = self.push_window_s
        if not 0 <= a <= b:
            raise ValueError(f"push_window_s must be (start, end) with 0 <= start <= end s, got {self.push_window_s!r}")

    @classmethod
    def replicate(
        cls, seed: int, scored_window_s: tuple[float, float] | None = None, push_scale: float = 1.0
    ) -> Perturbation:
        """The book's replicate: 5 mm start offset, 0.5 deg tilt, a push of
        push_scale x 5 N for 0.1 s, 1 mm and 5 mm/s sensor noise (std).

        Args:
            seed: the replicate's seed (>= 0).
            scored_window_s: (transient end, run end) in s: the push time is
                drawn in :func:`push_window_s` of it, inside the scored hops.
                None keeps the historical 5-15 s window (which falls in the
                paper profile's unscored transient).
            push_scale: factor on the push force, in [0, :data:`MAX_PUSH_SCALE`]
                (0: no push).

        Raises:
            ValueError: a bad seed or window, or a scale that is not a
                number in [0, 100] (:func:`check_push_scale`).
        """
        window = (5.0, 15.0) if scored_window_s is None else push_window_s(*scored_window_s)
        push_scale = check_push_scale(push_scale)
        return cls(
            seed=seed,
            start_offset_m=0.005,
            start_tilt_rad=math.radians(0.5),
            push_force_n=REPLICATE_PUSH_FORCE_N * push_scale,
            push_duration_s=REPLICATE_PUSH_DURATION_S,
            push_window_s=window,
            noise_pos_m=0.001,
            noise_vel_m_s=0.005,
        )

    @property
    def has_noise(self) -> bool:
        return self.noise_pos_m > 0 or self.noise_vel_m_s > 0

    def draw(self, duration_s: float, timestep_s: float):
        """Deterministic draws: (start xy offset m, start roll/pitch rad,
        push [t0, t1, fx, fy], noise table (n, 6), steps per noise row)."""
        rng = np.random.default_rng(self.seed)
        start_xy = rng.normal(0.0, 1.0, 2) * self.start_offset_m
        tilt = rng.normal(0.0, 1.0, 2) * self.start_tilt_rad
        t0 = rng.uniform(*self.push_window_s)
        angle = rng.uniform(0.0, 2 * math.pi)
        push = np.array(
            [t0, t0 + self.push_duration_s, self.push_force_n * math.cos(angle), self.push_force_n * math.sin(angle)]
        )
        every = max(1, int(round(self.noise_period_s / timestep_s)))
        if self.has_noise:
            n = int(math.ceil(duration_s / timestep_s / every)) + 1
            noise = rng.normal(0.0, 1.0, (n, 6))
            noise[:, :3] *= self.noise_pos_m
            noise[:, 3:] *= self.noise_vel_m_s
        else:
            noise = np.zeros((1, 6))
            every = 1 << 60
        return start_xy, tilt, push, noise, every


NO_PUSH = np.array([np.inf, np.inf, 0.0, 0.0])


def push_window_s(transient_s: float, duration_s: float) -> tuple[float, float]:
    """Where a replicate's push starts (s): PUSH_WINDOW_FRACTION of the way
    through the scored window [transient_s, duration_s].

    Args:
        transient_s: the scored window's start (the transient's end), s.
        duration_s: the run's end, s.

    Returns:
        (start, end) of the push window, s: transient_s + f (duration_s -
        transient_s) for each f of :data:`PUSH_WINDOW_FRACTION` (0.1, 0.5).

    >>> push_window_s(20.0, 60.0)
    (24.0, 40.0)

    Raises:
        ValueError: duration_s not after transient_s, a negative
            transient_s, or either not finite.
    """
    t0, t1 = float(transient_s), float(duration_s)
    if not (math.isfinite(t0) and math.isfinite(t1) and 0 <= t0 < t1):
        raise ValueError(f"the scored window needs 0 <= transient_s < duration_s, got {transient_s!r}, {duration_s!r}")
    a, b = PUSH_WINDOW_FRACTION
    return (t0 + a * (t1 - t0), t0 + b * (t1 - t0))
