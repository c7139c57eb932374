"""Fast headless rollouts in simulated time.

:func:`simulate` runs one design on one behaviour and returns a
:class:`Rollout` of arrays recorded at ``record_rate_hz`` (default 1 kHz).
The whole loop (MuJoCo step, controller, desired path, divergence check,
recording) is one numba-compiled function that calls libmujoco's
``mj_step1``/``mj_step2`` through ctypes on the Python bindings' own
buffers, so the rollout costs little more than the bare physics.

Per physics step: ``mj_step1`` (positions, velocities, their sensors), the
controller on that state, ``mj_step2`` (forces, integration). The touch
sensor is an acceleration-stage sensor, so the controller sees the ground
force of the previous step (0.1 ms old at the default time step).

Numerical divergence (a NaN or inf, or |qacc| > 1e6) ends the run early and
marks it unstable with the simulated time it happened; MuJoCo's automatic
reset is disabled so divergence can never pass unseen.

Set ``NUMBA_DISABLE_JIT=1`` to run the very same loop as plain Python.
"""

from __future__ import annotations

import ctypes
import logging
import math
import os
from dataclasses import dataclass, field

import mujoco
import numba
import numpy as np

from . import reference as ref
from .behaviours import Behaviour, desired_state
from .behaviours import behaviour as get_behaviour
from .control import (
    LIFTOFF,
    OUT_SIZE,
    S_LAST_HEIGHT,
    S_PHASE,
    S_THRUST,
    TOUCHDOWN,
    ControllerSettings,
    controller_step,
    euler_zyx,
    initial_state,
)
from .materials import DEFAULT_CONVENTION, LegDesign, check_convention, parse_design
from .model import HopperModel, build_model
from .perturbations import NO_PUSH, Perturbation

DEFAULT_RECORD_RATE_HZ = 1000.0

# Recorded channels: column name -> index in the record array.
CHANNELS = (
    "t",
    "x", "y", "z", "vx", "vy", "vz", "ax", "ay", "az",
    "roll", "pitch", "yaw", "roll_rate", "pitch_rate",
    "x_des", "y_des", "vx_des", "vy_des",
    "hip_y", "hip_x", "hip_y_rate", "hip_x_rate",
    "hip_y_target", "hip_x_target", "hip_y_target_rate", "hip_x_target_rate",
    "force_hip_y", "force_hip_x", "force_thrust",
    "touch", "phase", "thrust_setting", "foot_spring", "foot_spring_rate",
)
C = {name: i for i, name in enumerate(CHANNELS)}
N_CHANNELS = len(CHANNELS)

# ---------------------------------------------------------------------------
# libmujoco, reached through ctypes from compiled code


def _libmujoco():
    here = os.path.dirname(mujoco.__file__)
    names = sorted(f for f in os.listdir(here) if f.startswith("libmujoco.so"))
    if not names:
        raise RuntimeError(f"libmujoco not found next to the mujoco bindings in {here}")
    return ctypes.CDLL(os.path.join(here, names[-1]))


_LIB = _libmujoco()
_log = logging.getLogger("mat_hopper.mujoco")


def route_mujoco_warnings() -> None:
    """Send MuJoCo's warnings to logging instead of stderr and a
    MUJOCO_LOG.TXT in the working folder. Divergence is detected and
    reported by the rollout itself; a user's own handler is left alone."""
    if mujoco.get_mju_user_warning() is None:
        mujoco.set_mju_user_warning(lambda msg: _log.debug("MuJoCo: %s", msg))


_STEP_PROTO = ctypes.CFUNCTYPE(None, ctypes.c_void_p, ctypes.c_void_p)
MJ_STEP = _STEP_PROTO(("mj_step", _LIB))
MJ_STEP1 = _STEP_PROTO(("mj_step1", _LIB))
MJ_STEP2 = _STEP_PROTO(("mj_step2", _LIB))


@numba.njit(cache=True)
def _diverged(qpos, qacc, limit):
    for v in qacc:
        if not (abs(v) <= limit):          # catches nan too
            return True
    for v in qpos:
        if not math.isfinite(v):
            return True
    return False


@numba.njit(cache=True)
def rollout_loop(step1, step2, m_ptr, d_ptr, qpos, qvel, qacc, ctrl, sensordata, actuator_force,
                 xfrc_applied, lay, gains, path_kind, path_params, path_table, state, step0, n_steps,
                 dt, every, qacc_limit, push, noise, noise_every, rec, qpos_rec, events):
    """The closed loop for physics steps step0 .. step0 + n_steps - 1. Fills
    rec (samples x channels) every `every` steps and events (time, kind, hop
    height); qpos_rec (samples x nq, or 0 rows) gets the joint positions
    after the step, for rendering. push = [t0, t1, fx, fy] (N) on the base;
    noise rows (position m, velocity m/s) are added to the controller's
    readings, one row per noise_every steps. Returns (samples recorded, events recorded, step of divergence
    or -1)."""
    out = np.zeros(OUT_SIZE)
    hip_angle = np.zeros(2)
    hip_rate = np.zeros(2)
    desired = np.zeros(4)
    pos = np.zeros(3)
    vel = np.zeros(3)
    noisy = noise_every < n_steps + step0
    pushing = xfrc_applied[lay.base_body, 0] != 0.0 or xfrc_applied[lay.base_body, 1] != 0.0
    n_rec = 0
    n_ev = 0
    for i in range(step0, step0 + n_steps):
        t = i * dt
        step1(m_ptr, d_ptr)
        hip_angle[0] = qpos[lay.hip_y_qpos]
        hip_angle[1] = qpos[lay.hip_x_qpos]
        hip_rate[0] = qvel[lay.hip_y_dof]
        hip_rate[1] = qvel[lay.hip_x_dof]
        dx, dy, dvx, dvy = desired_state(t, path_kind, path_params, path_table)
        desired[0], desired[1], desired[2], desired[3] = dx, dy, dvx, dvy
        for k in range(3):
            pos[k] = sensordata[lay.base_pos + k]
            vel[k] = sensordata[lay.base_linvel + k]
        if noisy:
            nrow = noise[min(i // noise_every, noise.shape[0] - 1)]
            for k in range(3):
                pos[k] += nrow[k]
                vel[k] += nrow[3 + k]
        if (push[0] <= t < push[1]) != pushing:
            pushing = not pushing
            xfrc_applied[lay.base_body, 0] = push[2] if pushing else 0.0
            xfrc_applied[lay.base_body, 1] = push[3] if pushing else 0.0
        quat = sensordata[lay.base_quat:lay.base_quat + 4]
        gyro = sensordata[lay.base_gyro:lay.base_gyro + 3]
        touch = sensordata[lay.touch]
        event = controller_step(t, touch, pos, quat, gyro, vel, hip_angle, hip_rate, desired,
                                gains, state, out)
        ctrl[lay.act_hip_y] = out[0]
        ctrl[lay.act_hip_x] = out[1]
        ctrl[lay.act_thrust] = out[2]
        if event != 0 and n_ev < events.shape[0]:
            events[n_ev, 0] = t
            events[n_ev, 1] = event
            events[n_ev, 2] = state[S_LAST_HEIGHT]
            n_ev += 1
        foot, foot_rate = qpos[lay.spring_qpos], qvel[lay.spring_dof]
        step2(m_ptr, d_ptr)
        bad = _diverged(qpos, qacc, qacc_limit)
        if i % every == 0 or bad:
            if n_rec < rec.shape[0]:
                r = rec[n_rec]      # columns in CHANNELS order (tests/test_sim.py checks)
                r[0] = t
                for k in range(3):
                    r[1 + k] = sensordata[lay.base_pos + k]
                    r[4 + k] = sensordata[lay.base_linvel + k]
                    r[7 + k] = qacc[lay.base_dof + k]
                roll, pitch, yaw = euler_zyx(quat)
                r[10], r[11], r[12] = roll, pitch, yaw
                r[13], r[14] = gyro[0], gyro[1]
                r[15], r[16], r[17], r[18] = dx, dy, dvx, dvy
                r[19], r[20], r[21], r[22] = hip_angle[0], hip_angle[1], hip_rate[0], hip_rate[1]
                r[23], r[24], r[25], r[26] = out[3], out[4], out[5], out[6]
                r[27] = actuator_force[lay.act_hip_y]
                r[28] = actuator_force[lay.act_hip_x]
                r[29] = actuator_force[lay.act_thrust]
                r[30] = sensordata[lay.touch]
                r[31] = state[S_PHASE]
                r[32] = state[S_THRUST]
                r[33] = foot
                r[34] = foot_rate
                if n_rec < qpos_rec.shape[0]:
                    qpos_rec[n_rec, :] = qpos
                n_rec += 1
        if bad:
            return n_rec, n_ev, i
    return n_rec, n_ev, -1


# ---------------------------------------------------------------------------


@dataclass(frozen=True)
class SimSettings:
    """Everything besides design and behaviour that changes a rollout.

    duration_s, transient_s, timestep_s in s; record_rate_hz in Hz;
    convention: modulus-to-stiffness convention ("paper" or "axial").
    """

    duration_s: float = ref.DURATION_S
    timestep_s: float = ref.TIMESTEP_S
    transient_s: float = ref.TRANSIENT_S
    convention: str = DEFAULT_CONVENTION
    record_rate_hz: float = DEFAULT_RECORD_RATE_HZ
    controller: ControllerSettings = field(default_factory=ControllerSettings)
    perturbation: Perturbation | None = None

    def __post_init__(self):
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
        check_convention(self.convention)
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
    qpos: np.ndarray | None = None   # (n, nq) joint positions, if recorded

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
        return self.data[:, C["x"]:C["z"] + 1]

    @property
    def base_vel(self) -> np.ndarray:
        """m/s, world frame (n, 3)"""
        return self.data[:, C["vx"]:C["vz"] + 1]

    @property
    def base_acc(self) -> np.ndarray:
        """m/s^2, world frame (n, 3)"""
        return self.data[:, C["ax"]:C["az"] + 1]

    @property
    def desired_pos(self) -> np.ndarray:
        """m (n, 2)"""
        return self.data[:, C["x_des"]:C["y_des"] + 1]

    @property
    def desired_vel(self) -> np.ndarray:
        """m/s (n, 2)"""
        return self.data[:, C["vx_des"]:C["vy_des"] + 1]

    @property
    def hip_angle(self) -> np.ndarray:
        """rad, (hip_y, hip_x) (n, 2)"""
        return self.data[:, C["hip_y"]:C["hip_x"] + 1]

    @property
    def hip_rate(self) -> np.ndarray:
        """rad/s, (hip_y, hip_x) (n, 2)"""
        return self.data[:, C["hip_y_rate"]:C["hip_x_rate"] + 1]

    @property
    def actuator_force(self) -> np.ndarray:
        """N m (hips, after the gear) and N (thrust) (n, 3)"""
        return self.data[:, C["force_hip_y"]:C["force_thrust"] + 1]

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


def prepare(design, behaviour, settings: SimSettings, start_xy_offset=(0.0, 0.0),
            start_tilt=(0.0, 0.0)) -> tuple[HopperModel, mujoco.MjData]:
    """Model and initial data for a rollout: start pose per the behaviour,
    plus an optional offset (m) and roll/pitch tilt (rad)."""
    design = _as_design(design)
    beh = get_behaviour(behaviour)
    hm = build_model(design, ramp_grade_deg=beh.ramp_grade_deg, timestep=settings.timestep_s,
                     convention=settings.convention, sensors="control")
    data = mujoco.MjData(hm.model)
    b = hm.layout.base_qpos       # base joints: x, y, z, roll, pitch, yaw
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
        self.design = _as_design(design)
        self.behaviour = get_behaviour(behaviour)
        self.settings = settings
        p = settings.perturbation
        if p is None:
            offset, tilt, self._push, self._noise, self._noise_every = (0.0, 0.0), (0.0, 0.0), NO_PUSH, np.zeros((1, 6)), 1 << 60
        else:
            offset, tilt, self._push, self._noise, self._noise_every = p.draw(settings.duration_s, settings.timestep_s)
        self.hopper, self.data = prepare(self.design, self.behaviour, settings, offset, tilt)
        n_rec = settings.n_steps // settings.record_every + 2
        self._rec = np.zeros((n_rec, N_CHANNELS))
        self._qpos = np.zeros((n_rec if record_qpos else 0, self.hopper.model.nq))
        lock = settings.controller.phase_lock_s
        n_ev = int(settings.duration_s / lock) + 16 if lock > 0 else settings.n_steps + 1
        self._events = np.zeros((n_ev, 3))
        self._state = initial_state(settings.controller)
        self._gains = settings.controller.gains()
        self.step = 0
        self._n_rec = 0
        self._n_ev = 0
        self.diverged_step = -1

    @property
    def done(self) -> bool:
        return self.step >= self.settings.n_steps or self.diverged_step >= 0

    def advance(self, n_steps: int | None = None) -> "RolloutRunner":
        """Run up to n_steps more physics steps (all that remain by default)."""
        if self.done:
            return self
        remaining = self.settings.n_steps - self.step
        n = remaining if n_steps is None else min(int(n_steps), remaining)
        d, hm, beh = self.data, self.hopper, self.behaviour
        n_rec, n_ev, bad = rollout_loop(
            MJ_STEP1, MJ_STEP2, hm.model._address, d._address, d.qpos, d.qvel, d.qacc, d.ctrl,
            d.sensordata, d.actuator_force, d.xfrc_applied, hm.layout, self._gains, beh.path_code,
            beh.path_params, beh.table_xy_m, self._state, self.step, n, self.settings.timestep_s,
            self.settings.record_every, ref.DIVERGENCE_QACC, self._push, self._noise,
            self._noise_every, self._rec[self._n_rec:],
            self._qpos[self._n_rec:], self._events[self._n_ev:])
        self._n_rec += n_rec
        self._n_ev += n_ev
        if bad >= 0:
            self.diverged_step = int(bad)
        self.step += n
        return self

    def result(self) -> Rollout:
        r = Rollout(self.design, self.behaviour, self.settings, self._rec[:self._n_rec].copy(),
                    self._events[:self._n_ev].copy(), self.diverged_step,
                    self.hopper.total_mass_kg, self.hopper.spring_stiffness_n_m)
        if len(self._qpos):
            r.qpos = self._qpos[:self._n_rec].copy()
        return r


def simulate(design, behaviour, duration_s: float = ref.DURATION_S, timestep_s: float = ref.TIMESTEP_S, *,
             transient_s: float = ref.TRANSIENT_S, convention: str = DEFAULT_CONVENTION,
             controller: ControllerSettings | None = None,
             record_rate_hz: float = DEFAULT_RECORD_RATE_HZ, record_qpos: bool = False,
             perturbation: Perturbation | None = None, settings: SimSettings | None = None) -> Rollout:
    """Run a design on a behaviour for `duration_s` simulated seconds.

    design: a LegDesign or a name (``"SS"``, ``"PVC-Ti-SS"``, ``"rho-inc"``);
    behaviour: a Behaviour or ``"static"``, ``"forward"``, ``"ramp"``,
    ``"circle"``; timestep_s: physics time step, s; transient_s: s (hop cycles before it are
    not scored; the run must outlast it); convention ``"paper"`` or
    ``"axial"``; record_rate_hz: samples per simulated second (1 kHz);
    record_qpos: also keep all joint positions (``Rollout.qpos``) for
    rendering; perturbation: seeded disturbances for replicates. Pass ``settings`` to give all of these at once.
    Divergence never raises: see :attr:`Rollout.stable`.
    """
    if settings is None:
        settings = SimSettings(duration_s=duration_s, timestep_s=timestep_s, transient_s=transient_s,
                               convention=convention, record_rate_hz=record_rate_hz,
                               controller=controller or ControllerSettings(), perturbation=perturbation)
    return RolloutRunner(design, behaviour, settings, record_qpos=record_qpos).advance().result()
