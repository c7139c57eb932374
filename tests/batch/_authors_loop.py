"""An independent CPU reference for the batch: the authors' loop in plain Python.

MuJoCo's own CPU bindings, step by step: ``mj_forward`` once, then per
step read ``d.sensordata`` (as the previous ``mj_step`` left it) and the
hips from ``d.qpos``/``d.qvel``, run ``control.controller_step.py_func``,
``mj_step``. Samples are recorded as :mod:`mat_hopper.core.sim` records them
(the state at t_i, hip power from ``d.qfrc_actuator``, joint space), so
:func:`mat_hopper.physics.metrics.run_summary` scores them: metrics by the package's
own definitions, physics by MuJoCo's CPU engine in float64.
"""

from __future__ import annotations

import math

import mujoco
import numpy as np

from mat_hopper.core import reference as ref
from mat_hopper.core.behaviours import behaviour as get_behaviour
from mat_hopper.core.controller import (
    OUT_SIZE,
    S_LAST_HEIGHT,
    S_PHASE,
    S_THRUST,
    controller_step,
    euler_zyx,
    initial_state,
)
from mat_hopper.core.materials import parse_design
from mat_hopper.core.rollout import Rollout
from mat_hopper.core.sim import CHANNELS, prepare

_C = {n: i for i, n in enumerate(CHANNELS)}


def authors_rollout(design, behaviour, settings, *, trace_qpos: int = 0):
    """Run design on behaviour with settings (BatchSettings); returns
    (Rollout, qpos trace (first trace_qpos steps, state after each step))."""
    design = parse_design(design) if isinstance(design, str) else design
    beh = get_behaviour(behaviour)
    sim = settings
    hm, d = prepare(design, beh, sim)  # mj_forward done: sensors of the initial state
    m, lay = hm.model, hm.layout
    gains = settings.controller.gains()
    state = initial_state(settings.controller)
    out = np.zeros(OUT_SIZE)
    dt, every, n_steps = settings.timestep_s, settings.record_every, settings.n_steps
    rows, events, trace = [], [], []
    diverged = -1
    step = controller_step.py_func
    for i in range(n_steps):
        t = i * dt
        sd = d.sensordata
        pos = sd[lay.base_pos : lay.base_pos + 3].copy()
        vel = sd[lay.base_linvel : lay.base_linvel + 3].copy()
        quat = sd[lay.base_quat : lay.base_quat + 4].copy()
        gyro = sd[lay.base_gyro : lay.base_gyro + 3].copy()
        touch = float(sd[lay.touch])
        hip_angle = np.array([d.qpos[lay.hip_y_qpos], d.qpos[lay.hip_x_qpos]])
        hip_rate = np.array([d.qvel[lay.hip_y_dof], d.qvel[lay.hip_x_dof]])
        desired = np.array(beh.desired(t))
        event = step(t, touch, pos, quat, gyro, vel, hip_angle, hip_rate, desired, gains, state, out)
        d.ctrl[lay.act_hip_y], d.ctrl[lay.act_hip_x], d.ctrl[lay.act_thrust] = out[0], out[1], out[2]
        if event:
            events.append((t, event, state[S_LAST_HEIGHT]))
        foot, foot_rate = d.qpos[lay.spring_qpos], d.qvel[lay.spring_dof]
        mujoco.mj_step(m, d)
        if i < trace_qpos:
            trace.append(d.qpos.copy())
        bad = not (np.all(np.abs(d.qacc) <= ref.DIVERGENCE_QACC) and np.all(np.isfinite(d.qpos)))
        if i % every == 0 or bad:
            r = np.zeros(len(CHANNELS))
            r[_C["t"]] = t
            r[_C["x"] : _C["z"] + 1] = d.sensordata[lay.base_pos : lay.base_pos + 3]  # state at t_i
            r[_C["vx"] : _C["vz"] + 1] = d.sensordata[lay.base_linvel : lay.base_linvel + 3]
            r[_C["ax"] : _C["az"] + 1] = d.qacc[lay.base_dof : lay.base_dof + 3]
            r[_C["roll"] : _C["yaw"] + 1] = euler_zyx(d.sensordata[lay.base_quat : lay.base_quat + 4])
            r[_C["roll_rate"] : _C["pitch_rate"] + 1] = d.sensordata[lay.base_gyro : lay.base_gyro + 2]
            r[_C["x_des"] : _C["vy_des"] + 1] = desired
            r[_C["hip_y"] : _C["hip_x"] + 1] = hip_angle
            r[_C["hip_y_rate"] : _C["hip_x_rate"] + 1] = hip_rate
            r[_C["hip_y_target"] : _C["hip_x_target_rate"] + 1] = out[3:7]
            r[_C["ctrl_hip_y"] : _C["ctrl_thrust"] + 1] = out[:3]
            r[_C["torque_hip_y"]] = d.qfrc_actuator[lay.hip_y_dof]  # joint space: gear x control
            r[_C["torque_hip_x"]] = d.qfrc_actuator[lay.hip_x_dof]
            r[_C["force_thrust"]] = d.qfrc_actuator[lay.spring_dof]
            r[_C["touch"]] = d.sensordata[lay.touch]
            r[_C["phase"]] = state[S_PHASE]
            r[_C["thrust_setting"]] = state[S_THRUST]
            r[_C["foot_spring"]], r[_C["foot_spring_rate"]] = foot, foot_rate
            rows.append(r)
        if bad:
            diverged = i
            break
    data = np.array(rows).reshape(-1, len(CHANNELS))
    ev = np.array(events, dtype=float).reshape(-1, 3)
    rollout = Rollout(design, beh, sim, data, ev, diverged, hm.total_mass_kg, hm.spring_stiffness_n_m)
    return rollout, np.array(trace)


def summary_row(rollout) -> dict:
    """The batch row of a rollout, by mat_hopper.physics.metrics.run_summary."""
    from mat_hopper.physics.metrics import run_summary

    s = run_summary(rollout)
    return {
        "design": rollout.design.name,
        "n_hops": int(s["n_hops"]),
        "hop_height_m": s["mean_hop_height_m"],
        "tracking_error_m": s["mean_tracking_error_m"],
        "power_w": s["mean_power_w"],
        "stable": bool(s["stable"]),
        "diverged_at_s": s["diverged_at_s"],
    }


def rel(a: float, b: float) -> float:
    """|a - b| / |b|."""
    return abs(a - b) / abs(b) if b else math.inf
