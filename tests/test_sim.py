import json
import subprocess
import sys

import numpy as np
import pytest
from conftest import run_python

from mat_hopper.behaviours import behaviour
from mat_hopper.perturbations import Perturbation
from mat_hopper.sim import CHANNELS, RolloutRunner, SimSettings, simulate


@pytest.fixture(scope="module")
def ss_forward():
    return simulate("SS", "forward", duration_s=4.0, transient_s=1.0, record_qpos=True)


def test_rollout_arrays(ss_forward):
    r = ss_forward
    n = len(r.time)
    assert n == 4001 or n == 4000
    assert np.allclose(np.diff(r.time), 1e-3)
    assert r.base_pos.shape == (n, 3) and r.hip_angle.shape == (n, 2) and r.actuator_force.shape == (n, 3)
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
    # hip angles in the record match the recorded joint positions one step later
    assert np.allclose(r.hip_angle[1:, 0], r.qpos[:-1, 6], atol=2e-3)
    # actuator force = gear x control; thrust only in stance
    assert np.all(r.actuator_force[r.touch == 0, 2] == 0)
    assert r.actuator_force[:, 2].max() > 100
    # velocity is the derivative of position
    assert np.allclose(np.gradient(r["z"], r.time)[5:-5], r["vz"][5:-5], atol=0.05)


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


def test_compiled_and_plain_python_loops_give_the_same_trajectory():
    """The same loop with NUMBA_DISABLE_JIT=1 (every function as plain
    Python, MuJoCo through ctypes) reproduces the compiled trajectory."""
    code = ("import numpy as np, sys; from mat_hopper.sim import simulate; "
            "r = simulate('SS', 'forward', duration_s=0.6, transient_s=0.0); "
            "np.save(sys.argv[-1] if False else '/dev/stdout', r.data) if False else "
            "print(__import__('json').dumps(r.data.tolist()))")
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
    p = Perturbation.replicate(3)
    a = simulate("MD", "static", duration_s=3.0, transient_s=0.0, perturbation=p)
    b = simulate("MD", "static", duration_s=3.0, transient_s=0.0, perturbation=p)
    c = simulate("MD", "static", duration_s=3.0, transient_s=0.0, perturbation=Perturbation.replicate(4))
    plain = simulate("MD", "static", duration_s=3.0, transient_s=0.0)
    assert np.array_equal(a.data, b.data)
    assert not np.array_equal(a.data, c.data)
    assert np.abs(plain.base_pos[:, :2]).max() < 1e-12    # symmetric: round-off lateral motion only
    assert np.abs(a.base_pos[:, :2]).max() > 1e-4


@pytest.mark.parametrize("kwargs, field", [
    (dict(timestep_s=0), "timestep"), (dict(timestep_s=-1e-4), "timestep"),
    (dict(duration_s=10.0, transient_s=20.0), "duration"), (dict(convention="beam"), "convention"),
    (dict(transient_s=-1.0), "transient"), (dict(record_rate_hz=0), "record_rate_hz"),
])
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
    code = ("import mujoco, mat_hopper, mat_hopper.sim as s\n"
            "assert mujoco.get_mju_user_warning() is None\n"
            "s.route_mujoco_warnings()\n"
            "assert mujoco.get_mju_user_warning() is not None\n")
    subprocess.run([sys.executable, "-c", code], check=True, timeout=120)
