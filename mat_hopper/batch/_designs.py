"""Designs for a batch: parsing, CSV input, grouping by model topology.

One batched simulation holds one compiled topology. Two designs share it
when they have the same number of segments and the same segments are rigid
(a rigid segment has no spring joint: the paper's MD leg has none at all).
Densities and moduli then only change per-world masses, inertias and
spring stiffnesses.
"""

from __future__ import annotations

import math
import re
import warnings
from collections import OrderedDict
from collections.abc import Iterable, Sequence

import pandas as pd

from ..materials import LegDesign, parse_design

_DENSITY_COL = re.compile(r"^density_(\d+)$")
_MODULUS_COL = re.compile(r"^modulus_(\d+)$")
_RIGID = ("", "rigid", "none", "inf")


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


def parse_design_list(text: str) -> list[LegDesign]:
    """Designs from a comma-separated list of names.

    Args:
        text: e.g. ``"SS,rho-inc,PVC-Ti-SS"``.

    Returns:
        The LegDesigns, in order.

    Raises:
        ValueError: an empty item (``"SS,,PVC"``, as in every comma list of the CLI) or an unknown name.
    """
    names = [p.strip() for p in str(text).split(",")]
    if not any(names):
        raise ValueError(f"--designs needs at least one design name, got {text!r}")
    if not all(names):
        raise ValueError(f"--designs must be comma-separated design names, got {text!r} (an empty item)")
    return [parse_design(n) for n in names]


def topology_key(design: LegDesign) -> tuple[bool, ...]:
    """Which segments are rigid, base to foot: equal keys compile to one topology.

    Args:
        design: a LegDesign.

    Returns:
        One bool per segment, True where rigid.
    """
    return tuple(m.rigid for m in design.segments)


def group_by_topology(designs: Sequence[LegDesign]) -> OrderedDict[tuple[bool, ...], list[int]]:
    """The designs grouped by topology (one compiled model per group).

    Args:
        designs: LegDesigns.

    Returns:
        {topology key: indices of its designs}, groups and indices in input order.
    """
    groups: OrderedDict[tuple[bool, ...], list[int]] = OrderedDict()
    for i, d in enumerate(designs):
        groups.setdefault(topology_key(d), []).append(i)
    return groups


def _cell(value) -> str:
    if value is None or (isinstance(value, float) and math.isnan(value)):
        return ""
    return str(value).strip()


def designs_from_frame(frame: pd.DataFrame, source: str = "table") -> list[LegDesign]:
    """Designs from a table of per-segment properties.

    Args:
        frame: columns density_1..density_N (g/cm^3) and modulus_1..modulus_N
            (GPa; empty or ``rigid`` for a rigid segment), and an optional
            ``design`` column of names. A row's segment count is its number of
            densities (density_1 .. density_n, no gaps).
        source: how errors name the table (e.g. its file).

    Returns:
        One LegDesign per row, in row order.

    Raises:
        ValueError: a missing column, a gap, or a value out of range (naming row and column).
    """
    dens_cols = {int(m.group(1)): c for c in frame.columns if (m := _DENSITY_COL.match(str(c).strip()))}
    mod_cols = {int(m.group(1)): c for c in frame.columns if (m := _MODULUS_COL.match(str(c).strip()))}
    if not dens_cols:
        raise ValueError(f"{source}: needs columns density_1..density_N (g/cm^3) and modulus_1..modulus_N (GPa)")
    n_max = max(dens_cols)
    if min(dens_cols) < 1 or sorted(dens_cols) != list(range(1, n_max + 1)):
        raise ValueError(
            f"{source}: density columns must be density_1..density_N without gaps, got {sorted(dens_cols)}"
        )
    missing = [f"modulus_{i}" for i in range(1, n_max + 1) if i not in mod_cols]
    if missing:  # a rigid segment is said in its cell ('rigid' or empty), never by a missing column
        raise ValueError(
            f"{source}: no column {', '.join(missing)} (write 'rigid' or leave the cell empty for a rigid segment)"
        )
    designs = []
    for row_no, (_, row) in enumerate(frame.iterrows(), start=1):
        dens, mods = [], []
        for i in range(1, n_max + 1):
            d = _cell(row[dens_cols[i]])
            if not d:
                break
            try:
                dens.append(float(d))
            except ValueError:
                raise ValueError(f"{source}, row {row_no}: density_{i} must be a number in g/cm^3, got {d!r}") from None
            e = _cell(row[mod_cols[i]]) if i in mod_cols else ""
            if e.lower() in _RIGID:
                mods.append(None)
            else:
                try:
                    mods.append(float(e))
                except ValueError:
                    raise ValueError(
                        f"{source}, row {row_no}: modulus_{i} must be a number in GPa or 'rigid', got {e!r}"
                    ) from None
        if not dens:
            raise ValueError(f"{source}, row {row_no}: no densities (density_1 is empty)")
        name = _cell(row["design"]) if "design" in frame.columns else ""
        try:
            designs.append(LegDesign.from_properties(dens, mods, name=name))
        except ValueError as e:
            raise ValueError(f"{source}, row {row_no}: {e}") from None
    if not designs:
        raise ValueError(f"{source}: no designs (the table has no rows)")
    return designs


def designs_from_csv(path) -> list[LegDesign]:
    """Designs from a CSV file.

    Args:
        path: the file, columns as :func:`designs_from_frame` reads them.

    Returns:
        One LegDesign per row.

    Raises:
        ValueError: an empty name, a file pandas cannot parse, or a bad table (:func:`designs_from_frame`).
    """
    if path is None or not str(path).strip():
        raise ValueError("--designs-csv: empty file name")
    try:
        with warnings.catch_warnings():
            # a row longer than the header: pandas would shift it into an index, or drop fields
            warnings.simplefilter("error", pd.errors.ParserWarning)
            frame = pd.read_csv(path, dtype=str, keep_default_na=False, index_col=False)
    except pd.errors.ParserWarning:
        raise ValueError(f"{path}: a row has more fields than the header has columns") from None
    except (pd.errors.EmptyDataError, pd.errors.ParserError, UnicodeDecodeError) as e:
        reason = "empty file" if isinstance(e, pd.errors.EmptyDataError) else str(e).splitlines()[0]
        raise ValueError(f"{path}: not a CSV table of designs ({reason})") from None
    return designs_from_frame(frame, source=str(path))


def designs_to_frame(designs: Iterable[LegDesign]) -> pd.DataFrame:
    """The inverse of :func:`designs_from_frame`.

    Args:
        designs: LegDesigns.

    Returns:
        One row per design: design, density_1..density_N (g/cm^3),
        modulus_1..modulus_N (GPa, ``"rigid"`` where rigid).
    """
    designs = list(designs)
    n_max = max(d.n_segments for d in designs)
    rows = []
    for d in designs:
        row = {"design": d.name}
        for i in range(1, n_max + 1):
            seg = d.segments[i - 1] if i <= d.n_segments else None
            row[f"density_{i}"] = "" if seg is None else repr(seg.density_g_cm3)
            row[f"modulus_{i}"] = "" if seg is None else ("rigid" if seg.rigid else repr(seg.modulus_gpa))
        rows.append(row)
    return pd.DataFrame(rows)
