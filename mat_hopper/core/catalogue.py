"""The material catalogue: the :class:`Material` record (density g/cm^3,
modulus GPa, Ashby class), the named materials of the paper and the Ashby
chapter (:data:`CATALOGUE`), and the porosity <-> bulk-density conversions.

The paper's five (MD, PVC, Al, Ti, SS) come from :mod:`mat_hopper.core.reference`
(the authors' code); the others are typical mid-range values from
M. F. Ashby, "Materials Selection in Mechanical Design", 4th ed. (2011),
and U. G. K. Wegst & M. F. Ashby, Phil. Mag. 84 (2004), each with its
source. A material's density and modulus must lie in the accepted ranges of
:mod:`mat_hopper.core.ranges`.
"""

from __future__ import annotations

from dataclasses import dataclass

from ..util.parsing import parse_name
from . import reference as ref
from .ranges import DENSITY_RANGE_G_CM3, MODULUS_RANGE_GPA, _check_number

__all__ = ["CATALOGUE", "MATERIAL_CLASSES", "MONO_NAMES", "Material", "bulk_density", "material", "porosity"]

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
        from ..util.parsing import did_you_mean

        known = [m.name for m in CATALOGUE.values()]
        hint = f"; {did_you_mean(name, known)}" if isinstance(name, str) and did_you_mean(name, known) else ""
        raise ValueError(f"unknown material {name!r}; accepted: {', '.join(known)}{hint}") from None


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
