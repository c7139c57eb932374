"""Leg design -> MuJoCo model of the reference hopper, built in memory.

Geometry follows ``reference.py`` (the authors' hopper): a 15 kg base on six
unactuated joints, a two-axis hip, a stub, N material segments and a sprung
foot. Each material segment straddles its axial spring ``mat_spring_i``:
half of its mass above the spring, half below. Density sets the capsules'
mass (porosity through mass); modulus sets the spring's stiffness. A rigid
material has no spring at all (the paper's MD leg).

Nothing is written to disk: :func:`build_spec` returns an ``MjSpec`` (to
edit further, e.g. for rendering) and :func:`build_model` compiles it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import NamedTuple

import mujoco
import numpy as np

from ..util.parsing import parse_name
from . import reference as ref
from .damping import DEFAULT_DAMPING, check_damping, loss_factor, spring_damping
from .materials import (
    AXIAL_CONVENTIONS,
    BENDING_CONVENTIONS,
    DEFAULT_CONVENTION,
    DEFAULT_SEGMENT_MASS,
    LegDesign,
    bending_stiffness,
    capsule_density_scale,
    check_convention,
    check_segment_mass,
    prbm_constants,
    second_moment_m4,
    spring_stiffness,
)

BASE_JOINTS = ("base_x", "base_y", "base_z", "base_roll", "base_pitch", "base_yaw")
HIP_JOINTS = ("hip_y", "hip_x")
ACTUATORS = ("hip_y", "hip_x", "thrust")
SENSORS = ("touch", "base_pos", "base_quat", "base_gyro", "base_linvel", "hip_torque", "base_acc")
# What the controller reads. The hip torque and accelerometer sensors make
# MuJoCo run its post-constraint dynamics pass (mj_rnePostConstraint) every
# step (a few percent of a step) and feed nothing back: rollouts leave them out
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


class Layout(NamedTuple):
    """Addresses into qpos/qvel/sensordata/ctrl, looked up by name (ints)."""

    base_qpos: int  # first of the 6 base joints in qpos (x, y, z, roll, pitch, yaw)
    base_dof: int  # same in qvel / qacc
    base_body: int  # body id of the base (for pushes)
    hip_y_qpos: int
    hip_x_qpos: int
    hip_y_dof: int
    hip_x_dof: int
    spring_qpos: int  # the foot spring (the thrust actuator's joint)
    spring_dof: int
    touch: int  # sensordata addresses
    base_pos: int
    base_quat: int
    base_gyro: int
    base_linvel: int
    act_hip_y: int  # actuator indices
    act_hip_x: int
    act_thrust: int


@dataclass(frozen=True, eq=False)
class HopperModel:
    """A compiled hopper: the MjModel plus what built it."""

    model: mujoco.MjModel
    design: LegDesign
    convention: str
    ramp_grade_deg: float | None
    timestep_s: float
    sensors: str  # "all" (the spec's seven) or "control" (the five the controller reads)
    layout: Layout
    spring_stiffness_n_m: tuple[float, ...]  # per segment; 0 for rigid
    segment_mass: str = DEFAULT_SEGMENT_MASS  # "leg" (mass independent of N) or "capsule" (the authors')
    bending_stiffness_n_m_rad: tuple[float, ...] = ()  # per segment, each of its two hinges; 0 if none
    damping: str = DEFAULT_DAMPING  # "authors" or "loss-factor"

    @property
    def total_mass_kg(self) -> float:
        return float(self.model.body_subtreemass[0])


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


# deg, exclusive: a grade of +-90 deg is a wall (tan is infinite), beyond it
# the ramp is upside down. The paper's ramp is 2 deg; the Behaviour class
# itself accepts [0, 30) deg (a ramp the hopper can climb).
MAX_RAMP_GRADE_DEG = 90.0


def check_ramp_grade(ramp_grade_deg) -> float | None:
    """The ramp's pitch as a float strictly inside (-90, 90) deg, or None
    (flat ground); ValueError naming it otherwise.

    Args:
        ramp_grade_deg: None for flat ground, else the pitch, deg: an int or
            a float.

    Returns:
        None, or the pitch as a float, deg.

    Raises:
        ValueError: a bool, a string or other non-number, nan, inf, or a
            pitch not strictly between -90 and 90 deg (a vertical or
            overhanging ramp).
    """
    if ramp_grade_deg is None:
        return None
    ok = not isinstance(ramp_grade_deg, bool) and isinstance(ramp_grade_deg, (int, float, np.integer, np.floating))
    a = float(ramp_grade_deg) if ok else math.nan
    if not (math.isfinite(a) and -MAX_RAMP_GRADE_DEG < a < MAX_RAMP_GRADE_DEG):
        raise ValueError(
            f"ramp_grade_deg must be None (flat) or a finite number strictly between -{MAX_RAMP_GRADE_DEG:g} and "
            f"{MAX_RAMP_GRADE_DEG:g} deg, got {ramp_grade_deg!r}"
        )
    return a


def ramp_pose(grade_deg: float) -> tuple[np.ndarray, np.ndarray]:
    """Centre (m) and quaternion (w, x, y, z) of the ramp box pitched up by
    grade_deg (deg).

    The centre is the authors' exact (RAMP_CENTER_X, 0, RAMP_CENTER_Z):
    -0.03 m is not a rounding of the height at which the top face would
    meet the ground at x = 0 (-0.0302 m at 2 deg); it leaves a step of about
    0.2 mm there, and ramp results move by 5-15 % if it is "corrected"
    (docs/reference-hopper.md).

    Args:
        grade_deg: the ramp's pitch, deg (the paper's 2), strictly between
            -90 and 90 (:func:`check_ramp_grade`).

    Returns:
        (centre, quat): the box's centre, (3,) array in m, always
        (RAMP_CENTER_X, 0, RAMP_CENTER_Z) = (2, 0, -0.03) m; and its
        orientation, (4,) unit quaternion (w, x, y, z), a rotation by
        -grade about the y axis.

    Raises:
        ValueError: a pitch :func:`check_ramp_grade` refuses (None included:
            a flat ground has no ramp box).
    """
    if grade_deg is None:
        raise ValueError("grade_deg: a ramp needs a pitch in deg (None is flat ground, which has no ramp)")
    a = math.radians(check_ramp_grade(grade_deg))
    quat = np.array([math.cos(-a / 2), 0.0, math.sin(-a / 2), 0.0])
    return np.array([ref.RAMP_CENTER_X, 0.0, ref.RAMP_CENTER_Z]), quat


def terrain_height_m(x_m, y_m, ramp_grade_deg: float | None = None):
    """Height (m) of the terrain under world points (x, y): 0 on the flat
    ground; on the ramp behaviour the higher of the ground and the ramp
    box's top face, z = cz + hz / cos(a) + tan(a) (x - cx) over the box's
    footprint (a the grade angle; the box's far end and sides are not
    modelled: the hopper never reaches them). Arrays broadcast.
    tests/core/test_model.py checks it against MuJoCo's own ray casts.

    Args:
        x_m: world x of the points, m (scalar or array).
        y_m: world y of the points, m (broadcast against `x_m`).
        ramp_grade_deg: None for flat ground (default), else the ramp's
            pitch, deg (as :class:`mat_hopper.core.behaviours.Behaviour` holds
            it), strictly between -90 and 90.

    Returns:
        Float array of the broadcast shape of `x_m` and `y_m` (0-d for
        scalars), m: 0 on flat ground or off the ramp's footprint.

    Raises:
        ValueError: a pitch :func:`check_ramp_grade` refuses.
    """
    ramp_grade_deg = check_ramp_grade(ramp_grade_deg)
    x, y = np.asarray(x_m, dtype=float), np.asarray(y_m, dtype=float)
    ground = np.zeros(np.broadcast(x, y).shape)
    if ramp_grade_deg is None:
        return ground
    a = math.radians(ramp_grade_deg)
    (cx, _, cz), _ = ramp_pose(ramp_grade_deg)
    hx, hy, hz = ref.RAMP_HALF_SIZE
    u = (x - cx + hz * math.sin(a)) / math.cos(a)  # along the top face, from its centre
    top = cz + hz / math.cos(a) + math.tan(a) * (x - cx)
    on = (np.abs(u) <= hx) & (np.abs(y) <= hy)
    return np.where(on, np.maximum(ground, top), ground)


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
) -> mujoco.MjSpec:
    """The hopper with this leg as an editable ``MjSpec`` (not compiled).

    Built in named steps, each adding one part under the names of the
    constants block above: options, terrain, base, leg (hips, stub, material
    segments), foot, actuators, start keyframe, sensors.

    sensors: "all" (the spec's seven, in its order) or "control" (the first
    five, which the controller reads; what rollouts use, see CONTROL_SENSORS);
    segment_mass: "leg" (each segment 1/N of the 3-segment leg's material
    mass; identical to the authors' model at N = 3) or "capsule" (the
    authors' per-capsule density at any N), see :mod:`mat_hopper.core.materials`.

    Args:
        design: the :class:`~mat_hopper.core.materials.LegDesign`.
        ramp_grade_deg: None for flat ground (default), else the ramp box's
            pitch, deg (:func:`ramp_pose`), finite and strictly between -90
            and 90 (:func:`check_ramp_grade`).
        timestep_s: the physics step, s, in (0, 0.1] (default 1e-4, the
            paper's).
        convention: the stiffness convention (``paper``, ``axial``,
            ``bending``, ``axial+bending``; any case; default ``paper``).
        sensors: ``"all"`` (default) or ``"control"``, any case
            (:func:`check_sensors`).
        segment_mass: ``"leg"`` (default) or ``"capsule"``, any case.

    Returns:
        The uncompiled ``mujoco.MjSpec``, named ``hopper_<design name>``,
        with the ``start`` keyframe.

    Raises:
        ValueError: a design that is not a LegDesign, an unknown sensor
            set, convention or segment-mass convention, a time step not
            in (0, 0.1] s (:func:`check_timestep`), or a ramp pitch not
            finite and strictly between -90 and 90 deg
            (:func:`check_ramp_grade`).
    """
    if not isinstance(design, LegDesign):
        raise ValueError(f"design must be a LegDesign, got {type(design).__name__}")
    sensors = check_sensors(sensors)
    convention = check_convention(convention)
    segment_mass = check_segment_mass(segment_mass)
    dt = check_timestep(timestep_s)
    ramp_grade_deg = check_ramp_grade(ramp_grade_deg)
    spec = mujoco.MjSpec()
    spec.modelname = f"hopper_{design.name}"
    _set_options(spec, dt)
    _add_terrain(spec.worldbody, ramp_grade_deg)
    base = _add_base(spec.worldbody)
    last = _add_leg(base, design, convention, segment_mass)
    _add_foot(*last)
    _add_actuators(spec)
    spec.add_key(name=START_KEY, qpos=_start_qpos(design, convention))
    _add_sensors(spec, sensors)
    return spec


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


def layout_of(model: mujoco.MjModel) -> Layout:
    """Look every address the controller needs up by name.

    Args:
        model: a compiled hopper ``MjModel`` (:func:`build_model`; either
            sensor set has the five sensors read here).

    Returns:
        The :class:`Layout`: qpos and dof addresses of the base (its first
        joint, ``base_x``), hips and foot spring, the base body's id, the
        sensordata addresses of the five controller sensors and the three
        actuator indices.

    Raises:
        KeyError: a model lacking one of the names (MuJoCo's named access).
    """
    jq = lambda n: int(model.joint(n).qposadr[0])
    jd = lambda n: int(model.joint(n).dofadr[0])
    sa = lambda n: int(model.sensor(n).adr[0])
    act = lambda n: int(model.actuator(n).id)
    return Layout(
        jq("base_x"),
        jd("base_x"),
        int(model.body("base").id),
        jq("hip_y"),
        jq("hip_x"),
        jd("hip_y"),
        jd("hip_x"),
        jq("spring"),
        jd("spring"),
        sa("touch"),
        sa("base_pos"),
        sa("base_quat"),
        sa("base_gyro"),
        sa("base_linvel"),
        act("hip_y"),
        act("hip_x"),
        act("thrust"),
    )


def reset_to_start(model: mujoco.MjModel, data: mujoco.MjData) -> None:
    """Reset data to the keyframe ``start`` (base z slide at 1.2 m, all else
    0) and compute the derived quantities (mj_forward).

    Args:
        model: the compiled hopper ``MjModel`` (with the ``start`` keyframe).
        data: its ``MjData``, overwritten in place.

    Raises:
        KeyError: a model without the ``start`` keyframe.
    """
    mujoco.mj_resetDataKeyframe(model, data, model.key(START_KEY).id)
    mujoco.mj_forward(model, data)


def build_model(
    design: LegDesign,
    *,
    ramp_grade_deg: float | None = None,
    timestep_s: float = ref.TIMESTEP_S,
    convention: str = DEFAULT_CONVENTION,
    sensors: str = "all",
    segment_mass: str = DEFAULT_SEGMENT_MASS,
    damping: str = DEFAULT_DAMPING,
) -> HopperModel:
    """Compile the hopper for this leg, terrain (flat or ramp), time step (s),
    stiffness convention, sensor set and segment-mass convention (see
    :func:`build_spec`), and damping (``authors``: every joint 1 N s/m or
    N m s/rad, as the spec; ``loss-factor``: each material spring's damping
    set on the compiled model from its material's loss factor,
    :func:`mat_hopper.core.damping.spring_damping` with MuJoCo's dof_M0 as the
    inertia). Raises ValueError for invalid arguments.

    Args:
        design: the :class:`~mat_hopper.core.materials.LegDesign`.
        ramp_grade_deg: None for flat ground (default), else the ramp's
            pitch, deg, finite and strictly between -90 and 90
            (:func:`check_ramp_grade`).
        timestep_s: the physics step, s, in (0, 0.1] (default 1e-4).
        convention: the stiffness convention, any case (default ``paper``).
        sensors: ``"all"`` (default) or ``"control"``, any case.
        segment_mass: ``"leg"`` (default) or ``"capsule"``, any case.
        damping: ``"authors"`` (default) or ``"loss-factor"``, any case
            (:func:`mat_hopper.core.damping.check_damping`).

    Returns:
        The :class:`HopperModel`: the compiled ``MjModel``, the arguments
        (the names ``convention``, ``sensors``, ``segment_mass`` and
        ``damping`` in their canonical spelling, e.g. ``"Bending"`` as
        ``"bending"``), its :class:`Layout`,
        and per segment the axial spring stiffness (N/m) and each bending
        hinge's stiffness (N m/rad), 0.0 for a rigid segment or where the
        convention has no such spring.

    Raises:
        ValueError: an unknown damping, or any argument :func:`build_spec`
            refuses (a time step not in (0, 0.1] s, a ramp pitch not
            strictly between -90 and 90 deg, ...).
    """
    damping = check_damping(damping)
    ramp_grade_deg = check_ramp_grade(ramp_grade_deg)
    convention = check_convention(convention)
    segment_mass = check_segment_mass(segment_mass)
    sensors = check_sensors(sensors)
    spec = build_spec(
        design,
        ramp_grade_deg=ramp_grade_deg,
        timestep_s=timestep_s,
        convention=convention,
        sensors=sensors,
        segment_mass=segment_mass,
    )
    model = spec.compile()
    n = design.n_segments
    stiffness = tuple(0.0 if m.rigid else spring_stiffness(m.modulus_gpa, convention, n) for m in design.segments)
    bending = tuple(
        0.0 if m.rigid or convention not in BENDING_CONVENTIONS else bending_stiffness(m.modulus_gpa, n)
        for m in design.segments
    )
    if damping == "loss-factor":
        _set_loss_factor_damping(model, design)
    return HopperModel(
        model,
        design,
        convention,
        ramp_grade_deg,
        float(timestep_s),
        sensors,
        layout_of(model),
        stiffness,
        segment_mass,
        bending,
        damping,
    )


def material_joints(model: mujoco.MjModel, design: LegDesign) -> list[tuple[int, str]]:
    """(segment index from 0, joint name) of every material spring in the
    compiled model: the axial slide and the two bending hinges, where the
    convention gives them.

    Args:
        model: the compiled hopper ``MjModel``.
        design: the design it was built from (only its segment count is
            read).

    Returns:
        A list of (segment index from 0, joint name) pairs, segment by
        segment and, within one, ``mat_spring_i``, ``mat_bend_x_i``,
        ``mat_bend_y_i`` as present; empty for a rigid leg.
    """
    out = []
    for i in range(1, design.n_segments + 1):
        for name in (AXIAL_SPRING, *BEND_SPRINGS):
            jname = name.format(i=i)
            if mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, jname) >= 0:
                out.append((i - 1, jname))
    return out


def _set_loss_factor_damping(model: mujoco.MjModel, design: LegDesign) -> None:
    for seg, jname in material_joints(model, design):
        j = model.joint(jname)
        dof = int(j.dofadr[0])
        eta = loss_factor(design.segments[seg])
        model.dof_damping[dof] = spring_damping(eta, float(j.stiffness[0]), float(model.dof_M0[dof]))


def stress_gains(hm: HopperModel) -> tuple[np.ndarray, np.ndarray]:
    """(adr, gain) of the loop's stress probe (issue 21), both (N, 3): per
    segment the qpos address of its axial slide and of its hinges about x
    and y (-1 where there is none), and the Pa per unit of joint position
    that turns each into a section stress. The spring's force or moment is
    stiffness x position (MuJoCo's qfrc_spring = -k q, the section carries
    +k q): axial sigma = k q / A with A = pi r^2 (tension > 0 when the slide
    along -z extends); bending sigma = k_b theta c / I at the extreme fibre
    c = r, I = pi r^4 / 4.

    Args:
        hm: the compiled :class:`HopperModel` (the stiffnesses are read from
            its model's ``jnt_stiffness``).

    Returns:
        (adr, gain), both (N, 3) with columns axial slide, hinge about x,
        hinge about y: adr an int64 array of qpos addresses (-1 where the
        segment has no such spring); gain a float array, Pa/m for the slide
        column and Pa/rad for the hinge columns (0.0 where there is none).
    """
    m, n = hm.model, hm.design.n_segments
    r = ref.MATERIAL_RADIUS
    area, inertia = math.pi * r**2, second_moment_m4(r)
    adr = np.full((n, 3), -1, dtype=np.int64)
    gain = np.zeros((n, 3))
    for i in range(1, n + 1):
        for col, name in enumerate((AXIAL_SPRING, *BEND_SPRINGS)):
            jid = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_JOINT, name.format(i=i))
            if jid < 0:
                continue
            k = float(m.jnt_stiffness[jid])
            adr[i - 1, col] = int(m.jnt_qposadr[jid])
            gain[i - 1, col] = k / area if col == 0 else k * r / inertia
    return adr, gain
