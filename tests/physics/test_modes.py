import math

import pytest

from mat_hopper.core.materials import LegDesign, material, parse_design, segment_masses
from mat_hopper.core.stable_step import auto_substeps, chain_frequencies, estimate_timestep
from mat_hopper.physics.modes import _rod_roots, axial_modes


def test_chain_two_masses_by_hand():
    # two masses on one spring: w^2 = k (1/m1 + 1/m2)
    w = chain_frequencies([2.0, 3.0], [600.0])
    assert w[0] == pytest.approx(0.0, abs=1e-6)
    assert w[1] == pytest.approx(math.sqrt(600.0 * (1 / 2.0 + 1 / 3.0)), rel=1e-12)


@pytest.mark.parametrize(
    "a1, a2, first",
    [
        (0.0, 0.0, math.pi),  # free-free rod: z = n pi
        (1e9, 0.0, math.pi / 2),  # top fixed (huge mass), bottom free: z = pi / 2
    ],
)
def test_rod_roots_limits_by_hand(a1, a2, first):
    assert _rod_roots(a1, a2, 3)[0] == pytest.approx(first, rel=1e-6)


def test_rod_root_with_a_tip_mass_by_hand():
    """Fixed-free rod with a tip mass equal to its own (a2 = 1): z tan z = 1,
    first root 0.8603 (tabulated, e.g. Rao, Vibration of Continuous Systems)."""
    assert _rod_roots(1e12, 1.0, 1)[0] == pytest.approx(0.8603, abs=1e-4)


def test_chain_converges_to_the_rod_as_one_over_n_squared():
    err = {n: abs(axial_modes(LegDesign.mono("SS", n))["error_pct"].iloc[0]) for n in (4, 8, 16, 32)}
    assert err[16] < 1.0 and err[32] < 1.0  # mode 1 within 1 % at N >= 16
    for n in (4, 8, 16):
        assert 3.0 < err[n] / err[2 * n] < 5.0  # halving the segment: error / 4


def test_modes_need_a_uniform_elastic_leg():
    with pytest.raises(ValueError, match="one elastic material"):
        axial_modes(parse_design("rho-inc"))
    with pytest.raises(ValueError, match="one elastic material"):
        axial_modes(parse_design("MD"))


def test_auto_substeps_below_the_safety_fraction():
    for n in (3, 12):
        k, dt, bound = auto_substeps(LegDesign.mono("SS", n), "axial")
        assert dt == pytest.approx(1e-4 / k)
        assert dt <= 0.5 * bound < 1e-4 / (k - 1)  # the smallest such k
        assert bound == pytest.approx(estimate_timestep(LegDesign.mono("SS", n), "axial")[1])


def test_bending_modes_beside_the_euler_bernoulli_cantilever():
    # issue 21: beta_n L of the clamped-free beam (1 + cos b cosh b = 0): 1.8751, 4.6941, 7.8548
    from mat_hopper.physics.modes import bending_modes

    t = bending_modes(LegDesign.mono("SS", 8), n_modes=3)
    assert list(t["beta_l"].round(4)) == [1.8751, 4.6941, 7.8548]
    # by hand: SS, E I = 193e9 x pi 0.025^4 / 4 = 5.9212e4 N m^2; mu = leg mass / 0.3 m
    # (the segment_masses of the 'leg' convention); f1 = 1.8751^2 sqrt(E I / (mu L^4)) / 2 pi
    mu = sum(segment_masses(LegDesign.mono("SS", 8))) / 0.3
    f1 = 1.8751**2 * math.sqrt(5.9212e4 / (mu * 0.3**4)) / (2 * math.pi)
    assert t["beam_hz"].iloc[0] == pytest.approx(f1, rel=1e-4)
    # the hinge chain's first mode within 2 % of the beam's (N = 8; rotary inertia kept)
    assert abs(t["error_pct"].iloc[0]) < 2.0
    with pytest.raises(ValueError, match="bending convention"):
        bending_modes(LegDesign.mono("SS", 3), convention="axial")


def test_stable_step_covers_the_rotational_modes():
    from mat_hopper.core.stable_step import auto_substeps, estimate_timestep, model_frequencies

    d = LegDesign.mono("SS", 16)
    w_bend, bound = estimate_timestep(d, "bending")
    assert w_bend == pytest.approx(model_frequencies(d, "bending").max())
    # the 16 short hinged segments ring faster than the 1e-4 s step can follow: substeps needed
    k, dt, _ = auto_substeps(d, "bending")
    assert k > 1 and dt <= 0.5 * bound
    # axial+bending: the slides' chain is part of the same model, its w_max no lower
    assert estimate_timestep(d, "axial+bending")[0] >= estimate_timestep(d, "axial")[0] * (1 - 1e-9)


def test_auto_shortens_the_control_period_only_where_the_controller_limit_binds():
    from mat_hopper.core.sim import simulate
    from mat_hopper.core.stable_step import auto_control_period, controller_timestep

    ss = LegDesign.mono(material("SS"))
    assert auto_control_period(ss, "paper") == 1e-4  # the paper's designs keep the authors' period
    assert auto_control_period(ss, "axial") == 1e-4
    soft = LegDesign.mono(material("TrabecularBone"))
    limit = controller_timestep(soft, "bending")
    assert limit < 1e-4  # its hips' flight damping on the hinge-free hip: 5.8e-5 s
    period = auto_control_period(soft, "bending")
    assert period <= 0.5 * limit and round(1e-4 / period) * period == pytest.approx(1e-4)
    # at the authors' period it diverges in the first flight; at auto's it hops
    assert not simulate(soft, "forward", duration_s=0.5, transient_s=0.0, convention="bending").stable
    r = simulate(soft, "forward", duration_s=2.0, transient_s=0.0, convention="bending", timestep_s="auto")
    assert r.stable and r.settings.control_period_s == pytest.approx(period)


def test_the_analytic_bounds_are_the_compiled_models():
    """The bounds --timestep auto reads from the design (no model compiled)
    are those of the compiled model: its modes (sprung_eig of MuJoCo's mass
    matrix), its base inertia and its hip_y inertia with the hinges free."""
    import mujoco
    import numpy as np

    from mat_hopper.core.model import START_KEY, build_model
    from mat_hopper.core.stable_step import controller_timestep, hip_flight_timestep, model_frequencies, sprung_eig

    for d, conv in ((LegDesign.mono("TrabecularBone", 4), "bending"), (parse_design("rho-inc"), "axial+bending")):
        m = build_model(d, convention=conv).model
        np.testing.assert_allclose(model_frequencies(d, conv), sprung_eig(m), rtol=1e-9, atol=1e-6)
        data = mujoco.MjData(m)
        mujoco.mj_resetDataKeyframe(m, data, m.key(START_KEY).id)
        mujoco.mj_forward(m, data)
        full = np.zeros((m.nv, m.nv))
        mujoco.mj_fullM(m, data, full)
        idx = [m.joint("hip_y").dofadr[0]] + [
            m.joint(j).dofadr[0] for j in (m.joint(i).name for i in range(m.njnt)) if j.startswith("mat_bend_")
        ]
        inertia = 1.0 / np.linalg.inv(full[np.ix_(idx, idx)])[0, 0]
        assert hip_flight_timestep(d, conv) == pytest.approx(2.0 * inertia / (0.1 * 600.0), rel=1e-12)
        base = m.body("base").id  # both capsules centred on the hip; its smallest moment is a horizontal one
        stance = 1.0 * min(m.body_inertia[base]) / (1.0 * 600.0)  # c(1) = 1, the authors' lag
        assert controller_timestep(d, "paper") == pytest.approx(stance, rel=1e-12)


def test_timestep_bounds_read_the_convention_any_case():
    from mat_hopper.core.stable_step import controller_timestep, model_frequencies

    soft = LegDesign.mono(material("TrabecularBone"))
    # the hips' flight limit (bending only) binds for this leg: < 1e-4 s under either spelling
    assert controller_timestep(soft, "Bending") == controller_timestep(soft, "bending") < 1e-4
    d = LegDesign.mono("SS", 3)
    assert estimate_timestep(d, "Axial+Bending") == estimate_timestep(d, "axial+bending")
    assert estimate_timestep(d, " PAPER ") == estimate_timestep(d, "paper")
    assert list(model_frequencies(d, "Bending")) == list(model_frequencies(d, "bending"))


def test_modes_tables_read_the_convention_any_case():
    import pandas as pd

    from mat_hopper.physics.modes import bending_modes

    pd.testing.assert_frame_equal(
        bending_modes(LegDesign.mono("SS", 4), convention="Axial+Bending", n_modes=2),
        bending_modes(LegDesign.mono("SS", 4), convention="axial+bending", n_modes=2),
    )
    ss = LegDesign.mono("SS", 3)
    pd.testing.assert_frame_equal(axial_modes(ss, convention="AXIAL"), axial_modes(ss, convention="axial"))
    with pytest.raises(ValueError, match="axial slides"):
        axial_modes(ss, convention="Bending")  # no mat_spring_i: a clear ValueError, not a KeyError
    with pytest.raises(ValueError, match="unknown stiffness convention"):
        axial_modes(ss, convention="radial")


@pytest.mark.parametrize("n_modes", [float("nan"), 2.5, "2", 10**9, -1, 0, True])
def test_mode_tables_refuse_a_bad_mode_count(n_modes):
    from mat_hopper.core.materials import parse_design
    from mat_hopper.physics.modes import axial_modes, bending_modes

    for table, convention in ((axial_modes, "axial"), (bending_modes, "bending")):
        with pytest.raises(ValueError, match="n_modes"):
            table(parse_design("SS"), convention=convention, n_modes=n_modes)


def test_mode_tables_refuse_a_design_name():
    from mat_hopper.physics.modes import axial_modes, bending_modes

    for table in (axial_modes, bending_modes):
        with pytest.raises(ValueError, match="must be a LegDesign"):
            table("SS")


# A gain, gear, period or fraction that is not finite and > 0 (or beyond its
# range) is refused by name before any model is built; before the fix
# controller_timestep took stance_kd=nan or gear=0 (nan, inf or a ZeroDivisionError).
_BAD_POSITIVE = [float("nan"), float("inf"), -float("inf"), 0, 0.0, -1.0, True, "1"]


@pytest.mark.parametrize("bad", _BAD_POSITIVE)
def test_timestep_limits_refuse_a_bad_gain_or_gear(bad):
    from mat_hopper.core.stable_step import controller_timestep, hip_flight_timestep

    ss = parse_design("SS")
    calls = [
        ("stance_kd", lambda: controller_timestep(ss, stance_kd=bad)),
        ("gear", lambda: controller_timestep(ss, gear=bad)),
        ("flight_kd", lambda: hip_flight_timestep(ss, flight_kd=bad)),
        ("gear", lambda: hip_flight_timestep(ss, gear=bad)),
    ]
    for name, call in calls:
        with pytest.raises(ValueError, match=f"{name} must be"):
            call()


@pytest.mark.parametrize("bad", [*_BAD_POSITIVE, 1.5])
def test_auto_step_refuses_a_bad_period_or_safety(bad):
    from mat_hopper.core.stable_step import auto_control_period

    ss = parse_design("SS")
    for name, call in (
        ("safety", lambda: auto_substeps(ss, safety=bad)),
        ("safety", lambda: auto_control_period(ss, safety=bad)),
        ("control_period_s", lambda: auto_substeps(ss, control_period_s=bad if bad != 1.5 else 0.2)),
        ("control_period_s", lambda: auto_control_period(ss, control_period_s=bad if bad != 1.5 else 0.2)),
    ):
        with pytest.raises(ValueError, match=f"{name} must be in"):
            call()


@pytest.mark.parametrize("bad", [float("nan"), float("inf"), -1, 1.5, True, "1"])
def test_delayed_damping_factor_refuses_a_bad_latency(bad):
    from mat_hopper.core.stable_step import delayed_damping_factor

    with pytest.raises(ValueError, match=r"latency_steps must be an integer in \[0, 1000\]"):
        delayed_damping_factor(bad)
    assert delayed_damping_factor(1.0) == delayed_damping_factor(1) == pytest.approx(1.0)


def test_chain_refuses_an_infinite_mass():
    with pytest.raises(ValueError, match="finite and > 0"):
        chain_frequencies([1.0, math.inf], [1e3])


def test_delayed_damping_factor_caps_latency_as_sensor_timing_does():
    from mat_hopper.core.controller import MAX_SENSOR_LATENCY_STEPS, SensorTiming
    from mat_hopper.core.stable_step import delayed_damping_factor

    assert delayed_damping_factor(MAX_SENSOR_LATENCY_STEPS) > 0
    SensorTiming(MAX_SENSOR_LATENCY_STEPS)
    for bad in (MAX_SENSOR_LATENCY_STEPS + 1, 10**9):
        with pytest.raises(ValueError, match=r"latency_steps must be an integer in \[0, 1000\]"):
            delayed_damping_factor(bad)


def test_auto_substeps_refuses_a_control_period_below_the_smallest_step():
    from mat_hopper.core.materials import parse_design
    from mat_hopper.core.model import MIN_TIMESTEP_S
    from mat_hopper.core.stable_step import auto_substeps

    d = parse_design("SS")
    with pytest.raises(ValueError, match="control_period_s must be in"):
        auto_substeps(d, control_period_s=1e-12)
    k, dt, _ = auto_substeps(d, control_period_s=MIN_TIMESTEP_S)
    assert k >= 1 and dt <= MIN_TIMESTEP_S
