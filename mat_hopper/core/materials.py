"""Materials, leg designs, and the conversions the paper relies on.

A :class:`Material` is a density (g/cm^3) and an elastic modulus (GPa), or
rigid. A :class:`LegDesign` is an ordered tuple of materials, segment 1
nearest the base. Modulus becomes a spring stiffness (N/m) under one of two
named conventions:

``paper``
    the authors' code: k = 3 E I / L^3 with E the bare number of GPa,
    I = pi r 4 and L = 0.01 m, i.e. 9.4248e5 N/m per GPa whatever the
    segment's size. Default, for reproductions.
``axial``
    a physical axial spring: k = E A / L with A = pi r^2 the capsule's
    cross-section and L the segment's length (0.1 m for 3 segments).
``bending``
    the leg bends: each sprung segment carries two hinge springs, about two
    orthogonal axes perpendicular to the leg, of the pseudo-rigid-body
    model's stiffness K = gamma K_Theta E I / l (:func:`bending_stiffness`,
    I = pi r^4 / 4); axially rigid.
``axial+bending``
    both: the ``axial`` slide spring and the two ``bending`` hinges.

Pseudo-rigid-body model (PRBM; L. L. Howell, *Compliant Mechanisms*,
Wiley 2001, ch. 5). Howell's end-force cantilever puts one pivot at
(1 - gamma) L from the clamp with gamma = 0.85 and K = gamma K_Theta E I / L,
K_Theta = 2.65; Howell states the tip-position error under 0.5 % for
pseudo-rigid-body angles up to 64.3 deg (gamma) and gives K_Theta as an
average over the deflection range. In the small-deflection limit its tip
deflection is (gamma / K_Theta) P L^3 / (E I) = 0.962 x P L^3 / (3 E I)
(-3.8 %). A one-segment leg (N = 1) uses exactly these values. Howell's
values do not carry over to each segment of a chain: a segment in a chain
carries the bending moment of everything below it, and under a pure end
moment a pivot of gamma K_Theta E I / l = 2.25 E I / l rotates 2.25 times
too little (the beam's end rotation is M l / E I). For N >= 2 each hinge
sits at its segment's midpoint with K = E I / l (gamma = 1/2, K_Theta = 2;
the segment's characteristic pivot at its centre, the bar-chain of Hencky):
the chain's rotations are then exact under any end force and moment, and
its tip deflection under an end force is P L^3 / (3 E I) (1 - 1 / (4 N^2)),
i.e. -6.25 % at N = 2, -2.78 % at N = 3 and -0.10 % at N = 16
(:func:`prbm_tip_deflection_ratio`; worked by hand in
tests/test_bending.py). Shear (Timoshenko) and large-deflection effects
are not modelled: the leg (L / d = 6) is a stubby beam, for which shear
adds a few per cent of compliance.

Density sets each segment's mass under one of two named conventions of
segment mass (``SEGMENT_MASSES``):

``leg``
    each of N segments carries 1/N of the material mass that the authors'
    3-segment leg of that material has, half above and half below its
    spring: every capsule's density is scaled by the ratio of the
    3-segment capsule volume to the N-segment one
    (:func:`capsule_density_scale`), exactly 1 at N = 3. Default: a leg cut
    finer is the same leg.
``capsule``
    the authors' per-capsule geometry at any N: each half-segment is a
    capsule of the material's density *with its own hemispherical end
    caps*, so the leg's mass grows with N (SS: 21.68 kg at N = 1, 23.77 kg
    at N = 3, 45.76 kg at N = 24).

Accepted physical ranges (:data:`DENSITY_RANGE_G_CM3`,
:data:`MODULUS_RANGE_GPA`, :data:`MAX_SEGMENTS`) bound what a design may
ask for; values outside raise ValueError naming the range.
"""

from __future__ import annotations

import math
import re
from collections.abc import Sequence
from dataclasses import dataclass

from ..util.parsing import is_decimal
from . import reference as ref

CONVENTIONS = ("paper", "axial", "bending", "axial+bending")
# The conventions the reproduction compares (claims, convention checks, the
# book's stable-step maps); the bending ones are issue 21's, run on request.
REPRODUCTION_CONVENTIONS = ("paper", "axial")
DEFAULT_CONVENTION = "paper"
AXIAL_CONVENTIONS = ("paper", "axial", "axial+bending")  # a slide spring per segment
BENDING_CONVENTIONS = ("bending", "axial+bending")  # two hinge springs per segment
# Howell 2001, sec. 5.1 (end-force cantilever): characteristic radius factor
# and stiffness coefficient. Used as such at N = 1 (module doc).
PRBM_GAMMA = 0.85
PRBM_K_THETA = 2.65
# N >= 2: the midpoint pivot of each segment (module doc).
CHAIN_GAMMA = 0.5
CHAIN_K_THETA = 2.0
SEGMENT_MASSES = ("leg", "capsule")
DEFAULT_SEGMENT_MASS = "leg"

# Accepted physical ranges. Densities: from aerogels (about 0.001 g/cm^3) to
# beyond osmium (22.6 g/cm^3); moduli: from soft gels (kPa, 1e-6 GPa) to
# beyond diamond (about 1200 GPa). Segments: a cap on model size (the
# convergence study goes to 24).
DENSITY_RANGE_G_CM3 = (0.001, 30.0)
MODULUS_RANGE_GPA = (1e-6, 2000.0)
MAX_SEGMENTS = 64


def _check_number(
    value, field: str, accepted: str, *, allow_zero: bool = False, bounds: tuple[float, float] | None = None
) -> float:
    """A finite number > 0 (>= 0 with allow_zero), inside bounds if given.
    Numeric strings ("8", " 1e3 ") are parsed as ASCII decimals only
    (:func:`mat_hopper.util.parsing.is_decimal`: not "inf", "1_0" or "٨");
    anything else is refused."""
    if isinstance(value, bool) or (isinstance(value, str) and not is_decimal(value)):
        raise ValueError(f"{field} must be a number {accepted}, got {value!r}")
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{field} must be a number {accepted}, got {value!r}") from None
    if not math.isfinite(x) or x < 0 or (x == 0 and not allow_zero):
        raise ValueError(f"{field} must be {accepted}, got {value!r}")
    if bounds is not None and not bounds[0] <= x <= bounds[1]:
        raise ValueError(f"{field} must be {accepted}, got {value!r}")
    return x


def check_n_segments(n_segments) -> int:
    """An integer number of segments in [1, MAX_SEGMENTS] (no bools, no 2.5).

    Args:
        n_segments: the count asked for: an int, or any value that
            ``float()`` and ``int()`` both read to the same integer (3.0,
            ``"3"``).

    Returns:
        The count as an int.

    Raises:
        ValueError: a bool, a value that is not an integer (2.5, ``"3.0"``,
            nan, inf, None), a string of non-ASCII digits (``"٣"``) or one
            outside [1, :data:`MAX_SEGMENTS`] (64).
    """
    from ..util.parsing import is_decimal

    try:
        ok = (not isinstance(n_segments, bool)) and float(n_segments) == int(n_segments)
        ok = ok and (is_decimal(n_segments) if isinstance(n_segments, str) else True)  # ASCII only: not "٣"
    except (TypeError, ValueError, OverflowError):
        ok = False
    if not ok or not 1 <= int(n_segments) <= MAX_SEGMENTS:
        raise ValueError(f"n_segments must be an integer in [1, {MAX_SEGMENTS}], got {n_segments!r}")
    return int(n_segments)


def check_segment_mass(segment_mass: str) -> str:
    """The segment-mass convention named (case-insensitive), as spelled in SEGMENT_MASSES.

    Args:
        segment_mass: ``"leg"`` or ``"capsule"``, any case, blanks trimmed.

    Returns:
        The name as spelled in :data:`SEGMENT_MASSES`.

    Raises:
        ValueError: an empty name or one not in :data:`SEGMENT_MASSES` (from
            :func:`mat_hopper.util.parsing.parse_name`).
    """
    from ..util.parsing import parse_name

    return parse_name(segment_mass, SEGMENT_MASSES, "segment mass convention")


# The Ashby chart's classes a material may name (damping.LOSS_FACTORS and
# fatigue.CLASS_STRENGTH cover the physical ones), plus the paper's rigid
# reference and "custom" (a class read off the modulus).
MATERIAL_CLASSES = ("custom", "reference", "metal", "polymer", "ceramic", "composite", "natural")


@dataclass(frozen=True)
class Material:
    """A material: bulk density in g/cm^3 and elastic modulus in GPa.

    Args:
        name: the material's name (a label, not physics).
        density_g_cm3: bulk density, g/cm^3, in [0.001, 30].
        modulus_gpa: Young's modulus, GPa, in [1e-6, 2000]; None is a rigid
            material (no spring: the paper's MD).
        material_class: one of :data:`MATERIAL_CLASSES`, any case (stored
            as spelled there): ``"metal"``, ``"polymer"``, ... (the Ashby
            chart's classes); ``"custom"`` (default): read off the modulus.
        source: where the numbers come from.

    Raises:
        ValueError: a density or modulus that is not a finite number in its
            range, or an unknown material class.
    """

    name: str
    density_g_cm3: float
    modulus_gpa: float | None
    material_class: str = "custom"
    source: str = ""

    def __post_init__(self):
        from ..util.parsing import parse_name

        object.__setattr__(self, "material_class", parse_name(self.material_class, MATERIAL_CLASSES, "material class"))
        lo, hi = DENSITY_RANGE_G_CM3
        d = _check_number(
            self.density_g_cm3, f"density of {self.name}", f"in [{lo:g}, {hi:g}] g/cm^3", bounds=DENSITY_RANGE_G_CM3
        )
        object.__setattr__(self, "density_g_cm3", d)
        if self.modulus_gpa is not None:
            lo, hi = MODULUS_RANGE_GPA
            e = _check_number(
                self.modulus_gpa,
                f"modulus of {self.name}",
                f"in [{lo:g}, {hi:g}] GPa, or rigid (None in Python)",
                bounds=MODULUS_RANGE_GPA,
            )
            object.__setattr__(self, "modulus_gpa", e)

    @property
    def rigid(self) -> bool:
        return self.modulus_gpa is None

    @property
    def density_kg_m3(self) -> float:
        return self.density_g_cm3 * 1000.0

    @property
    def modulus_pa(self) -> float | None:
        return None if self.modulus_gpa is None else self.modulus_gpa * 1e9


def _m(name, rho, e, cls, source):
    return Material(name, rho, e, cls, source)


_PAPER = "paper / authors' code (spec)"
# Extra materials for the Ashby chapter. Typical mid-range values from
# M. F. Ashby, "Materials Selection in Mechanical Design", 4th ed. (2011),
# ch. 4 property charts and appendix C, and U. G. K. Wegst & M. F. Ashby,
# "The mechanical efficiency of natural materials", Phil. Mag. 84 (2004).
CATALOGUE: dict[str, Material] = {
    m.name.lower(): m
    for m in (
        _m("MD", *ref.MONO_MATERIALS["MD"], "reference", "MuJoCo default density, rigid"),
        _m("PVC", *ref.MONO_MATERIALS["PVC"], "polymer", _PAPER),
        _m("Al", *ref.MONO_MATERIALS["Al"], "metal", _PAPER),
        _m("Ti", *ref.MONO_MATERIALS["Ti"], "metal", _PAPER),
        _m("SS", *ref.MONO_MATERIALS["SS"], "metal", _PAPER),
        # Wegst & Ashby 2004, table 1: compact bone 1.8-2.1 g/cm^3, 10-20 GPa.
        _m("CorticalBone", 1.9, 18.0, "natural", "Wegst & Ashby 2004, table 1"),
        # Wegst & Ashby 2004, fig. 3: cancellous bone 0.2-0.9 g/cm^3, 0.1-1 GPa (mid of the band).
        _m("TrabecularBone", 0.6, 0.5, "natural", "Wegst & Ashby 2004, fig. 3"),
        # Wegst & Ashby 2004, table 1: tendon about 1.1 g/cm^3, about 1 GPa along the fibre.
        _m("Tendon", 1.12, 1.2, "natural", "Wegst & Ashby 2004, table 1"),
        # Ashby 2011, app. C: alumina 3.8-3.98 g/cm^3, 343-390 GPa.
        _m("Alumina", 3.9, 370.0, "ceramic", "Ashby 2011, app. C"),
        # Ashby 2011, app. C: CFRP epoxy matrix (quasi-isotropic) 1.5-1.6 g/cm^3, 69-150 GPa.
        _m("CFRP", 1.55, 110.0, "composite", "Ashby 2011, app. C"),
        # Ashby 2011, app. C: polyamide (nylon) 1.12-1.14 g/cm^3, 2.6-3.2 GPa.
        _m("Nylon", 1.13, 2.9, "polymer", "Ashby 2011, app. C"),
        # Ashby 2011, app. C: magnesium alloys 1.74-1.95 g/cm^3, 42-47 GPa.
        _m("Mg", 1.8, 45.0, "metal", "Ashby 2011, app. C"),
        # Ashby 2011, app. C: tungsten carbide 15.3-15.9 g/cm^3, 600-720 GPa.
        _m("WC", 15.6, 650.0, "ceramic", "Ashby 2011, app. C"),
    )
}

MONO_NAMES = tuple(ref.MONO_MATERIALS)  # MD, PVC, Al, Ti, SS: the paper's five

# The design space: the property ranges the paper's sweeps span, with the
# density floor of engineering polymers (the optimizer's box, the Ashby
# chart's). Not the accepted input range (DENSITY_RANGE_G_CM3 above).
_SWEEP_DENSITIES = [v for s in ref.SWEEPS.values() for v in s["density"]]
_SWEEP_MODULI = [v for s in ref.SWEEPS.values() for v in s["modulus"]]
POLYMER_DENSITY_FLOOR_G_CM3 = 0.9  # polyolefins (Ashby 2011, app. C)
DENSITY_BOUNDS_G_CM3 = (POLYMER_DENSITY_FLOOR_G_CM3, float(max(_SWEEP_DENSITIES)))  # (0.9, 20)
MODULUS_BOUNDS_GPA = (float(min(_SWEEP_MODULI)), float(max(_SWEEP_MODULI)))  # (0.1, 1000)


def material(name: str) -> Material:
    """A catalogue material by name.

    Args:
        name: a :data:`CATALOGUE` name, any case (``"SS"``, ``"pvc"``).

    Returns:
        The :class:`Material`.

    Raises:
        ValueError: an unknown name (the accepted ones listed).
    """
    try:
        return CATALOGUE[name.strip().lower()]
    except (KeyError, AttributeError):
        known = ", ".join(m.name for m in CATALOGUE.values())
        raise ValueError(f"unknown material {name!r}; accepted: {known}") from None


# --- conversions -----------------------------------------------------------


def porosity(bulk_density_g_cm3: float, solid_density_g_cm3: float) -> float:
    """Porosity Phi = 1 - rho_b / rho_s (dimensionless, 0 for a solid).

    Args:
        bulk_density_g_cm3: bulk density rho_b, g/cm^3 (finite, > 0; a
            decimal string is read).
        solid_density_g_cm3: density of the solid rho_s, g/cm^3 (finite,
            > 0).

    Returns:
        Phi in [0, 1), a float.

    Raises:
        ValueError: a density that is not a finite number > 0, or a bulk
            density above the solid density.
    """
    rb = _check_number(bulk_density_g_cm3, "bulk density", "finite and > 0 g/cm^3")
    rs = _check_number(solid_density_g_cm3, "solid density", "finite and > 0 g/cm^3")
    if rb > rs:
        raise ValueError(f"bulk density {rb} g/cm^3 exceeds solid density {rs} g/cm^3")
    return 1.0 - rb / rs


def bulk_density(porosity_fraction: float, solid_density_g_cm3: float) -> float:
    """Bulk density rho_b = rho_s (1 - Phi) in g/cm^3, for 0 <= Phi < 1.

    Args:
        porosity_fraction: porosity Phi (dimensionless, a fraction, not %).
        solid_density_g_cm3: density of the solid rho_s, g/cm^3 (finite,
            > 0).

    Returns:
        rho_b in g/cm^3, a float.

    Raises:
        ValueError: Phi not a number in [0, 1) (nan, None, a bool, a list or
            a string other than an ASCII decimal included), or a solid
            density that is not a finite number > 0.
    """
    phi = _check_number(porosity_fraction, "porosity", "in [0, 1) (a fraction, not %)", allow_zero=True)
    if not phi < 1.0:
        raise ValueError(f"porosity must be in [0, 1) (a fraction, not %), got {porosity_fraction!r}")
    rs = _check_number(solid_density_g_cm3, "solid density", "finite and > 0 g/cm^3")
    return rs * (1.0 - phi)


def check_convention(convention: str) -> str:
    """The stiffness convention named (case-insensitive, mat_hopper.util.parsing),
    as spelled in CONVENTIONS. Raises ValueError for any other.

    Args:
        convention: ``"paper"``, ``"axial"``, ``"bending"`` or
            ``"axial+bending"``, any case, blanks trimmed.

    Returns:
        The name as spelled in :data:`CONVENTIONS`.

    Raises:
        ValueError: an empty name or one not in :data:`CONVENTIONS` (from
            :func:`mat_hopper.util.parsing.parse_name`).
    """
    from ..util.parsing import parse_name

    return parse_name(convention, CONVENTIONS, "stiffness convention")


def segment_length(n_segments: int) -> float:
    """Length in m of one material segment when 0.3 m is split in n.

    Args:
        n_segments: number of material segments, an integer in [1, 64]
            (:func:`check_n_segments`).

    Returns:
        0.3 m / `n_segments`, m (0.1 m for the paper's 3 segments).

    Raises:
        ValueError: a segment count that is not an integer in [1, 64]
            (:func:`check_n_segments`; 0 included).
    """
    return ref.MATERIAL_LENGTH / check_n_segments(n_segments)


def capsule_volume_m3(radius_m: float, length_m: float) -> float:
    """Volume (m^3) of a capsule: a cylinder of this length plus its two
    hemispherical end caps (what MuJoCo's ``fromto`` capsule holds).

    Args:
        radius_m: the capsule's radius, m.
        length_m: the length of its cylindrical part (between the caps'
            centres), m.

    Returns:
        pi r^2 L + 4/3 pi r^3, m^3.

    Raises:
        ValueError: a radius that is not a finite number > 0, or a length
            that is not a finite number >= 0.
    """
    radius_m = _check_number(radius_m, "capsule radius", "finite and > 0 m")
    length_m = _check_number(length_m, "capsule length", "finite and >= 0 m", allow_zero=True)
    return math.pi * radius_m**2 * length_m + 4.0 / 3.0 * math.pi * radius_m**3


def capsule_density_scale(n_segments: int, segment_mass: str = DEFAULT_SEGMENT_MASS) -> float:
    """Factor on each material capsule's density (module doc): ``leg``,
    V3 / (N/3 V_N) with V_N the volume of one half-segment capsule of an
    N-segment leg (exactly 1.0 at N = 3); ``capsule``, 1.

    Args:
        n_segments: the leg's number of material segments N, in [1, 64].
        segment_mass: the segment-mass convention, ``"leg"`` (default) or
            ``"capsule"``, any case.

    Returns:
        The dimensionless density factor (< 1 for N > 3, > 1 for N < 3
        under ``leg``: more segments, more end caps; 1.0 under
        ``capsule``).

    Raises:
        ValueError: an unknown segment-mass convention
            (:func:`check_segment_mass`) or a segment count that is not an
            integer in [1, 64] (:func:`check_n_segments`).
    """
    segment_mass = check_segment_mass(segment_mass)
    n = check_n_segments(n_segments)
    if segment_mass == "capsule":
        return 1.0
    r, ref_n = ref.MATERIAL_RADIUS, ref.REFERENCE_SEGMENTS
    v_ref = capsule_volume_m3(r, segment_length(ref_n) / 2.0)
    v_n = capsule_volume_m3(r, segment_length(n) / 2.0)
    return (ref_n * v_ref) / (n * v_n)


def segment_masses(design: LegDesign, segment_mass: str = DEFAULT_SEGMENT_MASS) -> tuple[float, ...]:
    """Mass in kg of each material segment of a design, base to foot, as the
    model builds it: m = rho V, V two half-segment capsules of radius
    0.025 m (:func:`capsule_volume_m3`, end caps included), rho scaled by the
    segment-mass convention (:func:`capsule_density_scale`). The rest of the
    robot (base, hip stub, foot) is in :mod:`mat_hopper.core.model`; MuJoCo's
    total is ``build_model(d).total_mass_kg``.

    Args:
        design: the :class:`LegDesign`.
        segment_mass: the segment-mass convention, ``"leg"`` (default) or
            ``"capsule"``, any case.

    Returns:
        A tuple of N floats, kg, segment 1 (nearest the base) first; a rigid
        segment has its mass too.

    Raises:
        ValueError: an unknown segment-mass convention (from
            :func:`capsule_density_scale`).
    """
    n = design.n_segments
    v = 2.0 * capsule_volume_m3(ref.MATERIAL_RADIUS, segment_length(n) / 2.0)
    scale = capsule_density_scale(n, segment_mass)
    return tuple(m.density_kg_m3 * scale * v for m in design.segments)


def spring_stiffness(
    modulus_gpa: float, convention: str = DEFAULT_CONVENTION, n_segments: int = ref.REFERENCE_SEGMENTS
) -> float:
    """Axial spring stiffness in N/m for a segment of the given modulus
    (GPa); 0 under ``bending`` (axially rigid). ``axial+bending`` takes the
    ``axial`` value.

    Args:
        modulus_gpa: Young's modulus, GPa (finite, > 0; not checked against
            :data:`MODULUS_RANGE_GPA`).
        convention: the stiffness convention, any case (default
            ``"paper"``).
        n_segments: the leg's number of segments N (default 3); read (and
            checked, an integer in [1, 64]) only under ``axial`` and
            ``axial+bending`` (L = 0.3 m / N).

    Returns:
        k in N/m: ``paper``, 9.4248e5 N/m per GPa x E (whatever N);
        ``axial`` and ``axial+bending``, E A / L with A = pi (0.025 m)^2;
        ``bending``, 0.0.

    Raises:
        ValueError: an unknown convention, a modulus that is not a finite
            number > 0, or under ``axial`` and ``axial+bending`` a segment
            count that is not an integer in [1, 64].
    """
    convention = check_convention(convention)
    e = _check_number(modulus_gpa, "modulus", "finite and > 0 GPa")
    if convention not in AXIAL_CONVENTIONS:
        return 0.0
    if convention == "paper":
        return ref.PAPER_STIFFNESS_PER_GPA * e
    area = math.pi * ref.MATERIAL_RADIUS**2
    return e * 1e9 * area / segment_length(n_segments)


def second_moment_m4(radius_m: float = ref.MATERIAL_RADIUS) -> float:
    """Second moment of area I = pi r^4 / 4 (m^4) of a solid circular
    section about a diameter.

    Args:
        radius_m: the section's radius, m (default 0.025 m, the material
            capsules').

    Returns:
        I in m^4.

    Raises:
        ValueError: a radius that is not a finite number > 0.
    """
    radius_m = _check_number(radius_m, "section radius", "finite and > 0 m")
    return math.pi * radius_m**4 / 4.0


def prbm_constants(n_segments: int) -> tuple[float, float]:
    """(gamma, K_Theta) of each segment's pivot (module doc): Howell's
    end-force values (0.85, 2.65) for one segment, the midpoint pivot
    (0.5, 2) for a chain. The pivot lies (1 - gamma) l below the segment's
    top.

    Args:
        n_segments: the leg's number of segments N, in [1, 64].

    Returns:
        (gamma, K_Theta), both dimensionless: (0.85, 2.65) at N = 1, else
        (0.5, 2.0).

    Raises:
        ValueError: a segment count that is not an integer in [1, 64]
            (:func:`check_n_segments`).
    """
    n = check_n_segments(n_segments)
    return (PRBM_GAMMA, PRBM_K_THETA) if n == 1 else (CHAIN_GAMMA, CHAIN_K_THETA)


def bending_stiffness(modulus_gpa: float, n_segments: int = ref.REFERENCE_SEGMENTS) -> float:
    """Stiffness (N m/rad) of each of a segment's two hinge springs:
    K = gamma K_Theta E I / l with l = 0.3 m / N, I = pi r^4 / 4 and
    (gamma, K_Theta) from :func:`prbm_constants` (Howell 2001, ch. 5).

    Args:
        modulus_gpa: Young's modulus E, GPa (finite, > 0; not checked
            against :data:`MODULUS_RANGE_GPA`).
        n_segments: the leg's number of segments N, in [1, 64] (default 3).

    Returns:
        K in N m/rad (r = 0.025 m).

    Raises:
        ValueError: a modulus that is not a finite number > 0, or a segment
            count that is not an integer in [1, 64].
    """
    e = _check_number(modulus_gpa, "modulus", "finite and > 0 GPa")
    gamma, k_theta = prbm_constants(n_segments)
    return gamma * k_theta * e * 1e9 * second_moment_m4() / segment_length(n_segments)


def prbm_tip_deflection_ratio(n_segments: int) -> float:
    """The chain's small-deflection tip deflection under an end force, over
    Euler-Bernoulli's P L^3 / (3 E I): the PRBM's stated error + 1. One
    segment: 3 gamma / K_Theta (0.962); N >= 2 midpoint pivots:
    1 - 1 / (4 N^2).

    Args:
        n_segments: the leg's number of segments N, in [1, 64].

    Returns:
        The dimensionless ratio (1 would be exact Euler-Bernoulli).

    Raises:
        ValueError: a segment count that is not an integer in [1, 64]
            (:func:`check_n_segments`).
    """
    n = check_n_segments(n_segments)
    gamma, k_theta = prbm_constants(n)
    # sum over pivots of (lever arm)^2 / K, lever arm (N - i + gamma) l
    s = sum((j + gamma) ** 2 for j in range(n)) / (gamma * k_theta)
    return s / (n**3 / 3.0)


# --- leg designs -----------------------------------------------------------


@dataclass(frozen=True)
class LegDesign:
    """A leg of N material segments, segment 1 nearest the base.

    Args:
        segments: the N Materials, 1 <= N <= 64, from the hip down.
        name: a label (default: the materials' names joined by ``-``).

    Raises:
        ValueError: no segments, more than 64, or a segment that is not a Material.
    """

    segments: tuple[Material, ...]
    name: str = ""

    def __post_init__(self):
        segs = tuple(self.segments)
        if not 1 <= len(segs) <= MAX_SEGMENTS:
            raise ValueError(f"a leg needs 1 to {MAX_SEGMENTS} segments, got {len(segs)}")
        for s in segs:
            if not isinstance(s, Material):
                raise ValueError(f"segments must be Material objects, got {s!r}")
        object.__setattr__(self, "segments", segs)
        if not self.name:
            object.__setattr__(self, "name", "-".join(s.name for s in segs))

    @property
    def n_segments(self) -> int:
        return len(self.segments)

    @property
    def densities_g_cm3(self) -> tuple[float, ...]:
        return tuple(s.density_g_cm3 for s in self.segments)

    @property
    def moduli_gpa(self) -> tuple[float | None, ...]:
        return tuple(s.modulus_gpa for s in self.segments)

    def resample(self, n_segments: int) -> LegDesign:
        """This leg's material profile on n_segments equal segments, by cell
        averages over each new segment's share of the leg: density as the
        length-weighted arithmetic mean (the material mass is conserved),
        modulus as the length-weighted harmonic mean (springs in series: the
        leg's axial compliance is conserved); rigid only where every source
        segment under it is rigid (a partly rigid cell takes the harmonic
        mean of its elastic part). The same N returns this design; N a
        multiple of the current count splits each segment."""
        n = check_n_segments(n_segments)
        if n == self.n_segments:
            return self
        m = self.n_segments
        edges_new = [j / n for j in range(n + 1)]
        segs = []
        for j in range(n):
            a, b = edges_new[j], edges_new[j + 1]
            mass, comp, elastic, rigid_len = 0.0, 0.0, 0.0, 0.0
            for i, mat in enumerate(self.segments):
                w = max(0.0, min(b, (i + 1) / m) - max(a, i / m))
                if w <= 0:
                    continue
                mass += w * mat.density_g_cm3
                if mat.rigid:
                    rigid_len += w
                else:
                    comp += w / mat.modulus_gpa
                    elastic += w
            rho = mass / (b - a)
            e = None if elastic == 0 else elastic / comp
            segs.append(Material(f"seg{j + 1}", rho, e))
        return LegDesign(tuple(segs), name=f"{self.name}@{n}" if self.name else "")

    @classmethod
    def mono(cls, mat: Material | str, n_segments: int = ref.REFERENCE_SEGMENTS) -> LegDesign:
        """A homogeneous leg of one material."""
        m = material(mat) if isinstance(mat, str) else mat
        return cls((m,) * check_n_segments(n_segments), name=m.name)

    @classmethod
    def from_properties(
        cls, densities_g_cm3: Sequence[float], moduli_gpa: Sequence[float | None], name: str = ""
    ) -> LegDesign:
        """A leg from per-segment densities (g/cm^3) and moduli (GPa; None
        or the word ``"rigid"`` = rigid, as on the command line; inf is
        refused in both). Raises ValueError for lists of different lengths
        (one value is used for every segment), values out of range, or a
        string or None in place of a sequence."""
        for arg, what in ((densities_g_cm3, "densities_g_cm3"), (moduli_gpa, "moduli_gpa")):
            if arg is None or isinstance(arg, (str, bytes)):  # a string would be read a character at a time
                raise ValueError(f"{what} must be a sequence of numbers, one per segment; got {arg!r}")
        dens = list(densities_g_cm3)
        mods = [None if isinstance(e, str) and e.strip().lower() == "rigid" else e for e in moduli_gpa]
        if len(mods) == 1 and len(dens) > 1:
            mods = mods * len(dens)
        if len(dens) == 1 and len(mods) > 1:
            dens = dens * len(mods)
        if len(dens) != len(mods):
            raise ValueError(f"density and modulus need one value per segment (got {len(dens)} and {len(mods)})")
        if not 1 <= len(dens) <= MAX_SEGMENTS:
            raise ValueError(f"a leg needs 1 to {MAX_SEGMENTS} segments, got {len(dens)}")
        segs = tuple(Material(f"seg{i + 1}", d, e) for i, (d, e) in enumerate(zip(dens, mods)))
        if not name:  # from the parsed values (numeric strings are accepted above)
            name = (
                "custom("
                + ",".join(f"{s.density_g_cm3:g}/{'rigid' if s.rigid else f'{s.modulus_gpa:g}'}" for s in segs)
                + ")"
            )
        return cls(segs, name=name)


def _named_designs() -> dict[str, LegDesign]:
    inc = LegDesign.from_properties(ref.GRADIENT_DENSITIES, [ref.GRADIENT_MODULUS_GPA], name="rho-inc")
    dec = LegDesign.from_properties(ref.GRADIENT_DENSITIES[::-1], [ref.GRADIENT_MODULUS_GPA], name="rho-dec")
    return {"rho-inc": inc, "rho-dec": dec}


NAMED_DESIGNS = _named_designs()


_CUSTOM = re.compile(r"custom\((.*)\)", re.IGNORECASE)
_MAP_NAME = re.compile(r"rho=(\S+)\s+E=(\S+)", re.IGNORECASE)


def _written_design(text: str, n_segments: int) -> LegDesign | None:
    """The design of a name from_properties or the stability map wrote, or None."""
    from ..util.parsing import parse_number

    if m := _CUSTOM.fullmatch(text):
        pairs = [p.split("/") for p in m.group(1).split(",")]
        if not all(len(p) == 2 for p in pairs):
            raise ValueError(f"design {text!r}: custom(...) holds DENSITY/MODULUS pairs, e.g. custom(1.39/70,8/rigid)")
        dens = [parse_number(d, f"design {text!r}: density", unit="g/cm^3") for d, _ in pairs]
        mods = [parse_number(e, f"design {text!r}: modulus", rigid=True, unit="GPa") for _, e in pairs]
        return LegDesign.from_properties(dens, mods)
    if m := _MAP_NAME.fullmatch(text):
        d = parse_number(m.group(1), f"design {text!r}: rho", unit="g/cm^3")
        e = parse_number(m.group(2), f"design {text!r}: E", unit="GPa")
        return LegDesign((Material(f"rho{d:g}-E{e:g}", d, e),) * check_n_segments(n_segments), name=text)
    return None


def parse_design(text: str, n_segments: int = ref.REFERENCE_SEGMENTS) -> LegDesign:
    """A design from its name.

    Args:
        text: a material (``"SS"``: N segments of it), a gradient
            (``"PVC-Ti-SS"``: one segment per name, from the hip down), a
            named design (``"rho-inc"``, ``"rho-dec"``), or a name the tool
            writes for a design of given properties: ``custom(1.39/70,8/rigid)``
            (density g/cm^3 / modulus GPa per segment,
            :meth:`LegDesign.from_properties`) and the stability map's
            ``rho=8 E=193`` (n_segments alike); any case.
        n_segments: segments of a single-material design (default 3, the paper's).

    Returns:
        The :class:`LegDesign`.

    Raises:
        ValueError: an empty or unknown name, or a gradient with an empty
            name between its separators (``"SS--Ti"``, ``"-SS"``,
            ``"SS-"``).

    >>> parse_design("PVC-Ti-SS").densities_g_cm3
    (1.39, 4.43, 8.0)
    >>> parse_design(LegDesign.from_properties([1, 2], [70, None]).name).moduli_gpa
    (70.0, None)
    """
    if isinstance(text, str) and (written := _written_design(text.strip(), n_segments)) is not None:
        return written
    if not isinstance(text, str) or not text.strip():
        raise ValueError(
            f"design must be a material, a gradient like PVC-Ti-SS, or one of {', '.join(NAMED_DESIGNS)}; got {text!r}"
        )
    key = text.strip().lower()
    for name, design in NAMED_DESIGNS.items():
        if key == name:
            return design
    parts = [p.strip() for p in re.split(r"[-_/]", text.strip())]
    if not all(parts):  # "SS--Ti", "-SS", "SS-", "SS- -Ti": a name left out, not a shorter leg
        raise ValueError(
            f"design {text!r} has an empty name between separators (- _ /); write one material per segment, "
            "e.g. PVC-Ti-SS"
        )
    if len(parts) == 1:
        return LegDesign.mono(parts[0], n_segments)
    mats = tuple(material(p) for p in parts)
    return LegDesign(mats, name="-".join(m.name for m in mats))


def paper_designs() -> dict[str, LegDesign]:
    """The paper's mono-materials and gradients, by name.

    Returns:
        A dict name -> :class:`LegDesign`, in this order: the five
        mono-materials (MD, PVC, Al, Ti, SS; 3 segments each), ``rho-inc``,
        ``rho-dec``, ``PVC-Ti-SS`` and ``SS-Ti-PVC``.
    """
    out = {n: LegDesign.mono(n) for n in MONO_NAMES}
    out.update(NAMED_DESIGNS)
    for g in ("PVC-Ti-SS", "SS-Ti-PVC"):
        out[g] = parse_design(g)
    return out


PAPER_DESIGN_ORDER = (*MONO_NAMES, "rho-inc", "rho-dec", "PVC-Ti-SS", "SS-Ti-PVC")  # the paper's tables and figures


def order_designs(designs) -> list[str]:
    """Design names in the paper's order (:data:`PAPER_DESIGN_ORDER`), then
    the others as first seen; each once.

    Args:
        designs: an iterable of design names (str), repeats allowed.

    Returns:
        A list of the distinct names: those of :data:`PAPER_DESIGN_ORDER` in
        that order, then the rest in order of first appearance.

    >>> order_designs(["mine", "SS", "rho-inc", "MD", "SS"])
    ['MD', 'SS', 'rho-inc', 'mine']
    """
    seen = list(dict.fromkeys(designs))
    return [d for d in PAPER_DESIGN_ORDER if d in seen] + [d for d in seen if d not in PAPER_DESIGN_ORDER]


def as_design(design) -> LegDesign:
    """A design as a LegDesign.

    Args:
        design: a LegDesign (returned as is) or a name (``"SS"``, ``"PVC-Ti-SS"``, ``"rho-inc"``).

    Returns:
        The LegDesign.

    Raises:
        ValueError: anything else, or an unknown name.
    """
    if isinstance(design, LegDesign):
        return design
    if isinstance(design, str):
        return parse_design(design)
    raise ValueError(f"design must be a LegDesign or a design name, got {design!r}")
