"""The hopper's bodies from the design alone (mat_hopper.core.lumped) against
the compiled model's own numbers: masses, centres of mass, inertias,
stiffnesses and MuJoCo's joint-space inertia at the start pose."""

import mujoco
import numpy as np
import pytest

from mat_hopper.core.catalogue import CATALOGUE
from mat_hopper.core.conventions import CONVENTIONS, SEGMENT_MASSES
from mat_hopper.core.lumped import LumpedHopper, capsule_inertia
from mat_hopper.core.materials import LegDesign, parse_design
from mat_hopper.core.model import START_KEY, build_model
from mat_hopper.core.stable_step import leg_chain

DESIGNS = [
    *(LegDesign.mono(m, n) for m, n in (("SS", 3), ("PVC", 1), ("TrabecularBone", 5), ("WC", 2), ("MD", 3))),
    parse_design("rho-inc"),
    parse_design("PVC-Ti-SS"),
    LegDesign.from_properties([1.4, 8.0, 3.0, 2.0], [None, 100.0, None, 5.0]),  # rigid segments between springs
]


def _compiled(design, convention, segment_mass):
    m = build_model(design, convention=convention, segment_mass=segment_mass).model
    d = mujoco.MjData(m)
    mujoco.mj_resetDataKeyframe(m, d, m.key(START_KEY).id)
    mujoco.mj_forward(m, d)
    full = np.zeros((m.nv, m.nv))
    mujoco.mj_fullM(m, d, full)
    return m, d, full


@pytest.mark.parametrize("convention", CONVENTIONS)
@pytest.mark.parametrize("segment_mass", SEGMENT_MASSES)
def test_bodies_and_mass_matrix_are_the_compiled_models(convention, segment_mass):
    for design in DESIGNS:
        hopper = LumpedHopper(design, convention, segment_mass)
        m, d, full = _compiled(design, convention, segment_mass)
        ids = [m.body(b.name).id for b in hopper.bodies]
        assert len(ids) == m.nbody - 1  # every body but the world
        np.testing.assert_allclose([b.mass_kg for b in hopper.bodies], m.body_mass[ids], rtol=1e-14, atol=0)
        z0 = d.xpos[m.body("base").id][2]  # the base starts 1.2 m up
        np.testing.assert_allclose([b.com_z_m for b in hopper.bodies], d.xipos[ids, 2] - z0, rtol=0, atol=1e-14)
        assert [d.name for d in hopper.dofs] == [m.joint(m.dof_jntid[v]).name for v in range(m.nv)]
        np.testing.assert_array_equal(hopper.stiffness(), m.jnt_stiffness[m.dof_jntid])
        np.testing.assert_allclose(hopper.mass_matrix(), full, rtol=0, atol=1e-13 * np.abs(full).max())


def test_body_inertias_are_mujocos():
    hopper = LumpedHopper(parse_design("PVC-Ti-SS"), "axial+bending")
    m, _, _ = _compiled(hopper.design, "axial+bending", "leg")
    for b in hopper.bodies:
        i = m.body(b.name).id
        rot = np.zeros(9)
        mujoco.mju_quat2Mat(rot, m.body_iquat[i])
        rot = rot.reshape(3, 3)
        tensor = rot @ np.diag(m.body_inertia[i]) @ rot.T  # about the centre of mass, world axes
        np.testing.assert_allclose(tensor, np.diag(b.inertia_kg_m2), rtol=0, atol=1e-12 * tensor.max())


def test_capsule_inertia_by_hand():
    # a sphere (no cylinder): 2 m r^2 / 5 about every axis
    assert capsule_inertia(2.0, 0.1, 0.0) == pytest.approx((0.008, 0.008), rel=1e-12)
    # a long thin capsule tends to a rod: m L^2 / 12 across it
    transverse, _ = capsule_inertia(1.0, 1e-6, 0.5)
    assert transverse == pytest.approx(1.0 / 12.0, rel=1e-5)


def test_the_axial_chain_is_the_compiled_models_body_mass():
    """leg_chain's lumped masses, what --timestep auto's spring bound rests on,
    are MuJoCo's body_mass summed as the chain lumps them, for every catalogue
    material (to round-off)."""
    for mat in CATALOGUE.values():
        for segment_mass in SEGMENT_MASSES:
            design = LegDesign.mono(mat, 4)
            masses, springs = leg_chain(design, "axial", segment_mass)
            m = build_model(design, convention="axial", segment_mass=segment_mass).model
            mass = lambda name, m=m: m.body_mass[m.body(name).id]
            if mat.rigid:
                want = [mass("base") + mass("leg") + sum(mass(f"seg{i}") for i in range(1, 5)), mass("foot")]
            else:
                want = [mass("base") + mass("leg"), *(mass(f"seg{i}") for i in range(1, 5)), mass("foot")]
            np.testing.assert_allclose(masses, want, rtol=1e-14, atol=0)
            assert len(springs) == len(masses) - 1


def test_bad_input_is_refused():
    with pytest.raises(ValueError, match="LegDesign"):
        LumpedHopper("SS")
    with pytest.raises(ValueError, match="stiffness convention"):
        LumpedHopper(parse_design("SS"), "twisted")
    with pytest.raises(ValueError, match="rotational springs"):
        LumpedHopper(parse_design("SS"), "Bending").axial_chain()
    assert LumpedHopper(parse_design("SS"), " AXIAL ", "Capsule").convention == "axial"
