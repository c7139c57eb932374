"""Controls and mass properties, against a hand calculation.

The expected leg mass, centre of mass and hip inertia are worked out here
from first principles: each capsule is a cylinder plus two hemispheres
(volume pi r^2 h + 4/3 pi r^3), its transverse moment of inertia about its
own centre is m_cyl (r^2/4 + h^2/12) + m_sph (2 r^2/5 + h^2/4 + 3 h r/8)
(the two hemispheres together a sphere's 2/5 m r^2, moved out by the
parallel-axis theorem), and every capsule is moved to the hip axis by the
parallel-axis theorem. Geometry: the reference hopper's numbers
(docs/reference-hopper.md), typed in here as the referee would.
"""

import math

import mujoco
import numpy as np
import pytest

from mat_hopper.core import materials as mats
from mat_hopper.core.control_legs import (
    CONTROLS,
    control,
    control_kind,
    control_of,
    inertia_matched,
    mass_matched,
    mass_properties,
    rigid_twin,
)
from mat_hopper.core.materials import LegDesign, parse_design
from mat_hopper.core.model import build_model, reset_to_start


def _capsule(rho, r, h, z_top, mass=None):
    """(mass kg, centre z m, transverse inertia about own centre kg m^2)."""
    v_cyl, v_sph = math.pi * r**2 * h, 4.0 / 3.0 * math.pi * r**3
    if mass is not None:
        rho = mass / (v_cyl + v_sph)
    m_c, m_s = rho * v_cyl, rho * v_sph
    i_c = m_c * (r**2 / 4 + h**2 / 12) + m_s * (2 * r**2 / 5 + h**2 / 4 + 3 * h * r / 8)
    return m_c + m_s, z_top - h / 2, i_c


def _hand(densities_g_cm3):
    """Leg of 3 segments (hip at z = 0): stub, 6 half-segment capsules, foot upper, foot."""
    parts = [_capsule(1000.0, 0.03, 0.05, 0.0)]
    z = -0.05
    for rho in densities_g_cm3:
        for _ in range(2):
            parts.append(_capsule(rho * 1000.0, 0.025, 0.05, z))
            z -= 0.05
    parts.append(_capsule(1000.0, 0.025, 0.05, z))
    parts.append(_capsule(None, 0.04, 0.2, z - 0.05, mass=0.5))
    m = sum(p[0] for p in parts)
    com = -sum(p[0] * p[1] for p in parts) / m
    inertia = sum(p[2] + p[0] * p[1] ** 2 for p in parts)
    return m, com, inertia


@pytest.mark.parametrize("name", ["MD", "PVC", "SS", "rho-inc", "rho-dec", "PVC-Ti-SS"])
def test_mass_properties_match_hand_calculation(name):
    d = parse_design(name)
    m, com, inertia = _hand(d.densities_g_cm3)
    p = mass_properties(d)
    assert p.leg_mass_kg == pytest.approx(m, rel=1e-9)
    assert p.leg_com_m == pytest.approx(com, rel=1e-9)
    assert p.hip_inertia_kg_m2 == pytest.approx(inertia, rel=1e-9)


def test_hip_inertia_is_mujocos_joint_space_inertia():
    """MuJoCo's own: the hip_y diagonal of the joint-space inertia matrix is
    the leg subtree's inertia about that axis (armature 0)."""
    d = parse_design("rho-dec")
    hm = build_model(d)
    data = mujoco.MjData(hm.model)
    reset_to_start(hm.model, data)
    full = np.zeros((hm.model.nv, hm.model.nv))
    mujoco.mj_fullM(hm.model, data, full)
    dof = hm.layout.hip_y_dof
    assert mass_properties(d).hip_inertia_kg_m2 == pytest.approx(full[dof, dof], rel=1e-12)


def test_ss_leg_mass_is_robot_mass_minus_base():
    # reference: the SS robot weighs 23.77 kg (MuJoCo), the base 15 kg
    assert mass_properties(parse_design("SS")).leg_mass_kg == pytest.approx(23.77 - 15.0, abs=0.01)


@pytest.mark.parametrize("name", ["SS", "MD", "rho-inc", "rho-dec", "PVC-Ti-SS", "SS-Ti-PVC", "Al-Ti"])
def test_controls_match_what_they_promise(name):
    d = parse_design(name)
    p = mass_properties(d)
    twin, mm, im = rigid_twin(d), mass_matched(d), inertia_matched(d)
    assert all(s.rigid for s in twin.segments) and twin.densities_g_cm3 == d.densities_g_cm3
    assert mass_properties(twin) == p
    assert len(set(mm.densities_g_cm3)) == 1 and len(set(mm.moduli_gpa)) == 1
    assert mass_properties(mm).leg_mass_kg == pytest.approx(p.leg_mass_kg, rel=1e-12)
    pi = mass_properties(im)
    assert pi.leg_mass_kg == pytest.approx(p.leg_mass_kg, rel=1e-12)
    assert pi.hip_inertia_kg_m2 == pytest.approx(p.hip_inertia_kg_m2, rel=1e-10)
    steps = np.diff(im.densities_g_cm3)
    assert np.allclose(steps, steps[0]) if len(steps) else True  # a linear profile
    for c in (twin, mm, im):
        assert c.n_segments == d.n_segments


def test_mass_matched_modulus_is_series_equivalent():
    # PVC-Ti-SS: 4, 120, 193 GPa in series -> 3 / (1/4 + 1/120 + 1/193)
    mm = mass_matched(parse_design("PVC-Ti-SS"))
    assert mm.moduli_gpa[0] == pytest.approx(3 / (1 / 4 + 1 / 120 + 1 / 193))
    assert mm.densities_g_cm3[0] == pytest.approx((1.39 + 4.43 + 8.0) / 3)


def test_a_homogeneous_leg_of_rho_inc_mass():
    # a homogeneous leg with rho-inc's mass: 4.607 g/cm^3, 70 GPa
    mm = mass_matched(parse_design("rho-inc"))
    assert mm.densities_g_cm3[0] == pytest.approx(4.607, abs=5e-4) and mm.moduli_gpa[0] == 70.0


def test_mono_controls_and_segment_mass_convention():
    d = LegDesign.mono("Ti", 6)
    for seg in mats.SEGMENT_MASSES:
        im = inertia_matched(d, seg)
        assert mass_properties(im, seg).hip_inertia_kg_m2 == pytest.approx(
            mass_properties(d, seg).hip_inertia_kg_m2, rel=1e-10
        )
    assert inertia_matched(LegDesign.mono("SS", 1)).densities_g_cm3 == (8.0,)


def test_names_and_errors():
    d = parse_design("rho-inc")
    assert [control(d, k).name for k in CONTROLS] == ["rho-inc~rigid", "rho-inc~mass", "rho-inc~inertia"]
    assert control_kind("rho-inc~mass") == "mass" and control_kind("SS") is None
    assert control_of("rho-inc~mass") == "rho-inc" and control_of("SS") == "SS"
    with pytest.raises(ValueError, match="unknown control 'stiff'; accepted: rigid, mass, inertia"):
        control(d, "stiff")
    assert rigid_twin("SS") == rigid_twin(parse_design("SS"))  # a design name is read as simulate reads it
    with pytest.raises(ValueError, match="unknown"):
        rigid_twin("kryptonite")
    with pytest.raises(ValueError, match="no linear-profile leg"):
        inertia_matched(LegDesign.from_properties([20.0, 0.001, 0.001], [70.0]))


def test_mass_matched_keeps_the_compliance_of_a_partly_rigid_leg():
    # (rigid, rigid, 193 GPa): one spring in series; the homogeneous leg's 3 springs must add to its compliance
    from mat_hopper.core.materials import LegDesign, spring_stiffness
    from mat_hopper.core.model import build_model

    d = LegDesign.from_properties([2.0, 2.0, 8.0], [None, None, 193.0], name="rrSS")
    mm = mass_matched(d)
    comp = [sum(1 / k for k in build_model(x).spring_stiffness_n_m if k > 0) for x in (d, mm)]
    assert comp[1] == pytest.approx(comp[0], rel=1e-9)  # MuJoCo-side spring stiffnesses, series compliance
    assert comp[0] == pytest.approx(1 / spring_stiffness(193.0, "paper", 3))
    with pytest.raises(ValueError, match="outside"):
        mass_matched(LegDesign.from_properties([2.0, 2.0, 8.0], [None, None, 1500.0], name="stiff"))


def test_the_design_itself_is_found_by_its_physics_key():
    from mat_hopper.analysis.beyond_mass import _is_own_mass_leg

    assert _is_own_mass_leg("SS") and not _is_own_mass_leg("rho-inc")
    # rho-dec and rho-inc have other centres of mass but neither is its own mass-matched leg
    assert not _is_own_mass_leg("rho-dec")


def test_control_kind_any_case():
    from mat_hopper.core.control_legs import check_control

    d = parse_design("rho-inc")
    assert check_control(" Inertia ") == "inertia"
    assert control(d, "MASS").name == "rho-inc~mass"
    assert control(d, "Rigid").densities_g_cm3 == control(d, "rigid").densities_g_cm3


def test_control_legs_equal_but_for_round_off_are_one_design():
    """A mean or a series sum in another order changes the last bit: the
    canonical form makes such legs one design, so one cache key and one run."""
    from mat_hopper.core.control_legs import canonical
    from mat_hopper.util.keys import design_key

    al = mats.parse_design("Al")
    assert float(np.mean(al.densities_g_cm3)) != 2.7  # the raw mean carries round-off
    assert design_key(mass_matched(al)) == design_key(al)
    inc, dec = mats.parse_design("PVC-Ti-SS"), mats.parse_design("SS-Ti-PVC")
    assert design_key(mass_matched(inc)) == design_key(mass_matched(dec))
    assert canonical(2.7000000000000006) == 2.7 and canonical(None) is None
    # far above round-off: a real difference of 1e-9 stays a difference
    assert canonical(2.7 + 1e-9) != 2.7
