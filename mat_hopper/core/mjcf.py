"""The hopper's MuJoCo model as an editable ``MjSpec``, built in memory from
a leg design (:func:`build_spec`), and the names of its parts.

Geometry follows :mod:`mat_hopper.core.reference` (the authors' hopper): a
15 kg base on six unactuated joints, a two-axis hip, a stub, N material
segments and a sprung foot. Each material segment straddles its springs:
half of its mass above them, half below. Density sets the capsules' mass
(:mod:`mat_hopper.core.conventions`' segment-mass conventions); modulus sets
the springs' stiffness (its stiffness conventions). A rigid material has no
spring at all (the paper's MD leg). The names below are the one source for
the builder, :func:`mat_hopper.core.model.layout_of`, the loop's stress
probe and the tests. :func:`mat_hopper.core.model.build_model` compiles the
spec.
"""

from __future__ import annotations

import math

import mujoco
import numpy as np

from ..util.parsing import parse_name
from . import reference as ref
from .contact import DEFAULT_CONTACT, check_contact, contact_solref, elliptic_cone
from .conventions import (
    AXIAL_CONVENTIONS,
    BENDING_CONVENTIONS,
    CONVENTIONS,
    DEFAULT_CONVENTION,
    DEFAULT_SEGMENT_MASS,
    bending_stiffness,
    capsule_density_scale,
    check_segment_mass,
    prbm_constants,
    spring_stiffness,
)
from .materials import LegDesign
from .terrain import check_ramp_grade, ramp_pose

__all__ = [
    "ACTUATORS",
    "AXIAL_SPRING",
    "BASE_BODY",
    "BASE_CAPSULES",
    "BASE_JOINTS",
    "BEND_SPRINGS",
    "CONTROL_SENSORS",
    "FOOT_BODY",
    "FOOT_GEOM",
    "FOOT_SPRING",
    "FOOT_UPPER_GEOM",
    "GROUND_GEOM",
    "HIP_JOINTS",
    "HIP_SITE",
    "IMU_SITE",
    "LEG_BODY",
    "LIGHT",
    "MAX_TIMESTEP_S",
    "MIN_TIMESTEP_S",
    "RAMP_GEOM",
    "SEGMENT_BODY",
    "SEGMENT_LOWER",
    "SEGMENT_UPPER",
    "SENSORS",
    "SENSOR_SETS",
    "START_KEY",
    "STUB_GEOM",
    "TOE_SITE",
    "build_spec",
    "check_sensors",
    "check_timestep",
]

BASE_JOINTS = ("base_x", "base_y", "base_z", "base_roll", "base_pitch", "base_yaw")
HIP_JOINTS = ("hip_y", "hip_x")
ACTUATORS = ("hip_y", "hip_x", "thrust")
SENSORS = ("touch", "base_pos", "base_quat", "base_gyro", "base_linvel", "hip_torque", "base_acc")
# What the controller reads. The hip torque and accelerometer sensors make
# MuJoCo run its post-constraint dynamics pass (mj_rnePostConstraint) every
# step and feed nothing back: rollouts leave them out
# (sensors="control"); the recorded acceleration is the base's qacc and the
# hip torque the actuator force. tests/core/test_model.py checks that the
# trajectory is bit-identical either way.
CONTROL_SENSORS = SENSORS[:5]
SENSOR_SETS = {"all": SENSORS, "control": CONTROL_SENSORS}
START_KEY = "start"  # keyframe: the hopper at rest, base 1.2 m up (qpos of the z slide)
# Names of the model's parts, one source for the builder, the layout, the
# loop's stress channels and the tests (as MuJoCo Playground's models keep
# theirs). Per-segment names take i = 1 .. N (segment 1 nearest the base).
LIGHT = "sun"
GROUND_GEOM = "ground"
RAMP_GEOM = "ramp"
BASE_BODY = "base"
BASE_CAPSULES = ("base_capsule_x", "base_capsule_y")
IMU_SITE = "imu"
LEG_BODY = "leg"
HIP_SITE = "hip"
STUB_GEOM = "stub"
SEGMENT_BODY = "seg{i}"
SEGMENT_UPPER = "seg{i}_upper"
SEGMENT_LOWER = "seg{i}_lower"
AXIAL_SPRING = "mat_spring_{i}"  # slide along the leg (paper, axial, axial+bending)
BEND_SPRINGS = ("mat_bend_x_{i}", "mat_bend_y_{i}")  # hinges about x and y (bending, axial+bending)
FOOT_UPPER_GEOM = "foot_upper"
FOOT_BODY = "foot"
FOOT_SPRING = "spring"  # the thrust actuator's joint
FOOT_GEOM = "foot"
TOE_SITE = "toe"

MAX_TIMESTEP_S = 0.1  # s, the largest physics step accepted anywhere
# s, the smallest physics step the package plans (the stable-step search's floor,
# mat_hopper.physics.stability.DT_MIN_S; the shortest control period auto substeps take)
MIN_TIMESTEP_S = 1e-6


def check_timestep(timestep_s) -> float:
    """The physics step as a float in (0, MAX_TIMESTEP_S] s; ValueError naming it otherwise.

    Args:
        timestep_s: the physics step, s: a number or anything ``float()``
            reads (a numeric string).

    Returns:
        The step as a float, s.

    Raises:
        ValueError: a bool, a value ``float()`` cannot read, or a step that
            is not finite or not in (0, :data:`MAX_TIMESTEP_S`] (0.1 s).
    """
    if isinstance(timestep_s, bool):
        raise ValueError(f"timestep must be a number > 0 s, got {timestep_s!r}")
    try:
        dt = float(timestep_s)
    except (TypeError, ValueError):
        raise ValueError(f"timestep must be a number > 0 s, got {timestep_s!r}") from None
    if not (math.isfinite(dt) and 0 < dt <= MAX_TIMESTEP_S):
        raise ValueError(f"timestep must be in (0, {MAX_TIMESTEP_S:g}] s, got {timestep_s!r}")
    return dt


def _capsule(body, name, z0, z1, radius, *, density=None, mass=None, rgba=None):
    g = body.add_geom(name=name, type=mujoco.mjtGeom.mjGEOM_CAPSULE, fromto=[0, 0, z0, 0, 0, z1], size=[radius, 0, 0])
    if mass is not None:
        g.mass = mass
    else:
        g.density = density
    if rgba is not None:
        g.rgba = rgba
    return g


def _slide(body, name, stiffness, damping, *, limit=None):
    j = body.add_joint(name=name, type=mujoco.mjtJoint.mjJNT_SLIDE, axis=[0, 0, -1])
    j.stiffness[0] = stiffness
    j.damping[0] = damping
    if limit is None:
        j.limited = mujoco.mjtLimited.mjLIMITED_FALSE
    else:
        j.limited = mujoco.mjtLimited.mjLIMITED_TRUE
        j.range = [-limit, limit]
    return j


def check_sensors(sensors: str) -> str:
    """The sensor set named (case-insensitive, blanks trimmed;
    :func:`mat_hopper.util.parsing.parse_name`), as spelled in :data:`SENSOR_SETS`.

    Args:
        sensors: ``"all"`` or ``"control"``, any case.

    Returns:
        The name as spelled in :data:`SENSOR_SETS` (``"Control"`` gives
        ``"control"``).

    Raises:
        ValueError: an empty name or one not in :data:`SENSOR_SETS` (the
            message lists them).
    """
    return parse_name(sensors, SENSOR_SETS, "sensors")


def build_spec(
    design: LegDesign,
    *,
    ramp_grade_deg: float | None = None,
    timestep_s: float = ref.TIMESTEP_S,
    convention: str = DEFAULT_CONVENTION,
    sensors: str = "all",
    segment_mass: str = DEFAULT_SEGMENT_MASS,
    contact: str = DEFAULT_CONTACT,
) -> mujoco.MjSpec:
    """The hopper with this leg as an editable ``MjSpec`` (not compiled).

    Built in named steps, each adding one part under the names of the
    constants block above: options, terrain, base, leg (hips, stub, material
    segments), foot, actuators, start keyframe, sensors, contact parameters.

    sensors: "all" (the spec's seven, in its order) or "control" (the first
    five, which the controller reads; what rollouts use, see CONTROL_SENSORS);
    segment_mass: "leg" (each segment 1/N of the 3-segment leg's material
    mass; identical to the authors' model at N = 3) or "capsule" (the
    authors' per-capsule density at any N), see :mod:`mat_hopper.core.conventions`.

    Args:
        design: the :class:`~mat_hopper.core.materials.LegDesign`.
        ramp_grade_deg: None for flat ground (default), else the ramp box's
            pitch, deg (:func:`ramp_pose`), finite and strictly between -90
            and 90 (:func:`check_ramp_grade`).
        timestep_s: the physics step, s, in (0, 0.1] (default 1e-4, the
            paper's).
        convention: the stiffness convention (``paper``, ``axial``,
            ``bending``, ``axial+bending``; default ``paper``), as spelled
            in :data:`~mat_hopper.core.conventions.CONVENTIONS`: the entry
            points (SimSettings, :func:`mat_hopper.core.model.build_model`,
            the commands) spell it; other spellings are refused.
        sensors: ``"all"`` (default) or ``"control"``, any case
            (:func:`check_sensors`).
        segment_mass: ``"leg"`` (default) or ``"capsule"``, any case.
        contact: ``"authors"`` (default: MuJoCo's default solref (0.02, 1)),
            ``"stiff"`` (0.001, 1) or ``"stiff-elliptic"`` (``stiff`` with
            elliptic friction cones), any case (:mod:`mat_hopper.core.contact`);
            the solref set on every geom that can touch (:func:`_set_contact`).

    Returns:
        The uncompiled ``mujoco.MjSpec``, named ``hopper_<design name>``,
        with the ``start`` keyframe.

    Raises:
        ValueError: a design that is not a LegDesign, an unknown sensor
            set, convention, segment-mass convention or contact, a time step not
            in (0, 0.1] s (:func:`check_timestep`), or a ramp pitch not
            finite and strictly between -90 and 90 deg
            (:func:`check_ramp_grade`).
    """
    if not isinstance(design, LegDesign):
        raise ValueError(f"design must be a LegDesign, got {type(design).__name__}")
    sensors = check_sensors(sensors)
    if convention not in CONVENTIONS:  # spelled once, at the entry points
        raise ValueError(f"stiffness convention {convention!r}: give one of {', '.join(CONVENTIONS)}, as spelled")
    segment_mass = check_segment_mass(segment_mass)
    contact = check_contact(contact)
    solref = contact_solref(contact)
    dt = check_timestep(timestep_s)
    ramp_grade_deg = check_ramp_grade(ramp_grade_deg)
    spec = mujoco.MjSpec()
    spec.modelname = f"hopper_{design.name}"
    _set_options(spec, dt)
    if elliptic_cone(contact):
        spec.option.cone = mujoco.mjtCone.mjCONE_ELLIPTIC
    _add_terrain(spec.worldbody, ramp_grade_deg)
    base = _add_base(spec.worldbody)
    last = _add_leg(base, design, convention, segment_mass)
    _add_foot(*last)
    _add_actuators(spec)
    spec.add_key(name=START_KEY, qpos=_start_qpos(design, convention))
    _add_sensors(spec, sensors)
    _set_contact(spec, solref)
    return spec


def _set_contact(spec: mujoco.MjSpec, solref: tuple[float, float]) -> None:
    """The contact's solref (timeconst s, dampratio) on every geom that can
    touch (contype or conaffinity set: the foot and the terrain). MuJoCo
    mixes a contact's solref from its two geoms' by their solmix weights
    (a weighted mean): equal on both sides, the mix is exactly `solref`.
    The default solimp is kept."""
    for g in spec.geoms:
        if g.contype or g.conaffinity:
            g.solref = list(solref)


def _set_options(spec: mujoco.MjSpec, dt: float) -> None:
    spec.compiler.degree = False
    opt = spec.option
    opt.timestep = dt
    opt.solver = mujoco.mjtSolver.mjSOL_NEWTON
    opt.iterations = ref.SOLVER_ITERATIONS
    opt.tolerance = ref.SOLVER_TOLERANCE
    opt.jacobian = mujoco.mjtJacobian.mjJAC_DENSE
    opt.cone = mujoco.mjtCone.mjCONE_PYRAMIDAL
    # Divergence is a result we detect and report: never silently reset.
    opt.disableflags |= mujoco.mjtDisableBit.mjDSBL_AUTORESET
    spec.default.joint.damping[0] = ref.JOINT_DAMPING_DEFAULT
    spec.default.joint.armature = 0.0
    spec.default.geom.contype = 0
    spec.default.geom.conaffinity = 0


def _add_terrain(world, ramp_grade_deg: float | None) -> None:
    """Light, ground plane and (on the ramp behaviour) the ramp box."""
    world.add_light(name=LIGHT, pos=[0, 0, 6], dir=[0, 0, -1], type=mujoco.mjtLightType.mjLIGHT_DIRECTIONAL)
    world.add_geom(
        name=GROUND_GEOM,
        type=mujoco.mjtGeom.mjGEOM_PLANE,
        size=[0, 0, 1],
        contype=1,
        conaffinity=1,
        condim=ref.FOOT_CONDIM,
        rgba=[0.85, 0.85, 0.82, 1],
    )
    if ramp_grade_deg is not None:
        pos, quat = ramp_pose(ramp_grade_deg)
        world.add_geom(
            name=RAMP_GEOM,
            type=mujoco.mjtGeom.mjGEOM_BOX,
            size=list(ref.RAMP_HALF_SIZE),
            pos=pos,
            quat=quat,
            friction=list(ref.RAMP_FRICTION),
            contype=1,
            conaffinity=1,
            condim=ref.FOOT_CONDIM,
            rgba=[0.55, 0.6, 0.7, 1],
        )


def _add_base(world):
    """The base body on its six unactuated joints, with its two capsules
    and the IMU site.

    The base body sits at the world origin and starts 1.2 m up through the
    qpos of its z slide joint (keyframe "start"), as in the authors' file:
    the same pose as a body offset, but not the same floating-point sums."""
    base = world.add_body(name=BASE_BODY, pos=[0, 0, 0])
    for name, jtype, axis in zip(BASE_JOINTS, ["slide"] * 3 + ["hinge"] * 3, np.vstack([np.eye(3)] * 2)):
        j = base.add_joint(
            name=name,
            axis=axis,
            limited=mujoco.mjtLimited.mjLIMITED_FALSE,
            type=mujoco.mjtJoint.mjJNT_SLIDE if jtype == "slide" else mujoco.mjtJoint.mjJNT_HINGE,
        )
        j.damping[0] = 0.0
    r, h = ref.BASE_CAPSULE_RADIUS, ref.BASE_CAPSULE_HALF_LENGTH
    for name, a in ((BASE_CAPSULES[0], [h, 0, 0]), (BASE_CAPSULES[1], [0, h, 0])):
        base.add_geom(
            name=name,
            type=mujoco.mjtGeom.mjGEOM_CAPSULE,
            size=[r, 0, 0],
            fromto=[-a[0], -a[1], 0, a[0], a[1], 0],
            mass=ref.BASE_CAPSULE_MASS,
            rgba=[0.3, 0.3, 0.35, 1],
        )
    base.add_site(name=IMU_SITE, pos=[0, 0, 0])
    return base


def _add_leg(base, design: LegDesign, convention: str, segment_mass: str):
    """The leg body on its two hips, the stub, and the material segments.

    Each material segment: upper half in the parent, its springs, lower
    half in the child (:func:`_add_segment_springs`). Returns (the last
    segment's body, the z of its lower end in that body's frame)."""
    leg = base.add_body(name=LEG_BODY, pos=[0, 0, 0])
    hip_range = math.radians(ref.HIP_RANGE_DEG)
    for name, axis in zip(HIP_JOINTS, ([0, 1, 0], [1, 0, 0])):
        j = leg.add_joint(
            name=name,
            type=mujoco.mjtJoint.mjJNT_HINGE,
            axis=axis,
            limited=mujoco.mjtLimited.mjLIMITED_TRUE,
            range=[-hip_range, hip_range],
        )
        j.stiffness[0] = ref.HIP_STIFFNESS
        j.damping[0] = ref.HIP_DAMPING
    leg.add_site(name=HIP_SITE, pos=[0, 0, 0])
    _capsule(leg, STUB_GEOM, 0.0, -ref.STUB_LENGTH, ref.STUB_RADIUS, density=ref.STUB_DENSITY, rgba=[0.4, 0.4, 0.45, 1])
    n = design.n_segments
    scale = capsule_density_scale(n, segment_mass)  # exactly 1.0 at N = 3
    half = ref.MATERIAL_LENGTH / n / 2.0  # m, each half of a segment
    parent, top = leg, -ref.STUB_LENGTH
    for i, mat in enumerate(design.segments, start=1):
        rho = mat.density_kg_m3 * scale
        _capsule(parent, SEGMENT_UPPER.format(i=i), top, top - half, ref.MATERIAL_RADIUS, density=rho)
        child = parent.add_body(name=SEGMENT_BODY.format(i=i), pos=[0, 0, top - half])
        if not mat.rigid:
            _add_segment_springs(child, i, mat.modulus_gpa, convention, n, half)
        _capsule(child, SEGMENT_LOWER.format(i=i), 0.0, -half, ref.MATERIAL_RADIUS, density=rho)
        parent, top = child, -half
    return parent, top


def _add_segment_springs(child, i: int, modulus_gpa: float, convention: str, n: int, half: float) -> None:
    """Segment i's springs in its child body (origin at the segment's
    midpoint): the axial slide (``paper``, ``axial``, ``axial+bending``)
    and the two bending hinges about x and y (``bending``,
    ``axial+bending``), each at the PRBM pivot (1 - gamma) l below the
    segment's top (:func:`mat_hopper.core.materials.prbm_constants`)."""
    if convention in AXIAL_CONVENTIONS:
        _slide(child, AXIAL_SPRING.format(i=i), spring_stiffness(modulus_gpa, convention, n), ref.JOINT_DAMPING_DEFAULT)
    if convention in BENDING_CONVENTIONS:
        gamma, _ = prbm_constants(n)
        pivot_z = half - (1.0 - gamma) * 2.0 * half  # 0 at the midpoint (gamma = 1/2)
        k = bending_stiffness(modulus_gpa, n)
        for name, axis in zip(BEND_SPRINGS, ([1, 0, 0], [0, 1, 0])):
            j = child.add_joint(name=name.format(i=i), type=mujoco.mjtJoint.mjJNT_HINGE, axis=axis, pos=[0, 0, pivot_z])
            j.stiffness[0] = k
            j.damping[0] = ref.JOINT_DAMPING_DEFAULT
            j.limited = mujoco.mjtLimited.mjLIMITED_FALSE


def _add_foot(parent, top: float) -> None:
    """The foot's upper capsule under the last segment, the foot body on
    its spring, the foot capsule (the only colliding leg geom) and the toe."""
    _capsule(
        parent,
        FOOT_UPPER_GEOM,
        top,
        top - ref.FOOT_UPPER_LENGTH,
        ref.MATERIAL_RADIUS,
        density=ref.FOOT_UPPER_DENSITY,
        rgba=[0.4, 0.4, 0.45, 1],
    )
    foot = parent.add_body(name=FOOT_BODY, pos=[0, 0, top - ref.FOOT_UPPER_LENGTH])
    _slide(foot, FOOT_SPRING, ref.FOOT_SPRING_STIFFNESS, ref.FOOT_SPRING_DAMPING, limit=ref.FOOT_SPRING_RANGE)
    g = _capsule(
        foot, FOOT_GEOM, 0.0, -ref.FOOT_LENGTH, ref.FOOT_RADIUS, mass=ref.FOOT_MASS, rgba=[0.15, 0.15, 0.15, 1]
    )
    g.contype, g.conaffinity, g.condim = 1, 1, ref.FOOT_CONDIM
    foot.add_site(name=TOE_SITE, pos=[0, 0, -ref.FOOT_LENGTH], size=[ref.TOE_SITE_RADIUS, 0, 0])


def _add_actuators(spec: mujoco.MjSpec) -> None:
    for name, joint, gear in zip(ACTUATORS, (*HIP_JOINTS, FOOT_SPRING), (ref.HIP_GEAR, ref.HIP_GEAR, 1.0)):
        a = spec.add_actuator(name=name, target=joint, trntype=mujoco.mjtTrn.mjTRN_JOINT)
        a.set_to_motor()
        a.gear[0] = gear
        a.ctrllimited = mujoco.mjtLimited.mjLIMITED_FALSE


def _start_qpos(design: LegDesign, convention: str) -> np.ndarray:
    """Start pose: every joint at 0 except the base's z slide at
    BASE_START_Z. qpos: 6 base joints, 2 hips, per sprung segment its slide
    and/or two hinges, the foot spring."""
    per_segment = (convention in AXIAL_CONVENTIONS) + 2 * (convention in BENDING_CONVENTIONS)
    nq = len(BASE_JOINTS) + len(HIP_JOINTS) + per_segment * sum(not m.rigid for m in design.segments) + 1
    start = np.zeros(nq)
    start[BASE_JOINTS.index("base_z")] = ref.BASE_START_Z
    return start


def _add_sensors(spec: mujoco.MjSpec, sensors: str) -> None:
    S, OBJ = mujoco.mjtSensor, mujoco.mjtObj
    spec.add_sensor(name="touch", type=S.mjSENS_TOUCH, objtype=OBJ.mjOBJ_SITE, objname=TOE_SITE)
    spec.add_sensor(name="base_pos", type=S.mjSENS_FRAMEPOS, objtype=OBJ.mjOBJ_XBODY, objname=BASE_BODY)
    spec.add_sensor(name="base_quat", type=S.mjSENS_FRAMEQUAT, objtype=OBJ.mjOBJ_XBODY, objname=BASE_BODY)
    spec.add_sensor(name="base_gyro", type=S.mjSENS_GYRO, objtype=OBJ.mjOBJ_SITE, objname=IMU_SITE)
    spec.add_sensor(name="base_linvel", type=S.mjSENS_FRAMELINVEL, objtype=OBJ.mjOBJ_XBODY, objname=BASE_BODY)
    if sensors == "all":
        spec.add_sensor(name="hip_torque", type=S.mjSENS_TORQUE, objtype=OBJ.mjOBJ_SITE, objname=HIP_SITE)
        spec.add_sensor(name="base_acc", type=S.mjSENS_ACCELEROMETER, objtype=OBJ.mjOBJ_SITE, objname=IMU_SITE)
