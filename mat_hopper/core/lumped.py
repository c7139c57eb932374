"""The hopper's rigid bodies at its start pose, from the design alone.

What the analytic stable time step needs of the model (the bodies' masses,
centres of mass and inertias, the joints and their stiffnesses, MuJoCo's
joint-space inertia M), computed from the leg design and the reference
geometry of :mod:`mat_hopper.core.reference` as :func:`mat_hopper.core.mjcf.build_spec`
lays it out, without compiling a MuJoCo model. Resolving
``timestep_s="auto"`` (:mod:`mat_hopper.core.timestep`) builds settings,
and building settings must not compile a model; the tests check every
quantity here against the compiled model's (``body_mass``,
``body_inertia``, ``jnt_stiffness``, ``mj_fullM``) to round-off.

The start pose is straight: every body's centre of mass lies on the leg's
axis (z), every capsule lies along a coordinate axis, so every inertia
tensor is diagonal in the world axes. Capsule masses and inertias follow
MuJoCo's own formulas for a capsule of uniform density (cylinder plus two
hemispherical caps; ``fromto`` capsules, MuJoCo's ``inertiafromgeom``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from . import reference as ref
from .conventions import (
    AXIAL_CONVENTIONS,
    BENDING_CONVENTIONS,
    DEFAULT_CONVENTION,
    DEFAULT_SEGMENT_MASS,
    bending_stiffness,
    capsule_density_scale,
    check_convention,
    check_segment_mass,
    prbm_constants,
    spring_stiffness,
)
from .materials import LegDesign
from .mjcf import (
    AXIAL_SPRING,
    BASE_BODY,
    BASE_JOINTS,
    BEND_SPRINGS,
    FOOT_BODY,
    FOOT_SPRING,
    HIP_JOINTS,
    LEG_BODY,
    SEGMENT_BODY,
)

__all__ = ["Body", "Dof", "LumpedHopper", "capsule_inertia"]

_AXES = {"x": (1.0, 0.0, 0.0), "y": (0.0, 1.0, 0.0), "z": (0.0, 0.0, 1.0)}


def capsule_inertia(mass_kg: float, radius_m: float, half_length_m: float) -> tuple[float, float]:
    """(transverse, axial) moments of inertia (kg m^2) of a uniform capsule
    about its centre: a cylinder of length 2 h plus two hemispherical caps
    (MuJoCo's formula for a capsule geom).

    Args:
        mass_kg: the capsule's mass, kg.
        radius_m: its radius r, m.
        half_length_m: half the length h of its cylindrical part, m.

    Returns:
        (I_transverse, I_axial), kg m^2: about an axis through the centre
        across the capsule, and about its own axis.
    """
    r, height = radius_m, 2.0 * half_length_m
    volume = math.pi * (r * r * height + 4.0 * r * r * r / 3.0)
    sphere = mass_kg * (4.0 * math.pi * r * r * r / 3.0) / volume
    cylinder = mass_kg - sphere
    caps = 2.0 * sphere * r * r / 5.0
    transverse = (
        cylinder * (3.0 * r * r + height * height) / 12.0 + caps + sphere * height * (3.0 * r + 2.0 * height) / 8.0
    )
    axial = cylinder * r * r / 2.0 + caps
    return transverse, axial


@dataclass(frozen=True)
class Body:
    """One rigid body at the start pose: mass (kg), centre of mass on the
    leg's axis (z, m, in the base's frame) and the diagonal of its inertia
    tensor about that centre in the world axes (kg m^2)."""

    name: str
    mass_kg: float
    com_z_m: float
    inertia_kg_m2: tuple[float, float, float]


@dataclass(frozen=True)
class Dof:
    """One joint degree of freedom: a ``slide`` along or a ``hinge`` about
    ``axis`` (world axes at the start pose) through the point ``anchor_z_m``
    on the leg's axis; it moves body ``body`` (an index into
    :attr:`LumpedHopper.bodies`) and every body below; ``stiffness``: N/m
    or N m/rad (0: none)."""

    name: str
    kind: str
    axis: tuple[float, float, float]
    anchor_z_m: float
    body: int
    stiffness: float


def _capsule_body(name: str, frame_z: float, capsules) -> Body:
    """A body from its capsules (axis, z0, z1 in the body's frame, radius,
    density or None, mass or None): masses rho V (or as given), the centre
    of mass, and the inertia about it by the parallel-axis theorem."""
    parts = []
    for axis, z0, z1, radius, density, mass, half in capsules:
        h = abs(z1 - z0) / 2.0 if half is None else half
        volume = math.pi * (radius * radius * (2.0 * h) + 4.0 * radius * radius * radius / 3.0)
        m = density * volume if mass is None else mass
        parts.append((axis, (z0 + z1) / 2.0, m, *capsule_inertia(m, radius, h)))
    total = sum(p[2] for p in parts)
    com = sum(p[2] * p[1] for p in parts) / total
    inertia = np.zeros(3)
    for axis, z, m, transverse, axial in parts:
        own = np.full(3, transverse)
        own["xyz".index(axis)] = axial
        inertia += own + m * (z - com) ** 2 * np.array([1.0, 1.0, 0.0])
    return Body(name, total, frame_z + com, tuple(float(v) for v in inertia))


@dataclass(frozen=True)
class LumpedHopper:
    """The hopper of one design under one stiffness and segment-mass
    convention, as rigid bodies and joints at its start pose (module doc).

    Args:
        design: the :class:`~mat_hopper.core.materials.LegDesign`.
        convention: the stiffness convention, any case (stored as spelled
            in :data:`mat_hopper.core.materials.CONVENTIONS`).
        segment_mass: ``"leg"`` (default) or ``"capsule"``, any case.

    Raises:
        ValueError: a design that is not a LegDesign, or an unknown
            convention or segment-mass convention.
    """

    design: LegDesign
    convention: str = DEFAULT_CONVENTION
    segment_mass: str = DEFAULT_SEGMENT_MASS
    bodies: tuple[Body, ...] = field(init=False, repr=False, compare=False)
    dofs: tuple[Dof, ...] = field(init=False, repr=False, compare=False)

    def __post_init__(self):
        if not isinstance(self.design, LegDesign):
            raise ValueError(f"design must be a LegDesign, got {type(self.design).__name__}")
        object.__setattr__(self, "convention", check_convention(self.convention))
        object.__setattr__(self, "segment_mass", check_segment_mass(self.segment_mass))
        bodies, dofs = _layout(self.design, self.convention, self.segment_mass)
        object.__setattr__(self, "bodies", tuple(bodies))
        object.__setattr__(self, "dofs", tuple(dofs))

    def body(self, name: str) -> Body:
        """The body named as in the model (``base``, ``leg``, ``seg1``, ..., ``foot``)."""
        for b in self.bodies:
            if b.name == name:
                return b
        raise ValueError(f"no body {name!r}; the bodies: {', '.join(b.name for b in self.bodies)}")

    def dof(self, name: str) -> int:
        """The index (in MuJoCo's dof order) of the joint named as in the model."""
        for i, d in enumerate(self.dofs):
            if d.name == name:
                return i
        raise ValueError(f"no joint {name!r}; the joints: {', '.join(d.name for d in self.dofs)}")

    def axial_chain(self) -> tuple[list[float], list[float]]:
        """(masses kg, stiffnesses N/m) of the leg's axial spring chain: base
        and leg body, each elastic segment's body (a rigid segment's body
        added to the node above), the foot; between them each elastic
        segment's slide, the foot spring last. Under a convention without
        slides (``bending``) a ValueError."""
        if self.convention not in AXIAL_CONVENTIONS:
            raise ValueError(
                f"convention {self.convention!r} has rotational springs: the axial chain does not describe it "
                "(see model_frequencies)"
            )
        mass = {b.name: b.mass_kg for b in self.bodies}
        masses = [mass[BASE_BODY] + mass[LEG_BODY]]
        springs = []
        for i, seg in enumerate(self.design.segments, start=1):
            name = SEGMENT_BODY.format(i=i)
            if seg.rigid:
                masses[-1] += mass[name]
            else:
                springs.append(self.dofs[self.dof(AXIAL_SPRING.format(i=i))].stiffness)
                masses.append(mass[name])
        springs.append(ref.FOOT_SPRING_STIFFNESS)
        masses.append(mass[FOOT_BODY])
        return masses, springs

    def mass_matrix(self) -> np.ndarray:
        """(nv, nv) joint-space inertia M at the start pose, kg or kg m^2
        (MuJoCo's ``mj_fullM``; no armature): the sum over every body both
        joints move of m v_i . v_j + w_i . I w_j, with v, w each joint's
        unit velocity of the body's centre of mass and its angular velocity."""
        n = len(self.dofs)
        lin = np.zeros((n, len(self.bodies), 3))
        ang = np.zeros((n, 3))
        for i, d in enumerate(self.dofs):
            axis = np.array(d.axis)
            for b in range(d.body, len(self.bodies)):
                if d.kind == "slide":
                    lin[i, b] = axis
                else:
                    lin[i, b] = np.cross(axis, [0.0, 0.0, self.bodies[b].com_z_m - d.anchor_z_m])
            if d.kind == "hinge":
                ang[i] = axis
        M = np.zeros((n, n))
        for b, body in enumerate(self.bodies):
            moved = [i for i, d in enumerate(self.dofs) if d.body <= b]
            v, w = lin[moved, b], ang[moved]
            M[np.ix_(moved, moved)] += body.mass_kg * v @ v.T + w @ np.diag(body.inertia_kg_m2) @ w.T
        return M

    def stiffness(self) -> np.ndarray:
        """(nv,) joint stiffnesses in MuJoCo's dof order (N/m or N m/rad)."""
        return np.array([d.stiffness for d in self.dofs])


def _layout(design: LegDesign, convention: str, segment_mass: str) -> tuple[list[Body], list[Dof]]:
    """The bodies and joints of :func:`mat_hopper.core.mjcf.build_spec`, in its
    order: the base on its six joints, the leg on its hips (stub and the
    first segment's upper half), each segment's body on its springs (its
    lower half and the next upper half, or the foot's upper capsule), the
    foot on its spring."""
    n = design.n_segments
    scale = capsule_density_scale(n, segment_mass)
    half = ref.MATERIAL_LENGTH / n / 2.0
    r, rb, hb = ref.MATERIAL_RADIUS, ref.BASE_CAPSULE_RADIUS, ref.BASE_CAPSULE_HALF_LENGTH
    base = [(a, 0.0, 0.0, rb, None, ref.BASE_CAPSULE_MASS, hb) for a in ("x", "y")]
    bodies = [_capsule_body(BASE_BODY, 0.0, base)]
    dofs = [
        Dof(name, kind, _AXES[a], 0.0, 0, 0.0)
        for name, kind, a in zip(BASE_JOINTS, ("slide",) * 3 + ("hinge",) * 3, "xyzxyz")
    ]
    dofs += [Dof(name, "hinge", _AXES[a], 0.0, 1, ref.HIP_STIFFNESS) for name, a in zip(HIP_JOINTS, "yx")]
    rho = [m.density_kg_m3 * scale for m in design.segments]
    top = -ref.STUB_LENGTH
    parts = [
        ("z", 0.0, top, ref.STUB_RADIUS, ref.STUB_DENSITY, None, None),
        ("z", top, top - half, r, rho[0], None, None),
    ]
    frame_z, name = 0.0, LEG_BODY
    gamma = prbm_constants(n)[0] if convention in BENDING_CONVENTIONS else None
    for i, mat in enumerate(design.segments, start=1):
        bodies.append(_capsule_body(name, frame_z, parts))
        frame_z, name, top = frame_z + (top - half), SEGMENT_BODY.format(i=i), -half
        if not mat.rigid:
            if convention in AXIAL_CONVENTIONS:
                k = spring_stiffness(mat.modulus_gpa, convention, n)
                dofs.append(Dof(AXIAL_SPRING.format(i=i), "slide", (0.0, 0.0, -1.0), frame_z, len(bodies), k))
            if gamma is not None:
                pivot = frame_z + (half - (1.0 - gamma) * 2.0 * half)
                k = bending_stiffness(mat.modulus_gpa, n)
                for jname, a in zip(BEND_SPRINGS, "xy"):
                    dofs.append(Dof(jname.format(i=i), "hinge", _AXES[a], pivot, len(bodies), k))
        parts = [("z", 0.0, -half, r, rho[i - 1], None, None)]
        if i < n:
            parts.append(("z", top, top - half, r, rho[i], None, None))
    parts.append(("z", top, top - ref.FOOT_UPPER_LENGTH, r, ref.FOOT_UPPER_DENSITY, None, None))
    bodies.append(_capsule_body(name, frame_z, parts))
    foot_z = frame_z + (top - ref.FOOT_UPPER_LENGTH)
    bodies.append(
        _capsule_body(FOOT_BODY, foot_z, [("z", 0.0, -ref.FOOT_LENGTH, ref.FOOT_RADIUS, None, ref.FOOT_MASS, None)])
    )
    dofs.append(Dof(FOOT_SPRING, "slide", (0.0, 0.0, -1.0), foot_z, len(bodies) - 1, ref.FOOT_SPRING_STIFFNESS))
    return bodies, dofs
