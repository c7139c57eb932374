"""mat_hopper.core.reference against the reference hopper's specification
(docs/reference-hopper.md and the authors' code it summarises).

Every expected value below is typed from the specification's text, not
computed with the package's formulas; where the specification states what
MuJoCo computes (masses), MuJoCo's own number is compared too."""

import math

import pytest

from mat_hopper.core import reference as ref
from mat_hopper.core.materials import LegDesign
from mat_hopper.core.model import build_model


def test_protocol_numbers():
    # "Each run lasts 60 s of simulated time; hop cycles that start after 20 s are scored."
    assert ref.DURATION_S == 60.0 and ref.TRANSIENT_S == 20.0
    # "timestep | 1e-4 s (paper experiments)"
    assert ref.TIMESTEP_S == 1e-4
    # stable run: "every |qacc| <= 1e6, body above 0.1 m at the end"
    assert ref.DIVERGENCE_QACC == 1e6 and ref.STABLE_MIN_BASE_Z == 0.1


def test_geometry_and_joints():
    # base: two capsules, radius 0.09, from -0.12 to +0.12, 7.5 kg each
    assert (ref.BASE_CAPSULE_RADIUS, ref.BASE_CAPSULE_HALF_LENGTH, ref.BASE_CAPSULE_MASS) == (0.09, 0.12, 7.5)
    # hip: range +-70 deg, stiffness 20, damping 20; gear 600 on both hips
    assert (ref.HIP_RANGE_DEG, ref.HIP_STIFFNESS, ref.HIP_DAMPING, ref.HIP_GEAR) == (70.0, 20.0, 20.0, 600.0)
    # material capsules radius 0.025, 3 segments of 0.1 m
    assert ref.MATERIAL_RADIUS == 0.025 and ref.REFERENCE_SEGMENTS == 3 and ref.MATERIAL_LENGTH == 0.3
    # foot spring: stiffness 8000 N/m, damping 10, range +-0.1 m; foot capsule radius 0.04, length 0.2, 0.5 kg
    assert (ref.FOOT_SPRING_STIFFNESS, ref.FOOT_SPRING_DAMPING, ref.FOOT_SPRING_RANGE) == (8000.0, 10.0, 0.1)
    assert (ref.FOOT_RADIUS, ref.FOOT_LENGTH, ref.FOOT_MASS, ref.FOOT_CONDIM) == (0.04, 0.2, 0.5, 6)
    # "the controller uses 0.61 m"
    assert ref.LEG_LENGTH_CONTROLLER == 0.61


def test_ramp():
    # half-sizes (2, 0.5, 0.1) m centred at (2, 0, -0.03), -2 deg, friction (1, 0.005, 0.0001)
    assert ref.RAMP_HALF_SIZE == (2.0, 0.5, 0.1) and ref.RAMP_CENTER_X == 2.0 and ref.RAMP_CENTER_Z == -0.03
    assert ref.RAMP_FRICTION == (1.0, 0.005, 0.0001)
    # "a 3.5 % grade": tan(2 deg) = 0.03492
    assert math.tan(math.radians(ref.RAMP_GRADE_DEG)) == pytest.approx(0.035, abs=5e-4)


def test_authors_stiffness_per_gpa():
    # "Net effect: k = 9.4248e5 N/m per GPa (PVC 3.77e6 N/m, SS 1.819e8 N/m)"
    assert ref.PAPER_STIFFNESS_PER_GPA == pytest.approx(9.4248e5, rel=1e-5)
    assert 4.0 * ref.PAPER_STIFFNESS_PER_GPA == pytest.approx(3.77e6, rel=1e-3)
    assert 193.0 * ref.PAPER_STIFFNESS_PER_GPA == pytest.approx(1.819e8, rel=1e-3)


def test_controller_numbers():
    # "F starts at 200 N", "F <- F + 100 * (1.0 - last hop height)", phase lock 0.1 s
    assert (ref.THRUST_START_N, ref.THRUST_ADAPT_GAIN, ref.HOP_HEIGHT_TARGET) == (200.0, 100.0, 1.0)
    assert ref.PHASE_LOCK_S == 0.1 and ref.THRUST_MIN_RISE_SPEED == 0.01
    # "clamp(0.2 * desired local velocity + 0.5 * desired local position offset, -0.1, +0.1)"
    assert (ref.VELOCITY_GAIN_DESIRED, ref.VELOCITY_GAIN_POSITION, ref.VELOCITY_LIMIT) == (0.2, 0.5, 0.1)
    # "x_f = v * T_st / 2 + 0.05 * (v - v_des)", T_st = 0.1 s
    assert ref.STANCE_DURATION_S == 0.1 and ref.FOOT_PLACEMENT_GAIN == 0.05
    # stance: 4 * pitch + 1 * pitch rate; flight: -10 * (angle - target) - 0.1 * (rate - target rate)
    assert (ref.STANCE_KP, ref.STANCE_KD, ref.FLIGHT_KP, ref.FLIGHT_KD) == (4.0, 1.0, 10.0, 0.1)
    # the base sensors lag one physics step in the authors' loop
    assert ref.SENSOR_LATENCY_STEPS == 1
    # desired path at 0.05 m/s; circle of radius 0.5 m
    assert ref.SPEED_M_S == 0.05 and ref.CIRCLE_RADIUS == 0.5


def test_materials_and_experiments():
    assert ref.MONO_MATERIALS == {
        "MD": (1.0, None),
        "PVC": (1.39, 4.0),
        "Al": (2.7, 70.0),
        "Ti": (4.43, 120.0),
        "SS": (8.0, 193.0),
    }
    assert ref.SWEEPS["PVC"] == {"density": (1.10, 1.39, 1.45, 1.90, 2.5), "modulus": (0.1, 0.45, 2.01, 4, 9)}
    assert ref.SWEEPS["Al"] == {"density": (2.7, 3.95, 8.66), "modulus": (20, 62.14, 70)}
    assert ref.SWEEPS["Ti"]["modulus"] == (18, 63.76, 120, 225.85, 800)
    assert ref.SWEEPS["SS"]["density"] == (2.0, 4.31, 8.0, 9.28, 20.0)
    # rho-inc (1.39, 4.43, 8) at 70 GPa
    assert ref.GRADIENT_DENSITIES == (1.39, 4.43, 8.0) and ref.GRADIENT_MODULUS_GPA == 70.0
    # a 20 x 20 grid, densities over [1.39, 8], moduli 4-340 GPa; 20 steps from 1e-3 s down to 1e-5 s
    assert ref.STABILITY_GRID_SIZE == 20
    assert ref.STABILITY_DENSITY_RANGE == (1.39, 8.0) and ref.STABILITY_MODULUS_RANGE == (4.0, 340.0)
    assert ref.STABILITY_TIMESTEP_RANGE == (1e-3, 1e-5)


def test_masses_are_mujocos():
    # "rigid MD design 16.90 kg in all ...; stainless steel (8 g/cm^3) design 23.77 kg"
    assert ref.MASS_MD_KG == 16.90 and ref.MASS_SS_KG == 23.77
    md = build_model(LegDesign.mono("MD")).model.body_subtreemass[0]
    ss = build_model(LegDesign.mono("SS")).model.body_subtreemass[0]
    assert md == pytest.approx(16.90, abs=0.005) and ss == pytest.approx(23.77, abs=0.005)
    # "each 0.1 m of material at 1 g/cm^3 weighs 0.327 kg, end caps included": SS adds 3 x 7 x 0.327 kg
    assert ss - md == pytest.approx(3 * 7 * 0.327, abs=0.01)
