import math
import pickle

import mujoco
import numpy as np
import pytest

from mat_hopper.core import controller as c
from mat_hopper.core.controller import ControllerSettings, controller_step, initial_state, update_phase
from mat_hopper.core.materials import parse_design
from mat_hopper.core.model import build_model

G = ControllerSettings().gains()
LEVEL = np.array([1.0, 0.0, 0.0, 0.0])


def step(
    t,
    touch,
    vel=(0, 0, 0),
    pos=(0, 0, 1.0),
    quat=LEVEL,
    gyro=(0, 0, 0),
    hip=(0, 0),
    hip_rate=(0, 0),
    desired=(0, 0, 0, 0),
    state=None,
    fn=controller_step,
):
    out = np.zeros(c.OUT_SIZE)
    ev = fn(
        t,
        touch,
        np.array(pos, float),
        np.array(quat, float),
        np.array(gyro, float),
        np.array(vel, float),
        np.array(hip, float),
        np.array(hip_rate, float),
        np.array(desired, float),
        G,
        state,
        out,
    )
    return ev, out


def test_state_machine_switching_and_phase_lock():
    s = initial_state(ControllerSettings())
    assert s[c.S_PHASE] == c.FLIGHT
    # the lock's clock starts at t = 0: no switch in the first 0.1 s (spec)
    assert update_phase(0.05, 10.0, 1.0, -0.5, G, s) == c.NO_EVENT
    # touching but rising: no touchdown
    assert update_phase(0.10, 10.0, 1.0, +0.5, G, s) == c.NO_EVENT
    assert update_phase(0.11, 10.0, 1.0, -0.5, G, s) == c.TOUCHDOWN
    assert s[c.S_PHASE] == c.STANCE
    # first touchdown adapts nothing
    assert s[c.S_THRUST] == 200.0 and math.isnan(s[c.S_LAST_HEIGHT])
    # lift-off blocked by the 0.1 s phase lock, then allowed
    assert update_phase(0.15, 0.0, 1.0, +0.5, G, s) == c.NO_EVENT
    assert update_phase(0.211, 0.0, 1.0, +0.5, G, s) == c.LIFTOFF
    assert s[c.S_PHASE] == c.FLIGHT and s[c.S_LIFTOFFS] == 1
    # apex at 1.2 m, then touchdown: thrust adapts by 100 * (1 - 1.2) = -20 N
    update_phase(0.4, 0.0, 1.2, 0.0, G, s)
    assert update_phase(0.6, 5.0, 0.9, -1.0, G, s) == c.TOUCHDOWN
    assert s[c.S_LAST_HEIGHT] == pytest.approx(1.2)
    assert s[c.S_THRUST] == pytest.approx(180.0)
    assert s[c.S_Z_MAX] == pytest.approx(0.9)  # running max reset


def test_thrust_only_while_rising_in_stance():
    s = initial_state(ControllerSettings())
    _, out = step(0.0, touch=5.0, vel=(0, 0, 0.5), state=s)
    assert out[c.O_THRUST] == 200.0
    _, out = step(0.0, touch=5.0, vel=(0, 0, 0.005), state=s)
    assert out[c.O_THRUST] == 0.0
    _, out = step(0.0, touch=0.0, vel=(0, 0, 0.5), state=s)
    assert out[c.O_THRUST] == 0.0


def toe_offset(hip_y, hip_x):
    """Toe position relative to the hip (m) at these hip angles, by MuJoCo."""
    m = build_model(parse_design("MD")).model
    d = mujoco.MjData(m)
    d.qpos[m.joint("hip_y").qposadr[0]] = hip_y
    d.qpos[m.joint("hip_x").qposadr[0]] = hip_x
    mujoco.mj_kinematics(m, d)
    return d.site("toe").xpos - d.body("base").xpos


def test_ik_signs_place_the_foot_where_asked():
    s = initial_state(ControllerSettings())
    # Moving forward (+x) faster than asked: the foot goes ahead (+x) of the hip.
    _, out = step(0.0, 0.0, vel=(0.3, 0, 0), state=s)
    toe = toe_offset(out[c.O_TARGET_Y], out[c.O_TARGET_X])
    assert out[c.O_TARGET_Y] < 0 and toe[0] > 0.01 and abs(toe[1]) < 1e-9
    # Drifting sideways (+y): the foot goes to +y.
    _, out = step(0.0, 0.0, vel=(0, 0.3, 0), state=s)
    toe = toe_offset(out[c.O_TARGET_Y], out[c.O_TARGET_X])
    assert out[c.O_TARGET_X] > 0 and toe[1] > 0.01
    # Behind the desired point at rest: step towards it (foot behind, body falls forward).
    _, out = step(0.0, 0.0, desired=(1.0, 0, 0, 0), state=s)
    assert out[c.O_TARGET_Y] > 0


def test_flight_pd_and_stance_attitude_signs():
    s = initial_state(ControllerSettings())
    _, out = step(0.0, 0.0, hip=(0.1, -0.1), state=s)  # flight, target 0
    assert out[c.O_HIP_Y] == pytest.approx(-1.0) and out[c.O_HIP_X] == pytest.approx(1.0)
    pitch = 0.05
    quat = [math.cos(pitch / 2), 0, math.sin(pitch / 2), 0]
    _, out = step(0.0, 5.0, quat=quat, gyro=(0, 0.2, 0), state=s)  # stance
    assert out[c.O_HIP_Y] == pytest.approx(4 * pitch + 0.2)
    assert out[c.O_HIP_X] == pytest.approx(0.0, abs=1e-12)


def test_yaw_frame_rotation():
    s = initial_state(ControllerSettings())
    yaw = math.pi / 2  # base faces +y: world +y velocity is local +x
    quat = [math.cos(yaw / 2), 0, 0, math.sin(yaw / 2)]
    _, a = step(0.0, 0.0, vel=(0, 0.3, 0), quat=quat, state=s)
    _, b = step(0.0, 0.0, vel=(0.3, 0, 0), state=s)
    assert a[c.O_TARGET_Y] == pytest.approx(b[c.O_TARGET_Y])


def test_compiled_and_plain_controller_agree():
    rng = np.random.default_rng(0)
    for _ in range(50):
        args = dict(
            touch=float(rng.choice([0.0, 3.0])),
            vel=rng.normal(size=3),
            pos=rng.normal(size=3),
            quat=(q := rng.normal(size=4)) / np.linalg.norm(q),
            gyro=rng.normal(size=3),
            hip=rng.normal(size=2) * 0.3,
            hip_rate=rng.normal(size=2),
            desired=rng.normal(size=4),
        )
        s1, s2 = initial_state(ControllerSettings()), initial_state(ControllerSettings())
        e1, o1 = step(0.2, state=s1, **args)
        e2, o2 = step(0.2, state=s2, fn=controller_step.py_func, **args)
        assert e1 == e2
        np.testing.assert_array_equal(o1, o2)
        np.testing.assert_array_equal(s1, s2)


def test_settings_validation():
    with pytest.raises(ValueError, match="flight_kp"):
        ControllerSettings(flight_kp=float("nan"))
    with pytest.raises(ValueError, match="leg_length_m"):
        ControllerSettings(leg_length_m=0)


def test_gains_follow_the_settings_by_name():
    g = ControllerSettings(flight_kp=7.0, stance_kd=2.5).gains()
    assert g.flight_kp == 7.0 and g.stance_kd == 2.5
    # the other gains keep the authors' values (docs/reference-hopper.md, "Controller"), as floats
    authors = {
        "phase_lock_s": 0.1,
        "thrust_start_n": 200.0,
        "thrust_adapt_gain": 100.0,
        "hop_height_target_m": 1.0,
        "thrust_min_rise_speed": 0.01,
        "velocity_gain_desired": 0.2,
        "velocity_gain_position": 0.5,
        "velocity_limit_m_s": 0.1,
        "stance_duration_s": 0.1,
        "foot_placement_gain": 0.05,
        "leg_length_m": 0.61,
        "flight_kd": 0.1,
        "stance_kp": 4.0,
    }
    assert {k: getattr(g, k) for k in authors} == authors
    assert set(g._fields) == set(authors) | {"flight_kp", "stance_kd"}
    assert all(type(v) is float for v in g)


@pytest.mark.parametrize(
    "timing, steps, name",
    [
        ("authors", 1, "authors"),
        ("fresh", 0, "fresh"),
        ("AUTHORS", 1, "authors"),
        (3, 3, "latency-3"),
        ("latency-10", 10, "latency-10"),
        ("latency-1", 1, "authors"),
        (np.int64(0), 0, "fresh"),
    ],
)
def test_sensor_timing_is_a_latency_with_a_name(timing, steps, name):
    t = c.SensorTiming(timing)
    assert int(t) == t.latency_steps == steps and t == steps and t == name and name == t
    assert t != "no-such-timing" and t != steps + 1
    assert t.name == str(t) == f"{t}" == name
    assert c.SensorTiming(t) is t  # stored once, passed on as is
    assert pickle.loads(pickle.dumps(t)) == t and pickle.loads(pickle.dumps(t)).name == name


def test_sensor_timing_default_is_the_authors():
    # the authors' loop reads the base sensors one physics step old (docs/reference-hopper.md)
    assert c.SensorTiming().name == "authors" and int(c.SensorTiming()) == 1


@pytest.mark.parametrize("bad", [True, 1.0, -1, 1001, "late", "latency-x", None])
def test_sensor_timing_refuses(bad):
    with pytest.raises(ValueError, match="sensor"):
        c.SensorTiming(bad)


@pytest.mark.parametrize(
    "field, value",
    [("hop_height_target_m", 0.5), ("hop_height_target_m", 10.0), ("thrust_start_n", -1.0), ("phase_lock_s", -0.1)],
)
def test_unphysical_settings_refused(field, value):
    with pytest.raises(ValueError, match=field):
        ControllerSettings(**{field: value})


def test_thrust_never_adapts_below_zero():
    """Apexes of 3 m against a 1 m target: 200 + 100 (1 - 3) = 0 N after the
    first scored hop, then 0 - 200 N would follow; the foot actuator only
    pushes, so F stays at 0 N."""
    s = initial_state(ControllerSettings())
    assert update_phase(0.2, 5.0, 0.9, -1.0, G, s) == c.TOUCHDOWN  # first: adapts nothing
    thrusts = []
    for t0 in (0.4, 1.0):
        assert update_phase(t0, 0.0, 0.9, 1.0, G, s) == c.LIFTOFF
        update_phase(t0 + 0.2, 0.0, 3.0, 0.0, G, s)  # apex at 3 m
        assert update_phase(t0 + 0.4, 5.0, 0.9, -1.0, G, s) == c.TOUCHDOWN
        thrusts.append(s[c.S_THRUST])
    assert thrusts == [0.0, 0.0]


def test_a_latency_is_read_in_ascii_digits_only():
    # "latency-٣" (an Arabic-Indic three) was read as 3 by str.isdigit
    from mat_hopper.core.controller import SensorTiming

    assert int(SensorTiming("latency-3")) == 3
    for bad in ("latency-٣", "latency-²", "latency-3.0", "latency--1"):
        with pytest.raises(ValueError, match="sensor timing"):
            SensorTiming(bad)
