import mujoco
import numpy as np
import pytest

from mat_hopper.core import model
from mat_hopper.core import reference as ref
from mat_hopper.core.materials import LegDesign, parse_design
from mat_hopper.core.model import CONTROL_SENSORS, SENSORS, build_model, reset_to_start
from mat_hopper.core.sim import simulate


def test_reference_masses():
    assert build_model(parse_design("MD")).total_mass_kg == pytest.approx(ref.MASS_MD_KG, abs=0.005)
    assert build_model(parse_design("SS")).total_mass_kg == pytest.approx(ref.MASS_SS_KG, abs=0.005)


def test_capsule_geometry_adds_end_caps():
    # The authors' per-capsule geometry: each half-segment capsule has its own
    # two hemispherical end caps, so 6 segments carry 6 more spheres than 3.
    m3 = build_model(LegDesign.mono("SS", 3), segment_mass="capsule").total_mass_kg
    m6 = build_model(LegDesign.mono("SS", 6), segment_mass="capsule").total_mass_kg
    r = ref.MATERIAL_RADIUS
    cap = 4 / 3 * np.pi * r**3 * 8000.0  # one sphere (two hemispheres) per capsule
    assert m6 - m3 == pytest.approx(6 * cap, rel=1e-6)  # 12 vs 6 half-capsules


@pytest.mark.parametrize("n", [1, 2, 3, 5])
def test_geometry_any_segment_count(n):
    hm = build_model(LegDesign.mono("Ti", n))
    m, d = hm.model, mujoco.MjData(hm.model)
    reset_to_start(m, d)
    toe = d.site("toe").xpos
    assert toe[2] == pytest.approx(ref.BASE_START_Z - 0.6)  # hip to toe 0.6 m
    assert [m.joint(f"mat_spring_{i}").type for i in range(1, n + 1)] == [mujoco.mjtJoint.mjJNT_SLIDE] * n
    assert len(hm.spring_stiffness_n_m) == n


def test_rigid_leg_has_no_material_springs():
    m = build_model(parse_design("MD")).model
    names = [m.joint(i).name for i in range(m.njnt)]
    assert not any(n.startswith("mat_spring") for n in names)
    assert "spring" in names and "hip_y" in names


def test_stiffness_damping_and_options():
    hm = build_model(parse_design("SS"), timestep_s=2e-4)
    m = hm.model
    j = m.joint("mat_spring_2")
    assert m.jnt_stiffness[j.id] == pytest.approx(1.819e8, rel=1e-3)
    assert m.dof_damping[j.dofadr[0]] == 1.0
    assert m.opt.timestep == 2e-4
    assert m.opt.iterations == 50 and m.opt.tolerance == 1e-10
    assert m.opt.disableflags & mujoco.mjtDisableBit.mjDSBL_AUTORESET
    assert list(m.actuator_gear[:, 0]) == [600.0, 600.0, 1.0]
    assert m.jnt_range[m.joint("hip_y").id][1] == pytest.approx(np.radians(70))


def test_start_pose_as_the_authors_file_sets_it():
    """The base body sits at the world origin; the 1.2 m start height is the
    qpos of its z slide joint (numbers from the spec, by hand)."""
    m = build_model(parse_design("SS")).model
    assert list(m.body("base").pos) == [0.0, 0.0, 0.0]
    d = mujoco.MjData(m)
    reset_to_start(m, d)
    assert d.qpos[m.joint("base_z").qposadr[0]] == 1.2
    assert d.xpos[m.body("base").id][2] == 1.2
    assert np.count_nonzero(d.qpos) == 1


def test_ramp_centre_is_exact():
    """The ramp box's centre is (2, 0, -0.03) m exactly, not the -0.0302 m
    at which its top face would meet the ground at x = 0."""
    ramp = build_model(parse_design("SS"), ramp_grade_deg=2.0).model
    assert list(ramp.geom("ramp").pos) == [2.0, 0.0, -0.03]


def test_ramp_only_when_asked():
    flat = build_model(parse_design("SS")).model
    ramp = build_model(parse_design("SS"), ramp_grade_deg=2.0).model
    with pytest.raises(KeyError):
        flat.geom("ramp")
    g = ramp.geom("ramp")
    # Top face rises 3.5 % per m in x.
    d = mujoco.MjData(ramp)
    mujoco.mj_forward(ramp, d)
    normal = d.geom_xmat[g.id].reshape(3, 3)[:, 2]
    assert -normal[0] / normal[2] == pytest.approx(0.0349, abs=2e-4)


@pytest.mark.parametrize("dt", [0, -1e-4, float("nan"), 1.0])
def test_bad_timestep(dt):
    with pytest.raises(ValueError, match="timestep"):
        build_model(parse_design("SS"), timestep_s=dt)


def test_sensor_sets():
    full = build_model(parse_design("SS")).model
    lean = build_model(parse_design("SS"), sensors="control").model
    assert [full.sensor(i).name for i in range(full.nsensor)] == list(SENSORS)
    assert [lean.sensor(i).name for i in range(lean.nsensor)] == list(CONTROL_SENSORS)
    with pytest.raises(ValueError, match="sensors"):
        build_model(parse_design("SS"), sensors="some")


def test_unread_sensors_do_not_change_the_trajectory(monkeypatch):
    """Rollouts drop the hip torque and accelerometer sensors: nothing reads
    them, so a rollout with the spec's seven is bit-identical."""
    lean = simulate("SS", "ramp", duration_s=3.0, transient_s=1.0)
    built = []

    def with_all_sensors(*args, **kwargs):
        hm = build_model(*args, **{**kwargs, "sensors": "all"})
        built.append(hm.model.nsensor)
        return hm

    monkeypatch.setattr(model, "build_model", with_all_sensors)
    full = simulate("SS", "ramp", duration_s=3.0, transient_s=1.0)
    assert built == [len(SENSORS)]
    np.testing.assert_array_equal(full.data, lean.data)
    np.testing.assert_array_equal(full.events, lean.events)


@pytest.mark.parametrize("name, kg", [("SS", 23.77), ("MD", 16.90)])
def test_total_mass_independent_of_segment_count(name, kg):
    """The spec's masses (by hand, 2 decimals) for N = 1 ... 24 under the
    default segment mass ``leg``."""
    for n in (1, 3, 6, 12, 24):
        design = LegDesign.mono(name, n) if name != "MD" else LegDesign.mono("MD", n)
        assert build_model(design).total_mass_kg == pytest.approx(kg, rel=0.005)


def test_capsule_geometry_grows_with_n():
    """The authors' per-capsule geometry, kept under segment_mass='capsule':
    the leg's mass grows with N (SS, kg)."""
    for n, kg in ((1, 21.68), (3, 23.77), (6, 26.91), (12, 33.20), (24, 45.76)):
        assert build_model(LegDesign.mono("SS", n), segment_mass="capsule").total_mass_kg == pytest.approx(kg, abs=0.01)


@pytest.mark.parametrize("design", ["SS", "MD", "rho-inc", "PVC-Ti-SS"])
def test_three_segments_bit_identical_to_the_authors_geometry(design):
    """At N = 3 the mass-conserving geometry compiles to exactly the
    authors' model: every numeric array of the MjModel is equal."""
    a = build_model(parse_design(design), ramp_grade_deg=2.0).model
    b = build_model(parse_design(design), ramp_grade_deg=2.0, segment_mass="capsule").model
    compared = 0
    for name in dir(a):
        if name.startswith("_"):
            continue
        va = getattr(a, name)
        if isinstance(va, np.ndarray) and va.dtype.kind in "fiu":
            np.testing.assert_array_equal(va, getattr(b, name), err_msg=name)
            compared += 1
    assert compared > 100


def test_terrain_height_against_mujoco_ray_casts():
    """terrain_height_m against MuJoCo's own mj_ray straight down (the
    hopper out of the way at y = 0.4 m)."""
    from mat_hopper.core.model import terrain_height_m

    m = build_model(parse_design("SS"), ramp_grade_deg=2.0).model
    d = mujoco.MjData(m)
    reset_to_start(m, d)
    geomid = np.zeros(1, dtype=np.int32)
    for x in (-0.5, 0.0, 0.05, 0.5, 1.0, 2.0, 3.5):
        dist = mujoco.mj_ray(m, d, np.array([x, 0.4, 2.0]), np.array([0.0, 0.0, -1.0]), None, 1, -1, geomid)
        assert terrain_height_m(x, 0.4, 2.0) == pytest.approx(2.0 - dist, abs=1e-9), x
    assert terrain_height_m(0.0, 0.0, 2.0) == pytest.approx(2.2e-4, abs=2e-5)  # the spec's 0.2 mm step
    assert terrain_height_m([1.0, 2.0], 0.0, None).tolist() == [0.0, 0.0]


# --- names enter any case and are stored in their canonical spelling ---------

_MODEL_ARRAYS = ("jnt_type", "jnt_stiffness", "dof_damping", "body_mass", "geom_size", "sensor_type", "qpos0")


def _assert_same_mjmodel(a: mujoco.MjModel, b: mujoco.MjModel) -> None:
    for name in _MODEL_ARRAYS:
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name), err_msg=name)


def test_build_model_bending_convention_any_case():
    d = LegDesign.mono("SS", 3)
    mixed, plain = build_model(d, convention="Bending"), build_model(d, convention="bending")
    _assert_same_mjmodel(mixed.model, plain.model)
    assert mixed.convention == "bending"
    assert mixed.bending_stiffness_n_m_rad == plain.bending_stiffness_n_m_rad
    assert all(k > 0 for k in mixed.bending_stiffness_n_m_rad)  # SS hinges: not zero


def test_build_model_segment_mass_damping_and_sensors_any_case():
    d = LegDesign.mono("Ti", 3)
    mixed = build_model(d, segment_mass=" Capsule ", damping="Loss-Factor", sensors="CONTROL")
    plain = build_model(d, segment_mass="capsule", damping="loss-factor", sensors="control")
    _assert_same_mjmodel(mixed.model, plain.model)
    assert (mixed.segment_mass, mixed.damping, mixed.sensors) == ("capsule", "loss-factor", "control")
    assert mixed.model.nsensor == len(CONTROL_SENSORS)
    with pytest.raises(ValueError, match="unknown sensors 'some'; accepted: all, control"):
        build_model(d, sensors="some")


@pytest.mark.parametrize("grade", [90, -90, 90.0, 135.0, -180, float("nan"), float("inf"), -float("inf"), True, "2"])
def test_ramp_grade_refused_unless_finite_and_strictly_between_minus_90_and_90(grade):
    # a vertical (or overhanging) ramp, nan or inf was compiled before the fix
    from mat_hopper.core.model import build_spec, check_ramp_grade, ramp_pose, terrain_height_m

    for call in (
        lambda: build_model(parse_design("SS"), ramp_grade_deg=grade),
        lambda: build_spec(parse_design("SS"), ramp_grade_deg=grade),
        lambda: ramp_pose(grade),
        lambda: terrain_height_m(0.0, 0.0, grade),
        lambda: check_ramp_grade(grade),
    ):
        with pytest.raises(ValueError, match=r"ramp_grade_deg must be .*strictly between -90 and 90 deg"):
            call()


def test_ramp_grade_accepted_inside_the_open_interval():
    from mat_hopper.core.model import check_ramp_grade

    assert check_ramp_grade(None) is None
    assert check_ramp_grade(2) == 2.0 and check_ramp_grade(-89.9) == -89.9 and check_ramp_grade(np.float64(45)) == 45.0
    hm = build_model(parse_design("SS"), ramp_grade_deg=2)
    assert hm.ramp_grade_deg == 2.0 and hm.model.geom("ramp").id >= 0
