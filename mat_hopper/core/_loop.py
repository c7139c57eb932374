"""The compiled closed loop (private; the public API is :mod:`mat_hopper.core.sim`).

One numba-compiled function runs many physics steps: ``mj_step1``, the
controller on the readings of the chosen sensor timing, ``mj_step2``, the
divergence check and recording. libmujoco is called through ctypes on the
Python bindings' own buffers, so the rollout costs little more than the
bare physics (``benchmarks/rollout.py``).

Physics substeps: the controller runs on every ``substeps``-th physics step
(its own period is ``substeps x dt``) and its control is held in between;
the readings are still taken, and lag, in physics steps. With one substep
(the default) the control runs every step, as in the authors' loop.

When each reading is taken (see :mod:`mat_hopper.core.controller`): after
``mj_step1`` at step i, ``sensordata`` holds the position- and
velocity-stage sensors of state s_i, and the touch sensor (an
acceleration-stage sensor) still holds s_{i-1}'s value from the previous
``mj_step2``. Each step's readings are pushed into a short history (a ring
of latency + 1 rows), and the controller reads the base from the row L steps
back and the touch force from the row max(L - 1, 0) steps back, i.e. the
touch force of s_{i-max(L,1)}. The hips are read from ``qpos``/``qvel``
(s_i). With L = 1 this is exactly the authors' read-control-``mj_step``
loop.

Apex reference (:mod:`mat_hopper.core.controller`): with
``apex_reference = "ground"`` (:class:`ApexReference`), at each lift-off the
loop sets the controller's reference height ``S_GROUND_Z`` to the terrain
height under the foot geom's centre in s_i
(:func:`mat_hopper.core.terrain.terrain_height_at`); with ``"world"`` the
reference stays 0 and nothing is read.

Records are written by channel name into a numpy structured array
(:data:`RECORD_DTYPE`, one float64 field per channel of :data:`CHANNELS`,
written as ``r["name"]``, which numba compiles to a fixed offset);
``Rollout.data`` views it as a 2-D array.

Set ``NUMBA_DISABLE_JIT=1`` to run the very same loop as plain Python.
"""

from __future__ import annotations

import ctypes
import math
import os
from typing import NamedTuple

import mujoco
import numba
import numpy as np

from . import reference as ref
from .behaviours import desired_state
from .controller import LIFTOFF, S_GROUND_Z, S_LAST_HEIGHT, S_PHASE, S_THRUST, controller_step, euler_zyx
from .terrain import terrain_height_at, terrain_params

# Recorded channels, in column order. Each row is the state s_i at t = i dt
# (what MuJoCo computed for it), not what the controller read.
CHANNELS = (
    "t",
    "x",
    "y",
    "z",
    "vx",
    "vy",
    "vz",
    "ax",
    "ay",
    "az",
    "roll",
    "pitch",
    "yaw",
    "roll_rate",
    "pitch_rate",
    "x_des",
    "y_des",
    "vx_des",
    "vy_des",
    "hip_y",
    "hip_x",
    "hip_y_rate",
    "hip_x_rate",
    "hip_y_target",
    "hip_x_target",
    "hip_y_target_rate",
    "hip_x_target_rate",
    "ctrl_hip_y",
    "ctrl_hip_x",
    "ctrl_thrust",  # actuator space (the controls)
    "torque_hip_y",
    "torque_hip_x",
    "force_thrust",  # joint space (MuJoCo's qfrc_actuator)
    "touch",
    "phase",
    "thrust_setting",
    "foot_spring",
    "foot_spring_rate",
    "az_filtered",
    "jerk_z",  # low-passed base z acceleration, its derivative
    # the base's z acceleration averaged over each record interval
    # (every physics step since the previous record): an anti-aliasing box
    # filter, so the record-rate signal can be low-passed with zero phase
    # afterwards (mat_hopper.physics.jerk).
    "az_mean",
    # The foot's contact at the physics rate over each record interval
    # (every physics step since the previous record; ContactProbe):
    # the toe's touch-sensor on/off switches (touch > 0 N is on), counted
    # on the reading the controller gets (the sensor max(L, 1) physics
    # steps old, L the sensor latency), so that a toggle falls in the
    # record of the phase switch it causes; and the least signed distance,
    # m, between the foot geom and the terrain (MuJoCo's mj_geomDistance on
    # each state s_i within NEAR_GROUND_M of the ground, every
    # FAR_CHECK_S above it; capped at CLEARANCE_CAP_M; negative: the foot is
    # that deep in the ground).
    "touch_toggles",
    "foot_clearance_min",
)
C = {name: i for i, name in enumerate(CHANNELS)}
N_CHANNELS = len(CHANNELS)
RECORD_DTYPE = np.dtype([(name, np.float64) for name in CHANNELS])

# m, the cap of the foot's recorded clearance (mj_geomDistance's distmax): well above any hop.
CLEARANCE_CAP_M = 10.0
# The distance query costs about a third of a physics step, so it runs at
# every step only near the ground, where the penetration is: within
# NEAR_GROUND_M (m) of it. Above, once every FAR_CHECK_S (s): at the 10 m/s
# that no hop reaches, the foot falls 1 cm between two checks, so it never
# reaches the ground unseen, and every penetration is measured at every step.
NEAR_GROUND_M = 0.05
FAR_CHECK_S = 1e-3

# One row of the reading history: what the base sensors gave at one step.
H_POS, H_QUAT, H_GYRO, H_VEL, H_TOUCH = 0, 3, 7, 10, 13
HISTORY_WIDTH = 14


class Buffers(NamedTuple):
    """The MuJoCo data arrays the loop reads and writes (views, no copies)."""

    qpos: np.ndarray
    qvel: np.ndarray
    qacc: np.ndarray
    ctrl: np.ndarray
    sensordata: np.ndarray
    qfrc_actuator: np.ndarray
    xfrc_applied: np.ndarray
    geom_xpos: np.ndarray


def buffers(data) -> Buffers:
    """The :class:`Buffers` of a ``mujoco.MjData`` (its own arrays, no copies)."""
    d = data
    return Buffers(d.qpos, d.qvel, d.qacc, d.ctrl, d.sensordata, d.qfrc_actuator, d.xfrc_applied, d.geom_xpos)


class Path(NamedTuple):
    """A behaviour's desired path as the compiled code reads it."""

    kind: int
    params: np.ndarray
    table: np.ndarray


# noise_every of a run without sensor noise: no step ever reaches it.
NO_NOISE_EVERY = 1 << 60


class Disturbance(NamedTuple):
    """push = [t0, t1, fx, fy] (s, s, N, N) on the base; noise rows
    (position m x3, velocity m/s x3) added to the controller's readings, one
    row per ``noise_every`` steps from step 0 (:data:`NO_NOISE_EVERY`: no noise)."""

    push: np.ndarray
    noise: np.ndarray
    noise_every: int


class JerkFilter(NamedTuple):
    """A second-order low-pass section (b0, b1, b2, a1, a2; a0 = 1) applied
    to the base's z acceleration at every physics step (transposed direct
    form II), and its state [z1, z2, previous output, sum of az since the
    last record, steps in that sum], carried between calls. Coefficients from scipy.signal.butter (mat_hopper.core.sim)."""

    coef: np.ndarray
    state: np.ndarray


class StressProbe(NamedTuple):
    """The material springs the loop turns into stress at every
    physics step. adr: (N, 3) qpos addresses of segment s's axial slide and
    its hinges about x and y (-1 where the convention has none); gain:
    (N, 3) Pa per unit of joint position, k / A for the slide (F / A) and
    k c / I for the hinges (M c / I); peak: (N,) the largest section stress
    |sigma_axial| + sqrt(sigma_x^2 + sigma_y^2) since the last record,
    carried between calls.

    A separate per-segment array rather than record channels: the number
    of segments varies by design, the record's channels do not."""

    adr: np.ndarray
    gain: np.ndarray
    peak: np.ndarray


class ContactProbe(NamedTuple):
    """The foot's contact, evaluated at every physics step: the touch
    reading's toggles (the controller's reading, see CHANNELS) and the
    foot-terrain distance of s_i after mj_step2. foot: the foot geom's id;
    terrain: ids of the terrain geoms (ground, ramp) it can touch; state:
    [touch reading on (1) or off (0) at the last step, toggles since the
    last record, least foot-terrain distance m since the last record, the
    last distance measured m], carried between calls."""

    foot: int
    terrain: np.ndarray
    state: np.ndarray


def contact_probe(model, touch_on: bool) -> ContactProbe:
    """The :class:`ContactProbe` of a compiled hopper model, its touch
    state starting at `touch_on` (the start state's touch sensor > 0 N,
    which every row of the reading history starts with)."""
    from .mjcf import FOOT_GEOM, GROUND_GEOM, RAMP_GEOM

    ids = [mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, n) for n in (GROUND_GEOM, RAMP_GEOM)]
    terrain = np.array([i for i in ids if i >= 0], dtype=np.int64)
    foot = int(model.geom(FOOT_GEOM).id)
    return ContactProbe(foot, terrain, np.array([1.0 if touch_on else 0.0, 0.0, CLEARANCE_CAP_M, 0.0]))


class ApexReference(NamedTuple):
    """What the controller's hop height is measured from (module doc).
    ground: True for ``"ground"`` (the terrain under the foot at each
    lift-off), False for ``"world"`` (z = 0); foot: the foot geom's id;
    terrain: :func:`mat_hopper.core.terrain.terrain_params` of the terrain."""

    ground: bool
    foot: int
    terrain: np.ndarray


def apex_reference_of(model, apex_reference: str, ramp_grade_deg) -> ApexReference:
    """The :class:`ApexReference` of a compiled hopper model on a terrain.

    Args:
        model: the compiled ``MjModel`` (its foot geom).
        apex_reference: ``"world"`` or ``"ground"``, as checked by
            :func:`mat_hopper.core.controller.check_apex_reference`.
        ramp_grade_deg: None for flat ground, else the ramp's pitch, deg.
    """
    from .mjcf import FOOT_GEOM

    foot = int(model.geom(FOOT_GEOM).id)
    return ApexReference(apex_reference == "ground", foot, terrain_params(ramp_grade_deg))


# Jerk is computed at the physics rate: the base's z acceleration through a
# causal Butterworth low-pass, then differentiated step by step. The cut-off
# lies far below the leg's axial modes (2.5-4 kHz, barely damped) and the
# record rates' Nyquist frequencies, and above the hop's body dynamics
# (stance about 0.1 s): the number does not depend on the record rate.
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
    lower the cut-off to 0.2 / timestep_s, below their Nyquist frequency.

    Args:
        timestep_s: the physics time step, s (> 0).
        az0_m_s2: the filter's steady-state input, m/s^2 (default -g, the
            base's free fall at the start).

    Returns:
        :class:`JerkFilter`: coef (b0, b1, b2, a1, a2) of
        the order-:data:`JERK_FILTER_ORDER` Butterworth at
        min(:data:`JERK_CUTOFF_HZ`, 0.2 / timestep_s) Hz, and state (z1, z2,
        az0_m_s2 as the previous output, 0, 0).
    """
    import scipy.signal

    cutoff = min(JERK_CUTOFF_HZ, 0.2 / timestep_s)
    sos = scipy.signal.butter(JERK_FILTER_ORDER, cutoff, fs=1.0 / timestep_s, output="sos")
    ((b0, b1, b2, _, a1, a2),) = sos
    zi = scipy.signal.sosfilt_zi(sos)[0] * az0_m_s2
    return JerkFilter(np.array([b0, b1, b2, a1, a2]), np.array([zi[0], zi[1], az0_m_s2, 0.0, 0.0]))


# Columns of the stress record (one (N, 4) block per record), Pa: axial F / A
# (tension > 0), bending M c / I about x and about y (signed), and the
# physics-rate peak of the section's largest normal stress since the last record.
STRESS_COLUMNS = ("axial_pa", "bending_x_pa", "bending_y_pa", "peak_pa")


class Steps(NamedTuple):
    """Which physics steps to run and how."""

    first: int  # index of the first physics step of this call
    count: int  # how many physics steps
    dt: float  # s, the physics step
    record_every: int  # physics steps between records
    qacc_limit: float  # |qacc| above this is divergence
    substeps: int  # physics steps per control period (the control is held between updates)


# ---------------------------------------------------------------------------
# libmujoco, reached through ctypes from compiled code


def _libmujoco():
    here = os.path.dirname(mujoco.__file__)
    names = sorted(f for f in os.listdir(here) if f.startswith("libmujoco.so"))
    if not names:
        raise RuntimeError(f"libmujoco not found next to the mujoco bindings in {here}")
    return ctypes.CDLL(os.path.join(here, names[-1]))


_LIB = _libmujoco()
_STEP_PROTO = ctypes.CFUNCTYPE(None, ctypes.c_void_p, ctypes.c_void_p)
MJ_STEP = _STEP_PROTO(("mj_step", _LIB))
MJ_STEP1 = _STEP_PROTO(("mj_step1", _LIB))
MJ_STEP2 = _STEP_PROTO(("mj_step2", _LIB))
# mjtNum mj_geomDistance(const mjModel*, const mjData*, int geom1, int geom2, mjtNum distmax, mjtNum fromto[6])
_DISTANCE_PROTO = ctypes.CFUNCTYPE(
    ctypes.c_double, ctypes.c_void_p, ctypes.c_void_p, ctypes.c_int, ctypes.c_int, ctypes.c_double, ctypes.c_void_p
)
MJ_GEOM_DISTANCE = _DISTANCE_PROTO(("mj_geomDistance", _LIB))


@numba.njit(cache=True)
def read_sensors(sensordata, lay, row):
    """Copy the base readings of ``sensordata`` into one history row."""
    for k in range(3):
        row[H_POS + k] = sensordata[lay.base_pos + k]
        row[H_GYRO + k] = sensordata[lay.base_gyro + k]
        row[H_VEL + k] = sensordata[lay.base_linvel + k]
    for k in range(4):
        row[H_QUAT + k] = sensordata[lay.base_quat + k]
    row[H_TOUCH] = sensordata[lay.touch]


@numba.njit(cache=True)
def _diverged(qpos, qacc, limit):
    for v in qacc:
        if not (abs(v) <= limit):  # catches nan too
            return True
    for v in qpos:
        if not math.isfinite(v):
            return True
    return False


# Exempt from the 100-line rule: the whole closed loop is one compiled function so a rollout never returns to Python per step.
@numba.njit(cache=True)
def rollout_loop(
    step1,
    step2,
    geom_distance,
    m_ptr,
    d_ptr,
    buf,
    lay,
    gains,
    path,
    dist,
    steps,
    history,
    state,
    out,
    jerk,
    rec,
    qpos_rec,
    events,
    probe,
    stress_rec,
    contact,
    apex,
):
    """Run physics steps ``steps.first`` .. ``steps.first + steps.count - 1``.

    history: (latency + 1, HISTORY_WIDTH) ring of past readings, carried
    between calls; state: the controller's state; out: (OUT_SIZE,) the
    controller's last outputs (controls and hip targets), carried between
    calls so a record taken before a call's first control update (physics
    substeps) holds the held control's targets; rec: structured records (RECORD_DTYPE), one every
    ``record_every`` steps; qpos_rec: (records, nq) joint positions after
    the step, or 0 rows; events: (n, 3) rows of (time s, kind, hop height m);
    jerk: the JerkFilter run on the base's z acceleration every step;
    probe: the StressProbe evaluated on s_i every step; stress_rec: (records,
    N, 4) stress rows (STRESS_COLUMNS) written with each record; contact:
    the ContactProbe evaluated on s_i after every mj_step2 (geom_distance
    is libmujoco's mj_geomDistance; the positions it reads are still s_i's);
    apex: the ApexReference, read at each lift-off (module doc).
    Returns (records written, events written, step of divergence or -1)."""
    hip_angle = np.zeros(2)
    hip_rate = np.zeros(2)
    desired = np.zeros(4)
    pos = np.zeros(3)
    vel = np.zeros(3)
    ring = history.shape[0]
    latency = ring - 1
    touch_lag = latency - 1 if latency > 0 else 0
    noisy = dist.noise_every < NO_NOISE_EVERY
    base = lay.base_body
    pushing = buf.xfrc_applied[base, 0] != 0.0 or buf.xfrc_applied[base, 1] != 0.0
    n_rec = 0
    n_ev = 0
    n_seg = probe.adr.shape[0]
    stress_now = np.zeros((n_seg, 3))
    far_every = max(1, int(FAR_CHECK_S / steps.dt))
    for i in range(steps.first, steps.first + steps.count):
        t = i * steps.dt
        step1(m_ptr, d_ptr)
        read_sensors(buf.sensordata, lay, history[i % ring])
        # touch toggles, on the reading the controller gets (as below): in step with its phase switches
        on = 1.0 if history[(i + ring - touch_lag) % ring][H_TOUCH] > 0.0 else 0.0
        if on != contact.state[0]:
            contact.state[0] = on
            contact.state[1] += 1.0
        hip_angle[0] = buf.qpos[lay.hip_y_qpos]
        hip_angle[1] = buf.qpos[lay.hip_x_qpos]
        hip_rate[0] = buf.qvel[lay.hip_y_dof]
        hip_rate[1] = buf.qvel[lay.hip_x_dof]
        if i % steps.substeps == 0:
            lagged = history[(i + ring - latency) % ring]
            touch = history[(i + ring - touch_lag) % ring][H_TOUCH]
            for k in range(3):
                pos[k] = lagged[H_POS + k]
                vel[k] = lagged[H_VEL + k]
            if noisy:
                nrow = dist.noise[min(i // dist.noise_every, dist.noise.shape[0] - 1)]
                for k in range(3):
                    pos[k] += nrow[k]
                    vel[k] += nrow[3 + k]
            quat = lagged[H_QUAT : H_QUAT + 4]
            gyro = lagged[H_GYRO : H_GYRO + 3]
            dx, dy, dvx, dvy = desired_state(t, path.kind, path.params, path.table)
            desired[0], desired[1], desired[2], desired[3] = dx, dy, dvx, dvy
            event = controller_step(t, touch, pos, quat, gyro, vel, hip_angle, hip_rate, desired, gains, state, out)
            buf.ctrl[lay.act_hip_y] = out[0]
            buf.ctrl[lay.act_hip_x] = out[1]
            buf.ctrl[lay.act_thrust] = out[2]
            if event == LIFTOFF and apex.ground:  # the apex above the ground this hop leaves from
                fx, fy = buf.geom_xpos[apex.foot, 0], buf.geom_xpos[apex.foot, 1]
                state[S_GROUND_Z] = terrain_height_at(fx, fy, apex.terrain)
            if event != 0 and n_ev < events.shape[0]:
                events[n_ev, 0] = t
                events[n_ev, 1] = event
                events[n_ev, 2] = state[S_LAST_HEIGHT]
                n_ev += 1
        if (dist.push[0] <= t < dist.push[1]) != pushing:
            pushing = not pushing
            buf.xfrc_applied[base, 0] = dist.push[2] if pushing else 0.0
            buf.xfrc_applied[base, 1] = dist.push[3] if pushing else 0.0
        foot, foot_rate = buf.qpos[lay.spring_qpos], buf.qvel[lay.spring_dof]
        for s in range(n_seg):  # section stress of s_i, peak at the physics rate
            sa = probe.gain[s, 0] * buf.qpos[probe.adr[s, 0]] if probe.adr[s, 0] >= 0 else 0.0
            sx = probe.gain[s, 1] * buf.qpos[probe.adr[s, 1]] if probe.adr[s, 1] >= 0 else 0.0
            sy = probe.gain[s, 2] * buf.qpos[probe.adr[s, 2]] if probe.adr[s, 2] >= 0 else 0.0
            stress_now[s, 0], stress_now[s, 1], stress_now[s, 2] = sa, sx, sy
            mag = abs(sa) + math.sqrt(sx * sx + sy * sy)
            if mag > probe.peak[s]:
                probe.peak[s] = mag
        step2(m_ptr, d_ptr)
        bad = _diverged(buf.qpos, buf.qacc, steps.qacc_limit)
        az = buf.qacc[lay.base_dof + 2]
        c, z = jerk.coef, jerk.state
        az_f = c[0] * az + z[0]
        z[0] = c[1] * az - c[3] * az_f + z[1]
        z[1] = c[2] * az - c[4] * az_f
        jerk_z = (az_f - z[2]) / steps.dt
        z[2] = az_f
        z[3] += az
        z[4] += 1.0
        cs = contact.state
        if not bad and (cs[3] < NEAR_GROUND_M or i % far_every == 0):
            nearest = CLEARANCE_CAP_M
            for g in contact.terrain:
                gap = geom_distance(m_ptr, d_ptr, g, contact.foot, CLEARANCE_CAP_M, 0)
                if gap < nearest:
                    nearest = gap
            cs[3] = nearest
            if nearest < cs[2]:
                cs[2] = nearest
        if (i % steps.record_every == 0 or bad) and n_rec < rec.shape[0]:
            r = rec[n_rec]
            now = history[i % ring]  # the state s_i as MuJoCo computed it
            r["t"] = t
            r["x"], r["y"], r["z"] = now[H_POS], now[H_POS + 1], now[H_POS + 2]
            r["vx"], r["vy"], r["vz"] = now[H_VEL], now[H_VEL + 1], now[H_VEL + 2]
            r["ax"] = buf.qacc[lay.base_dof]
            r["ay"] = buf.qacc[lay.base_dof + 1]
            r["az"] = buf.qacc[lay.base_dof + 2]
            r["roll"], r["pitch"], r["yaw"] = euler_zyx(now[H_QUAT : H_QUAT + 4])
            r["roll_rate"], r["pitch_rate"] = now[H_GYRO], now[H_GYRO + 1]
            r["x_des"], r["y_des"], r["vx_des"], r["vy_des"] = desired_state(t, path.kind, path.params, path.table)
            r["hip_y"], r["hip_x"] = hip_angle[0], hip_angle[1]
            r["hip_y_rate"], r["hip_x_rate"] = hip_rate[0], hip_rate[1]
            r["hip_y_target"], r["hip_x_target"] = out[3], out[4]
            r["hip_y_target_rate"], r["hip_x_target_rate"] = out[5], out[6]
            r["ctrl_hip_y"] = buf.ctrl[lay.act_hip_y]
            r["ctrl_hip_x"] = buf.ctrl[lay.act_hip_x]
            r["ctrl_thrust"] = buf.ctrl[lay.act_thrust]
            r["torque_hip_y"] = buf.qfrc_actuator[lay.hip_y_dof]
            r["torque_hip_x"] = buf.qfrc_actuator[lay.hip_x_dof]
            r["force_thrust"] = buf.qfrc_actuator[lay.spring_dof]
            r["touch"] = buf.sensordata[lay.touch]  # s_i's ground force, after mj_step2
            r["phase"] = state[S_PHASE]
            r["thrust_setting"] = state[S_THRUST]
            r["foot_spring"] = foot
            r["foot_spring_rate"] = foot_rate
            r["az_filtered"] = az_f
            r["jerk_z"] = jerk_z
            r["az_mean"] = z[3] / z[4]
            z[3] = 0.0
            z[4] = 0.0
            r["touch_toggles"] = cs[1]
            r["foot_clearance_min"] = cs[2]
            cs[1] = 0.0
            cs[2] = CLEARANCE_CAP_M
            if n_rec < qpos_rec.shape[0]:
                qpos_rec[n_rec, :] = buf.qpos
            for s in range(n_seg):
                for k in range(3):
                    stress_rec[n_rec, s, k] = stress_now[s, k]
                stress_rec[n_rec, s, 3] = probe.peak[s]
                probe.peak[s] = 0.0
            n_rec += 1
        if bad:
            return n_rec, n_ev, i
    return n_rec, n_ev, -1
