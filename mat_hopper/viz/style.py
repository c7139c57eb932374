"""The figures' common style: colours and labels of designs and behaviours
(their order is the paper's: :func:`mat_hopper.core.materials.order_designs`,
:func:`mat_hopper.core.behaviours.order_behaviours`), metric units, log-axis ticks, and :func:`save_figure` (atomic,
dated-metadata-free PNG/SVG/PDF). Nothing here switches the matplotlib
backend: figures are ``matplotlib.figure.Figure`` objects.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pandas as pd
from matplotlib import rc_context
from matplotlib.figure import Figure
from matplotlib.ticker import FuncFormatter, LogLocator, NullFormatter

from ..util.atomic import atomic_path
from ..util.parsing import is_real

# --- style -------------------------------------------------------------------

STYLE = {
    "font.size": 9,
    "axes.titlesize": 10,
    "axes.labelsize": 9,
    "xtick.labelsize": 8,
    "ytick.labelsize": 8,
    "legend.fontsize": 8,
    "legend.frameon": False,
    "axes.spines.top": False,
    "axes.spines.right": False,
    "axes.grid": True,
    "axes.grid.axis": "y",
    "grid.alpha": 0.3,
    "grid.linewidth": 0.6,
    "svg.fonttype": "none",
    "svg.hashsalt": "mat-hopper",
}
DPI = 200

# Colour-blind-safe (seaborn "colorblind"), one colour per design everywhere
# (in materials.PAPER_DESIGN_ORDER).
DESIGN_COLOURS = {
    "MD": "#949494",
    "PVC": "#029e73",
    "Al": "#56b4e9",
    "Ti": "#cc78bc",
    "SS": "#0173b2",
    "rho-inc": "#de8f05",
    "rho-dec": "#d55e00",
    "PVC-Ti-SS": "#9467bd",
    "SS-Ti-PVC": "#8c564b",
}
_FALLBACK = ("#ece133", "#fbafe4", "#1f77b4", "#2ca02c", "#9467bd", "#17becf")
DESIGN_LABELS = {"rho-inc": "ρ-inc", "rho-dec": "ρ-dec"}
BEHAVIOUR_LABELS = {"static": "Static", "forward": "Forward", "ramp": "Ramp", "circle": "Circle"}
CLASS_COLOURS = {
    "metal": "#0173b2",
    "ceramic": "#d55e00",
    "polymer": "#029e73",
    "natural": "#de8f05",
    "composite": "#cc78bc",
    "reference": "#949494",
}

# metric column -> (label, SI unit, allow SI prefixes)
METRIC_INFO = {
    "power_w": ("Hip power", "W", True),
    "power_paper_w": ("Hip power, authors' formula", "W", True),
    "jerk_m_s3": ("Jerk", "m/s³", False),
    "tracking_error_m": ("Tracking error", "m", True),
    "hop_height_m": ("Hop height", "m", False),
    "energy_j": ("Energy per hop", "J", True),
}
_PREFIXES = ((1.0, ""), (1e-3, "m"), (1e-6, "µ"))


# Ashby-chart envelopes of the two material classes the paper uses (g/cm^3,
# GPa), drawn as rounded boxes in log-log space. Approximate extents read
# off Ashby's density-modulus chart (Ashby, "Materials Selection in
# Mechanical Design", 4th ed., 2011, fig. 4.3): metals 1.7-20 g/cm^3 and
# 40-400 GPa, technical ceramics 2.2-16 g/cm^3 and 100-1000 GPa; polymers
# 0.9-2 g/cm^3 and 0.2-10 GPa, natural materials 0.4-2 g/cm^3 and 0.1-30 GPa.
def _new_figure(width_in: float, height_in: float) -> Figure:
    return Figure(figsize=(width_in, height_in), dpi=100, layout="constrained")


def design_colour(design: str, i: int = 0) -> str:
    """The design's colour (fixed for the paper's designs).

    Args:
        design: the design name.
        i: index into the fallback colours, used for a design not in
            :data:`DESIGN_COLOURS` (cycled).

    Returns:
        A hex colour string, e.g. ``"#0173b2"``.
    """
    return DESIGN_COLOURS.get(design, _FALLBACK[i % len(_FALLBACK)])


def design_label(design: str) -> str:
    """The design's name as the figures print it (``rho-inc`` as ``ρ-inc``).

    Args:
        design: the design name.

    Returns:
        Its label in :data:`DESIGN_LABELS`, else the name itself.
    """
    return DESIGN_LABELS.get(design, design)


def metric_scale(metric: str, values=None) -> tuple[float, str]:
    """(factor, axis label with unit) for a metric: values times factor are
    in the labelled unit; an SI prefix is chosen so typical values are >= 1.

    Args:
        metric: the metric column; those of :data:`METRIC_INFO` get a label and
            unit, any other is its own label.
        values: the metric's values (array-like, SI), whose median magnitude
            (finite, non-zero values) picks the prefix (none, m or µ); None:
            no prefix. Only the metrics of :data:`METRIC_INFO` allowing
            prefixes take one.

    Returns:
        (factor, label): the multiplier (1, 1e3 or 1e6) and the axis label,
        e.g. ``(1000.0, "Tracking error (mm)")``.
    """
    label, unit, prefixes = METRIC_INFO.get(metric, (metric, "", False))
    factor, prefix = 1.0, ""
    if prefixes and values is not None:
        v = np.abs(np.asarray(values, dtype=float))
        v = v[np.isfinite(v) & (v > 0)]
        if len(v):
            typical = float(np.median(v))
            for f, p in _PREFIXES:
                factor, prefix = 1.0 / f, p
                if typical >= f:
                    break
    return factor, (f"{label} ({prefix}{unit})" if unit else label)


def _panel_label(ax, letter: str):
    ax.text(-0.02, 1.02, letter, transform=ax.transAxes, fontsize=12, fontweight="bold", ha="right", va="bottom")


def plain_log_ticks(axis) -> None:
    """Plain-number tick labels (0.5, 1, 2, 5, 10, ...) on a log axis
    (an ``ax.xaxis``, ``ax.yaxis`` or a colorbar's ``cb.ax.yaxis``); 1-2-5
    steps when the axis spans fewer than three decades.

    Args:
        axis: the matplotlib ``Axis``, already on a log scale with its view
            limits set (they choose the steps).
    """
    lo, hi = sorted(abs(v) for v in axis.get_view_interval())
    decades = math.log10(hi / lo) if lo > 0 and hi > 0 else 10.0
    subs = (1.0, 2.0, 5.0) if decades < 3 else (1.0,)
    axis.set_major_locator(LogLocator(base=10, subs=subs))
    axis.set_major_formatter(FuncFormatter(_plain_number))
    axis.set_minor_formatter(NullFormatter())


def _plain_number(x, _pos=None) -> str:
    if x == 0 or not np.isfinite(x):
        return ""
    if 1e-3 <= abs(x) < 1e5:
        return f"{x:g}"
    return f"{x:.0e}".replace("e-0", "e-").replace("e+0", "e")


def _require(table: pd.DataFrame, columns, what: str):
    missing = [c for c in columns if c not in table.columns]
    if missing:
        raise ValueError(f"{what} needs columns {missing}; the table has {list(table.columns)}")


# --- saving --------------------------------------------------------------------


def save_figure(fig: Figure, path_stem, *, formats=("png", "svg"), dpi: int = DPI) -> list[Path]:
    """Write `fig` as ``<path_stem>.png`` and ``<path_stem>.svg`` (folders
    made as needed), each atomically: a temp file in the same folder, then
    ``os.replace``. Metadata carry no date, so the same figure gives the
    same files. Returns the paths written.

    Args:
        fig: the ``matplotlib.figure.Figure``.
        path_stem: the file path without extension (str or path); a
            ``.png``, ``.svg`` or ``.pdf`` suffix is dropped.
        formats: the formats written, in order, among ``"png"``, ``"svg"``
            and ``"pdf"``.
        dpi: resolution, dots per inch.

    Returns:
        The paths written, ``<path_stem>.<format>`` per format.

    Raises:
        ValueError: `formats` empty or a plain string, a format not among
            png, svg, pdf, or a `dpi` that is not a finite number > 0 (all
            checked before any folder or file is written).
    """
    if isinstance(formats, str):
        raise ValueError(f"formats must be a sequence of formats, e.g. ('png',), not the string {formats!r}")
    formats = list(formats)
    if not formats:
        raise ValueError("formats must name at least one of png, svg, pdf")
    bad = [f for f in formats if f not in ("png", "svg", "pdf")]
    if bad:
        raise ValueError(f"formats must be among png, svg, pdf; got {', '.join(map(repr, bad))}")
    if not is_real(dpi) or not (math.isfinite(dpi) and dpi > 0):
        raise ValueError(f"dpi must be a finite number > 0, got {dpi!r}")
    stem = Path(path_stem)
    if stem.suffix.lower() in (".png", ".svg", ".pdf"):
        stem = stem.with_suffix("")
    stem.parent.mkdir(parents=True, exist_ok=True)
    written = []
    for fmt in formats:
        target = stem.parent / f"{stem.name}.{fmt}"
        meta = {"Software": None} if fmt == "png" else {"Date": None} if fmt == "svg" else {"CreationDate": None}
        with (
            atomic_path(target) as tmp,
            rc_context({"svg.hashsalt": STYLE["svg.hashsalt"], "svg.fonttype": STYLE["svg.fonttype"]}),
        ):
            fig.savefig(tmp, format=fmt, dpi=dpi, metadata=meta)
        written.append(target)
    return written
