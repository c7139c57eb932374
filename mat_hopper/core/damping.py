"""How the leg's material springs dissipate energy: one named setting,
``SimSettings.damping``.

``authors``
    every joint 1 N s/m (or N m s/rad), the authors' file. Default.
``loss-factor``
    each material spring's damping from its material's loss factor eta
    (:func:`loss_factor`, :func:`spring_damping`), per material class with
    published sources (:data:`LOSS_FACTORS`).
"""

from __future__ import annotations

import math

from ..util.parsing import parse_name
from .materials import Material

# How the material springs dissipate (one named setting, SimSettings.damping):
# "authors": every joint 1 N s/m (or N m s/rad), the authors' file;
# "loss-factor": each material spring's damping from its material's loss
# factor eta (:func:`loss_factor`, :func:`spring_damping`).
DAMPINGS = ("authors", "loss-factor")
DEFAULT_DAMPING = "authors"
# Loss factor eta (dimensionless) per material class: mid-range values of the
# loss-coefficient chart of M. F. Ashby, Materials Selection in Mechanical
# Design, 4th ed. (2011), fig. 4.9 (metals 1e-4 to 1e-3, engineering
# polymers 1e-2 to 1e-1, technical ceramics 1e-5 to 1e-4, composites about
# 1e-3 to 1e-2); natural: bone about 1e-2 (R. S. Lakes, Viscoelastic
# Materials, CUP 2009, ch. 10: tan delta of compact bone 0.01-0.02).
LOSS_FACTORS = {
    "metal": 1e-3,
    "polymer": 5e-2,
    "ceramic": 1e-4,
    "composite": 5e-3,
    "natural": 1e-2,
}


def check_damping(damping: str) -> str:
    """The damping setting named (case-insensitive, blanks trimmed;
    :func:`mat_hopper.util.parsing.parse_name`), as spelled in :data:`DAMPINGS`.

    Args:
        damping: ``"authors"`` or ``"loss-factor"``, any case.

    Returns:
        The name as spelled in :data:`DAMPINGS` (``"Loss-Factor"`` gives
        ``"loss-factor"``).

    Raises:
        ValueError: an empty name or one not in :data:`DAMPINGS` (the
            message lists them).
    """
    return parse_name(damping, DAMPINGS, "damping")


def loss_factor_class(mat: Material) -> str:
    """The class a material's loss factor and S-N curve are read by: its
    own where :data:`LOSS_FACTORS` lists it; else ("custom": designs from
    properties, the sweeps) the class its modulus falls in on Ashby's
    loss-coefficient chart: >= 30 GPa metal, 1-30 GPa composite, < 1 GPa
    polymer.

    Args:
        mat: the :class:`~mat_hopper.core.materials.Material` (elastic).

    Returns:
        A key of :data:`LOSS_FACTORS`: the material's own ``material_class``
        where listed, else ``"metal"``, ``"composite"`` or ``"polymer"`` by
        its modulus (GPa).

    Raises:
        ValueError: a rigid material (modulus None: no spring).
    """
    if mat.rigid:
        raise ValueError(f"material {mat.name} is rigid: it has no spring")
    if mat.material_class in LOSS_FACTORS:
        return mat.material_class
    e = mat.modulus_gpa
    return "metal" if e >= 30.0 else "composite" if e >= 1.0 else "polymer"


def loss_factor(mat: Material) -> float:
    """A material's loss factor eta: its class's (:data:`LOSS_FACTORS`,
    class by :func:`loss_factor_class`). Raises ValueError for a rigid one.

    Args:
        mat: the :class:`~mat_hopper.core.materials.Material` (elastic).

    Returns:
        The loss factor eta (dimensionless), e.g. 1e-3 for a metal.

    Raises:
        ValueError: a rigid material (from :func:`loss_factor_class`).
    """
    return LOSS_FACTORS[loss_factor_class(mat)]


def spring_damping(eta: float, stiffness: float, inertia: float) -> float:
    """Viscous damping (N s/m or N m s/rad) of a spring of this stiffness
    (N/m or N m/rad) on a degree of freedom of this inertia (kg or kg m^2,
    MuJoCo's dof_M0): c = eta sqrt(k m), i.e. a damping ratio zeta = eta / 2,
    the hysteretic loss factor's equivalent at the spring's own frequency
    sqrt(k / m) (Lakes 2009, ch. 2).

    Args:
        eta: the loss factor (dimensionless, :func:`loss_factor`).
        stiffness: the spring's stiffness k, N/m (slide) or N m/rad (hinge).
        inertia: the degree of freedom's inertia m, kg (slide) or kg m^2
            (hinge).

    Returns:
        The damping coefficient c = eta sqrt(k m), N s/m or N m s/rad.

    Raises:
        ValueError: stiffness x inertia < 0 (from :func:`math.sqrt`).
    """
    return eta * math.sqrt(stiffness * inertia)
