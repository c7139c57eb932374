"""Fast headless rollouts in simulated time.

:func:`simulate` runs one design on one behaviour and returns a
:class:`Rollout` of arrays recorded at ``record_rate_hz`` (default 1 kHz).
The whole loop (MuJoCo step, controller, desired path, divergence check,
recording) is one numba-compiled function (:mod:`mat_hopper._loop`) that
calls libmujoco's ``mj_step1``/``mj_step2`` through ctypes on the Python
bindings' own buffers, so the rollout costs little more than the bare
physics.

Sensor timing (``SimSettings.sensor_timing``, recorded in every result):
by default ``"authors"``, the authors' loop, in which the controller sees
the base sensors one physics step old and the hips current; ``"fresh"``
reads the base from the current state; an integer latency L (physics
steps) generalises both. See :mod:`mat_hopper.control` for exactly when
each reading is taken.

Numerical divergence (a NaN or inf, or |qacc| > 1e6) ends the run early and
marks it unstable with the simulated time it happened; MuJoCo's automatic
reset is disabled so divergence can never pass unseen.

Set ``NUMBA_DISABLE_JIT=1`` to run the very same loop as plain Python.
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass, field

import mujoco
import numpy as np

from . import reference as ref
from ._loop import (
    CHANNELS,
    HISTORY_WIDTH,
    MJ_STEP1,
    MJ_STEP2,
    N_CHANNELS,
    RECORD_DTYPE,
    Buffers,
    C,
    Disturbance,
    JerkFilter,
    Path,
    Steps,
    read_sensors,
    rollout_loop,
)
from .behaviours import Behaviour
from .behaviours import behaviour as get_behaviour
from .control import (
    DEFAULT_SENSOR_TIMING,
    LIFTOFF,
    TOUCHDOWN,
    ControllerSettings,
    initial_state,
    sensor_latency_steps,
    sensor_timing_name,
)
from .materials import (
    DEFAULT_CONVENTION,
    DEFAULT_SEGMENT_MASS,
    LegDesign,
    check_convention,
    check_segment_mass,
    parse_design,
)
from .model import HopperModel, build_model, reset_to_start
from .modes import auto_substeps
from .perturbations import NO_PUSH, Perturbation

__all__ = [
    "CHANNELS",
    "C",
    "N_CHANNELS",
    "DEFAULT_RECORD_RATE_HZ",
    "SimSettings",
    "Rollout",
    "RolloutRunner",
    "prepare",
    "simulate",
    "auto_timestep",
    "route_mujoco_warnings",
]

DEFAULT_RECORD_RATE_HZ = 1000.0
MAX_SUBSTEPS = 1000
# Run-size limits, checked before anything is allocated: 2e9 physics steps
# (about 3 h of one core), 5e6 recorded samples (1.5 GB of records).
MAX_STEPS = 2_000_000_000
MAX_SAMPLES = 5_000_000
# Physics steps per call of the compiled loop. Python runs signal handlers
# (Ctrl-C, SIGTERM) only between calls, so every call must end within a
# fraction of a second of wall time at any time step: sized in steps, not
# simulated seconds, and scaled down for longer chains (a 3-segment leg
# takes about 5 us a step: 20000 steps, 0.1 s; 64 segments 75 us a step:
# 1000 steps, 0.08 s). A call costs microseconds more than its steps
# (benchmarks/rollout.py's ratio is unchanged).
LOOP_CHUNK_STEPS = 20_000  # for legs of up to 3 segments


def loop_chunk_steps(n_segments: int) -> int:
    """Physics steps per compiled-loop call for a leg of n_segments."""
    return max(1000, LOOP_CHUNK_STEPS * 3 // max(3, int(n_segments)))


AUTO = "auto"
# Jerk is computed at the physics rate: the base's z acceleration through a
# causal Butterworth low-pass, then differentiated step by step. The cut-off
# lies far below the leg's axial modes (2.5-4 kHz, barely damped) and the
# record rates' Nyquist frequencies, and above the hop's body dynamics
# (stance about 0.1 s): the number no longer depends on the record rate.
# Butterworth filtering before differentiating is the standard treatment of
# noisy kinematic derivatives (D. A. Winter, Biomechanics and Motor Control
# of Human Movement, 4th ed., Wiley 2009, sec. 2.2); the coefficients come
# from scipy.signal.butter.
JERK_CUTOFF_HZ = 50.0
JERK_FILTER_ORDER = 2


def jerk_filter(timestep_s: float, az0_m_s2: float = -ref.GRAVITY_M_S2) -> JerkFilter:
    """The jerk low-pass for this physics step, at rest on input az0 (its
    steady state, scipy.signal.sosfilt_zi) so a run starts without a
    filter transient. Steps coarser than 4 ms (where jerk means little)
    lower the cut-off to 0.2 / timestep_s, below their Nyquist frequency."""
    import scipy.signal

    cutoff = min(JERK_CUTOFF_HZ, 0.2 / timestep_s)
    sos = scipy.signal.butter(JERK_FILTER_ORDER, cutoff, fs=1.0 / timestep_s, output="sos")
    ((b0, b1, b2, _, a1, a2),) = sos
    zi = scipy.signal.sosfilt_zi(sos)[0] * az0_m_s2
    return JerkFilter(np.array([b0, b1, b2, a1, a2]), np.array([zi[0], zi[1], az0_m_s2]))


_log = logging.getLogger("mat_hopper.mujoco")


def route_mujoco_warnings() -> None:
    """Send MuJoCo's warnings to logging (logger ``mat_hopper.mujoco``,
    level DEBUG) instead of stderr and a MUJOCO_LOG.TXT in the working
    folder. Divergence is detected and reported by the rollout itself. Not
    done on import (it is process-wide): the CLI calls it; a handler the
    user installed is left alone."""
    if mujoco.get_mju_user_warning() is None:
        mujoco.set_mju_user_warning(lambda msg: _log.debug("MuJoCo: %s", msg))


# ---------------------------------------------------------------------------


@dataclass(frozen=True)
class SimSettings:
    """Everything besides design and behaviour that changes a rollout.

    duration_s, transient_s, timestep_s in s; record_rate_hz in Hz;
    convention: modulus-to-stiffness convention ("paper" or "axial");
    sensor_timing: when the controller's base readings are taken,
    ``"authors"`` (default: one physics step old), ``"fresh"``, or an integer
    latency in physics steps (stored by its canonical name, e.g.
    ``"latency-5"``; see :func:`mat_hopper.control.sensor_latency_steps`);
    segment_mass: ``"leg"`` (default: mass independent of the number of
    segments, the authors' model at N = 3) or ``"capsule"`` (the authors'
    per-capsule density at any N; see :mod:`mat_hopper.materials`);
    substeps: physics steps per control period. ``timestep_s`` is the
    physics step; the controller runs every ``substeps`` of them, i.e. with
    period :attr:`control_period_s` (1 by default: every step, as the
    authors' loop). ``simulate(timestep_s="auto")`` chooses it.

    Raises ValueError on any invalid value.
    """

    duration_s: float = ref.DURATION_S
    timestep_s: float = ref.TIMESTEP_S
    transient_s: float = ref.TRANSIENT_S
    convention: str = DEFAULT_CONVENTION
    record_rate_hz: float = DEFAULT_RECORD_RATE_HZ
    controller: ControllerSettings = field(default_factory=ControllerSettings)
    perturbation: Perturbation | None = None
    sensor_timing: str | int = DEFAULT_SENSOR_TIMING
    segment_mass: str = DEFAULT_SEGMENT_MASS
    substeps: int = 1

    def __post_init__(self):
        if (
            isinstance(self.substeps, bool)
            or not isinstance(self.substeps, (int, np.integer))
            or not 1 <= self.substeps <= MAX_SUBSTEPS
        ):
            raise ValueError(
                f"substeps must be an integer in [1, {MAX_SUBSTEPS}] (physics steps per control "
                f"period), got {self.substeps!r}"
            )
        object.__setattr__(self, "sensor_timing", sensor_timing_name(self.sensor_timing))
        object.__setattr__(self, "segment_mass", check_segment_mass(self.segment_mass))
        for name in ("duration_s", "timestep_s", "transient_s", "record_rate_hz"):
            v = getattr(self, name)
            if not isinstance(v, (int, float)) or not math.isfinite(v):
                raise ValueError(f"{name} must be a finite number, got {v!r}")
        if not self.timestep_s > 0:
            raise ValueError(f"timestep must be > 0 s (e.g. 1e-4), got {self.timestep_s!r}")
        if self.timestep_s > 0.1:
            raise ValueError(f"timestep must be in (0, 0.1] s, got {self.timestep_s!r}")
        if self.transient_s < 0:
            raise ValueError(f"transient must be >= 0 s, got {self.transient_s!r}")
        if not self.duration_s > self.transient_s:
            raise ValueError(f"duration must be > transient ({self.transient_s:g} s), got {self.duration_s!r} s")
        if not self.record_rate_hz > 0:
            raise ValueError(f"record_rate_hz must be > 0 Hz, got {self.record_rate_hz!r}")
        if self.duration_s / self.timestep_s > MAX_STEPS:
            raise ValueError(
                f"duration / timestep = {self.duration_s / self.timestep_s:.3g} physics steps: over the "
                f"limit of {MAX_STEPS:.0e} (a longer duration_s or smaller timestep_s than supported)"
            )
        if self.n_steps / self.record_every > MAX_SAMPLES:
            raise ValueError(
                f"{self.n_steps / self.record_every:.3g} recorded samples: over the limit of "
                f"{MAX_SAMPLES:.0e}; lower record_rate_hz or duration_s"
            )
        object.__setattr__(self, "convention", check_convention(self.convention))
        if not isinstance(self.controller, ControllerSettings):
            raise ValueError("controller must be a ControllerSettings")
        if self.perturbation is not None and not isinstance(self.perturbation, Perturbation):
            raise ValueError("perturbation must be a Perturbation or None")

    @property
    def record_every(self) -> int:
        """Physics steps between recorded samples (>= 1)."""
        return max(1, int(round(1.0 / (self.record_rate_hz * self.timestep_s))))

    @property
    def n_steps(self) -> int:
        return int(round(self.duration_s / self.timestep_s))

    @property
    def control_period_s(self) -> float:
        """s, the controller's period: substeps x timestep_s."""
        return self.substeps * self.timestep_s

    @property
    def sensor_latency_steps(self) -> int:
        """Physics steps by which the controller's base readings lag."""
        return sensor_latency_steps(self.sensor_timing)


@dataclass(eq=False)
class Rollout:
    """What one rollout recorded. Arrays share the first axis (samples).

    ``data`` holds every channel of :data:`CHANNELS` as columns; the
    properties below are named views in SI units. Events are the state
    machine's switches: ``touchdown_times_s``, ``liftoff_times_s`` and the
    controller's own ``hop_heights_m`` (one per touchdown after the first
    lift-off)."""

    design: LegDesign
    behaviour: Behaviour
    settings: SimSettings
    data: np.ndarray
    events: np.ndarray
    diverged_step: int
    total_mass_kg: float
    spring_stiffness_n_m: tuple
    qpos: np.ndarray | None = None  # (n, nq) joint positions, if recorded

    def __getitem__(self, channel: str) -> np.ndarray:
        return self.data[:, C[channel]]

    # --- named views ---
    @property
    def time(self) -> np.ndarray:
        """s"""
        return self.data[:, C["t"]]

    @property
    def base_pos(self) -> np.ndarray:
        """m, world frame (n, 3)"""
        return self.data[:, C["x"] : C["z"] + 1]

    @property
    def base_vel(self) -> np.ndarray:
        """m/s, world frame (n, 3)"""
        return self.data[:, C["vx"] : C["vz"] + 1]

    @property
    def base_acc(self) -> np.ndarray:
        """m/s^2, world frame (n, 3)"""
        return self.data[:, C["ax"] : C["az"] + 1]

    @property
    def desired_pos(self) -> np.ndarray:
        """m (n, 2)"""
        return self.data[:, C["x_des"] : C["y_des"] + 1]

    @property
    def desired_vel(self) -> np.ndarray:
        """m/s (n, 2)"""
        return self.data[:, C["vx_des"] : C["vy_des"] + 1]

    @property
    def hip_angle(self) -> np.ndarray:
        """rad, (hip_y, hip_x) (n, 2)"""
        return self.data[:, C["hip_y"] : C["hip_x"] + 1]

    @property
    def hip_rate(self) -> np.ndarray:
        """rad/s, (hip_y, hip_x) (n, 2)"""
        return self.data[:, C["hip_y_rate"] : C["hip_x_rate"] + 1]

    @property
    def ctrl(self) -> np.ndarray:
        """Controls in actuator space, (hip_y, hip_x, thrust) (n, 3): the
        hips' before their gear of 600, the thrust in N (gear 1)."""
        return self.data[:, C["ctrl_hip_y"] : C["ctrl_thrust"] + 1]

    @property
    def hip_torque(self) -> np.ndarray:
        """N m, joint space (hip_y, hip_x) (n, 2): MuJoCo's qfrc_actuator at
        the hip joints, i.e. gear x control."""
        return self.data[:, C["torque_hip_y"] : C["torque_hip_x"] + 1]

    @property
    def thrust_force(self) -> np.ndarray:
        """N, joint space: the thrust actuator's force on the foot spring (n,)."""
        return self.data[:, C["force_thrust"]]

    @property
    def hip_power(self) -> np.ndarray:
        """W, mechanical power of each hip actuator, joint torque x joint
        rate (hip_y, hip_x) (n, 2)."""
        return self.hip_torque * self.hip_rate

    @property
    def touch(self) -> np.ndarray:
        """N"""
        return self.data[:, C["touch"]]

    @property
    def phase(self) -> np.ndarray:
        """0 flight, 1 stance"""
        return self.data[:, C["phase"]]

    @property
    def thrust(self) -> np.ndarray:
        """N, the adaptive thrust setting F"""
        return self.data[:, C["thrust_setting"]]

    @property
    def touchdown_times_s(self) -> np.ndarray:
        return self.events[self.events[:, 1] == TOUCHDOWN, 0]

    @property
    def liftoff_times_s(self) -> np.ndarray:
        return self.events[self.events[:, 1] == LIFTOFF, 0]

    @property
    def hop_heights_m(self) -> np.ndarray:
        h = self.events[self.events[:, 1] == TOUCHDOWN, 2]
        return h[np.isfinite(h)]

    # --- outcome ---
    @property
    def stable(self) -> bool:
        """True when the run reached its end without numerical divergence."""
        return self.diverged_step < 0

    @property
    def diverged_at_s(self) -> float | None:
        """Simulated time (s) of divergence, or None."""
        return None if self.stable else self.diverged_step * self.settings.timestep_s

    @property
    def upright(self) -> bool:
        """Stable and the base ended above 0.1 m (the paper's criterion)."""
        return self.stable and len(self.data) > 0 and self.data[-1, C["z"]] > ref.STABLE_MIN_BASE_Z

    def to_frame(self):
        """All channels as a pandas DataFrame, one row per sample."""
        import pandas as pd

        return pd.DataFrame(self.data, columns=list(CHANNELS))


def _as_design(design) -> LegDesign:
    if isinstance(design, LegDesign):
        return design
    if isinstance(design, str):
        return parse_design(design)
    raise ValueError(f"design must be a LegDesign or a design name, got {design!r}")


def prepare(
    design, behaviour, settings: SimSettings, start_xy_offset=(0.0, 0.0), start_tilt=(0.0, 0.0)
) -> tuple[HopperModel, mujoco.MjData]:
    """Model and initial data for a rollout: start pose per the behaviour,
    plus an optional offset (m) and roll/pitch tilt (rad)."""
    design = _as_design(design)
    beh = get_behaviour(behaviour)
    hm = build_model(
        design,
        ramp_grade_deg=beh.ramp_grade_deg,
        timestep_s=settings.timestep_s,
        convention=settings.convention,
        sensors="control",
        segment_mass=settings.segment_mass,
    )
    data = mujoco.MjData(hm.model)
    reset_to_start(hm.model, data)  # base z slide at 1.2 m, all else 0
    b = hm.layout.base_qpos  # base joints: x, y, z, roll, pitch, yaw
    data.qpos[b + 0] = beh.start_xy_m[0] + start_xy_offset[0]
    data.qpos[b + 1] = beh.start_xy_m[1] + start_xy_offset[1]
    data.qpos[b + 3] = start_tilt[0]
    data.qpos[b + 4] = start_tilt[1]
    mujoco.mj_forward(hm.model, data)
    return hm, data


class RolloutRunner:
    """A rollout that advances in chunks of physics steps (see :func:`simulate`).

    Useful to inspect or snapshot the MuJoCo state part-way; ``simulate``
    runs it in one chunk. record_qpos keeps every joint position at the
    record rate, which rendering needs."""

    def __init__(self, design, behaviour, settings: SimSettings, *, record_qpos: bool = False):
        if not isinstance(settings, SimSettings):
            raise ValueError(f"settings must be a SimSettings, got {type(settings).__name__}")
        self.design = _as_design(design)
        self.behaviour = get_behaviour(behaviour)
        self.settings = settings
        p = settings.perturbation
        if p is None:
            offset, tilt, self._push, self._noise, self._noise_every = (
                (0.0, 0.0),
                (0.0, 0.0),
                NO_PUSH,
                np.zeros((1, 6)),
                1 << 60,
            )
        else:
            offset, tilt, self._push, self._noise, self._noise_every = p.draw(settings.duration_s, settings.timestep_s)
        self.hopper, self.data = prepare(self.design, self.behaviour, settings, offset, tilt)
        n_rec = settings.n_steps // settings.record_every + 2
        self._rec = np.zeros(n_rec, RECORD_DTYPE)
        self._qpos = np.zeros((n_rec if record_qpos else 0, self.hopper.model.nq))
        lock = settings.controller.phase_lock_s
        n_ev = int(settings.duration_s / lock) + 16 if lock > 0 else settings.n_steps + 1
        self._events = np.zeros((n_ev, 3))
        self._state = initial_state(settings.controller)
        self._gains = settings.controller.gains()
        # Reading history: every lagged reading starts as the start state's.
        self._history = np.zeros((settings.sensor_latency_steps + 1, HISTORY_WIDTH))
        read_sensors(self.data.sensordata, self.hopper.layout, self._history[0])
        self._history[1:] = self._history[0]
        d = self.data
        self._buffers = Buffers(d.qpos, d.qvel, d.qacc, d.ctrl, d.sensordata, d.qfrc_actuator, d.xfrc_applied)
        beh = self.behaviour
        self._path = Path(beh.path_code, beh.path_params, beh.table_xy_m)
        self._disturbance = Disturbance(self._push, self._noise, self._noise_every)
        self._jerk = jerk_filter(settings.timestep_s)
        self.step = 0
        self._n_rec = 0
        self._n_ev = 0
        self.diverged_step = -1

    @property
    def done(self) -> bool:
        return self.step >= self.settings.n_steps or self.diverged_step >= 0

    def advance(self, n_steps: int | None = None) -> RolloutRunner:
        """Run up to n_steps more physics steps (all that remain by default)."""
        if self.done:
            return self
        remaining = self.settings.n_steps - self.step
        n = remaining if n_steps is None else min(int(n_steps), remaining)
        end = self.step + n
        while self.step < end and self.diverged_step < 0:  # signals are handled between chunks
            self._advance_chunk(min(end - self.step, loop_chunk_steps(self.design.n_segments)))
        return self

    def _advance_chunk(self, n: int) -> None:
        hm, st = self.hopper, self.settings
        steps = Steps(self.step, n, st.timestep_s, st.record_every, ref.DIVERGENCE_QACC, st.substeps)
        n_rec, n_ev, bad = rollout_loop(
            MJ_STEP1,
            MJ_STEP2,
            hm.model._address,
            self.data._address,
            self._buffers,
            hm.layout,
            self._gains,
            self._path,
            self._disturbance,
            steps,
            self._history,
            self._state,
            self._jerk,
            self._rec[self._n_rec :],
            self._qpos[self._n_rec :],
            self._events[self._n_ev :],
        )
        self._n_rec += n_rec
        self._n_ev += n_ev
        if bad >= 0:
            self.diverged_step = int(bad)
        self.step += n

    def result(self) -> Rollout:
        data = self._rec[: self._n_rec].view(np.float64).reshape(self._n_rec, N_CHANNELS).copy()
        r = Rollout(
            self.design,
            self.behaviour,
            self.settings,
            data,
            self._events[: self._n_ev].copy(),
            self.diverged_step,
            self.hopper.total_mass_kg,
            self.hopper.spring_stiffness_n_m,
        )
        if len(self._qpos):
            r.qpos = self._qpos[: self._n_rec].copy()
        return r


def simulate(
    design,
    behaviour,
    duration_s: float = ref.DURATION_S,
    timestep_s: float = ref.TIMESTEP_S,
    *,
    transient_s: float = ref.TRANSIENT_S,
    convention: str = DEFAULT_CONVENTION,
    sensor_timing: str | int = DEFAULT_SENSOR_TIMING,
    controller: ControllerSettings | None = None,
    record_rate_hz: float = DEFAULT_RECORD_RATE_HZ,
    record_qpos: bool = False,
    perturbation: Perturbation | None = None,
    settings: SimSettings | None = None,
) -> Rollout:
    """Run a design on a behaviour for ``duration_s`` simulated seconds.

    design: a LegDesign or a name (``"SS"``, ``"PVC-Ti-SS"``, ``"rho-inc"``);
    behaviour: a Behaviour or ``"static"``, ``"forward"``, ``"ramp"``,
    ``"circle"``; timestep_s: physics step (s); transient_s: hop cycles
    starting before it are not scored (the run must outlast it); convention:
    ``"paper"`` or ``"axial"`` stiffness; sensor_timing: ``"authors"``
    (default), ``"fresh"`` or an integer latency in physics steps;
    timestep_s may be ``"auto"``: physics substeps of the 1e-4 s control
    period, chosen from the analytic bound (:func:`auto_timestep`);
    record_rate_hz: samples per simulated second (1 kHz); record_qpos: also
    keep all joint positions (``Rollout.qpos``) for rendering; perturbation:
    seeded disturbances for replicates. Pass ``settings`` to give all of
    these at once. Divergence never raises: see :attr:`Rollout.stable`.
    Raises ValueError for invalid settings, designs or behaviours.

    >>> r = simulate("SS", "forward", duration_s=0.5, transient_s=0.0)
    >>> r.settings.sensor_timing, r.data.shape[1] == len(CHANNELS)
    ('authors', True)
    """
    if settings is None:
        substeps = 1
        if isinstance(timestep_s, str) and timestep_s.strip().lower() == AUTO:
            substeps, timestep_s = auto_timestep(_as_design(design), convention)
        settings = SimSettings(
            duration_s=duration_s,
            timestep_s=timestep_s,
            transient_s=transient_s,
            convention=convention,
            record_rate_hz=record_rate_hz,
            controller=controller or ControllerSettings(),
            perturbation=perturbation,
            sensor_timing=sensor_timing,
            substeps=substeps,
        )
    return RolloutRunner(design, behaviour, settings, record_qpos=record_qpos).advance().result()


def auto_timestep(
    design,
    convention: str = DEFAULT_CONVENTION,
    segment_mass: str = DEFAULT_SEGMENT_MASS,
    control_period_s: float = ref.TIMESTEP_S,
) -> tuple[int, float]:
    """(substeps, physics step s) for ``timestep_s="auto"``: the controller
    keeps its period (1e-4 s) and the physics takes the fewest substeps
    whose step is at most AUTO_SAFETY (0.5) x the spring chain's explicit
    bound (:func:`mat_hopper.modes.auto_substeps`)."""
    k, dt, _ = auto_substeps(_as_design(design), convention, segment_mass, control_period_s)
    return k, dt
