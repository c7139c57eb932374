"""Porosity and stiffness: how a porous (less dense) version of a solid
changes its modulus, one named setting (``porosity_model``).

``independent``
    the paper's: only the density changes. Default.
``gibson-ashby``
    E = E_s (rho / rho_s)^n with n = 2 (open-cell, bending-dominated
    foams; Gibson & Ashby, Cellular Solids, 2nd ed., CUP 1997, ch. 5).
"""

from __future__ import annotations

from ..core.materials import Material
from ..util.parsing import check_positive, parse_name

# How a porous (less dense) version of a solid changes its modulus:
# "independent": the paper's, only the density changes; "gibson-ashby":
# E = E_s (rho / rho_s)^n with n = 2 (open-cell, bending-dominated foams;
# L. J. Gibson and M. F. Ashby, Cellular Solids, 2nd ed., CUP 1997, ch. 5:
# E / E_s = C1 (rho / rho_s)^2 with C1 about 1).
POROSITY_MODELS = ("independent", "gibson-ashby")
DEFAULT_POROSITY_MODEL = "independent"
GIBSON_ASHBY_EXPONENT = 2.0


def check_porosity_model(porosity_model: str) -> str:
    """The porosity model named (case-insensitive, blanks trimmed;
    :func:`mat_hopper.util.parsing.parse_name`), as spelled in
    :data:`POROSITY_MODELS`.

    Args:
        porosity_model: ``"independent"`` or ``"gibson-ashby"``, any case.

    Returns:
        The name as spelled in :data:`POROSITY_MODELS` (``"Gibson-Ashby"``
        gives ``"gibson-ashby"``).

    Raises:
        ValueError: an empty name or one not in :data:`POROSITY_MODELS` (the
            message lists them).
    """
    return parse_name(porosity_model, POROSITY_MODELS, "porosity_model")


def gibson_ashby_modulus(solid_modulus_gpa: float, relative_density: float, n: float = GIBSON_ASHBY_EXPONENT) -> float:
    """E = E_s (rho / rho_s)^n (GPa) of an open-cell foam of relative
    density rho / rho_s in (0, 1] (Gibson & Ashby 1997, ch. 5; n = 2, C1 = 1).

    Args:
        solid_modulus_gpa: the solid's modulus E_s, GPa (a finite int or
            float > 0, no bool).
        relative_density: rho / rho_s, dimensionless, in (0, 1].
        n: the exponent (default :data:`GIBSON_ASHBY_EXPONENT`, 2; not
            checked).

    Returns:
        E, GPa, a float.

    Raises:
        ValueError: a modulus or relative density that is not a finite int
            or float > 0 (a bool included), or a relative density above 1.
    """
    es, rel = check_positive(solid_modulus_gpa, "solid modulus"), check_positive(relative_density, "relative density")
    if rel > 1.0:
        raise ValueError(f"relative density must be in (0, 1], got {relative_density!r}")
    return es * rel**n


def porous_modulus(solid: Material, density_g_cm3: float, porosity_model: str = DEFAULT_POROSITY_MODEL) -> float | None:
    """The modulus (GPa) of ``solid`` made to density_g_cm3: its own under
    ``independent``; under ``gibson-ashby`` softened as
    :func:`gibson_ashby_modulus` where the density lies below the solid's
    (a denser-than-solid point cannot be porous and keeps E_s).

    Args:
        solid: the solid :class:`~mat_hopper.core.materials.Material` (its
            density, g/cm^3, and modulus, GPa).
        density_g_cm3: the porous version's density, g/cm^3 (read only
            under ``gibson-ashby``, below the solid's).
        porosity_model: ``"independent"`` (default) or ``"gibson-ashby"``,
            any case (:func:`check_porosity_model`).

    Returns:
        The modulus, GPa; None for a rigid solid (modulus None).

    Raises:
        ValueError: an unknown porosity model, or under ``gibson-ashby`` a
            density that is not a finite number > 0 (from
            :func:`gibson_ashby_modulus`).
    """
    porosity_model = check_porosity_model(porosity_model)
    if solid.rigid or porosity_model == "independent" or density_g_cm3 >= solid.density_g_cm3:
        return solid.modulus_gpa
    return gibson_ashby_modulus(solid.modulus_gpa, density_g_cm3 / solid.density_g_cm3)
