"""Tables that describe the model for reading: the designs' segments
(materials, densities g/cm^3, moduli GPa) and the joints of the compiled
MuJoCo hopper (stiffness N/m or N m/rad, damping, range m or rad).
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ..core.materials import LegDesign, paper_designs


def design_table(designs: dict[str, LegDesign] | None = None) -> pd.DataFrame:
    """One row per design and segment (1 nearest the base): design,
    segment, material, density_g_cm3, modulus_gpa (nan: rigid).

    Args:
        designs: designs by name; None: :func:`mat_hopper.core.materials.paper_designs`.

    Returns:
        DataFrame with columns design, segment (1, 2, ...), material (name), density_g_cm3 (g/cm^3),
        modulus_gpa (GPa, nan: rigid).
    """
    designs = paper_designs() if designs is None else designs
    rows = []
    for name, d in designs.items():
        for i, m in enumerate(d.segments, start=1):
            rows.append(
                {
                    "design": name,
                    "segment": i,
                    "material": m.name,
                    "density_g_cm3": m.density_g_cm3,
                    "modulus_gpa": np.nan if m.modulus_gpa is None else m.modulus_gpa,
                }
            )
    return pd.DataFrame(rows)


_JOINT_TYPES = {0: "free", 1: "ball", 2: "slide", 3: "hinge"}


def joint_table(design: LegDesign | str = "SS", convention: str = "paper") -> pd.DataFrame:
    """Every joint of the compiled hopper, from the base down: name, type
    (slide m, hinge rad), stiffness (N/m or N m/rad), damping, range (nan:
    unlimited), the body it moves.

    Args:
        design: the leg, or its name (:func:`mat_hopper.core.materials.parse_design`).
        convention: the stiffness convention the model is built with (:func:`mat_hopper.core.model.build_model`).

    Returns:
        DataFrame, one row per joint in MuJoCo's order. Columns: joint (name), type (free, ball, slide
        or hinge), body, stiffness (N/m or N m/rad), damping (N s/m or N m s/rad, of the joint's first
        degree of freedom), range_low, range_high (m or rad; nan: unlimited).

    Raises:
        ValueError: an unknown design name, or invalid arguments to :func:`mat_hopper.core.model.build_model`
            (e.g. an unknown convention).
    """
    from ..core.materials import parse_design
    from ..core.model import build_model

    d = parse_design(design) if isinstance(design, str) else design
    m = build_model(d, convention=convention).model
    rows = []
    for j in range(m.njnt):
        jt = m.joint(j)
        limited = bool(m.jnt_limited[j])
        lo, hi = (float(m.jnt_range[j, 0]), float(m.jnt_range[j, 1])) if limited else (np.nan, np.nan)
        rows.append(
            {
                "joint": jt.name,
                "type": _JOINT_TYPES.get(int(m.jnt_type[j]), str(m.jnt_type[j])),
                "body": m.body(int(m.jnt_bodyid[j])).name,
                "stiffness": float(m.jnt_stiffness[j]),
                "damping": float(m.dof_damping[m.jnt_dofadr[j]]),
                "range_low": lo,
                "range_high": hi,
            }
        )
    return pd.DataFrame(rows)
