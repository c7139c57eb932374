"""Leg designs: a :class:`LegDesign` is an ordered tuple of materials,
segment 1 nearest the base, with the design-name parser
(:func:`parse_design`), the paper's designs and the mass of each segment as
the model builds it (:func:`segment_masses`).

The pieces a design is made of live in modules of their own and are
re-exported here, where callers import them:

- :mod:`mat_hopper.core.catalogue`: :class:`Material` (density g/cm^3,
  modulus GPa, or rigid), the :data:`CATALOGUE`, porosity conversions;
- :mod:`mat_hopper.core.conventions`: the stiffness conventions
  (``paper``, ``axial``, ``bending``, ``axial+bending``; modulus -> N/m or
  N m/rad, with the pseudo-rigid-body model of L. L. Howell, *Compliant
  Mechanisms*, Wiley 2001, ch. 5) and the segment-mass conventions
  (``leg``, ``capsule``);
- :mod:`mat_hopper.core.ranges`: the accepted physical ranges and the
  design space.
"""

from __future__ import annotations

import re
from collections.abc import Iterable, Sequence
from dataclasses import dataclass

from . import reference as ref
from .catalogue import CATALOGUE, MATERIAL_CLASSES, MONO_NAMES, Material, bulk_density, material, porosity
from .conventions import (
    AXIAL_CONVENTIONS,
    BENDING_CONVENTIONS,
    CHAIN_GAMMA,
    CHAIN_K_THETA,
    CONVENTIONS,
    DEFAULT_CONVENTION,
    DEFAULT_SEGMENT_MASS,
    PRBM_GAMMA,
    PRBM_K_THETA,
    REPRODUCTION_CONVENTIONS,
    SEGMENT_MASSES,
    bending_stiffness,
    capsule_density_scale,
    capsule_volume_m3,
    check_convention,
    check_segment_mass,
    prbm_constants,
    prbm_tip_deflection_ratio,
    second_moment_m4,
    segment_length,
    spring_stiffness,
)
from .ranges import (
    DENSITY_BOUNDS_G_CM3,
    DENSITY_RANGE_G_CM3,
    MAX_SEGMENTS,
    MODULUS_BOUNDS_GPA,
    MODULUS_RANGE_GPA,
    POLYMER_DENSITY_FLOOR_G_CM3,
    check_n_segments,
)

__all__ = [
    # leg designs (defined here)
    "NAMED_DESIGNS",
    "PAPER_DESIGN_ORDER",
    "LegDesign",
    "as_design",
    "order_designs",
    "paper_designs",
    "parse_design",
    "segment_masses",
    # re-exported: mat_hopper.core.catalogue
    "CATALOGUE",
    "MATERIAL_CLASSES",
    "MONO_NAMES",
    "Material",
    "bulk_density",
    "material",
    "porosity",
    # re-exported: mat_hopper.core.conventions
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
    # re-exported: mat_hopper.core.ranges
    "DENSITY_BOUNDS_G_CM3",
    "DENSITY_RANGE_G_CM3",
    "MAX_SEGMENTS",
    "MODULUS_BOUNDS_GPA",
    "MODULUS_RANGE_GPA",
    "POLYMER_DENSITY_FLOOR_G_CM3",
    "check_n_segments",
]


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
        string, a bare number or None in place of a sequence."""
        for arg, what in ((densities_g_cm3, "densities_g_cm3"), (moduli_gpa, "moduli_gpa")):
            # a string would be read a character at a time; a bare number is no sequence; a set has no order
            unordered = isinstance(arg, (set, frozenset, dict))
            if arg is None or isinstance(arg, (str, bytes)) or unordered or not isinstance(arg, Iterable):
                raise ValueError(f"{what} must be a sequence of numbers, one per segment (e.g. [2.7]); got {arg!r}")
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
        ValueError: an empty or unknown name (ending with "did you mean
            ...?" where a design or material is close:
            :func:`mat_hopper.util.parsing.did_you_mean`, e.g. ``rho_inc``
            for ``rho-inc``, ``PVC-Tii-SS`` for ``PVC-Ti-SS``), or a gradient
            with an empty name between its separators (``"SS--Ti"``,
            ``"-SS"``, ``"SS-"``).

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
    unknown = [p for p in parts if p.lower() not in CATALOGUE]
    if unknown:
        raise ValueError(_unknown_design(text.strip(), parts, unknown))
    if len(parts) == 1:
        return LegDesign.mono(parts[0], n_segments)
    mats = tuple(material(p) for p in parts)
    return LegDesign(mats, name="-".join(m.name for m in mats))


def _unknown_design(text: str, parts: list[str], unknown: list[str]) -> str:
    """The error of a design name with `unknown` material names among its
    `parts`: the accepted materials, and "did you mean ...?" for a named
    design spelt with other separators or case (``rho_inc``), a near
    material (``Tii``: ``Ti``) or a gradient whose every unknown part has
    one (``PVC-Tii-SS``: ``PVC-Ti-SS``)."""
    from ..util.parsing import close_names, did_you_mean

    known = [m.name for m in CATALOGUE.values()]
    accepted = f"accepted: {', '.join(known)}, a gradient like PVC-Ti-SS, or {', '.join(NAMED_DESIGNS)}"
    squash = lambda name: re.sub(r"[\s_\-/+.]+", "", name.lower())  # noqa: E731
    named = [n for n in NAMED_DESIGNS if squash(n) == squash(text)]
    if named:  # rho_inc, rho inc, rhoinc: a named design, not a gradient of materials "rho" and "inc"
        return f"unknown design {text!r}; {accepted}; did you mean {named[0]}?"
    fixes = {p: close_names(p, known) for p in unknown}
    if len(parts) == 1:
        hint = did_you_mean(text, [*known, *NAMED_DESIGNS])
    elif all(fixes.values()):  # PVC-Tii-SS: the gradient with each unknown name replaced by its nearest
        hint = f"did you mean {'-'.join(fixes[p][0] if p in fixes else material(p).name for p in parts)}?"
    else:
        hint = did_you_mean(text, NAMED_DESIGNS)
    where = f" in design {text!r}" if len(parts) > 1 else ""
    return f"unknown material {unknown[0]!r}{where}; {accepted}{f'; {hint}' if hint else ''}"


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
