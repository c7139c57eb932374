"""Controls for a leg design: legs that differ from it in one thing only.

A claim about a material holds only against a control that differs from
the design in that material alone. Three controls, each a
:class:`~mat_hopper.core.materials.LegDesign` that runs like any other:

``rigid`` (:func:`rigid_twin`)
    the same segment densities (so the same masses, centre of mass and
    inertia, exactly), no axial springs: what the moduli add;
``mass`` (:func:`mass_matched`)
    a homogeneous leg of the same leg mass: density the mean of the
    design's (segments have equal volumes), modulus the one whose N springs
    in series have the design's axial compliance (rigid segments add none:
    E_eq = N / sum over elastic segments of 1 / E_i, the harmonic mean for
    a leg elastic throughout); rigid where the design is rigid throughout.
    What the distribution of mass along the leg adds;
``inertia`` (:func:`inertia_matched`)
    a leg with the same leg mass *and* the same moment of inertia about
    the hip: the mass-matched leg's modulus, densities linear in segment
    position, rho_i = a + b (i - (N + 1) / 2). Why this leg: leg mass and
    hip inertia are both linear in the segment densities, so two
    parameters match both exactly (a is the mean density, b solves one
    linear equation), and a linear profile is the simplest shape with two
    parameters that stays a leg of material segments (no extra point mass
    the model does not have). A one-segment leg is homogeneous already: its
    inertia-matched leg is its mass-matched leg. For a three-segment
    gradient the linear profile is close to the design itself (for rho-inc,
    1.39 / 4.43 / 8.0 g/cm^3, ``inertia_matched(parse_design("rho-inc"))``
    gives about 1.28 / 4.61 / 7.93 g/cm^3): the control then differs in the
    profile's curvature only, where the design has one modulus throughout
    (rho-inc, rho-dec), and also in the modulus profile where it has
    several.

:func:`mass_properties` reads the leg's mass, centre of mass and hip
inertia from the compiled MuJoCo model (``body_mass``, ``xipos``,
``ximat``, ``body_inertia`` at the start pose); ``tests/core/test_control_legs.py``
checks them against a hand calculation of capsule volumes and the
parallel-axis theorem.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import mujoco
import numpy as np

from ..util.parsing import parse_name
from .materials import (
    DEFAULT_SEGMENT_MASS,
    DENSITY_RANGE_G_CM3,
    MODULUS_RANGE_GPA,
    LegDesign,
    Material,
    as_design,
    check_segment_mass,
)

CONTROLS = ("rigid", "mass", "inertia")
CONTROL_SUFFIX = "~"  # a control's name: "<design>~<control>", e.g. "rho-inc~mass"
# The columns every hop table, run summary and claims row carries (units in the names).
MASS_PROPERTY_COLUMNS = ("leg_mass_kg", "leg_com_m", "hip_inertia_kg_m2")


@dataclass(frozen=True)
class MassProperties:
    """The leg's mass properties (everything below the hip: stub, material
    segments, foot), at the start pose, straight down.

    Attributes:
        leg_mass_kg: mass of the leg (kg).
        leg_com_m: distance of the leg's centre of mass below the hip (m).
        hip_inertia_kg_m2: moment of inertia about the hip's pitch axis
            (kg m^2); the leg is axially symmetric, so the roll axis gives
            the same.
    """

    leg_mass_kg: float
    leg_com_m: float
    hip_inertia_kg_m2: float

    def as_dict(self) -> dict:
        return dict(zip(MASS_PROPERTY_COLUMNS, (self.leg_mass_kg, self.leg_com_m, self.hip_inertia_kg_m2)))


def _check_design(design) -> LegDesign:
    """A LegDesign, or a design name read as simulate reads it
    (:func:`~mat_hopper.core.materials.as_design`: ``"SS"``, ``"rho-inc"``)."""
    if isinstance(design, str):
        return as_design(design)
    if not isinstance(design, LegDesign):
        raise ValueError(f"design must be a LegDesign or a design name, got {type(design).__name__}")
    return design


@lru_cache(maxsize=256)  # designs are frozen (hashable); each miss compiles a MuJoCo model
def mass_properties(design: LegDesign, segment_mass: str = DEFAULT_SEGMENT_MASS) -> MassProperties:
    """Leg mass (kg), centre of mass below the hip (m) and hip inertia
    (kg m^2) of a design, from MuJoCo's compiled model.

    Args:
        design: the leg, a LegDesign or a design name (``"SS"``).
        segment_mass: the segment-mass convention (``leg`` or ``capsule``,
            :mod:`mat_hopper.core.conventions`).

    Returns:
        MassProperties, from the bodies of the leg's subtree: MuJoCo's
        ``body_mass``, its inertia ``body_inertia`` rotated to the world by
        ``ximat`` and moved to the hip axis by the parallel-axis theorem.

    Raises:
        ValueError: for a design that is not a LegDesign or an unknown
            segment-mass convention.
    """
    from .model import build_model, reset_to_start

    design = _check_design(design)
    check_segment_mass(segment_mass)
    m = build_model(design, segment_mass=segment_mass, sensors="control").model
    d = mujoco.MjData(m)
    reset_to_start(m, d)
    leg = m.body("leg").id
    sub = [b for b in range(m.nbody) if _in_subtree(m, b, leg)]
    hip = d.xpos[leg]  # the hip joints sit at the leg body's origin
    mass = float(m.body_mass[sub].sum())
    com_z = float((m.body_mass[sub] * d.xipos[sub, 2]).sum() / mass)
    inertia = 0.0
    for b in sub:
        rot = d.ximat[b].reshape(3, 3)
        i_world = rot @ np.diag(m.body_inertia[b]) @ rot.T
        r = d.xipos[b] - hip
        inertia += i_world[1, 1] + m.body_mass[b] * (r[0] ** 2 + r[2] ** 2)
    return MassProperties(mass, float(hip[2] - com_z), float(inertia))


def _in_subtree(model: mujoco.MjModel, body: int, root: int) -> bool:
    while body > 0:
        if body == root:
            return True
        body = int(model.body_parentid[body])
    return root == 0


def _name(design: LegDesign, control: str) -> str:
    return f"{design.name}{CONTROL_SUFFIX}{control}"


def rigid_twin(design: LegDesign) -> LegDesign:
    """The design's densities with no springs (every segment rigid).

    Args:
        design: the leg, a LegDesign or a design name (``"SS"``).

    Returns:
        LegDesign named ``<name>~rigid``, same segment count and densities.

    Raises:
        ValueError: design is neither a LegDesign nor a known design name.
    """
    design = _check_design(design)
    n = design.n_segments
    return LegDesign.from_properties(design.densities_g_cm3, [None] * n, name=_name(design, "rigid"))


# A control leg is derived by arithmetic (a mean, a series sum) whose last bit
# depends on the order of its terms: aluminium's mass-matched leg came out at
# 2.7000000000000006 g/cm^3, a second design (and cache key) for aluminium
# itself, and PVC-Ti-SS~mass and SS-Ti-PVC~mass two for one leg. Twelve
# significant digits lie far below any physical tolerance (1e-12 relative)
# and far above float round-off (about 1e-16), so legs equal but for
# round-off share one canonical form.
CANONICAL_DIGITS = 12


def canonical(value: float | None) -> float | None:
    """A derived density (g/cm^3) or modulus (GPa) in its canonical form:
    rounded to :data:`CANONICAL_DIGITS` significant digits (None, rigid,
    stays None).

    Args:
        value: the derived value, or None.

    Returns:
        The value rounded to 12 significant digits, as a float; None for None.

    >>> canonical(2.7000000000000006), canonical(None)
    (2.7, None)
    """
    return None if value is None else float(f"{float(value):.{CANONICAL_DIGITS}g}")


def _homogeneous(design: LegDesign) -> Material:
    """Mean density (equal segment volumes); the modulus whose N equal
    springs in series have the design's axial compliance: the design's
    compliance is the sum of its elastic segments' L / (E_i A) (a rigid
    segment adds none), so E_eq = N / sum_elastic(1 / E_i). For a leg
    elastic throughout that is the harmonic mean; a partly rigid leg gets
    a stiffer E_eq ((rigid, rigid, 193 GPa): 579 GPa), not the harmonic
    mean of its elastic part, which would triple its compliance.

    Raises:
        ValueError: E_eq outside MODULUS_RANGE_GPA.
    """
    n = design.n_segments
    rho = canonical(float(np.mean(design.densities_g_cm3)))
    elastic = [e for e in design.moduli_gpa if e is not None]
    if not elastic:
        return Material(f"{design.name} homogeneous", rho, None)
    e_eq = canonical(n / sum(1.0 / e for e in elastic))
    lo, hi = MODULUS_RANGE_GPA
    if not lo <= e_eq <= hi:
        raise ValueError(
            f"design {design.name!r}: a homogeneous leg with its axial compliance needs E = {e_eq:.4g} GPa, "
            f"outside [{lo:g}, {hi:g}] GPa"
        )
    return Material(f"{design.name} homogeneous", rho, e_eq)


def mass_matched(design: LegDesign) -> LegDesign:
    """A homogeneous leg of the design's leg mass (module doc).

    Args:
        design: the leg, a LegDesign or a design name (``"SS"``).

    Returns:
        LegDesign named ``<name>~mass``: N segments of the mean density and
        the series-equivalent modulus (rigid if the design is).

    Raises:
        ValueError: design is neither a LegDesign nor a known design name.
    """
    design = _check_design(design)
    mat = _homogeneous(design)
    n = design.n_segments
    return LegDesign.from_properties([mat.density_g_cm3] * n, [mat.modulus_gpa] * n, name=_name(design, "mass"))


def _linear_profile(mean: float, slope: float, n: int) -> list[float]:
    return [mean + slope * (i - (n - 1) / 2.0) for i in range(n)]


def inertia_matched(design: LegDesign, segment_mass: str = DEFAULT_SEGMENT_MASS) -> LegDesign:
    """A leg with the design's leg mass and hip inertia (module doc: a
    linear density profile with the mass-matched modulus).

    Args:
        design: the leg, a LegDesign or a design name (``"SS"``).
        segment_mass: the segment-mass convention the inertia is matched
            under (the linear solve is exact under either).

    Returns:
        LegDesign named ``<name>~inertia``.

    Raises:
        ValueError: design is neither a LegDesign nor a known design name, or the profile needs a
            density outside the accepted range (an extreme inertia for its
            mass).
    """
    design = _check_design(design)
    n = design.n_segments
    mat = _homogeneous(design)
    if n == 1:
        return LegDesign.from_properties([mat.density_g_cm3], [mat.modulus_gpa], name=_name(design, "inertia"))
    target = mass_properties(design, segment_mass).hip_inertia_kg_m2
    mean = mat.density_g_cm3
    # Hip inertia is affine in the slope b: two evaluations give it exactly.
    probe = 0.5 * mean / max(n - 1, 1)
    i0 = mass_properties(LegDesign.from_properties([mean] * n, [None] * n), segment_mass).hip_inertia_kg_m2
    i1 = mass_properties(
        LegDesign.from_properties(_linear_profile(mean, probe, n), [None] * n), segment_mass
    ).hip_inertia_kg_m2
    slope = probe * (target - i0) / (i1 - i0)
    dens = [canonical(d) for d in _linear_profile(mean, slope, n)]
    lo, hi = DENSITY_RANGE_G_CM3
    if min(dens) < lo or max(dens) > hi:
        raise ValueError(
            f"no linear-profile leg matches {design.name}'s mass and hip inertia inside [{lo:g}, {hi:g}] g/cm^3 "
            f"(needs {min(dens):.3g} to {max(dens):.3g})"
        )
    return LegDesign.from_properties(dens, [mat.modulus_gpa] * n, name=_name(design, "inertia"))


_BUILDERS = {"rigid": rigid_twin, "mass": mass_matched, "inertia": inertia_matched}


def check_control(kind: str) -> str:
    """The control kind named (case-insensitive, blanks trimmed;
    :func:`mat_hopper.util.parsing.parse_name`), as spelled in :data:`CONTROLS`.

    Args:
        kind: ``"rigid"``, ``"mass"`` or ``"inertia"``, any case.

    Returns:
        The kind as spelled in :data:`CONTROLS` (``"Mass"`` gives ``"mass"``).

    Raises:
        ValueError: an empty name or one not in :data:`CONTROLS` (the
            message lists them).
    """
    return parse_name(kind, CONTROLS, "control")


def control(design: LegDesign, kind: str, segment_mass: str = DEFAULT_SEGMENT_MASS) -> LegDesign:
    """The control of one kind (``rigid``, ``mass`` or ``inertia``) for a design.

    Args:
        design: the leg, a LegDesign or a design name (``"SS"``).
        kind: one of :data:`CONTROLS`, any case (:func:`check_control`).
        segment_mass: the segment-mass convention (matters for ``inertia``).

    Returns:
        LegDesign of the control, named ``<design>~<kind>`` with the kind
        as spelled in :data:`CONTROLS`.

    Raises:
        ValueError: unknown kind, or as the builder raises.
    """
    kind = check_control(kind)
    if kind == "inertia":
        return inertia_matched(design, segment_mass)
    return _BUILDERS[kind](design)


def control_kind(name: str) -> str | None:
    """The control kind a design name carries (``rho-inc~mass`` -> ``mass``), or None.

    Args:
        name: a design name (converted with ``str``).

    Returns:
        The text after the last ``~`` when it is one of :data:`CONTROLS` and
        a non-empty design name precedes it; None otherwise (no ``~``, an
        empty base or an unknown kind).
    """
    base, sep, kind = str(name).rpartition(CONTROL_SUFFIX)
    return kind if sep and base and kind in CONTROLS else None


def control_of(name: str) -> str:
    """The design a control's name belongs to (``rho-inc~mass`` -> ``rho-inc``); other names as they are.

    Args:
        name: a design name (converted with ``str``).

    Returns:
        The text before the last ``~`` when :func:`control_kind` finds a
        control kind in the name, else ``str(name)`` unchanged.
    """
    return str(name).rpartition(CONTROL_SUFFIX)[0] if control_kind(name) else str(name)
