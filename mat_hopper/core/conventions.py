"""Stiffness conventions (modulus -> spring) and segment-mass conventions
(density -> capsule mass): the conversions the paper relies on.

A material's modulus becomes a spring stiffness (N/m) under one of four
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
tests/core/test_model_bending.py). Shear (Timoshenko) and large-deflection effects
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

The leg designs these apply to are :class:`mat_hopper.core.materials.LegDesign`.
"""

from __future__ import annotations

import math

from ..util.parsing import parse_name
from . import reference as ref
from .ranges import _check_number, check_n_segments

__all__ = [
    "AXIAL_CONVENTIONS",
    "BENDING_CONVENTIONS",
    "CHAIN_GAMMA",
    "CHAIN_K_THETA",
    "CONVENTIONS",
    "DEFAULT_CONVENTION",
    "DEFAULT_SEGMENT_MASS",
    "PRBM_GAMMA",
    "PRBM_K_THETA",
    "REPRODUCTION_CONVENTIONS",
    "SEGMENT_MASSES",
    "bending_stiffness",
    "capsule_density_scale",
    "capsule_volume_m3",
    "check_convention",
    "check_segment_mass",
    "prbm_constants",
    "prbm_tip_deflection_ratio",
    "second_moment_m4",
    "segment_length",
    "spring_stiffness",
]

CONVENTIONS = ("paper", "axial", "bending", "axial+bending")
# The conventions the reproduction compares (claims, convention checks, the
# book's stable-step maps); the bending ones run on request.
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
    return parse_name(segment_mass, SEGMENT_MASSES, "segment mass convention")


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


def spring_stiffness(
    modulus_gpa: float, convention: str = DEFAULT_CONVENTION, n_segments: int = ref.REFERENCE_SEGMENTS
) -> float:
    """Axial spring stiffness in N/m for a segment of the given modulus
    (GPa); 0 under ``bending`` (axially rigid). ``axial+bending`` takes the
    ``axial`` value.

    Args:
        modulus_gpa: Young's modulus, GPa (finite, > 0; not checked against
            :data:`MODULUS_RANGE_GPA`).
        convention: the stiffness convention as spelled in
            :data:`CONVENTIONS` (default ``"paper"``): the entry points
            (SimSettings, the model builder, the commands) spell it with
            :func:`check_convention`; other spellings are refused.
        n_segments: the leg's number of segments N (default 3); read (and
            checked, an integer in [1, 64]) only under ``axial`` and
            ``axial+bending`` (L = 0.3 m / N).

    Returns:
        k in N/m: ``paper``, 9.4248e5 N/m per GPa x E (whatever N);
        ``axial`` and ``axial+bending``, E A / L with A = pi (0.025 m)^2;
        ``bending``, 0.0.

    Raises:
        ValueError: a convention not spelled as in :data:`CONVENTIONS`, a
            modulus that is not a finite number > 0, or under ``axial`` and
            ``axial+bending`` a segment count that is not an integer in [1, 64].
    """
    if convention not in CONVENTIONS:  # spelled once, at the entry points
        raise ValueError(f"stiffness convention {convention!r}: give one of {', '.join(CONVENTIONS)}, as spelled")
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
