"""Warp kernels of the batch: controller, per-hop metrics, divergence.

The controller is :mod:`mat_hopper.core.controller` line for line (``euler_zyx``,
``update_phase``, ``controller_step``), in float64 like the CPU code, one
thread per world; its gains arrive as a struct filled from
:class:`~mat_hopper.core.controller.ControllerSettings` field by field, and the
controller state uses control.py's own layout (``S_*`` indices) and
initial values. The desired path is :func:`mat_hopper.core.behaviours.desired_state`.

Per physics step i (time t_i = i dt) the host launches

1. :func:`park_kernel`: a diverged world is parked (see below);
2. ``mujoco_warp.step1``: position and velocity stages at t_i, their
   sensors included (base position, orientation, gyro, linear velocity of
   state s_i);
3. :func:`push_base_kernel`: those readings into the world's ring of past
   base readings (slot i mod ring);
4. :func:`control_kernel`: the controller at t_i on the readings of the
   sensor timing (:mod:`mat_hopper.core.controller`): with a latency of L physics
   steps the base readings of s_(i-L) and the touch force of
   s_(i-max(L,1)) (a ground force cannot be fresher than the previous
   control), the hips from the current ``qpos``/``qvel`` (s_i); before the
   first step every lagged reading is the start state's. L = 1 is the
   authors' read-control-``mj_step`` loop, L = 0 the fresh
   ``mj_step1``-read-control-``mj_step2`` loop, as in
   :mod:`mat_hopper.core._loop`. Writes ``ctrl``, the state machine's event and
   the hip rates it saw;
5. ``mujoco_warp.step2``: actuation, acceleration (the touch sensor of
   s_i), integration to t_(i+1);
6. :func:`metrics_kernel`: the sample of t_i, as the CPU rollout records
   it: base position from the sensors of s_i, desired path at t_i, hip
   power from ``qfrc_actuator`` (joint space, gear x control) times the hip
   rates at t_i; closes and opens hop cycles at lift-offs; then checks
   divergence (NaN/inf in qpos, or |qacc| above the limit); besides the hop
   cycles it keeps whole-run means of tracking error and hip power over
   every finite recorded sample (the divergence step's included, as the
   CPU rollout records it) and the base z of the last recorded sample;
7. :func:`push_touch_kernel`: s_i's touch force into the touch ring;
8. :func:`tick_kernel`: the step counter, kept on the device so that a
   CUDA graph of many steps can be replayed.

Per-hop metrics follow :mod:`mat_hopper.physics.metrics`: a hop cycle runs from a
lift-off to the next; a cycle counts when it starts at or after the
transient and holds at least one sample; per cycle the mean planar tracking
error, the max base z and the mean hip power norm over its samples (taken
every ``every`` steps); the results are means over the cycles.

A diverged world stops counting at its divergence step. From the next step
on it is parked: its state is reset to the initial pose at rest with zero
controls before every step, so that it cannot slow the solver of the
others.
"""

# Kernels are exempt from the 100-line rule: one kernel is one device launch, and splitting it adds launches per step.

from __future__ import annotations

import numpy as np
import warp as wp

from ..core import behaviours as _beh
from ..core import controller as _ctl
from ..core.model import Layout

F64 = wp.float64

# control.py's state layout, phases and events.
S_PHASE = wp.constant(_ctl.S_PHASE)
S_T_SWITCH = wp.constant(_ctl.S_T_SWITCH)
S_THRUST = wp.constant(_ctl.S_THRUST)
S_Z_MAX = wp.constant(_ctl.S_Z_MAX)
S_LAST_HEIGHT = wp.constant(_ctl.S_LAST_HEIGHT)
S_LIFTOFFS = wp.constant(_ctl.S_LIFTOFFS)
S_TOUCHDOWNS = wp.constant(_ctl.S_TOUCHDOWNS)
FLIGHT = wp.constant(_ctl.FLIGHT)
STANCE = wp.constant(_ctl.STANCE)
NO_EVENT = wp.constant(_ctl.NO_EVENT)
TOUCHDOWN = wp.constant(_ctl.TOUCHDOWN)
LIFTOFF = wp.constant(_ctl.LIFTOFF)
PATH_CIRCLE = wp.constant(_beh.PATH_CIRCLE)
PATH_TABLE = wp.constant(_beh.PATH_TABLE)

# The base readings as the ring holds them (float64 columns of one slot).
R_POS = 0  # base position (3), m, world frame
R_QUAT = 3  # base orientation quaternion (4), w x y z
R_GYRO = 7  # base angular velocity (3), rad/s, body frame
R_VEL = 10  # base linear velocity (3), m/s, world frame
R_WIDTH = 13
_R_POS, _R_QUAT, _R_GYRO, _R_VEL = (wp.constant(v) for v in (R_POS, R_QUAT, R_GYRO, R_VEL))


def ring_size(latency: int) -> int:
    """Slots of the reading rings for a latency of L physics steps: the
    readings of s_(i-max(L,1)) .. s_i."""
    return max(int(latency), 1) + 1


# Per-world metric accumulators (float64 columns).
A_OPEN = 0  # 1 while a hop cycle is open (after the first lift-off)
A_START = 1  # s, start of the open cycle
A_N = 2  # samples in the open cycle
A_ERR = 3  # sum of planar tracking error over them (m)
A_POW = 4  # sum of hip power norm over them (W)
A_ZMAX = 5  # max base z over them (m)
A_HOPS = 6  # scored cycles
A_HEIGHT_SUM = 7  # sums over scored cycles of the per-cycle values
A_ERR_SUM = 8
A_POW_SUM = 9
# Whole-run accumulators, over every recorded sample (the optimizer's fallback
# score of a run without scored hops, mat_hopper.optimize._objective):
A_RUN_NERR = 10  # finite tracking-error samples
A_RUN_ERR = 11  # their sum (m)
A_RUN_NPOW = 12  # finite hip-power samples
A_RUN_POW = 13  # their sum (W)
A_LAST_Z = 14  # base z of the last recorded sample (m): the run's upright test
N_ACC = 15
_A = {
    k: wp.constant(v)
    for k, v in dict(
        A_OPEN=A_OPEN,
        A_START=A_START,
        A_N=A_N,
        A_ERR=A_ERR,
        A_POW=A_POW,
        A_ZMAX=A_ZMAX,
        A_HOPS=A_HOPS,
        A_HEIGHT_SUM=A_HEIGHT_SUM,
        A_ERR_SUM=A_ERR_SUM,
        A_POW_SUM=A_POW_SUM,
        A_RUN_NERR=A_RUN_NERR,
        A_RUN_ERR=A_RUN_ERR,
        A_RUN_NPOW=A_RUN_NPOW,
        A_RUN_POW=A_RUN_POW,
        A_LAST_Z=A_LAST_Z,
    ).items()
}
W_OPEN, W_START, W_N, W_ERR, W_POW = _A["A_OPEN"], _A["A_START"], _A["A_N"], _A["A_ERR"], _A["A_POW"]
W_ZMAX, W_HOPS, W_HEIGHT_SUM, W_ERR_SUM, W_POW_SUM = (
    _A["A_ZMAX"],
    _A["A_HOPS"],
    _A["A_HEIGHT_SUM"],
    _A["A_ERR_SUM"],
    _A["A_POW_SUM"],
)
W_RUN_NERR, W_RUN_ERR, W_RUN_NPOW, W_RUN_POW, W_LAST_Z = (
    _A["A_RUN_NERR"],
    _A["A_RUN_ERR"],
    _A["A_RUN_NPOW"],
    _A["A_RUN_POW"],
    _A["A_LAST_Z"],
)


def _struct(name: str, fields, dtype):
    cls = type(name, (), {"__annotations__": {f: dtype for f in fields}, "__module__": __name__, "__qualname__": name})
    return wp.struct(cls)


# The gains, field for field as control.Gains (itself ControllerSettings' fields).
GainsW = _struct("GainsW", _ctl.Gains._fields, wp.float64)
# Addresses, field for field as model.Layout.
LayoutW = _struct("LayoutW", Layout._fields, wp.int32)


def make_gains(settings: _ctl.ControllerSettings):
    g = GainsW()
    for name, value in settings.gains()._asdict().items():
        setattr(g, name, float(value))
    return g


def make_layout(layout: Layout):
    s = LayoutW()
    for name, value in layout._asdict().items():
        setattr(s, name, int(value))
    return s


@wp.func
def euler_zyx(w: F64, x: F64, y: F64, z: F64):
    one = F64(1.0)
    two = F64(2.0)
    roll = wp.atan2(two * (w * x + y * z), one - two * (x * x + y * y))
    sp = two * (w * y - z * x)
    sp = wp.min(one, wp.max(-one, sp))
    pitch = wp.asin(sp)
    yaw = wp.atan2(two * (w * z + x * y), one - two * (y * y + z * z))
    return roll, pitch, yaw


@wp.func
def clamp(v: F64, limit: F64):
    return wp.min(limit, wp.max(-limit, v))


@wp.func
def update_phase(t: F64, touch: F64, z: F64, vz: F64, g: GainsW, state: wp.array2d(dtype=F64), w: int):
    zero = F64(0.0)
    one = F64(1.0)
    if z > state[w, S_Z_MAX]:
        state[w, S_Z_MAX] = z
    if t - state[w, S_T_SWITCH] < g.phase_lock_s:
        return NO_EVENT
    if state[w, S_PHASE] == F64(FLIGHT) and touch > zero and vz < zero:
        state[w, S_PHASE] = F64(STANCE)
        state[w, S_T_SWITCH] = t
        state[w, S_TOUCHDOWNS] = state[w, S_TOUCHDOWNS] + one
        if state[w, S_LIFTOFFS] > zero:  # the very first touchdown adapts nothing
            height = state[w, S_Z_MAX]
            state[w, S_LAST_HEIGHT] = height
            adapted = state[w, S_THRUST] + g.thrust_adapt_gain * (g.hop_height_target_m - height)
            state[w, S_THRUST] = wp.max(zero, adapted)
        state[w, S_Z_MAX] = z
        return TOUCHDOWN
    if state[w, S_PHASE] == F64(STANCE) and touch == zero and vz > zero:
        state[w, S_PHASE] = F64(FLIGHT)
        state[w, S_T_SWITCH] = t
        state[w, S_LIFTOFFS] = state[w, S_LIFTOFFS] + one
        return LIFTOFF
    return NO_EVENT


@wp.func
def desired_state(t: F64, kind: int, params: wp.array(dtype=F64), table: wp.array2d(dtype=F64)):
    speed = params[0]
    radius = params[1]
    heading = params[2]
    x0 = params[3]
    y0 = params[4]
    table_dt = params[5]
    zero = F64(0.0)
    if kind == PATH_CIRCLE:
        om = speed / radius
        c = wp.cos(om * t)
        s = wp.sin(om * t)
        return wp.vec4d(radius * c, radius * s, -speed * s, speed * c)
    if kind == PATH_TABLE:
        n = table.shape[0]
        u = t / table_dt
        i = wp.int32(wp.floor(u))
        if i >= n - 1:
            return wp.vec4d(table[n - 1, 0], table[n - 1, 1], zero, zero)
        if i < 0:
            return wp.vec4d(table[0, 0], table[0, 1], zero, zero)
        f = u - F64(i)
        dx = table[i + 1, 0] - table[i, 0]
        dy = table[i + 1, 1] - table[i, 1]
        return wp.vec4d(table[i, 0] + f * dx, table[i, 1] + f * dy, dx / table_dt, dy / table_dt)
    vx = speed * wp.cos(heading)
    vy = speed * wp.sin(heading)
    return wp.vec4d(x0 + vx * t, y0 + vy * t, vx, vy)


@wp.func
def controller_step(
    t: F64,
    touch: F64,
    pos: wp.vec3d,
    quat: wp.vec4d,
    gyro: wp.vec3d,
    vel: wp.vec3d,
    hip_angle: wp.vec2d,
    hip_rate: wp.vec2d,
    desired: wp.vec4d,
    g: GainsW,
    state: wp.array2d(dtype=F64),
    w: int,
):
    """control.controller_step for world w: returns (controls (hip_y, hip_x, thrust), event)."""
    zero = F64(0.0)
    two = F64(2.0)
    event = update_phase(t, touch, pos[2], vel[2], g, state, w)
    roll, pitch, yaw = euler_zyx(quat[0], quat[1], quat[2], quat[3])
    roll_rate = gyro[0]
    pitch_rate = gyro[1]

    # World -> yaw-aligned base frame.
    c = wp.cos(yaw)
    s = wp.sin(yaw)
    ex = desired[0] - pos[0]
    ey = desired[1] - pos[1]
    off_x = c * ex + s * ey
    off_y = -s * ex + c * ey
    vdx = c * desired[2] + s * desired[3]
    vdy = -s * desired[2] + c * desired[3]
    vx = c * vel[0] + s * vel[1]
    vy = -s * vel[0] + c * vel[1]

    # Velocity to aim for, then the foot placement that reaches it.
    aim_x = clamp(g.velocity_gain_desired * vdx + g.velocity_gain_position * off_x, g.velocity_limit_m_s)
    aim_y = clamp(g.velocity_gain_desired * vdy + g.velocity_gain_position * off_y, g.velocity_limit_m_s)
    foot_x = vx * g.stance_duration_s / two + g.foot_placement_gain * (vx - aim_x)
    foot_y = vy * g.stance_duration_s / two + g.foot_placement_gain * (vy - aim_y)

    # Inverse kinematics, corrected for body attitude.
    target_y = -wp.atan(foot_x / g.leg_length_m) - pitch
    target_x = wp.atan(foot_y / g.leg_length_m) - roll
    target_rate_y = -pitch_rate
    target_rate_x = -roll_rate

    u_y = zero
    u_x = zero
    if touch > zero:  # stance: attitude correction through the hips
        u_y = g.stance_kp * pitch + g.stance_kd * pitch_rate
        u_x = g.stance_kp * roll + g.stance_kd * roll_rate
    else:  # flight: PD to the foot placement targets
        u_y = -g.flight_kp * (hip_angle[0] - target_y) - g.flight_kd * (hip_rate[0] - target_rate_y)
        u_x = -g.flight_kp * (hip_angle[1] - target_x) - g.flight_kd * (hip_rate[1] - target_rate_x)
    thrust = zero
    if touch > zero and vel[2] > g.thrust_min_rise_speed:
        thrust = state[w, S_THRUST]
    return wp.vec3d(u_y, u_x, thrust), event


@wp.kernel
def park_kernel(
    qpos_init: wp.array2d(dtype=float),
    diverged: wp.array(dtype=wp.int32),
    qpos: wp.array2d(dtype=float),
    qvel: wp.array2d(dtype=float),
    qacc_warmstart: wp.array2d(dtype=float),
    ctrl: wp.array2d(dtype=float),
    event: wp.array(dtype=wp.int32),
):
    """A diverged world back to the initial pose, at rest, no controls."""
    w = wp.tid()
    if diverged[w] < 0:
        return
    for k in range(qpos.shape[1]):
        qpos[w, k] = qpos_init[w, k]
    for k in range(qvel.shape[1]):
        qvel[w, k] = float(0.0)
        qacc_warmstart[w, k] = float(0.0)
    for k in range(ctrl.shape[1]):
        ctrl[w, k] = float(0.0)
    event[w] = NO_EVENT


@wp.kernel
def push_base_kernel(
    clock: wp.array(dtype=wp.int32),
    lay: LayoutW,
    sensordata: wp.array2d(dtype=float),
    base_ring: wp.array3d(dtype=F64),
):
    """After step1: the base readings of s_i into slot i mod ring."""
    w = wp.tid()
    slot = clock[0] % base_ring.shape[1]
    for k in range(3):
        base_ring[w, slot, _R_POS + k] = F64(sensordata[w, lay.base_pos + k])
        base_ring[w, slot, _R_GYRO + k] = F64(sensordata[w, lay.base_gyro + k])
        base_ring[w, slot, _R_VEL + k] = F64(sensordata[w, lay.base_linvel + k])
    for k in range(4):
        base_ring[w, slot, _R_QUAT + k] = F64(sensordata[w, lay.base_quat + k])


@wp.kernel
def push_touch_kernel(
    clock: wp.array(dtype=wp.int32),
    lay: LayoutW,
    sensordata: wp.array2d(dtype=float),
    touch_ring: wp.array2d(dtype=F64),
):
    """After step2: the touch force of s_i into slot i mod ring."""
    w = wp.tid()
    touch_ring[w, clock[0] % touch_ring.shape[1]] = F64(sensordata[w, lay.touch])


@wp.kernel
def control_kernel(
    clock: wp.array(dtype=wp.int32),
    dt: F64,
    latency: int,
    g: GainsW,
    lay: LayoutW,
    path_kind: int,
    path_params: wp.array(dtype=F64),
    path_table: wp.array2d(dtype=F64),
    base_ring: wp.array3d(dtype=F64),
    touch_ring: wp.array2d(dtype=F64),
    diverged: wp.array(dtype=wp.int32),
    state: wp.array2d(dtype=F64),
    qpos: wp.array2d(dtype=float),
    qvel: wp.array2d(dtype=float),
    ctrl: wp.array2d(dtype=float),
    event: wp.array(dtype=wp.int32),
    hip_rate_seen: wp.array2d(dtype=F64),
):
    """The controller of world w at step i: base readings of s_(i-latency),
    touch of s_(i-max(latency,1)) (from the rings), hips of s_i."""
    w = wp.tid()
    if diverged[w] >= 0:  # parked (park_kernel)
        return
    i = clock[0]
    t = F64(i) * dt
    ring = base_ring.shape[1]
    b = (i + ring - latency) % ring
    touch = touch_ring[w, (i + ring - wp.max(latency, 1)) % ring]
    pos = wp.vec3d(base_ring[w, b, _R_POS], base_ring[w, b, _R_POS + 1], base_ring[w, b, _R_POS + 2])
    quat = wp.vec4d(
        base_ring[w, b, _R_QUAT],
        base_ring[w, b, _R_QUAT + 1],
        base_ring[w, b, _R_QUAT + 2],
        base_ring[w, b, _R_QUAT + 3],
    )
    gyro = wp.vec3d(base_ring[w, b, _R_GYRO], base_ring[w, b, _R_GYRO + 1], base_ring[w, b, _R_GYRO + 2])
    vel = wp.vec3d(base_ring[w, b, _R_VEL], base_ring[w, b, _R_VEL + 1], base_ring[w, b, _R_VEL + 2])
    hip_angle = wp.vec2d(F64(qpos[w, lay.hip_y_qpos]), F64(qpos[w, lay.hip_x_qpos]))
    hip_rate = wp.vec2d(F64(qvel[w, lay.hip_y_dof]), F64(qvel[w, lay.hip_x_dof]))
    desired = desired_state(t, path_kind, path_params, path_table)
    u, ev = controller_step(t, touch, pos, quat, gyro, vel, hip_angle, hip_rate, desired, g, state, w)
    ctrl[w, lay.act_hip_y] = float(u[0])
    ctrl[w, lay.act_hip_x] = float(u[1])
    ctrl[w, lay.act_thrust] = float(u[2])
    event[w] = ev
    hip_rate_seen[w, 0] = hip_rate[0]
    hip_rate_seen[w, 1] = hip_rate[1]


def rings_from_sensordata(sensordata, lay, latency: int):
    """(base ring (nworld, ring, R_WIDTH), touch ring (nworld, ring)), numpy
    float64, every slot holding the readings of `sensordata` (nworld,
    nsensordata): the start state's, before the first step."""
    sd = np.asarray(sensordata, dtype=np.float64)
    base = np.empty((sd.shape[0], R_WIDTH))
    base[:, R_POS : R_POS + 3] = sd[:, lay.base_pos : lay.base_pos + 3]
    base[:, R_QUAT : R_QUAT + 4] = sd[:, lay.base_quat : lay.base_quat + 4]
    base[:, R_GYRO : R_GYRO + 3] = sd[:, lay.base_gyro : lay.base_gyro + 3]
    base[:, R_VEL : R_VEL + 3] = sd[:, lay.base_linvel : lay.base_linvel + 3]
    n = ring_size(latency)
    return np.repeat(base[:, None, :], n, axis=1), np.repeat(sd[:, lay.touch][:, None], n, axis=1)


@wp.kernel
def metrics_kernel(
    clock: wp.array(dtype=wp.int32),
    dt: F64,
    transient: F64,
    every: int,
    qacc_limit: F64,
    lay: LayoutW,
    path_kind: int,
    path_params: wp.array(dtype=F64),
    path_table: wp.array2d(dtype=F64),
    sensordata: wp.array2d(dtype=float),
    qfrc_actuator: wp.array2d(dtype=float),
    qpos: wp.array2d(dtype=float),
    qacc: wp.array2d(dtype=float),
    event: wp.array(dtype=wp.int32),
    hip_rate_seen: wp.array2d(dtype=F64),
    diverged: wp.array(dtype=wp.int32),
    acc: wp.array2d(dtype=F64),
):
    w = wp.tid()
    if diverged[w] >= 0:
        return
    i = clock[0]
    t = F64(i) * dt
    zero = F64(0.0)
    one = F64(1.0)
    if event[w] == LIFTOFF:
        # Close the open cycle [start, t): scored if it started after the transient and holds samples.
        if acc[w, W_OPEN] > zero and acc[w, W_START] >= transient and acc[w, W_N] > zero:
            n = acc[w, W_N]
            acc[w, W_HOPS] = acc[w, W_HOPS] + one
            acc[w, W_HEIGHT_SUM] = acc[w, W_HEIGHT_SUM] + acc[w, W_ZMAX]
            acc[w, W_ERR_SUM] = acc[w, W_ERR_SUM] + acc[w, W_ERR] / n
            acc[w, W_POW_SUM] = acc[w, W_POW_SUM] + acc[w, W_POW] / n
        acc[w, W_OPEN] = one
        acc[w, W_START] = t
        acc[w, W_N] = zero
        acc[w, W_ERR] = zero
        acc[w, W_POW] = zero
        acc[w, W_ZMAX] = F64(-wp.inf)
    bad = bool(False)
    for k in range(qacc.shape[1]):
        if not (wp.abs(F64(qacc[w, k])) <= qacc_limit):  # catches nan too
            bad = True
    for k in range(qpos.shape[1]):
        if not wp.isfinite(qpos[w, k]):
            bad = True
    sample = i % every == 0
    if sample or bad:  # a recorded sample (the CPU rollout also records its divergence step)
        desired = desired_state(t, path_kind, path_params, path_table)
        x = F64(sensordata[w, lay.base_pos])
        y = F64(sensordata[w, lay.base_pos + 1])
        z = F64(sensordata[w, lay.base_pos + 2])
        err = wp.sqrt((x - desired[0]) * (x - desired[0]) + (y - desired[1]) * (y - desired[1]))
        p_y = F64(qfrc_actuator[w, lay.hip_y_dof]) * hip_rate_seen[w, 0]
        p_x = F64(qfrc_actuator[w, lay.hip_x_dof]) * hip_rate_seen[w, 1]
        pw = wp.sqrt(p_y * p_y + p_x * p_x)
        if wp.isfinite(err):
            acc[w, W_RUN_NERR] = acc[w, W_RUN_NERR] + one
            acc[w, W_RUN_ERR] = acc[w, W_RUN_ERR] + err
        if wp.isfinite(pw):
            acc[w, W_RUN_NPOW] = acc[w, W_RUN_NPOW] + one
            acc[w, W_RUN_POW] = acc[w, W_RUN_POW] + pw
        acc[w, W_LAST_Z] = z
        if acc[w, W_OPEN] > zero and sample:
            acc[w, W_N] = acc[w, W_N] + one
            acc[w, W_ERR] = acc[w, W_ERR] + err
            acc[w, W_POW] = acc[w, W_POW] + pw
            acc[w, W_ZMAX] = wp.max(acc[w, W_ZMAX], z)
    if bad:
        diverged[w] = i


@wp.kernel
def tick_kernel(clock: wp.array(dtype=wp.int32)):
    clock[0] = clock[0] + 1
