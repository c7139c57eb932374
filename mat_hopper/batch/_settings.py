"""Settings and result tables shared by the batch backends."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from .. import control as _ctl
from .. import reference as ref
from ..control import ControllerSettings
from ..materials import DEFAULT_CONVENTION, DEFAULT_SEGMENT_MASS, check_convention, check_segment_mass
from ..sim import DEFAULT_RECORD_RATE_HZ, SimSettings

# One row per design, in this column order (the CLI writes exactly these).
RESULT_COLUMNS = ("design", "n_hops", "hop_height_m", "tracking_error_m", "power_w", "stable")
# What the library's tables carry besides.
# upright: stable and the base above reference.STABLE_MIN_BASE_Z at the last
# recorded sample (Rollout.upright); run_tracking_error_m, run_power_w: means
# over every finite recorded sample of the run, hop cycles or not (the
# optimizer's score of a run without scored hops).
EXTRA_COLUMNS = (
    "behaviour",
    "sensor_timing",
    "diverged_at_s",
    "total_mass_kg",
    "backend",
    "upright",
    "run_tracking_error_m",
    "run_power_w",
)
BACKENDS = ("mujoco", "warp")


@dataclass(frozen=True)
class BatchSettings:
    """Run settings of a batch: the same for every design in it.

    duration_s, transient_s, timestep_s in s; record_rate_hz: the rate (Hz)
    at which per-hop metrics sample the run, as ``SimSettings`` records it
    (1 kHz); convention: modulus-to-stiffness convention; controller: the
    gains (one source: :class:`~mat_hopper.control.ControllerSettings`).

    sensor_latency_steps: how many physics steps old the base sensors are
    when the controller reads them (``SimSettings.sensor_timing`` as an
    integer; :mod:`mat_hopper.control`). 1 (reference.SENSOR_LATENCY_STEPS)
    is the authors' loop: ``d.sensordata`` as the previous physics step left
    it (touch, base position, quaternion, gyro and linear velocity one step
    old), hip angles and rates from the current ``qpos``/``qvel``; at step 0
    the sensors of the initial state. The mujoco backend takes any latency
    its ``SimSettings`` takes, and so does the warp backend (a ring of past
    readings on the device, :mod:`mat_hopper.batch._kernels`).

    segment_mass: how segment masses scale with their number (``"leg"`` or
    ``"capsule"``, as ``SimSettings.segment_mass``). The controller runs every
    physics step (``SimSettings.substeps`` = 1), as in the authors' loop.
    """

    duration_s: float = ref.DURATION_S
    timestep_s: float = ref.TIMESTEP_S
    transient_s: float = ref.TRANSIENT_S
    convention: str = DEFAULT_CONVENTION
    record_rate_hz: float = DEFAULT_RECORD_RATE_HZ
    controller: ControllerSettings = field(default_factory=ControllerSettings)
    sensor_latency_steps: int = ref.SENSOR_LATENCY_STEPS
    segment_mass: str = DEFAULT_SEGMENT_MASS

    def __post_init__(self):
        lat = self.sensor_latency_steps
        if isinstance(lat, (bool, np.bool_)) or not isinstance(lat, (int, np.integer)):
            raise ValueError(f"sensor_latency_steps must be an integer number of physics steps, got {lat!r}")
        _ctl.sensor_latency_steps(int(lat))  # control.py's range check
        object.__setattr__(self, "convention", check_convention(self.convention))
        object.__setattr__(self, "segment_mass", check_segment_mass(self.segment_mass))
        # SimSettings holds the shared checks (finite, timestep range, duration > transient, ...).
        self.sim_settings()

    @property
    def sensor_timing(self) -> str:
        """The canonical name of the timing ("authors", "fresh", "latency-L")."""
        return _ctl.sensor_timing_name(int(self.sensor_latency_steps))

    def sim_settings(self) -> SimSettings:
        """The same run as :class:`~mat_hopper.sim.SimSettings` (the CPU path)."""
        return SimSettings(
            duration_s=self.duration_s,
            timestep_s=self.timestep_s,
            transient_s=self.transient_s,
            convention=self.convention,
            record_rate_hz=self.record_rate_hz,
            controller=self.controller,
            sensor_timing=int(self.sensor_latency_steps),
            segment_mass=self.segment_mass,
        )

    @property
    def n_steps(self) -> int:
        return int(round(self.duration_s / self.timestep_s))

    @property
    def record_every(self) -> int:
        """Physics steps between metric samples (as SimSettings.record_every)."""
        return max(1, int(round(1.0 / (self.record_rate_hz * self.timestep_s))))


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
