"""Total actuator work, thrust included, against MuJoCo's own quantities.

The expected work is integrated here by a plain ``mj_step`` loop that
replays the rollout's recorded controls: at every physics step MuJoCo's
``data.actuator_force`` (actuator space) times ``data.actuator_velocity``
(gear x joint rate) for the three actuators. Nothing of the package's
energetics is used for it.
"""

import mujoco
import numpy as np
import pytest

from mat_hopper.core.materials import parse_design
from mat_hopper.core.sim import SimSettings, prepare, simulate
from mat_hopper.physics import energetics
from mat_hopper.physics.metrics import hop_table, run_summary

DT = 1e-4


@pytest.fixture(scope="module")
def replay():
    design = parse_design("SS")
    st = SimSettings(duration_s=1.6, transient_s=0.0, timestep_s=DT, record_rate_hz=1.0 / DT)
    ro = simulate(design, "forward", settings=st)
    hm, d = prepare(design, "forward", st)
    m = hm.model
    ctrl = ro.ctrl
    work_abs = work_pos = thrust_abs = 0.0
    for i in range(len(ctrl)):
        d.ctrl[:] = ctrl[i]
        mujoco.mj_step(m, d)
        p = d.actuator_force * d.actuator_velocity  # W, per actuator, state s_i
        work_abs += np.abs(p).sum() * DT
        work_pos += np.clip(p, 0, None).sum() * DT
        thrust_abs += abs(p[hm.layout.act_thrust]) * DT
    return ro, work_abs, work_pos, thrust_abs


def test_total_work_matches_mujoco_actuator_force_times_velocity(replay):
    ro, work_abs, work_pos, thrust_abs = replay
    n = len(ro.time)
    e = energetics.hop_energetics(ro, np.array([0]), np.array([n]), DT)
    assert thrust_abs > 10.0  # the thrust actuator did work in this window (a landing and a push-off)
    assert e["work_abs_j"][0] == pytest.approx(work_abs, rel=1e-6)
    assert e["work_pos_j"][0] == pytest.approx(work_pos, rel=1e-6)
    assert e["work_abs_j"][0] - e["hip_work_abs_j"][0] == pytest.approx(thrust_abs, rel=1e-6)


def test_hop_and_run_energetics_are_consistent():
    st = SimSettings(duration_s=8.0, transient_s=3.0)
    ro = simulate(parse_design("SS"), "circle", settings=st)
    hops = hop_table(ro)
    assert np.allclose(hops["work_abs_j"], hops["energy_j"])
    assert (hops["work_pos_j"] <= hops["work_abs_j"] + 1e-12).all()
    assert (hops["hip_work_abs_j"] < hops["work_abs_j"]).all()
    dur = hops["t_end_s"] - hops["t_start_s"]
    assert np.allclose(hops["power_total_w"], hops["work_abs_j"] / dur, rtol=2e-3)
    s = run_summary(ro)
    assert s["work_abs_j"] == pytest.approx(hops["work_abs_j"].sum())
    assert s["energy_per_hop_j"] == pytest.approx(hops["work_abs_j"].mean())
    assert 0.5 < s["thrust_work_fraction"] < 1.0  # the thrust does most of the work
    # a path is never shorter than the straight distance between its ends
    assert s["path_length_m"] >= s["distance_m"] > 0
    assert s["cost_of_transport"] == pytest.approx(s["work_abs_j"] / (ro.total_mass_kg * 9.81 * s["path_length_m"]))
    for col in ("leg_mass_kg", "leg_com_m", "hip_inertia_kg_m2"):
        assert s[col] > 0 and (hops[col] == s[col]).all()


def test_path_length_of_an_empty_window_is_zero(replay):
    ro = replay[0]
    assert energetics.path_length_m(ro, 5.0, 6.0) == 0.0


@pytest.mark.parametrize("bad", [float("nan"), float("inf"), True, "1"])
def test_path_length_refuses_a_bound_that_is_not_a_finite_number(replay, bad):
    ro = replay[0]
    with pytest.raises(ValueError, match="t0_s must be a finite number"):
        energetics.path_length_m(ro, bad, 1.0)
    with pytest.raises(ValueError, match="t1_s must be a finite number"):
        energetics.path_length_m(ro, 0.0, bad)
