"""Leg design -> compiled MuJoCo model of the reference hopper, built in
memory, and the addresses the controller reads.

:func:`build_model` compiles the spec of :func:`mat_hopper.core.mjcf.build_spec`
(the geometry, the names of the model's parts and the sensor sets live
there; the terrain in :mod:`mat_hopper.core.terrain`, both re-exported here)
and returns a :class:`HopperModel`: the ``MjModel``, what built it, its
:class:`Layout` of addresses and the springs' stiffnesses. Under the
``loss-factor`` damping each material spring's damping is set on the
compiled model from its material's loss factor
(:mod:`mat_hopper.core.damping`). :func:`stress_gains` turns the material
springs' joint positions into section stress (Pa). :func:`prepare` gives a
rollout's model and its data at the start pose.

Nothing is written to disk: :func:`build_spec` returns an ``MjSpec`` (to
edit further, e.g. for rendering) and :func:`build_model` compiles it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import NamedTuple

import mujoco
import numpy as np

from . import reference as ref
from .behaviours import behaviour as behaviour_of
from .contact import DEFAULT_CONTACT, check_contact
from .conventions import (
    BENDING_CONVENTIONS,
    DEFAULT_CONVENTION,
    DEFAULT_SEGMENT_MASS,
    bending_stiffness,
    check_convention,
    check_segment_mass,
    second_moment_m4,
    spring_stiffness,
)
from .damping import DEFAULT_DAMPING, check_damping, loss_factor, spring_damping
from .materials import LegDesign, as_design
from .mjcf import (
    ACTUATORS,
    AXIAL_SPRING,
    BASE_BODY,
    BASE_CAPSULES,
    BASE_JOINTS,
    BEND_SPRINGS,
    CONTROL_SENSORS,
    FOOT_BODY,
    FOOT_GEOM,
    FOOT_SPRING,
    FOOT_UPPER_GEOM,
    GROUND_GEOM,
    HIP_JOINTS,
    HIP_SITE,
    IMU_SITE,
    LEG_BODY,
    LIGHT,
    MAX_TIMESTEP_S,
    MIN_TIMESTEP_S,
    RAMP_GEOM,
    SEGMENT_BODY,
    SEGMENT_LOWER,
    SEGMENT_UPPER,
    SENSOR_SETS,
    SENSORS,
    START_KEY,
    STUB_GEOM,
    TOE_SITE,
    build_spec,
    check_sensors,
    check_timestep,
)
from .terrain import MAX_RAMP_GRADE_DEG, check_ramp_grade, ramp_pose, terrain_height_m

__all__ = [
    # defined here
    "HopperModel",
    "Layout",
    "build_model",
    "layout_of",
    "material_joints",
    "prepare",
    "reset_to_start",
    "stress_gains",
    # re-exported: mat_hopper.core.mjcf
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
    # re-exported: mat_hopper.core.terrain
    "MAX_RAMP_GRADE_DEG",
    "check_ramp_grade",
    "ramp_pose",
    "terrain_height_m",
]


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
    contact: str = DEFAULT_CONTACT  # "authors" (MuJoCo's default solref) or "stiff" (mat_hopper.core.contact)

    @property
    def total_mass_kg(self) -> float:
        return float(self.model.body_subtreemass[0])


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
    contact: str = DEFAULT_CONTACT,
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
        contact: ``"authors"`` (default) or ``"stiff"``, any case: the
            solref of every geom that can touch (:mod:`mat_hopper.core.contact`).

    Returns:
        The :class:`HopperModel`: the compiled ``MjModel``, the arguments
        (the names ``convention``, ``sensors``, ``segment_mass``,
        ``damping`` and ``contact`` in their canonical spelling, e.g. ``"Bending"`` as
        ``"bending"``), its :class:`Layout`,
        and per segment the axial spring stiffness (N/m) and each bending
        hinge's stiffness (N m/rad), 0.0 for a rigid segment or where the
        convention has no such spring.

    Raises:
        ValueError: an unknown damping or contact, or any argument :func:`build_spec`
            refuses (a time step not in (0, 0.1] s, a ramp pitch not
            strictly between -90 and 90 deg, ...).
    """
    damping = check_damping(damping)
    contact = check_contact(contact)
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
        contact=contact,
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
        contact,
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
    """(adr, gain) of the loop's stress probe, both (N, 3): per
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


def prepare(
    design, behaviour, settings, start_xy_offset=(0.0, 0.0), start_tilt=(0.0, 0.0)
) -> tuple[HopperModel, mujoco.MjData]:
    """Model and initial data for a rollout: start pose per the behaviour,
    plus an optional offset (m) and roll/pitch tilt (rad).

    Args:
        design: a :class:`~mat_hopper.core.materials.LegDesign` or a design name
            (:func:`mat_hopper.core.materials.parse_design`).
        behaviour: a behaviour name or :class:`~mat_hopper.core.behaviours.Behaviour`;
            its ramp grade shapes the terrain and its start_xy_m the start.
        settings: the :class:`~mat_hopper.core.sim.SimSettings`; its timestep_s, convention,
            segment_mass and damping build the model.
        start_xy_offset: (dx, dy), m, added to the behaviour's start position.
        start_tilt: (roll, pitch) of the base at the start, rad.

    Returns:
        (hopper, data): the compiled :class:`~mat_hopper.core.model.HopperModel`
        (control sensors) and its ``mujoco.MjData`` at the start keyframe
        (base z 1.2 m) with the position and tilt set, after ``mj_forward``.

    Raises:
        ValueError: a design that is neither a LegDesign nor a known name, an
            unknown behaviour, or a setting the model builder rejects.
    """
    design = as_design(design)
    beh = behaviour_of(behaviour)
    hm = build_model(
        design,
        ramp_grade_deg=beh.ramp_grade_deg,
        timestep_s=settings.timestep_s,
        convention=settings.convention,
        sensors="control",
        segment_mass=settings.segment_mass,
        damping=settings.damping,
        contact=settings.contact,
    )
    data = mujoco.MjData(hm.model)
    reset_to_start(hm.model, data)  # base z slide at 1.2 m, all else 0
    b = hm.layout.base_qpos  # base joints: x, y, z, roll, pitch, yaw
    data.qpos[b + 0] = beh.start_xy_m[0] + start_xy_offset[0]
    data.qpos[b + 1] = beh.start_xy_m[1] + start_xy_offset[1]
    data.qpos[b + 3] = start_tilt[0]
    data.qpos[b + 4] = start_tilt[1]
    mujoco.mj_forward(hm.model, data)
    return hm, data
