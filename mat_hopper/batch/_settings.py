"""Settings and result tables shared by the batch backends."""

from __future__ import annotations

import math
from dataclasses import dataclass, fields

import numpy as np
import pandas as pd

from ..core.sim import SimSettings

# One row per design, in this column order (the CLI writes exactly these).
RESULT_COLUMNS = ("design", "n_hops", "hop_height_m", "tracking_error_m", "power_w", "stable")
# What the library's tables carry besides.
# upright: stable and the base above reference.STABLE_MIN_BASE_Z at the last
# recorded sample (Rollout.upright); fell_at_s: when the base first tilted
# past core.rollout.FELL_TILT_DEG (s; NaN if never, and on the warp backend,
# which does not track the tilt); suspect_at_s: when a run that did not
# diverge first scored a hop apex far above the target, its numbers
# corrupted (core.rollout.Rollout.suspect_apex; s, NaN if never, and on the
# warp backend, which keeps no apexes); run_tracking_error_m, run_power_w: means
# over every finite recorded sample of the run, hop cycles or not (the
# optimizer's score of a run without scored hops).
EXTRA_COLUMNS = (
    "behaviour",
    "sensor_timing",
    "diverged_at_s",
    "total_mass_kg",
    "backend",
    "upright",
    "fell_at_s",
    "suspect_at_s",
    "run_tracking_error_m",
    "run_power_w",
)
BACKENDS = ("mujoco", "warp")


@dataclass(frozen=True)
class BatchSettings(SimSettings):
    """Run settings of a batch: a :class:`~mat_hopper.core.sim.SimSettings` (the
    one declaration of every field, its defaults and checks) restricted to
    what every backend runs, the same for every design in it.

    Args:
        **fields: any SimSettings field. ``record_rate_hz`` is the rate (Hz)
            at which per-hop metrics sample the run (1 kHz);
            ``sensor_timing`` (a :class:`~mat_hopper.core.controller.SensorTiming`)
            how many physics steps old the base sensors are when the
            controller reads them: 1 (``"authors"``) is the authors' loop,
            ``d.sensordata`` as the previous physics step left it (touch,
            base position, quaternion, gyro and linear velocity one step
            old), hip angles and rates from the current ``qpos``/``qvel``;
            at step 0 the sensors of the initial state. Both backends take
            any latency (the warp backend keeps a ring of past readings on
            the device, :mod:`mat_hopper.batch._kernels`).

    Raises:
        ValueError: for any invalid SimSettings value, and for
            ``substeps`` other than 1 (the controller runs every physics
            step, as in the authors' loop) or a ``perturbation`` (a batch
            runs the unperturbed protocol).
    """

    def __post_init__(self):
        super().__post_init__()
        if self.substeps != 1:
            raise ValueError(
                f"substeps must be 1 in a batch (the controller runs every physics step), got {self.substeps!r}"
            )
        if self.perturbation is not None:
            raise ValueError("perturbation must be None in a batch (it runs the unperturbed protocol)")

    @classmethod
    def of(cls, settings: SimSettings) -> BatchSettings:
        """The batch view of a SimSettings (the same fields; ValueError where a batch cannot run it)."""
        if isinstance(settings, cls):
            return settings
        return cls(**{f.name: getattr(settings, f.name) for f in fields(SimSettings)})


def design_settings(design, settings: BatchSettings, auto_timestep: bool = False) -> SimSettings:
    """The settings one design of a batch runs under.

    Args:
        design: the leg (a LegDesign or a name).
        settings: the batch's :class:`BatchSettings`.
        auto_timestep: False: the batch's own settings, one physics step for
            every design; True: the same with ``timestep_s="auto"`` for this
            design (its own physics substeps of its control period,
            :func:`mat_hopper.core.timestep.resolve_timestep`; the batch's
            timestep_s is then unused).

    Returns:
        `settings` itself, or the design's :class:`~mat_hopper.core.sim.SimSettings`.

    Raises:
        ValueError: as :func:`mat_hopper.core.sim.sim_settings` raises for
            ``"auto"`` (more than 1000 substeps).
    """
    if not auto_timestep:
        return settings
    from ..core.materials import as_design
    from ..core.sim import sim_settings

    given = {f.name: getattr(settings, f.name) for f in fields(SimSettings) if f.name not in ("timestep_s", "substeps")}
    return sim_settings(as_design(design), timestep_s="auto", **given)


def result_frame(rows: list[dict]) -> pd.DataFrame:
    """Rows (dicts) as the batch result table, columns in a fixed order."""
    cols = list(RESULT_COLUMNS) + list(EXTRA_COLUMNS)
    out = pd.DataFrame(rows, columns=cols)
    out["n_hops"] = out["n_hops"].astype(int)
    out["stable"] = out["stable"].astype(bool)
    out["upright"] = out["upright"].astype(bool)
    return out


def finite_mean(values) -> float:
    """Mean of the finite values, nan when there is none."""
    v = np.asarray(values, dtype=float)
    v = v[np.isfinite(v)]
    return float(v.mean()) if len(v) else math.nan


def mean_or_nan(total: float, n: int) -> float:
    return float(total) / n if n > 0 else math.nan
