"""The ``bending`` conventions: static tip deflection against Euler-Bernoulli
(the PRBM chain's ratio), the other conventions bit-identical, joint layout."""

import math

import mujoco
import numpy as np
import pytest

from mat_hopper.core import reference as ref
from mat_hopper.core.materials import LegDesign, bending_stiffness, prbm_tip_deflection_ratio
from mat_hopper.core.model import BEND_SPRINGS, SEGMENT_BODY, build_model

# Hand-worked values. Steel of the paper: E = 193 GPa; the leg's section a
# solid circle of r = 0.025 m: I = pi r^4 / 4 = pi x 3.90625e-7 / 4 = 3.0680e-7 m^4;
# E I = 5.9212e4 N m^2. Material length L = 0.3 m. A lateral end load P = 50 N
# gives P L^3 / (3 E I) = 50 x 0.027 / (3 x 5.9212e4) = 7.600e-6 m.
E_PA = 193e9
I_M4 = math.pi * 0.025**4 / 4.0
EI = 5.9212e4
P_N = 50.0
EULER_BERNOULLI_M = 7.600e-6
# The PRBM's tip deflection over P L^3 / (3 E I) (conventions module doc):
# N = 1, Howell's pivot: 3 gamma / K_Theta = 2.55 / 2.65; N >= 2, midpoint
# pivots of E I / l each: sum_{j=1..N} (j - 1/2)^2 l^2 / (E I / l) over
# N^3 l^3 / 3 = (4 N^2 - 1) / (4 N^2), i.e. the fractions below.
EXPECTED_RATIO = {
    1: 2.55 / 2.65,
    2: 15 / 16,
    3: 35 / 36,
    4: 63 / 64,
    5: 99 / 100,
    6: 143 / 144,
    7: 195 / 196,
    8: 255 / 256,
    9: 323 / 324,
    10: 399 / 400,
    11: 483 / 484,
    12: 575 / 576,
    13: 675 / 676,
    14: 783 / 784,
    15: 899 / 900,
    16: 1023 / 1024,
}


def test_hand_numbers():
    assert I_M4 == pytest.approx(3.0680e-7, rel=1e-4)
    assert E_PA * I_M4 == pytest.approx(EI, rel=1e-4)
    assert P_N * 0.3**3 / (3 * EI) == pytest.approx(EULER_BERNOULLI_M, rel=1e-3)
    # one hinge's stiffness at N = 3: E I / l = 5.9212e4 / 0.1 = 5.9212e5 N m/rad
    assert bending_stiffness(193.0, 3) == pytest.approx(5.9212e5, rel=1e-4)
    # N = 1: gamma K_Theta E I / L = 0.85 x 2.65 x 5.9212e4 / 0.3 = 4.4459e5 N m/rad
    assert bending_stiffness(193.0, 1) == pytest.approx(4.4459e5, rel=1e-4)
    for n, ratio in EXPECTED_RATIO.items():
        assert prbm_tip_deflection_ratio(n) == pytest.approx(ratio, rel=1e-12)


def _static_tip_deflection(n: int) -> float:
    """MuJoCo statics: the base and hips held (only the bending hinges move),
    gravity off, a lateral force P along +x at the material's lower end
    (applied as xfrc_applied on the last segment, moved to that point);
    fixed-point iteration K q = J(q)^T F on the hinges' dofs, each step
    from MuJoCo's own Jacobian at the current pose. Returns the tip's x
    displacement (m)."""
    hm = build_model(LegDesign.mono("SS", n), convention="bending")
    m = hm.model
    m.opt.gravity[:] = 0.0
    d = mujoco.MjData(m)
    mujoco.mj_resetDataKeyframe(m, d, 0)
    mujoco.mj_forward(m, d)
    body = m.body(SEGMENT_BODY.format(i=n)).id
    half = ref.MATERIAL_LENGTH / n / 2.0
    dofs = [int(m.joint(name.format(i=i)).dofadr[0]) for i in range(1, n + 1) for name in BEND_SPRINGS]
    k = np.array([m.jnt_stiffness[m.dof_jntid[v]] for v in dofs])

    def tip():
        return d.xpos[body] + d.xmat[body].reshape(3, 3) @ np.array([0.0, 0.0, -half])

    tip0 = tip().copy()
    force = np.array([P_N, 0.0, 0.0])
    jacp = np.zeros((3, m.nv))
    for _ in range(6):
        point = tip()
        # xfrc_applied acts at the body's centre of mass: move the force to the tip
        d.xfrc_applied[body, :3] = force
        d.xfrc_applied[body, 3:] = np.cross(point - d.xipos[body], force)
        mujoco.mj_jac(m, d, jacp, None, point, body)
        q = (jacp[:, dofs].T @ force) / k
        for v, qv in zip(dofs, q):
            d.qpos[m.jnt_qposadr[m.dof_jntid[v]]] = qv
        mujoco.mj_forward(m, d)
    # equilibrium: MuJoCo's spring force balances the applied load on every hinge
    mujoco.mj_jac(m, d, jacp, None, tip(), body)
    residual = d.qfrc_spring[dofs] + jacp[:, dofs].T @ force
    assert np.max(np.abs(residual)) < 1e-6 * P_N * ref.MATERIAL_LENGTH
    return float(tip()[0] - tip0[0])


@pytest.mark.parametrize("n", range(1, 17))
def test_tip_deflection_matches_euler_bernoulli_within_prbm_error(n):
    delta = _static_tip_deflection(n)
    ratio = delta / EULER_BERNOULLI_M
    # the model reproduces the PRBM's own value (to the 4-digit hand numbers)...
    assert ratio == pytest.approx(EXPECTED_RATIO[n], rel=2e-4)
    # ...so it lies within the PRBM's stated error of Euler-Bernoulli
    stated = abs(EXPECTED_RATIO[n] - 1.0)
    assert abs(ratio - 1.0) <= stated + 2e-4


def test_axial_plus_bending_has_both_springs():
    m = build_model(LegDesign.mono("Ti", 2), convention="axial+bending").model
    names = [m.joint(i).name for i in range(m.njnt)]
    assert [n for n in names if n.startswith("mat_")] == [
        "mat_spring_1",
        "mat_bend_x_1",
        "mat_bend_y_1",
        "mat_spring_2",
        "mat_bend_x_2",
        "mat_bend_y_2",
    ]
    rigid = build_model(LegDesign.from_properties([8.0] * 3, [None] * 3), convention="bending").model
    assert not any(rigid.joint(i).name.startswith("mat_") for i in range(rigid.njnt))


def test_loss_factor_damping():
    authors = build_model(LegDesign.mono("SS", 3), convention="bending").model
    lossy = build_model(LegDesign.mono("SS", 3), convention="bending", damping="loss-factor").model
    j = lossy.joint("mat_bend_x_1")
    dof = int(j.dofadr[0])
    assert authors.dof_damping[dof] == 1.0
    # steel, a metal: eta = 1e-3; c = eta sqrt(k M0)
    assert lossy.dof_damping[dof] == pytest.approx(1e-3 * math.sqrt(j.stiffness[0] * lossy.dof_M0[dof]))
    with pytest.raises(ValueError, match="damping"):
        build_model(LegDesign.mono("SS", 3), damping="viscous")
