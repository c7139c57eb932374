import json
import subprocess
import sys

import numpy as np
import pytest
from conftest import run_python

from mat_hopper.core.behaviours import behaviour
from mat_hopper.core.materials import parse_design
from mat_hopper.core.perturbations import Perturbation
from mat_hopper.core.sim import CHANNELS, RolloutRunner, SimSettings, simulate


@pytest.fixture(scope="module")
def ss_forward():
    return simulate("SS", "forward", duration_s=4.0, transient_s=1.0, record_qpos=True)


def test_rollout_arrays(ss_forward):
    r = ss_forward
    n = len(r.time)
    assert n == 4001 or n == 4000
    assert np.allclose(np.diff(r.time), 1e-3)
    assert r.base_pos.shape == (n, 3) and r.hip_angle.shape == (n, 2) and r.ctrl.shape == (n, 3)
    assert r.hip_torque.shape == (n, 2) and r.hip_power.shape == (n, 2)
    assert r.qpos.shape == (n, 12)
    assert r.stable and r.diverged_at_s is None and r.upright
    assert r.base_pos[0, 2] == pytest.approx(1.2)
    assert set(np.unique(r.phase)) == {0.0, 1.0}
    assert len(r.touchdown_times_s) >= 4 and len(r.liftoff_times_s) >= 3
    assert list(r.to_frame().columns) == list(CHANNELS)


def test_channels_hold_what_they_say(ss_forward):
    r = ss_forward
    b = behaviour("forward")
    for i in (0, 1234, 3000):
        t = r.time[i]
        assert r.desired_pos[i] == pytest.approx(b.desired(t)[:2])
        assert r["vx_des"][i] == pytest.approx(0.05)
    # recorded every step: a row's hip angle is the joint position left by the step before
    every = simulate("SS", "forward", duration_s=0.5, transient_s=0.0, record_rate_hz=1e4, record_qpos=True)
    np.testing.assert_array_equal(every.hip_angle[1:, 0], every.qpos[:-1, 6])
    # thrust only in stance (the controller's touch is one step old: compare its phase)
    assert np.all(r.ctrl[r.phase == 0, 2] == 0)
    assert r.ctrl[:, 2].max() > 100
    # velocity is the derivative of position
    assert np.allclose(np.gradient(r["z"], r.time)[5:-5], r["vz"][5:-5], atol=0.05)


def test_hip_torque_is_joint_space(ss_forward):
    """Actuator space -> joint space: the recorded hip torque is MuJoCo's
    qfrc_actuator, which must be the gear (600, the spec's number written
    here by hand) times the control; the thrust's gear is 1."""
    r = ss_forward
    np.testing.assert_allclose(r.hip_torque, 600.0 * r.ctrl[:, :2], rtol=1e-12, atol=1e-9)
    np.testing.assert_allclose(r.thrust_force, r.ctrl[:, 2], rtol=1e-12, atol=1e-9)
    assert np.abs(r.hip_torque).max() > 10.0  # N m: not the control's scale
    np.testing.assert_array_equal(r.hip_power, r.hip_torque * r.hip_rate)


def _reference_loop(design, behaviour, n_steps, latency):
    """An independent plain-Python closed loop on the public mujoco bindings,
    written the way the authors' loop is. latency 0: mj_step1, read
    sensordata, control, mj_step2. latency L >= 1: keep a copy of sensordata
    as each mj_step left it (past[k] after the k-th call holds state s_{k-1};
    past[0] from mj_forward holds s_0), read the base of s_{i-L} and the
    touch of s_{i-L}, hips from qpos/qvel, control, mj_step. With L = 1 that
    is the authors' read-control-mj_step loop. Returns qpos after each step."""
    import mujoco

    from mat_hopper.core.behaviours import behaviour as get_behaviour
    from mat_hopper.core.controller import ControllerSettings, controller_step, initial_state
    from mat_hopper.core.sim import SimSettings, prepare

    hm, d = prepare(design, behaviour, SimSettings(duration_s=1.0, transient_s=0.0))
    m, lay = hm.model, hm.layout
    beh = get_behaviour(behaviour)
    state, out = initial_state(ControllerSettings()), np.zeros(7)
    gains = ControllerSettings().gains()
    past = [d.sensordata.copy()]
    qpos = []
    for i in range(n_steps):
        t = i * m.opt.timestep
        if latency == 0:
            mujoco.mj_step1(m, d)
            sens = touch_src = d.sensordata.copy()
        else:
            sens = touch_src = past[max(i - latency + 1, 0)]
        sl = lambda a, adr, k: np.array(a[adr : adr + k])
        controller_step.py_func(
            t,
            touch_src[lay.touch],
            sl(sens, lay.base_pos, 3),
            sl(sens, lay.base_quat, 4),
            sl(sens, lay.base_gyro, 3),
            sl(sens, lay.base_linvel, 3),
            np.array([d.qpos[lay.hip_y_qpos], d.qpos[lay.hip_x_qpos]]),
            np.array([d.qvel[lay.hip_y_dof], d.qvel[lay.hip_x_dof]]),
            np.array(beh.desired(t), float),
            gains,
            state,
            out,
        )
        d.ctrl[lay.act_hip_y], d.ctrl[lay.act_hip_x], d.ctrl[lay.act_thrust] = out[0], out[1], out[2]
        if latency == 0:
            mujoco.mj_step2(m, d)
        else:
            mujoco.mj_step(m, d)
            past.append(d.sensordata.copy())
        qpos.append(d.qpos.copy())
    return np.array(qpos)


@pytest.mark.parametrize("timing, latency", [("authors", 1), ("fresh", 0), (2, 2), (5, 5)])
def test_sensor_timing_matches_an_independent_loop(timing, latency):
    """The compiled loop's ring of past readings against literal loops on
    the bindings: the authors' read-control-mj_step (base and touch one step
    old), the fresh mj_step1-read-control-mj_step2, and longer latencies.
    Five steps of latency exceed the delayed stance damping's bound at
    1e-4 s (c(5) I / (Kd gear) = 5.9e-5 s, mat_hopper.physics.modes): that run
    diverges in its first stance, and the two loops agree up to there."""
    n = 5000  # 0.5 s: falling, first touchdown, stance
    ref_qpos = _reference_loop("SS", "forward", n, latency)
    r = simulate(
        "SS",
        "forward",
        duration_s=n * 1e-4,
        transient_s=0.0,
        sensor_timing=timing,
        record_rate_hz=1e4,
        record_qpos=True,
    )
    assert r.settings.sensor_latency_steps == latency
    assert r.phase.max() == 1.0  # it reached stance
    assert r.stable == (latency < 5)
    k = len(r.qpos) - (0 if r.stable else 1)  # the diverged step itself is not compared
    np.testing.assert_allclose(r.qpos[:k], ref_qpos[:k], rtol=0, atol=1e-9)


def test_sensor_timings_differ_and_are_recorded():
    a = simulate("SS", "forward", duration_s=1.0, transient_s=0.0)
    b = simulate("SS", "forward", duration_s=1.0, transient_s=0.0, sensor_timing="fresh")
    c = simulate("SS", "forward", duration_s=1.0, transient_s=0.0, sensor_timing=1)
    assert a.settings.sensor_timing == "authors" and b.settings.sensor_timing == "fresh"
    assert np.array_equal(a.data, c.data)  # latency 1 is the authors' timing
    assert not np.array_equal(a.data, b.data)
    assert (
        simulate("SS", "forward", duration_s=0.2, transient_s=0.0, sensor_timing=5).settings.sensor_timing
        == "latency-5"
    )


@pytest.mark.parametrize("bad", [-1, 1.5, True, "late", "latency-x", 10**6])
def test_bad_sensor_timing(bad):
    with pytest.raises(ValueError, match="sensor"):
        SimSettings(sensor_timing=bad)


def test_determinism_bit_identical():
    a = simulate("rho-inc", "circle", duration_s=3.0, transient_s=0.0)
    b = simulate("rho-inc", "circle", duration_s=3.0, transient_s=0.0)
    assert np.array_equal(a.data, b.data) and np.array_equal(a.events, b.events, equal_nan=True)


def test_chunked_runner_equals_one_shot():
    s = SimSettings(duration_s=2.0, transient_s=0.0)
    one = simulate("Ti", "ramp", settings=s)
    run = RolloutRunner("Ti", "ramp", s)
    while not run.done:
        run.advance(777)
    assert np.array_equal(run.result().data, one.data)


def test_chunked_runner_with_substeps_records_the_held_targets():
    """Chunks that start between two control updates (3 substeps, chunks
    of 20 steps, a record every 20): the records there hold the targets of
    the control still in force, as in the single-call run."""
    s = SimSettings(duration_s=0.3, transient_s=0.0, timestep_s=5e-5, substeps=3)
    one = simulate("SS", "forward", settings=s)
    run = RolloutRunner("SS", "forward", s)
    while not run.done:
        run.advance(20)
    assert np.array_equal(run.result().data, one.data)


def test_chunked_runner_with_sensor_noise_from_the_first_step():
    """A first chunk shorter than one noise row (5 of 10 steps) still
    reads the first noise row, as the single-call run does."""
    s = SimSettings(duration_s=0.3, transient_s=0.0, perturbation=Perturbation.replicate(3, (0.0, 0.3)))
    one = simulate("SS", "forward", settings=s)
    run = RolloutRunner("SS", "forward", s).advance(5).advance()
    assert np.array_equal(run.result().data, one.data)


def test_compiled_and_plain_python_loops_give_the_same_trajectory():
    """The same loop with NUMBA_DISABLE_JIT=1 (every function as plain
    Python, MuJoCo through ctypes) reproduces the compiled trajectory."""
    code = (
        "import numpy as np, sys; from mat_hopper.core.sim import simulate; "
        "r = simulate('SS', 'forward', duration_s=0.6, transient_s=0.0); "
        "np.save(sys.argv[-1] if False else '/dev/stdout', r.data) if False else "
        "print(__import__('json').dumps(r.data.tolist()))"
    )
    plain = run_python(code, {"NUMBA_DISABLE_JIT": "1"})
    assert plain.returncode == 0, plain.stderr[-2000:]
    plain_data = np.array(json.loads(plain.stdout))
    compiled = simulate("SS", "forward", duration_s=0.6, transient_s=0.0).data
    assert plain_data.shape == compiled.shape
    np.testing.assert_array_equal(plain_data, compiled)


def test_divergence_is_a_result_not_a_crash():
    r = simulate("SS", "static", duration_s=2.0, timestep_s=2e-3, transient_s=0.0)
    assert not r.stable
    assert 0 <= r.diverged_at_s < 2.0
    assert not r.upright
    assert np.isfinite(r.time).all()


def test_perturbed_replicates_are_seeded():
    p = Perturbation.replicate(3, (0.0, 3.0))  # the push inside the 3 s run
    a = simulate("MD", "static", duration_s=3.0, transient_s=0.0, perturbation=p)
    b = simulate("MD", "static", duration_s=3.0, transient_s=0.0, perturbation=p)
    c = simulate("MD", "static", duration_s=3.0, transient_s=0.0, perturbation=Perturbation.replicate(4, (0.0, 3.0)))
    plain = simulate("MD", "static", duration_s=3.0, transient_s=0.0)
    assert np.array_equal(a.data, b.data)
    assert not np.array_equal(a.data, c.data)
    assert np.abs(plain.base_pos[:, :2]).max() < 1e-12  # symmetric: round-off lateral motion only
    assert np.abs(a.base_pos[:, :2]).max() > 1e-4


@pytest.mark.parametrize(
    "kwargs, field",
    [
        (dict(timestep_s=0), "timestep"),
        (dict(timestep_s=-1e-4), "timestep"),
        (dict(duration_s=10.0, transient_s=20.0), "duration"),
        (dict(convention="beam"), "convention"),
        (dict(transient_s=-1.0), "transient"),
        (dict(record_rate_hz=0), "record_rate_hz"),
        (dict(duration_s=1e9), "physics steps"),
        (dict(timestep_s=1e-300), "physics steps"),
        (dict(duration_s=3000.0, record_rate_hz=1e4), "recorded samples"),
    ],
)
def test_bad_settings(kwargs, field):
    args = dict(duration_s=30.0)
    args.update(kwargs)
    with pytest.raises(ValueError, match=field):
        simulate("SS", "forward", **args)


def test_bad_design_and_behaviour():
    with pytest.raises(ValueError, match="unknown material"):
        simulate("steel", "forward", duration_s=1.0, transient_s=0.0)
    with pytest.raises(ValueError, match="unknown behaviour"):
        simulate("SS", "backflip", duration_s=1.0, transient_s=0.0)


def test_importing_sim_installs_no_mujoco_warning_handler():
    """Importing the package leaves MuJoCo's global warning handler alone;
    route_mujoco_warnings() installs one (the CLI, the runner's workers and
    book.setup() call it)."""
    code = (
        "import mujoco, mat_hopper, mat_hopper.core.sim as s\n"
        "assert mujoco.get_mju_user_warning() is None\n"
        "s.route_mujoco_warnings()\n"
        "assert mujoco.get_mju_user_warning() is not None\n"
    )
    subprocess.run([sys.executable, "-c", code], check=True, timeout=120)


def test_one_substep_is_the_plain_loop_and_substeps_hold_the_control():
    a = simulate("SS", "forward", duration_s=0.5, transient_s=0.0)
    b = simulate("SS", "forward", settings=SimSettings(duration_s=0.5, transient_s=0.0, substeps=1))
    assert np.array_equal(a.data, b.data)
    s = SimSettings(duration_s=0.3, transient_s=0.0, timestep_s=2.5e-5, substeps=4, record_rate_hz=4e4)
    r = simulate("SS", "forward", settings=s)
    assert s.control_period_s == pytest.approx(1e-4)
    ctrl = r.ctrl[:, 0]
    # the control changes only at control steps (every 4th physics step)
    changes = np.nonzero(np.diff(ctrl))[0] + 1
    assert len(changes) > 100 and np.all(changes % 4 == 0)


def test_auto_timestep_runs_stiff_axial_legs():
    r = simulate("SS", "forward", duration_s=1.0, transient_s=0.0, timestep_s="auto", convention="axial")
    assert r.stable and r.settings.substeps > 1
    assert r.settings.control_period_s == pytest.approx(1e-4)
    bad = simulate("SS", "forward", duration_s=1.0, transient_s=0.0, timestep_s=1e-4, convention="axial")
    assert not bad.stable


@pytest.mark.parametrize("bad", [0, 2.5, True, 10**6])
def test_bad_substeps(bad):
    with pytest.raises(ValueError, match="substeps"):
        SimSettings(substeps=bad)


def test_simulate_refuses_settings_given_beside_settings():
    s = SimSettings(duration_s=0.2, transient_s=0.0)
    with pytest.raises(ValueError, match="duration_s, convention given beside settings="):
        simulate("SS", "static", duration_s=1.0, convention="axial", settings=s)
    with pytest.raises(ValueError, match="segment_mass given beside settings="):
        simulate("SS", "static", segment_mass="capsule", settings=s)
    with pytest.raises(ValueError, match="settings must be a SimSettings"):
        simulate("SS", "static", settings={"duration_s": 0.2})


def test_simulate_exposes_segment_mass_and_substeps():
    # "capsule" gives each capsule the authors' density at any N: a 6-segment SS leg is
    # heavier than under "leg", which keeps the N = 3 leg's mass.
    six = parse_design("SS", n_segments=6)
    leg = simulate(six, "static", duration_s=0.05, transient_s=0.0)
    capsule = simulate(six, "static", duration_s=0.05, transient_s=0.0, segment_mass="capsule")
    assert capsule.settings.segment_mass == "capsule" and capsule.total_mass_kg > leg.total_mass_kg
    two = simulate("SS", "static", duration_s=0.05, transient_s=0.0, timestep_s=5e-5, substeps=2)
    assert two.settings.substeps == 2 and two.settings.control_period_s == pytest.approx(1e-4)


def test_simulate_exposes_every_setting():
    """Every SimSettings field is a keyword of simulate() (damping was added
    to the settings without it: a setting the API could not reach)."""
    import dataclasses
    import inspect

    params = set(inspect.signature(simulate).parameters)
    assert {f.name for f in dataclasses.fields(SimSettings)} <= params
    r = simulate("SS", "static", duration_s=0.05, transient_s=0.0, damping="loss-factor")
    assert r.settings.damping == "loss-factor"


def test_sim_settings_is_the_one_builder():
    from mat_hopper.core.sim import sim_settings

    s = sim_settings(duration_s=2.0, transient_s=0.5, sensor_timing=5)
    assert s == SimSettings(duration_s=2.0, transient_s=0.5, sensor_timing="latency-5")
    auto = sim_settings("SS", timestep_s="auto", convention="axial")
    # the control period stays the paper's 1e-4 s, split into physics substeps
    assert auto.substeps > 1 and auto.substeps * auto.timestep_s == pytest.approx(1e-4)
    with pytest.raises(ValueError, match="unknown setting"):
        sim_settings(durations=1.0)
    with pytest.raises(ValueError, match="pass the design"):
        sim_settings(timestep_s="auto")
    with pytest.raises(ValueError, match="substeps cannot be given"):
        sim_settings("SS", timestep_s="auto", substeps=2)
