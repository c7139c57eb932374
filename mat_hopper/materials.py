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
"""

from __future__ import annotations

import math
import re
from collections.abc import Iterable, Sequence
from dataclasses import dataclass

from . import reference as ref

CONVENTIONS = ("paper", "axial")
DEFAULT_CONVENTION = "paper"


def _check_number(value, field: str, accepted: str, *, allow_zero: bool = False) -> float:
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{field} must be a number {accepted}, got {value!r}") from None
    if not math.isfinite(x) or x < 0 or (x == 0 and not allow_zero):
        raise ValueError(f"{field} must be {accepted}, got {value!r}")
    return x


@dataclass(frozen=True)
class Material:
    """A material: bulk density in g/cm^3 and elastic modulus in GPa.

    ``modulus_gpa=None`` is a rigid material (no spring: the paper's MD).
    """

    name: str
    density_g_cm3: float
    modulus_gpa: float | None
    material_class: str = "custom"
    source: str = ""

    def __post_init__(self):
        d = _check_number(self.density_g_cm3, f"density of {self.name}", "finite and > 0 g/cm^3")
        object.__setattr__(self, "density_g_cm3", d)
        if self.modulus_gpa is not None:
            e = _check_number(self.modulus_gpa, f"modulus of {self.name}", "finite and > 0 GPa, or rigid")
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

MONO_NAMES = tuple(ref.MONO_MATERIALS)   # MD, PVC, Al, Ti, SS: the paper's five


def material(name: str) -> Material:
    """Catalogue material by name (case-insensitive)."""
    try:
        return CATALOGUE[name.strip().lower()]
    except (KeyError, AttributeError):
        known = ", ".join(m.name for m in CATALOGUE.values())
        raise ValueError(f"unknown material {name!r}; accepted: {known}") from None


# --- conversions -----------------------------------------------------------

def porosity(bulk_density_g_cm3: float, solid_density_g_cm3: float) -> float:
    """Porosity Phi = 1 - rho_b / rho_s (dimensionless, 0 for a solid)."""
    rb = _check_number(bulk_density_g_cm3, "bulk density", "finite and > 0 g/cm^3")
    rs = _check_number(solid_density_g_cm3, "solid density", "finite and > 0 g/cm^3")
    if rb > rs:
        raise ValueError(f"bulk density {rb} g/cm^3 exceeds solid density {rs} g/cm^3")
    return 1.0 - rb / rs


def bulk_density(porosity_fraction: float, solid_density_g_cm3: float) -> float:
    """Bulk density rho_b = rho_s (1 - Phi) in g/cm^3, for 0 <= Phi < 1."""
    phi = float(porosity_fraction)
    if not (0.0 <= phi < 1.0):
        raise ValueError(f"porosity must be in [0, 1), got {porosity_fraction!r}")
    rs = _check_number(solid_density_g_cm3, "solid density", "finite and > 0 g/cm^3")
    return rs * (1.0 - phi)


def check_convention(convention: str) -> str:
    if convention not in CONVENTIONS:
        raise ValueError(f"unknown stiffness convention {convention!r}; accepted: {', '.join(CONVENTIONS)}")
    return convention


def segment_length(n_segments: int) -> float:
    """Length in m of one material segment when 0.3 m is split in n."""
    return ref.MATERIAL_LENGTH / n_segments


def spring_stiffness(modulus_gpa: float, convention: str = DEFAULT_CONVENTION,
                     n_segments: int = ref.REFERENCE_SEGMENTS) -> float:
    """Axial spring stiffness in N/m for a segment of the given modulus (GPa)."""
    check_convention(convention)
    e = _check_number(modulus_gpa, "modulus", "finite and > 0 GPa")
    if convention == "paper":
        return ref.PAPER_STIFFNESS_PER_GPA * e
    area = math.pi * ref.MATERIAL_RADIUS**2
    return e * 1e9 * area / segment_length(n_segments)


def capsule_volume_m3(radius_m: float, length_m: float) -> float:
    """Volume in m^3 of a capsule: a cylinder of `length_m` with a
    hemispherical cap of `radius_m` at each end, V = pi r^2 L + 4/3 pi r^3."""
    return math.pi * radius_m**2 * length_m + 4.0 / 3.0 * math.pi * radius_m**3


def segment_masses(design: LegDesign) -> tuple[float, ...]:
    """Mass in kg of each material segment of a design, m = rho V, base to
    foot, as the model builds it: two half capsules of radius 0.025 m, each
    half a segment long (0.3 m of material split evenly), end caps
    included. The rest of the robot (base, hip stub, foot) is in
    :mod:`mat_hopper.model`; MuJoCo's total is ``build_model(d).total_mass_kg``."""
    half = segment_length(design.n_segments) / 2.0
    v_half = capsule_volume_m3(ref.MATERIAL_RADIUS, half)
    return tuple(2.0 * v_half * m.density_kg_m3 for m in design.segments)


# --- leg designs -----------------------------------------------------------

@dataclass(frozen=True)
class LegDesign:
    """A leg of N >= 1 material segments, segment 1 nearest the base."""

    segments: tuple[Material, ...]
    name: str = ""

    def __post_init__(self):
        segs = tuple(self.segments)
        if len(segs) < 1:
            raise ValueError("segments: a leg needs at least 1 segment (got 0)")
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

    @classmethod
    def mono(cls, mat: Material | str, n_segments: int = ref.REFERENCE_SEGMENTS) -> LegDesign:
        """A homogeneous leg of one material."""
        m = material(mat) if isinstance(mat, str) else mat
        n = int(n_segments)
        if n < 1:
            raise ValueError(f"n_segments must be >= 1, got {n_segments!r}")
        return cls((m,) * n, name=m.name)

    @classmethod
    def from_properties(cls, densities_g_cm3: Sequence[float],
                        moduli_gpa: Sequence[float | None], name: str = "") -> LegDesign:
        """A leg from per-segment densities (g/cm^3) and moduli (GPa, None = rigid)."""
        dens, mods = list(densities_g_cm3), list(moduli_gpa)
        if len(mods) == 1 and len(dens) > 1:
            mods = mods * len(dens)
        if len(dens) == 1 and len(mods) > 1:
            dens = dens * len(mods)
        if len(dens) != len(mods):
            raise ValueError(f"density and modulus need one value per segment (got {len(dens)} and {len(mods)})")
        segs = tuple(Material(f"seg{i + 1}", d, e) for i, (d, e) in enumerate(zip(dens, mods)))
        if not name and segs:
            name = "custom(" + ",".join(f"{d:g}/{'rigid' if e is None else f'{e:g}'}" for d, e in zip(dens, mods)) + ")"
        return cls(segs, name=name)


def _named_designs() -> dict[str, LegDesign]:
    inc = LegDesign.from_properties(ref.GRADIENT_DENSITIES, [ref.GRADIENT_MODULUS_GPA], name="rho-inc")
    dec = LegDesign.from_properties(ref.GRADIENT_DENSITIES[::-1], [ref.GRADIENT_MODULUS_GPA], name="rho-dec")
    return {"rho-inc": inc, "rho-dec": dec}


NAMED_DESIGNS = _named_designs()


def parse_design(text: str, n_segments: int = ref.REFERENCE_SEGMENTS) -> LegDesign:
    """A design from its name: a material (``SS``), a gradient (``PVC-Ti-SS``)
    or a named design (``rho-inc``, ``rho-dec``). Case-insensitive."""
    if not isinstance(text, str) or not text.strip():
        raise ValueError(f"design must be a material, a gradient like PVC-Ti-SS, or one of "
                         f"{', '.join(NAMED_DESIGNS)}; got {text!r}")
    key = text.strip().lower()
    for name, design in NAMED_DESIGNS.items():
        if key == name:
            return design
    parts = [p for p in re.split(r"[-_/]", text.strip()) if p]
    if len(parts) == 1:
        return LegDesign.mono(parts[0], n_segments)
    mats = tuple(material(p) for p in parts)
    return LegDesign(mats, name="-".join(m.name for m in mats))


def paper_designs() -> dict[str, LegDesign]:
    """The paper's mono-materials and gradients, by name."""
    out = {n: LegDesign.mono(n) for n in MONO_NAMES}
    out.update(NAMED_DESIGNS)
    for g in ("PVC-Ti-SS", "SS-Ti-PVC"):
        out[g] = parse_design(g)
    return out


def iter_catalogue() -> Iterable[Material]:
    return iter(CATALOGUE.values())
