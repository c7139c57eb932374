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

from ..core.materials import LegDesign, parse_design

_DENSITY_COL = re.compile(r"^density_(\d+)$")
_MODULUS_COL = re.compile(r"^modulus_(\d+)$")
_LOOKS_LIKE_PROPERTY = re.compile(r"^(dens|mod|rho\b|e_)", re.IGNORECASE)
# The record columns the tool writes beside a design, which a design table
# may carry and which are not read: batch's rows (mat_hopper.batch RESULT_COLUMNS,
# EXTRA_COLUMNS and the settings of mat_hopper.cli.batch), the leg's mass
# properties, and optimize --export's record (mat_hopper.optimize._export), whose
# objectives and their standard errors (<objective>_se) are the optimizer's
# metrics (mat_hopper.physics.run_metrics.METRICS). Any other column is refused.
RECORD_COLUMNS = (
    *("n_hops", "hop_height_m", "tracking_error_m", "power_w", "stable"),
    *(
        "behaviour",
        "sensor_timing",
        "diverged_at_s",
        "total_mass_kg",
        "backend",
        "upright",
        "fell_at_s",
        "suspect_at_s",
    ),
    *("run_tracking_error_m", "run_power_w", "convention", "duration_s", "transient_s", "timestep_s", "substeps"),
    *("leg_mass_kg", "leg_com_m", "hip_inertia_kg_m2"),
    *("study", "trial", "state", "profile", "segment_mass", "replicates", "risk", "behaviours", "objectives"),
    "feasible",
    "not_feasible_because",
)


def _record_names() -> str:
    """The record columns a design table may carry, as a message lists them."""
    from ..physics.run_metrics import METRICS

    metrics = [m for m in METRICS if m not in RECORD_COLUMNS]
    return ", ".join(RECORD_COLUMNS) + f", the optimizer's metrics ({', '.join(metrics)}) and their <metric>_se"


def _unknown_columns(names) -> list[str]:
    """Of a design table's column names, those neither a design column nor
    a record column (:data:`RECORD_COLUMNS`, the optimizer's metrics and
    their ``_se``)."""
    left = [
        n
        for n in names
        if n != "design" and n not in RECORD_COLUMNS and not (_DENSITY_COL.match(n) or _MODULUS_COL.match(n))
    ]
    if left:  # the optimizer's metrics, loaded only for a table that has more columns
        from ..physics.run_metrics import METRICS

        left = [n for n in left if n not in METRICS and n.removesuffix("_se") not in METRICS]
    return left


def parse_design_list(text: str) -> list[LegDesign]:
    """Designs from a comma-separated list of names.

    Args:
        text: e.g. ``"SS,rho-inc,PVC-Ti-SS"``.

    Returns:
        The LegDesigns, in order.

    Raises:
        ValueError: an empty item (``"SS,,PVC"``, as in every comma list of
            the CLI), an unknown name, or two items that name the same
            design: the same name in another case or with blanks
            (``"SS, ss"``), or another spelling of the same leg
            (``"SS,SS-SS-SS"``, ``"rho-inc,custom(...)"`` of its
            properties), which would be run twice.
    """
    names = [p.strip() for p in str(text).split(",")]
    if not any(names):
        raise ValueError(f"--designs needs at least one design name, got {text!r}")
    if not all(names):
        raise ValueError(f"--designs must be comma-separated design names, got {text!r} (an empty item)")
    designs, by_name, by_leg = [], {}, {}
    for n in names:
        d = parse_design(n)
        leg = (d.densities_g_cm3, d.moduli_gpa)  # the physics (mat_hopper.util.keys.design_key): the name is a label
        first = by_name.get(d.name.lower()) or by_leg.get(leg)
        if first is not None:
            what = f"name the same design ({d.name})" if d.name.lower() in by_name else "are the same leg"
            raise ValueError(f"--designs: {first!r} and {n!r} {what}; give each design once")
        by_name[d.name.lower()], by_leg[leg] = n, n
        designs.append(d)
    return designs


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


def _number(cell: str, where: str, column: str, rigid: bool) -> float | None:
    from ..util.parsing import parse_number

    try:
        return parse_number(cell, column, rigid=rigid, unit="GPa" if rigid else "g/cm^3")
    except ValueError as e:
        raise ValueError(f"{where}: {e}{' or rigid' if rigid and 'rigid' not in str(e) else ''}") from None


def _columns(columns, source: str) -> tuple[int, dict, dict]:
    """(segments, density columns, modulus columns) of a design table's
    header: every column known and unique, density_1..N and modulus_1..N
    both complete."""
    names = [str(c).strip() for c in columns]
    dup = sorted({c for c in names if names.count(c) > 1})
    if dup:
        raise ValueError(f"{source}: column {', '.join(dup)} appears more than once")
    dens = {int(m.group(1)): c for c, n in zip(columns, names, strict=True) if (m := _DENSITY_COL.match(n))}
    mods = {int(m.group(1)): c for c, n in zip(columns, names, strict=True) if (m := _MODULUS_COL.match(n))}
    # Other columns (a record the tool wrote beside the design: optimize --export's
    # study, trial, leg_mass_kg, ...) are not read; one that looks like a design
    # property but is not one ("modulas_2", "Density_1", "density 3") is a typo,
    # and any other is refused too (RECORD_COLUMNS).
    unknown = [
        n for n in names if _LOOKS_LIKE_PROPERTY.match(n) and not (_DENSITY_COL.match(n) or _MODULUS_COL.match(n))
    ]
    if unknown:
        raise ValueError(
            f"{source}: unknown column {', '.join(map(repr, unknown))}; design columns are density_1..density_N "
            "and modulus_1..modulus_N"
        )
    unknown = _unknown_columns(names)
    if unknown:
        raise ValueError(
            f"{source}: unknown column {', '.join(map(repr, unknown))}; a design table has density_1..density_N, "
            f"modulus_1..modulus_N, optionally design, and the record columns the tool writes: {_record_names()}"
        )
    if not dens:
        raise ValueError(f"{source}: needs columns density_1..density_N (g/cm^3) and modulus_1..modulus_N (GPa)")
    n_max = max(dens)
    if sorted(dens) != list(range(1, n_max + 1)):
        raise ValueError(f"{source}: density columns must be density_1..density_N without gaps, got {sorted(dens)}")
    missing = [f"modulus_{i}" for i in range(1, n_max + 1) if i not in mods]
    extra = [f"modulus_{i}" for i in sorted(mods) if i not in dens]
    if missing or extra:  # a rigid segment is said in its cell ('rigid'), never by a missing column
        raise ValueError(
            f"{source}: "
            + (f"no column {', '.join(missing)} (write 'rigid' in a cell for a rigid segment)" if missing else "")
            + (f"{'; ' if missing else ''}{', '.join(extra)} without its density column" if extra else "")
        )
    return n_max, dens, mods


def designs_from_frame(frame: pd.DataFrame, source: str = "table") -> list[LegDesign]:
    """Designs from a table, read strictly: the one reader of design tables.

    Args:
        frame: columns density_1..density_N (g/cm^3), modulus_1..modulus_N
            (GPa, or ``rigid``), and optionally ``design`` (names); none
            twice; the record columns the tool writes beside a design
            (:data:`RECORD_COLUMNS`, the optimizer's objectives and their
            ``_se``) are not read, any other column is refused (one named
            like a property, ``modulas_2``, ``Density_1``, as a typo). Every cell of a row's segments holds an ASCII
            decimal number in the material ranges (or ``rigid`` for a
            modulus); a row with fewer segments leaves both cells of each
            segment past its last one empty (as :func:`designs_to_frame`
            writes legs of different lengths).
        source: named in errors (the file).

    Returns:
        one LegDesign per row, in order.

    Raises:
        ValueError: naming the row and column of the first bad cell, a
            repeated or unknown column, a repeated design name, or two rows
            of the same leg (the same densities and moduli) under two names.
    """
    n_max, dens_cols, mod_cols = _columns(frame.columns, source)
    designs, names, legs = [], {}, {}
    for row_no, (_, row) in enumerate(frame.iterrows(), start=1):
        where = f"{source}, row {row_no}"
        cells = [(_cell(row[dens_cols[i]]), _cell(row[mod_cols[i]])) for i in range(1, n_max + 1)]
        n = max((i for i, (d, e) in enumerate(cells, 1) if d or e), default=0)
        if n == 0:
            raise ValueError(f"{where}: no densities (density_1 is empty)")
        dens, mods = [], []
        for i, (d, e) in enumerate(cells[:n], start=1):
            if not d or not e:
                empty = f"density_{i}" if not d else f"modulus_{i}"
                hint = " (write rigid for a rigid segment)" if d else ""
                raise ValueError(
                    f"{where}: {empty} is empty{hint}; the row reaches segment {n} of the table's {n_max}, so "
                    f"density_1..density_{n} and modulus_1..modulus_{n} are needed (only the cells past a row's "
                    "last segment may be empty)"
                )
            dens.append(_number(d, where, f"density_{i}", rigid=False))
            mods.append(_number(e, where, f"modulus_{i}", rigid=True))
        name = _cell(row["design"]) if "design" in frame.columns else ""
        if "design" in frame.columns and not name:
            raise ValueError(f"{where}: the design cell is empty (name every row, or drop the column)")
        try:
            design = LegDesign.from_properties(dens, mods, name=name)
        except ValueError as e:
            raise ValueError(f"{where}: {e}") from None
        key = design.name.lower()
        if key in names:
            raise ValueError(f"{where}: design name {design.name!r} is also row {names[key]}'s; names must be unique")
        leg = (design.densities_g_cm3, design.moduli_gpa)  # the physics (mat_hopper.util.keys.design_key)
        if leg in legs:
            other, other_name = legs[leg]
            raise ValueError(
                f"{where}: design {design.name!r} is the same leg as row {other} ({other_name!r}): the same "
                "densities and moduli; give each design once"
            )
        names[key] = row_no
        legs[leg] = (row_no, design.name)
        designs.append(design)
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
        ValueError: an empty name, a file pandas cannot parse, a column
            named twice (which pandas would rename), or a bad table
            (:func:`designs_from_frame`).
    """
    if path is None or not str(path).strip():
        raise ValueError("--designs-csv: empty file name")
    try:
        with warnings.catch_warnings():
            # a row longer than the header: pandas would shift it into an index, or drop fields
            warnings.simplefilter("error", pd.errors.ParserWarning)
            header = pd.read_csv(path, dtype=str, keep_default_na=False, index_col=False, header=None, nrows=1)
            _columns(list(header.iloc[0]) if len(header) else [], str(path))
            frame = pd.read_csv(path, dtype=str, keep_default_na=False, index_col=False)
    except pd.errors.ParserWarning:
        raise ValueError(f"{path}: a row has more fields than the header has columns") from None
    except (pd.errors.EmptyDataError, pd.errors.ParserError, UnicodeDecodeError) as e:
        reason = "empty file" if isinstance(e, pd.errors.EmptyDataError) else str(e).splitlines()[0]
        raise ValueError(f"{path}: not a CSV table of designs ({reason})") from None
    return designs_from_frame(frame, source=str(path))


def design_columns(design: LegDesign, n_max: int | None = None, segment_mass: str = "leg") -> dict:
    """A design's properties as output columns: density_1..N (g/cm^3),
    modulus_1..N (GPa, ``rigid`` where rigid), leg_mass_kg (everything
    below the hip, :func:`mat_hopper.core.control_legs.mass_properties`, as the hop
    table's column); NaN past its last segment up to n_max. Every table of
    designs carries them, so that its rows can be told apart and read back.

    Args:
        design: a LegDesign.
        n_max: the number of segment columns; None (the default) for the
            design's own number of segments. Columns past the design's last
            segment hold NaN; a smaller n_max than the design's segments
            leaves out the segments past it.
        segment_mass: the segment-mass convention of leg_mass_kg (``leg``,
            the default, or ``capsule``; :mod:`mat_hopper.core.materials`).

    Returns:
        A dict {column: value}: ``density_1``..``density_<n_max>`` (float,
        g/cm^3), then ``modulus_1``..``modulus_<n_max>`` (float GPa, or the
        string ``"rigid"``), then ``leg_mass_kg`` (float, kg).

    Raises:
        ValueError: an unknown segment-mass convention (from
            :func:`mat_hopper.core.control_legs.mass_properties`).
    """
    from ..core.control_legs import mass_properties

    n_max = design.n_segments if n_max is None else n_max
    row: dict = {}
    for i in range(1, n_max + 1):
        seg = design.segments[i - 1] if i <= design.n_segments else None
        row[f"density_{i}"] = math.nan if seg is None else seg.density_g_cm3
    for i in range(1, n_max + 1):
        seg = design.segments[i - 1] if i <= design.n_segments else None
        row[f"modulus_{i}"] = math.nan if seg is None else "rigid" if seg.rigid else seg.modulus_gpa
    row["leg_mass_kg"] = float(mass_properties(design, segment_mass).leg_mass_kg)
    return row


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
