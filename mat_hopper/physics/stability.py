"""The largest stable time step of a design, measured and estimated.

Measured (the reference hopper's criterion, docs/reference-hopper.md). A time step is *stable* for a design when
2 s of static hopping at that step (transient 0) end with no NaN or inf,
every |qacc| <= 1e6 and the base above 0.1 m: :attr:`Rollout.upright`.

- :func:`largest_stable_timestep`: log-scale search in [1e-6, 1e-2] s.
  Bracket (default ``"analytic"``): start at the analytic bound (below)
  and step by a factor 1.5 up while stable, down while unstable, until
  the outcome changes; the estimate lies within a factor 2 of the measured
  step, so this takes two or three tries. (``"ladder"``: try 1e-2 s,
  then steps a factor sqrt(10) smaller until one is stable; unstable
  tries are cheap, most diverge within a few steps, stable ones cost
  2 s / dt steps.) Then bisect in log space between the last unstable
  and the first stable step until they are within a factor `tolerance`
  (1.25) or `max_iter` (10) bisection tries are spent. Result: the bracket
  [dt_stable_s, dt_unstable_s].
  Assumption: stability is monotone in the time step between the bracket's
  ends (every step below a stable one is stable). It need not be: the
  criterion includes the controller's outcome (base above 0.1 m), which
  can fail at one step and pass at a larger one. The search finds the
  first stable step from above on its coarse ladder, so a stable island
  above the first unstable step is missed, and an unstable pocket inside
  the final bracket is not seen.
- :func:`spec_scan`: the reference protocol (docs/reference-hopper.md), the first stable step of 20
  log-spaced steps from 1e-3 down to 1e-5 s (nan if none). Beside the
  bisection it tests the monotonicity assumption (:func:`scan_consistent`).

Estimated. :func:`spring_chain_wmax`: the leg along its axis is a chain of
lumped masses joined by springs: the base with the stub and the upper half
of segment 1 (one body in MuJoCo, the hips do not move axially); the lower
half of segment i with the upper half of segment i+1; the last lower half
with the foot's upper capsule; the foot (0.5 kg) below the foot spring
(8000 N/m). The masses are read from the compiled MjModel (per body),
the stiffnesses from its joints; a rigid segment merges its bodies. Its
highest natural frequency w_max solves K v = w^2 M v
(``scipy.linalg.eigh(K, M)``, free-free). MuJoCo's Euler integrator treats
joint damping implicitly but springs explicitly (semi-implicit Euler), and
that is stable for w dt < 2: the estimate is dt < 2 / w_max
(``analytic_timestep_s``).

A second limit, not the material's. The controller's stance attitude
feedback is a rate gain on the base's roll and pitch, applied explicitly
and, under the authors' sensor timing, from a gyro reading one physics step
old: a damper of c = stance_kd x gear = 1 x 600 N m s/rad on the base's
inertia about a horizontal axis through the hip, I ~ 0.127 kg m^2. A rate
feedback read L steps late is stable for dt < c(L) I / c with
c(L) = 2 cos(L pi / (2 L + 1)) (:func:`delayed_damping_factor`): 2 I / c
~ 4.2e-4 s when fresh, I / c ~ 2.1e-4 s with the authors' one-step lag
(``controller_timestep_s``), whatever the leg's material: soft, heavy
legs, whose spring limit lies above it, hit this one instead (the measured
map plateaus there).
``combined_timestep_s`` is the smaller of the two.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from ..core import reference as ref
from ..core.materials import DEFAULT_CONVENTION, LegDesign, check_convention
from ..core.model import MIN_TIMESTEP_S
from ..core.stable_step import (
    controller_timestep,
    delayed_damping_factor,
    estimate_timestep,
    leg_chain,
    spring_chain_wmax,
)
from ..util.keys import design_key, hash_key, versions
from ..util.parsing import parse_name

# The analytic bounds live in mat_hopper.physics.modes (pure physics, no runner);
# re-exported here where the measured ones are.
__all__ = [
    "controller_timestep",
    "delayed_damping_factor",
    "estimate_timestep",
    "leg_chain",
    "spring_chain_wmax",
    "try_timestep",
    "largest_stable_timestep",
    "spec_scan",
    "scan_consistent",
    "StabilitySpec",
    "stability_grid",
    "agreement",
]

DT_MAX_S = 1e-2
DT_MIN_S = MIN_TIMESTEP_S
BRACKET_FACTOR = math.sqrt(10.0)  # the "ladder" bracket's step
ANALYTIC_FACTOR = 1.5  # the "analytic" bracket's step
ANALYTIC_SPREAD = 2.0  # the analytic estimate lies within this factor of the measured stable step
BRACKETS = ("analytic", "ladder")
DEFAULT_BRACKET = "analytic"
DEFAULT_TOLERANCE = 1.25
DEFAULT_MAX_ITER = 10
SPEC_SCAN_N = 20


# ---------------------------------------------------------------------------
# one try


def try_timestep(
    design: LegDesign,
    timestep_s: float,
    *,
    duration_s: float = ref.STABILITY_TEST_DURATION_S,
    convention: str = DEFAULT_CONVENTION,
) -> dict:
    """Static hopping for duration_s at timestep_s (transient 0): a dict
    with dt_s, stable (no divergence), upright (the criterion of docs/reference-hopper.md),
    diverged_at_s (nan if none) and final_base_z_m.

    Args:
        design: the leg (a LegDesign, or a design name as
            :func:`mat_hopper.core.sim.simulate` reads it).
        timestep_s: the physics step to try, s.
        duration_s: simulated seconds of static hopping (2 s, the reference's).
        convention: the stiffness convention, any case (default ``paper``).

    Returns:
        dict: dt_s (float, s), stable (bool), upright (bool), diverged_at_s
        (s, nan when stable) and final_base_z_m (the base's last recorded
        height, m; nan when nothing was recorded).

    Raises:
        ValueError: invalid settings (time step, duration, convention) or design.
    """
    from ..core.sim import C, SimSettings, simulate

    settings = SimSettings(duration_s=duration_s, timestep_s=timestep_s, transient_s=0.0, convention=convention)
    r = simulate(design, "static", settings=settings, warn=False)  # a try above the bound is the scan's question
    return {
        "dt_s": float(timestep_s),
        "stable": bool(r.stable),
        "upright": bool(r.upright),
        "diverged_at_s": math.nan if r.stable else float(r.diverged_at_s),
        "final_base_z_m": float(r.data[-1, C["z"]]) if len(r.data) else math.nan,
    }


def _check_range(dt_min, dt_max, tolerance, max_iter):
    if not (0 < dt_min < dt_max <= 0.1):
        raise ValueError(f"time step range must satisfy 0 < dt_min < dt_max <= 0.1 s, got [{dt_min}, {dt_max}]")
    if not tolerance > 1:
        raise ValueError(f"tolerance must be a factor > 1 (e.g. 1.25), got {tolerance!r}")
    if int(max_iter) < 0:
        raise ValueError(f"max_iter must be >= 0, got {max_iter!r}")


def _analytic_bracket(ok, start, dt_min, dt_max) -> tuple[float, float]:
    """Bracket around the analytic bound: try `start`; while stable step up,
    while unstable step down, by ANALYTIC_FACTOR, within [dt_min, dt_max]."""
    lo, hi = math.nan, math.nan
    dt = min(max(start, dt_min), dt_max)
    if ok(dt, "bracket"):
        lo = dt
        while lo < dt_max * (1 - 1e-12):
            up = min(lo * ANALYTIC_FACTOR, dt_max)
            if not ok(up, "bracket"):
                return lo, up
            lo = up
        return lo, math.nan
    hi = dt
    while hi > dt_min * (1 + 1e-12):
        down = max(hi / ANALYTIC_FACTOR, dt_min)
        if ok(down, "bracket"):
            return down, hi
        hi = down
    return math.nan, hi


def largest_stable_timestep(
    design: LegDesign,
    *,
    dt_min: float = DT_MIN_S,
    dt_max: float = DT_MAX_S,
    tolerance: float = DEFAULT_TOLERANCE,
    max_iter: int = DEFAULT_MAX_ITER,
    duration_s: float = ref.STABILITY_TEST_DURATION_S,
    convention: str = DEFAULT_CONVENTION,
    tries: list | None = None,
    bracket: str = DEFAULT_BRACKET,
) -> tuple[float, float]:
    """(dt_stable_s, dt_unstable_s): the largest stable step found and the
    smallest unstable step above it (see module doc). dt_unstable_s is nan
    when dt_max itself is stable; dt_stable_s is nan when nothing down to
    dt_min is. Every try is appended to `tries` (dicts) if given.

    bracket: ``"analytic"`` (default) starts at the analytic bound (the
    smaller of the spring chain's 2 / w_max and the controller's limit) and
    steps by a factor ANALYTIC_FACTOR (1.5) until the outcome changes;
    ``"ladder"`` starts at dt_max and steps down by sqrt(10), as before.

    Args:
        design: the leg.
        dt_min: the smallest step tried, s (> 0).
        dt_max: the largest step tried, s (dt_min < dt_max <= 0.1).
        tolerance: bisection stops when dt_unstable_s / dt_stable_s <= this
            factor (> 1).
        max_iter: most bisection tries (>= 0).
        duration_s: simulated seconds of static hopping per try.
        convention: the stiffness convention, any case.
        tries: a list to append every try to (the dicts of
            :func:`try_timestep` with ``method`` ``"bracket"`` or ``"bisect"``);
            None keeps them nowhere.
        bracket: ``"analytic"`` or ``"ladder"``, any case
            (:func:`mat_hopper.util.parsing.parse_name`).

    Returns:
        (dt_stable_s, dt_unstable_s), s; either may be nan as above.

    Raises:
        ValueError: a range not 0 < dt_min < dt_max <= 0.1 s, tolerance <= 1,
            max_iter < 0, an unknown bracket, or invalid try settings.
    """
    _check_range(dt_min, dt_max, tolerance, max_iter)
    bracket = parse_name(bracket, BRACKETS, "bracket")
    tries = [] if tries is None else tries  # the convention is spelled by each try's SimSettings

    def ok(dt, method):
        r = try_timestep(design, dt, duration_s=duration_s, convention=convention)
        r["method"] = method
        tries.append(r)
        return r["upright"]

    if bracket == "analytic":
        start = min(estimate_timestep(design, convention)[1], controller_timestep(design, convention))
        lo, hi = _analytic_bracket(ok, start, dt_min, dt_max)
    else:
        lo, hi = math.nan, math.nan
        dt, k = dt_max, 0
        while dt >= dt_min * (1 - 1e-12):
            if ok(dt, "bracket"):
                lo = dt
                break
            hi = dt
            k += 1
            dt = max(float(f"{dt_max / BRACKET_FACTOR**k:.12g}"), dt_min) if dt > dt_min * (1 + 1e-12) else 0.0
    if math.isnan(lo) or math.isnan(hi):
        return lo, hi
    for _ in range(int(max_iter)):
        if hi / lo <= tolerance:
            break
        mid = math.sqrt(lo * hi)
        if ok(mid, "bisect"):
            lo = mid
        else:
            hi = mid
    return lo, hi


def spec_ladder(
    first: float = ref.STABILITY_TIMESTEP_RANGE[0], last: float = ref.STABILITY_TIMESTEP_RANGE[1], n: int = SPEC_SCAN_N
) -> np.ndarray:
    """The reference protocol's time steps (s), largest first: n log-spaced
    from `first` down to `last`. One definition for every scan: a try's
    outcome can depend on the last bit of its step.

    Args:
        first: the largest step, s (1e-3).
        last: the smallest step, s (1e-5).
        n: the number of steps (20).

    Returns:
        (n,) array of steps, s (``numpy.geomspace(first, last, n)``).
    """
    return np.geomspace(first, last, int(n))


def spec_scan(
    design: LegDesign,
    *,
    first: float = ref.STABILITY_TIMESTEP_RANGE[0],
    last: float = ref.STABILITY_TIMESTEP_RANGE[1],
    n: int = SPEC_SCAN_N,
    duration_s: float = ref.STABILITY_TEST_DURATION_S,
    convention: str = DEFAULT_CONVENTION,
    tries: list | None = None,
) -> float:
    """The reference protocol (docs/reference-hopper.md): the first stable of n log-spaced steps from
    `first` down to `last` (s); nan when none is stable.

    Args:
        design: the leg.
        first: the largest step tried, s.
        last: the smallest step tried, s.
        n: the number of steps (:func:`spec_ladder`).
        duration_s: simulated seconds of static hopping per try.
        convention: the stiffness convention.
        tries: a list to append every try to (the dicts of
            :func:`try_timestep` with ``method`` ``"spec"``); None keeps them
            nowhere.

    Returns:
        The first upright step, s, or nan. The scan stops at it.

    Raises:
        ValueError: invalid try settings (duration, convention) or design.
    """
    tries = [] if tries is None else tries
    for dt in spec_ladder(first, last, n):
        r = try_timestep(design, float(dt), duration_s=duration_s, convention=convention)
        r["method"] = "spec"
        tries.append(r)
        if r["upright"]:
            return float(dt)
    return math.nan


def scan_consistent(
    dt_stable: float,
    dt_unstable: float,
    dt_spec: float,
    *,
    first: float = ref.STABILITY_TIMESTEP_RANGE[0],
    last: float = ref.STABILITY_TIMESTEP_RANGE[1],
    n: int = SPEC_SCAN_N,
) -> bool:
    """Whether the reference scan's answer fits the bisection's bracket if
    stability were monotone in the step: no ladder step >= dt_unstable is
    stable, and no ladder step <= dt_stable is passed over.

    Args:
        dt_stable: the bisection's largest stable step, s (nan: none found).
        dt_unstable: its smallest unstable step above, s (nan: none).
        dt_spec: the scan's first stable step, s (nan: none).
        first: the ladder's largest step, s.
        last: the ladder's smallest step, s.
        n: the ladder's number of steps.

    Returns:
        True when consistent (steps compared with a relative tolerance of
        1e-9). With dt_stable nan, True only when dt_spec is nan too; with
        dt_spec nan, True only when no ladder step lies at or below dt_stable.
    """
    ladder = spec_ladder(first, last, n)
    eps = 1e-9
    if math.isnan(dt_stable):
        return math.isnan(dt_spec)
    below = ladder[ladder <= dt_stable * (1 + eps)]
    if math.isnan(dt_spec):
        return len(below) == 0
    if not math.isnan(dt_unstable) and dt_spec >= dt_unstable * (1 - eps):
        return False
    return not len(below) or dt_spec >= below[0] * (1 - eps)


# ---------------------------------------------------------------------------
# the task


@dataclass(frozen=True, eq=False)
class StabilitySpec:
    """Stable-time-step measurement of one design (a runner task).

    duration_s of static hopping per try; bisection in [dt_min, dt_max] s
    to `tolerance` in at most `max_iter` tries; `scan`: also run the reference (docs/reference-hopper.md)
    20-step protocol. `convention` and `bracket` are names, any case, stored
    (and keyed) in their canonical spelling."""

    design: LegDesign
    duration_s: float = ref.STABILITY_TEST_DURATION_S
    dt_min: float = DT_MIN_S
    dt_max: float = DT_MAX_S
    tolerance: float = DEFAULT_TOLERANCE
    max_iter: int = DEFAULT_MAX_ITER
    scan: bool = True
    convention: str = DEFAULT_CONVENTION
    labels: dict = field(default_factory=dict)
    bracket: str = DEFAULT_BRACKET

    kind = "stability"

    def __post_init__(self):
        _check_range(self.dt_min, self.dt_max, self.tolerance, self.max_iter)
        if not self.duration_s > 0:
            raise ValueError(f"duration_s must be > 0 s, got {self.duration_s!r}")
        object.__setattr__(self, "convention", check_convention(self.convention))
        object.__setattr__(self, "bracket", parse_name(self.bracket, BRACKETS, "bracket"))

    def estimated_steps(self) -> float:
        """Physics steps at most, before the run (the plan and the run-size
        limit), every try counted at full length (an unstable one stops at
        its divergence). With the analytic bracket and the estimate within
        :data:`ANALYTIC_SPREAD` of the measured step (module doc): at most
        three bracket tries and the bisection's, none below start /
        ANALYTIC_FACTOR^3, and a scan that stops by start / ANALYTIC_SPREAD.
        Otherwise (the ladder bracket): `max_iter` tries at the geometric
        mean of [dt_min, dt_max] and the whole ladder."""
        if self.bracket != "analytic":
            steps = self.max_iter * self.duration_s / math.sqrt(self.dt_min * self.dt_max)
            return float(steps + (sum(self.duration_s / dt for dt in spec_ladder()) if self.scan else 0.0))
        start = min(
            estimate_timestep(self.design, self.convention)[1], controller_timestep(self.design, self.convention)
        )
        start = min(max(start, self.dt_min), self.dt_max)
        bisect = math.ceil(math.log2(math.log(ANALYTIC_FACTOR) / math.log(self.tolerance))) if self.max_iter else 0
        tries = 3 + min(max(bisect, 0), int(self.max_iter))
        steps = tries * self.duration_s / max(start / ANALYTIC_FACTOR**3, self.dt_min)
        if self.scan:
            ladder = spec_ladder()
            last = np.flatnonzero(ladder <= start / ANALYTIC_SPREAD)  # the first ladder step surely stable
            steps += float(sum(self.duration_s / dt for dt in ladder[: (last[0] + 1) if len(last) else None]))
        return float(steps)

    def key_dict(self) -> dict:
        return {
            "kind": self.kind,
            "design": design_key(self.design),
            "duration_s": self.duration_s,
            "dt_min": self.dt_min,
            "dt_max": self.dt_max,
            "tolerance": self.tolerance,
            "max_iter": int(self.max_iter),
            "scan": bool(self.scan),
            "bracket": self.bracket,
            "bracket_factor": BRACKET_FACTOR if self.bracket == "ladder" else ANALYTIC_FACTOR,
            "scan_range": list(ref.STABILITY_TIMESTEP_RANGE),
            "scan_n": SPEC_SCAN_N,
            "criterion": [ref.DIVERGENCE_QACC, ref.STABLE_MIN_BASE_Z],
            "convention": self.convention,
            "versions": versions(),
        }

    def key(self) -> str:
        return f"{self.kind}-{hash_key(self.key_dict())}"

    def default_labels(self) -> dict:
        d = self.design
        return {
            "design": d.name,
            "density_g_cm3": d.densities_g_cm3[0] if d.n_segments else math.nan,
            "modulus_gpa": d.moduli_gpa[0],
        }

    def compute(self) -> tuple[pd.DataFrame, dict]:
        """(every try as a table, the design's summary: max_stable_timestep_s,
        unstable_timestep_s, spec_timestep_s, analytic_timestep_s, ...)."""
        tries: list[dict] = []
        lo, hi = largest_stable_timestep(
            self.design,
            dt_min=self.dt_min,
            dt_max=self.dt_max,
            tolerance=self.tolerance,
            max_iter=self.max_iter,
            duration_s=self.duration_s,
            convention=self.convention,
            tries=tries,
            bracket=self.bracket,
        )
        n_search = len(tries)
        dt_spec = (
            spec_scan(self.design, duration_s=self.duration_s, convention=self.convention, tries=tries)
            if self.scan
            else math.nan
        )
        masses, springs = leg_chain(self.design, self.convention)
        w = spring_chain_wmax(masses, springs)
        est = 2.0 / w
        ctrl = controller_timestep(self.design, self.convention)
        consistent = scan_consistent(lo, hi, dt_spec) if self.scan else True
        summary = {
            "n_segments": self.design.n_segments,
            "max_stable_timestep_s": lo,
            "unstable_timestep_s": hi,
            "n_tries": n_search,
            "spec_timestep_s": dt_spec,
            "n_spec_tries": len(tries) - n_search,
            "scan_consistent": bool(consistent),
            "w_max_rad_s": w,
            "analytic_timestep_s": est,
            "ratio_measured_to_analytic": lo / est if not math.isnan(lo) else math.nan,
            "controller_timestep_s": ctrl,
            "combined_timestep_s": min(est, ctrl),
            "max_material_spring_n_m": max(springs[:-1]) if len(springs) > 1 else math.nan,
            "lightest_mass_kg": min(masses),
            "status": "ok" if not math.isnan(lo) else "unstable",
        }
        return pd.DataFrame(
            tries, columns=["method", "dt_s", "stable", "upright", "diverged_at_s", "final_base_z_m"]
        ), summary


def stability_grid(size: int = ref.STABILITY_GRID_SIZE) -> tuple[np.ndarray, np.ndarray]:
    """The map axes of docs/reference-hopper.md: densities (g/cm^3) and moduli
    (GPa), log-spaced over its ranges and rounded to 0.1, `size` values each.

    Args:
        size: values per axis (an integer >= 1; 20, the reference's).

    Returns:
        (densities_g_cm3, moduli_gpa): two (size,) arrays, log-spaced over
        [1.39, 8.0] g/cm^3 and [4.0, 340.0] GPa before rounding; with size 1,
        each range's geometric mean (rounded alike).

    Raises:
        ValueError: size < 1.
    """
    size = int(size)
    if size < 1:
        raise ValueError(f"stability grid size must be >= 1, got {size!r}")
    if size == 1:
        return (
            np.array([round(math.sqrt(np.prod(ref.STABILITY_DENSITY_RANGE)), 1)]),
            np.array([round(math.sqrt(np.prod(ref.STABILITY_MODULUS_RANGE)), 1)]),
        )
    d = np.round(np.geomspace(*ref.STABILITY_DENSITY_RANGE, size), 1)
    e = np.round(np.geomspace(*ref.STABILITY_MODULUS_RANGE, size), 1)
    return d, e


ESTIMATES = {"spring": "analytic_timestep_s", "combined": "combined_timestep_s"}


def agreement(table: pd.DataFrame) -> pd.DataFrame:
    """How well each estimate predicts the measured map: ``spring`` (2 /
    w_max, analytic_timestep_s) and ``combined`` (the smaller of it and the
    controller limit), over the designs with a measured step: log-log
    Pearson r and least-squares slope of log(measured) on log(estimate),
    median and range of measured / estimate, the fractions within a factor
    2 and with the estimate inside the measured bracket [max_stable,
    unstable); and the fraction where the reference scan ("spec scan") fits the bracket.
    Columns: estimate, quantity, value.

    Args:
        table: the stability map's summary, one row per design (as
            :meth:`StabilitySpec.compute` gives): max_stable_timestep_s,
            unstable_timestep_s, analytic_timestep_s and/or
            combined_timestep_s (an estimate whose column is missing is
            skipped), optionally scan_consistent.

    Returns:
        DataFrame with columns estimate (``spring``, ``combined``, ``spec
        scan``), quantity and value. Per estimate: n_designs, n_measured
        (rows with a finite measured step and estimate); with one measured or
        more, median_ratio_measured_to_estimate, min_ratio, max_ratio,
        fraction_within_factor_2, fraction_estimate_in_bracket; with three or
        more (and spread in both), loglog_pearson_r and loglog_slope. The
        ``spec scan`` row, fraction_scan_consistent, is over every row of
        `table`.
    """
    rows = []
    for name, col in ESTIMATES.items():
        if col not in table.columns:
            continue
        for q, v in _agreement_one(table, col).items():
            rows.append({"estimate": name, "quantity": q, "value": v})
    if "scan_consistent" in table and len(table):
        rows.append(
            {
                "estimate": "spec scan",
                "quantity": "fraction_scan_consistent",
                "value": float(table["scan_consistent"].astype(bool).mean()),
            }
        )
    return pd.DataFrame(rows, columns=["estimate", "quantity", "value"])


def _agreement_one(table: pd.DataFrame, col: str) -> dict:
    meas, est = table["max_stable_timestep_s"].astype(float), table[col].astype(float)
    ok = table[np.isfinite(meas) & np.isfinite(est)]
    n = len(ok)
    rows = {"n_designs": float(len(table)), "n_measured": float(n)}
    if n >= 1:
        lo = ok["max_stable_timestep_s"].to_numpy(float)
        hi = ok["unstable_timestep_s"].to_numpy(float)
        an = ok[col].to_numpy(float)
        ratio = lo / an
        rows.update(
            {
                "median_ratio_measured_to_estimate": float(np.median(ratio)),
                "min_ratio": float(ratio.min()),
                "max_ratio": float(ratio.max()),
                "fraction_within_factor_2": float(np.mean((ratio >= 0.5) & (ratio <= 2.0))),
                "fraction_estimate_in_bracket": float(np.mean((lo <= an) & (~np.isfinite(hi) | (an < hi)))),
            }
        )
    if n >= 3:
        x, y = np.log(ok[col].to_numpy(float)), np.log(ok["max_stable_timestep_s"].to_numpy(float))
        if np.ptp(x) > 0 and np.ptp(y) > 0:
            rows["loglog_pearson_r"] = float(np.corrcoef(x, y)[0, 1])
            rows["loglog_slope"] = float(np.polyfit(x, y, 1)[0])
    return rows
