"""Maps of the material space: the measured stable time step over density
and modulus (:func:`stability_figure`), the Ashby chart of the catalogue
(:func:`ashby_figure`, :func:`catalogue_table`) and the leg designs side by
side (:func:`designs_figure`).
"""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
from matplotlib import rc_context
from matplotlib.colors import LogNorm
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Patch, Polygon, Rectangle
from matplotlib.ticker import FuncFormatter

from ..core.materials import CATALOGUE, DENSITY_BOUNDS_G_CM3, MODULUS_BOUNDS_GPA, LegDesign, Material
from .style import (
    CLASS_COLOURS,
    STYLE,
    _new_figure,
    _panel_label,
    _plain_number,
    _require,
    design_label,
    plain_log_ticks,
)

# Ashby-chart envelopes of the two material classes the paper uses (g/cm^3,
# GPa), drawn as rounded boxes in log-log space. Approximate extents read
# off Ashby's density-modulus chart (Ashby, "Materials Selection in
# Mechanical Design", 4th ed., 2011, fig. 4.3): metals 1.7-20 g/cm^3 and
# 40-400 GPa, technical ceramics 2.2-16 g/cm^3 and 100-1000 GPa; polymers
# 0.9-2 g/cm^3 and 0.2-10 GPa, natural materials 0.4-2 g/cm^3 and 0.1-30 GPa.
CLASS_REGIONS = {
    "metals and ceramics": {
        "density_g_cm3": (1.5, 22.0),
        "modulus_gpa": (30.0, 1200.0),
        "classes": ("metal", "ceramic"),
        "colour": "#0173b2",
    },
    "polymers and natural composites": {
        "density_g_cm3": (0.4, 2.2),
        "modulus_gpa": (0.08, 30.0),
        "label": "polymers and\nnatural composites",
        "classes": ("polymer", "natural"),
        "colour": "#029e73",
    },
}
# Design bounds of the material search (paper, Fig. 2 B: about 0.9-20 g/cm^3
# and 0.1-1000 GPa): the optimizer's own (mat_hopper.optimize._space).
DESIGN_BOUNDS = {"density_g_cm3": DENSITY_BOUNDS_G_CM3, "modulus_gpa": MODULUS_BOUNDS_GPA}


# --- stability ---------------------------------------------------------------------


def _edges(centres: np.ndarray) -> np.ndarray:
    """Cell edges (geometric midpoints) around log-spaced centres."""
    c = np.log(np.asarray(centres, dtype=float))
    if len(c) == 1:
        return np.exp(np.array([c[0] - 0.1, c[0] + 0.1]))
    mid = (c[1:] + c[:-1]) / 2
    return np.exp(np.concatenate([[c[0] - (mid[0] - c[0])], mid, [c[-1] + (c[-1] - mid[-1])]]))


MEASURED_COLUMNS = ("max_stable_timestep_s", "dt_stable_s", "spec_timestep_s", "dt_spec_s")
ANALYTIC_COLUMNS = ("analytic_timestep_s", "dt_estimate_s")
ANALYTIC_LABELS = {
    "analytic_timestep_s": "2/ω_max",
    "dt_estimate_s": "2/ω_max",
    "combined_timestep_s": "min(2/ω_max, controller limit)",
}


def stability_figure(
    stab: pd.DataFrame,
    *,
    materials=("PVC", "Al", "Ti", "SS"),
    convention: str | None = None,
    measured: str | None = None,
    analytic: str | None = None,
) -> Figure:
    """The largest stable time step (s) over density and modulus, measured
    (heat map, log colour scale; hatched: no tried step was stable) with
    the analytic estimate 2 / omega_max as labelled contours (left), and
    measured against analytic (right, log-log, the line y = x).

    stab: one row per grid point: density_g_cm3, modulus_gpa, a measured
    step (`measured`, default the first present of
    :data:`MEASURED_COLUMNS`: max_stable_timestep_s, the bisection of
    :mod:`mat_hopper.physics.stability`; pass ``measured="spec_timestep_s"`` for
    the 20-step scan of docs/reference-hopper.md) and the estimate (`analytic`, default
    analytic_timestep_s; ``analytic="combined_timestep_s"`` adds the
    controller limit); materials: catalogue names
    marked on the map; convention: keep the rows of this convention (when
    the table has a convention column) and name it in the title.

    Args:
        stab: the stability table, one row per grid point (and convention);
            several rows of one grid point keep the smallest steps.
        materials: catalogue names marked on the map (names not in the
            catalogue, rigid materials and those outside the map are skipped).
        convention: the convention kept; None: the table's only one (if any).
        measured: the measured-step column (s); None: the first present of
            :data:`MEASURED_COLUMNS`.
        analytic: the estimate's column (s); None: the first present of
            :data:`ANALYTIC_COLUMNS`.

    Returns:
        The ``matplotlib.figure.Figure`` (panels A and B).

    Raises:
        ValueError: a table of several conventions without `convention`, a
            missing column (named), or no rows left.
    """
    t, convention, measured_name, an_label = _stability_columns(stab, convention, measured, analytic)
    rho = np.sort(t["density_g_cm3"].unique())
    mod = np.sort(t["modulus_gpa"].unique())

    def grid_of(values):
        return t.pivot(index="modulus_gpa", columns="density_g_cm3", values=values).reindex(index=mod, columns=rho)

    measured = grid_of("max_stable_timestep_s").to_numpy(float)
    present = np.isfinite(grid_of("_one").to_numpy(float))
    an = grid_of("analytic_timestep_s").to_numpy(float)
    finite = measured[np.isfinite(measured) & (measured > 0)]
    an_ok = an[np.isfinite(an) & (an > 0)]
    vals = np.concatenate([finite, an_ok])
    vmin, vmax = (float(vals.min()), float(vals.max())) if len(vals) else (1e-5, 1e-3)
    if vmin == vmax:
        vmin, vmax = vmin / 2, vmax * 2
    with rc_context({**STYLE, "axes.grid": False}):
        fig = _new_figure(10.0, 4.2)
        ax, ax2 = fig.subplots(1, 2, width_ratios=[1.35, 1.0])
        xe, ye = _edges(rho), _edges(mod)
        unstable = present & ~np.isfinite(measured)
        _draw_stability_map(fig, ax, xe, ye, measured, unstable, LogNorm(vmin=vmin, vmax=vmax), measured_name)
        if len(an_ok) and len(rho) > 1 and len(mod) > 1:
            _draw_analytic_contours(ax, rho, mod, an, an_ok)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlim(xe[0], xe[-1])
        ax.set_ylim(ye[0], ye[-1])
        plain_log_ticks(ax.xaxis)
        plain_log_ticks(ax.yaxis)
        ax.set_xlabel("Density (g/cm³)")
        ax.set_ylabel("Modulus (GPa)")
        _mark_materials(ax, materials, xe, ye)
        ax.set_title("Largest stable time step" + (f", {convention} convention" if convention else ""))
        _panel_label(ax, "A")
        handles = [Line2D([], [], color="black", ls="--", lw=0.9, label=f"analytic {an_label}")]
        if unstable.any():
            handles.append(Patch(facecolor="#dddddd", hatch="///", edgecolor="#777777", label="no tried step stable"))
        ax.legend(handles=handles, loc="lower right", frameon=True, fontsize=7)
        _draw_measured_vs_analytic(fig, ax2, t, vmin, vmax, an_label)
        _panel_label(ax2, "B")
    return fig


def _stability_columns(stab, convention, measured, analytic):
    """(one row per grid point: density_g_cm3, modulus_gpa,
    max_stable_timestep_s and analytic_timestep_s from the chosen columns, and
    _one; the convention; the measured column's name; the estimate's label)."""
    if "convention" in stab.columns:
        convs = sorted(stab["convention"].dropna().unique())
        if convention is not None:
            stab = stab[stab["convention"] == convention]
        elif len(convs) > 1:
            raise ValueError(f"stability_figure: the table holds conventions {convs}; pass convention=")
        elif convs:
            convention = convs[0]
    measured = measured or next((c for c in MEASURED_COLUMNS if c in stab.columns), MEASURED_COLUMNS[0])
    analytic = analytic or next((c for c in ANALYTIC_COLUMNS if c in stab.columns), ANALYTIC_COLUMNS[0])
    _require(stab, ("density_g_cm3", "modulus_gpa", measured, analytic), "stability_figure")
    an_label = ANALYTIC_LABELS.get(analytic, "")
    stab = stab.rename(columns={measured: "_measured", analytic: "_analytic"})[
        ["density_g_cm3", "modulus_gpa", "_measured", "_analytic"]
    ].rename(columns={"_measured": "max_stable_timestep_s", "_analytic": "analytic_timestep_s"})
    stab = stab.apply(pd.to_numeric, errors="coerce")
    if len(stab) == 0:
        raise ValueError("stability_figure: the table is empty")
    values = ["max_stable_timestep_s", "analytic_timestep_s"]
    t = stab.groupby(["modulus_gpa", "density_g_cm3"], as_index=False)[values].min()
    return t.assign(_one=1.0), convention, measured, an_label


def _draw_stability_map(fig, ax, xe, ye, measured, unstable, norm, measured_name) -> None:
    """The measured step as a heat map (hatched where no tried step was stable) and its colour bar."""
    mesh = ax.pcolormesh(xe, ye, np.ma.masked_invalid(measured), norm=norm, cmap="viridis", shading="flat")
    if unstable.any():
        ax.pcolormesh(
            xe,
            ye,
            np.ma.masked_where(~unstable, np.ones_like(measured)),
            cmap="Greys",
            vmin=0,
            vmax=4,
            hatch="///",
            shading="flat",
            edgecolor="#777777",
            linewidth=0,
        )
    cb = fig.colorbar(mesh, ax=ax, pad=0.02)
    cb.set_label("Largest stable time step, measured (s)" + (" (spec scan)" if "spec" in measured_name else ""))
    plain_log_ticks(cb.ax.yaxis)


def _draw_analytic_contours(ax, rho, mod, an, an_ok) -> None:
    """The analytic estimate as labelled white contours every half decade."""
    lo, hi = math.floor(math.log10(an_ok.min()) * 2) / 2, math.ceil(math.log10(an_ok.max()) * 2) / 2
    levels = 10 ** np.arange(lo, hi + 0.01, 0.5)
    levels = levels[(levels > an_ok.min()) & (levels < an_ok.max())]
    if len(levels):
        cs = ax.contour(
            rho, mod, np.ma.masked_invalid(an), levels=levels, colors="white", linewidths=0.9, linestyles="--"
        )
        ax.clabel(cs, fmt=lambda v: f"{v:.0e} s".replace("e-0", "e-"), fontsize=7, inline=True)


def _mark_materials(ax, materials, xe, ye) -> None:
    """The catalogue materials inside the map, as labelled white dots."""
    for name in materials:
        m = CATALOGUE.get(name.lower())
        if m is None or m.modulus_gpa is None:
            continue
        if not (xe[0] <= m.density_g_cm3 <= xe[-1] and ye[0] <= m.modulus_gpa <= ye[-1]):
            continue
        ax.plot(m.density_g_cm3, m.modulus_gpa, "o", ms=6, markerfacecolor="white", markeredgecolor="black")
        ax.annotate(
            m.name,
            (m.density_g_cm3, m.modulus_gpa),
            xytext=(5, 4),
            textcoords="offset points",
            fontsize=8,
            color="white",
            fontweight="bold",
        )


def _draw_measured_vs_analytic(fig, ax2, t, vmin, vmax, an_label) -> None:
    """Panel B: measured against analytic, log-log, coloured by density, the line y = x."""
    ok = t[np.isfinite(t["max_stable_timestep_s"]) & np.isfinite(t["analytic_timestep_s"])]
    sc = ax2.scatter(
        ok["analytic_timestep_s"],
        ok["max_stable_timestep_s"],
        c=ok["density_g_cm3"],
        cmap="cividis",
        norm=LogNorm(),
        s=16,
        edgecolor="none",
    )
    cb2 = fig.colorbar(sc, ax=ax2, pad=0.02)
    cb2.set_label("Density (g/cm³)")
    plain_log_ticks(cb2.ax.yaxis)
    lims = [vmin / 1.5, vmax * 1.5]
    ax2.plot(lims, lims, color="black", lw=0.8, ls=":", label="measured = analytic")
    ax2.set_xscale("log")
    ax2.set_yscale("log")
    ax2.set_xlim(lims)
    ax2.set_ylim(lims)
    ax2.set_aspect("equal")
    ax2.set_xlabel(f"Analytic estimate {an_label} (s)")
    ax2.set_ylabel("Measured largest stable step (s)")
    ax2.grid(True, which="major", alpha=0.3)
    ax2.legend(loc="upper left")


# --- Ashby ---------------------------------------------------------------------------


def catalogue_table(catalogue=None) -> pd.DataFrame:
    """The material catalogue as a table: name, density_g_cm3, modulus_gpa
    (nan for rigid), material_class, source.

    Args:
        catalogue: {name: Material} or an iterable of
            :class:`~mat_hopper.core.materials.Material`; None (the default):
            :data:`mat_hopper.core.materials.CATALOGUE`. An empty selection (an
            empty dict, list, ...) is a selection of no material: an empty
            table, not the whole catalogue.

    Returns:
        DataFrame, one row per material (none for an empty selection),
        columns ``name``, ``density_g_cm3`` (g/cm^3), ``modulus_gpa`` (GPa),
        ``material_class`` and ``source``.

    Raises:
        ValueError: a string, or an entry that is not a
            :class:`~mat_hopper.core.materials.Material` (checked before the
            table is made).
    """
    if catalogue is None:
        catalogue = CATALOGUE
    if isinstance(catalogue, (str, bytes)):
        raise ValueError(f"catalogue must be {{name: Material}} or Materials, not the string {catalogue!r}")
    mats = list(catalogue.values() if isinstance(catalogue, dict) else catalogue)
    bad = [m for m in mats if not isinstance(m, Material)]
    if bad:
        raise ValueError(f"catalogue entries must be Materials; got {bad[0]!r}")
    return pd.DataFrame(
        [
            {
                "name": m.name,
                "density_g_cm3": m.density_g_cm3,
                "modulus_gpa": np.nan if m.modulus_gpa is None else m.modulus_gpa,
                "material_class": m.material_class,
                "source": m.source,
            }
            for m in mats
        ],
        columns=["name", "density_g_cm3", "modulus_gpa", "material_class", "source"],
    )


def _superellipse(x_range, y_range, n: float = 6.0, points: int = 200) -> np.ndarray:
    """Vertices of a rounded box spanning the ranges in log10 space."""
    lx, ly = np.log10(x_range), np.log10(y_range)
    cx, cy, ax_, ay = lx.mean(), ly.mean(), (lx[1] - lx[0]) / 2, (ly[1] - ly[0]) / 2
    th = np.linspace(0, 2 * np.pi, points, endpoint=False)
    c, s = np.cos(th), np.sin(th)
    x = cx + ax_ * np.sign(c) * np.abs(c) ** (2 / n)
    y = cy + ay * np.sign(s) * np.abs(s) ** (2 / n)
    return 10 ** np.column_stack([x, y])


def ashby_figure(
    materials: pd.DataFrame | None = None, *, regions=None, bounds=None, highlight=("PVC", "Al", "Ti", "SS")
) -> Figure:
    """Density (g/cm^3) against modulus (GPa), log-log: the catalogue's
    materials by class, the paper's two material classes as shaded regions
    (:data:`CLASS_REGIONS`) and the design bounds (:data:`DESIGN_BOUNDS`,
    dashed). materials: a table like :func:`catalogue_table` (the default);
    rigid materials (no modulus) are left out.

    Args:
        materials: table with columns ``name``, ``density_g_cm3``,
            ``modulus_gpa`` and ``material_class``; None: :func:`catalogue_table`.
        regions: {name: region} shaded, each with ``density_g_cm3`` and
            ``modulus_gpa`` ranges (lo, hi), ``colour`` and an optional
            ``label``; None: :data:`CLASS_REGIONS`.
        bounds: ``{"density_g_cm3": (lo, hi), "modulus_gpa": (lo, hi)}``, the
            dashed box; None: :data:`DESIGN_BOUNDS`.
        highlight: names of the materials drawn large, ringed and in bold.

    Returns:
        The ``matplotlib.figure.Figure``.

    Raises:
        ValueError: `materials` lacks a required column.
    """
    t = catalogue_table() if materials is None else materials
    _require(t, ("name", "density_g_cm3", "modulus_gpa", "material_class"), "ashby_figure")
    t = t[np.isfinite(t["modulus_gpa"].astype(float))]
    regions = CLASS_REGIONS if regions is None else regions
    bounds = DESIGN_BOUNDS if bounds is None else bounds
    with rc_context({**STYLE, "axes.grid": False}):
        fig = _new_figure(6.0, 4.8)
        ax = fig.subplots()
        _draw_class_regions(ax, regions)
        (r0, r1), (e0, e1) = bounds["density_g_cm3"], bounds["modulus_gpa"]
        ax.add_patch(Rectangle((r0, e0), r1 - r0, e1 - e0, fill=False, ls="--", lw=1.0, edgecolor="black", zorder=1))
        ax.text(r1 * 0.93, e0 * 1.25, "design bounds", ha="right", va="bottom", fontsize=8)
        for cls in dict.fromkeys(t["material_class"]):
            _draw_material_class(ax, t[t["material_class"] == cls], cls, highlight)
        ax.set_xscale("log")
        ax.set_yscale("log")
        xs = [*t["density_g_cm3"], r0, r1] + [v for r in regions.values() for v in r["density_g_cm3"]]
        ys = [*t["modulus_gpa"], e0, e1] + [v for r in regions.values() for v in r["modulus_gpa"]]
        ax.set_xlim(min(xs) / 1.5, max(xs) * 1.5)
        ax.set_ylim(min(ys) / 2.5, max(ys) * 2.5)
        plain_log_ticks(ax.xaxis)
        ax.yaxis.set_major_formatter(FuncFormatter(_plain_number))
        ax.set_xlabel("Density ρ (g/cm³)")
        ax.set_ylabel("Young's modulus E (GPa)")
        ax.grid(True, which="major", alpha=0.25, axis="both")
        handles, labels = ax.get_legend_handles_labels()
        handles.append(
            Line2D(
                [],
                [],
                ls="none",
                marker="o",
                ms=8,
                markerfacecolor="white",
                markeredgecolor="black",
                label="the paper's materials",
            )
        )
        ax.legend(
            handles=handles, loc="upper left", frameon=True, fontsize=7.5, title="material class", title_fontsize=8
        )
    return fig


def _draw_class_regions(ax, regions) -> None:
    """The paper's material classes as shaded, labelled superellipses."""
    for name, r in regions.items():
        verts = _superellipse(r["density_g_cm3"], r["modulus_gpa"])
        ax.add_patch(
            Polygon(
                verts, closed=True, facecolor=r["colour"], alpha=0.12, edgecolor=r["colour"], linewidth=1.0, zorder=0
            )
        )
        ax.text(
            math.sqrt(r["density_g_cm3"][0] * r["density_g_cm3"][1]),
            r["modulus_gpa"][1] * 0.8,
            r.get("label", name),
            ha="center",
            va="top",
            color=r["colour"],
            fontsize=8.5,
            fontweight="bold",
            zorder=1,
        )


def _draw_material_class(ax, s, cls, highlight) -> None:
    """One class's materials: small dots, the highlighted ones large and ringed, every one named."""
    colour = CLASS_COLOURS.get(cls, "#333333")
    big = s["name"].isin(highlight)
    ax.scatter(
        s["density_g_cm3"][~big],
        s["modulus_gpa"][~big],
        s=28,
        color=colour,
        edgecolor="white",
        linewidth=0.6,
        zorder=3,
        label=cls,
    )
    ax.scatter(
        s["density_g_cm3"][big],
        s["modulus_gpa"][big],
        s=60,
        color=colour,
        edgecolor="black",
        linewidth=0.9,
        zorder=4,
        label=None if (~big).any() else cls,
    )
    for _, row in s.iterrows():
        ax.annotate(
            row["name"],
            (row["density_g_cm3"], row["modulus_gpa"]),
            xytext=(5, -3),
            textcoords="offset points",
            fontsize=7.5,
            zorder=5,
            fontweight="bold" if row["name"] in highlight else "normal",
        )


def designs_figure(designs: dict[str, LegDesign] | None = None):
    """The legs side by side: one column of segments per design (segment 1
    at the top, nearest the base), coloured by density (left panel) and by
    modulus (right panel, grey: rigid), both on log colour scales.

    Args:
        designs: {name: :class:`~mat_hopper.core.materials.LegDesign`}, in column
            order; None: :func:`mat_hopper.core.materials.paper_designs`.

    Returns:
        The ``matplotlib.figure.Figure``; each cell is labelled with its
        value (g/cm^3 or GPa) or "rigid".
    """
    from ..analysis.tables import design_table

    t = design_table(designs)
    names = list(dict.fromkeys(t["design"]))
    n_seg = int(t["segment"].max())
    with rc_context({**STYLE, "axes.grid": False}):
        fig = Figure(figsize=(9.0, 3.0), layout="constrained")
        axes = fig.subplots(1, 2)
        for ax, col, label, cmap in (
            (axes[0], "density_g_cm3", "Density (g/cm³)", "cividis"),
            (axes[1], "modulus_gpa", "Modulus (GPa)", "viridis"),
        ):
            grid = np.full((n_seg, len(names)), np.nan)
            for r in t.itertuples():
                grid[r.segment - 1, names.index(r.design)] = getattr(r, col)
            vals = grid[np.isfinite(grid)]
            norm = LogNorm(vmin=vals.min(), vmax=vals.max())
            ax.set_facecolor("#bbbbbb")
            mesh = ax.pcolormesh(
                np.arange(len(names) + 1),
                np.arange(n_seg + 1),
                np.ma.masked_invalid(grid),
                norm=norm,
                cmap=cmap,
                edgecolors="white",
                linewidth=1.5,
            )
            for (i, j), v in np.ndenumerate(grid):
                txt = "rigid" if not np.isfinite(v) else f"{v:.3g}"
                light = np.isfinite(v) and norm(v) < 0.5
                ax.text(
                    j + 0.5, i + 0.5, txt, ha="center", va="center", fontsize=8, color="white" if light else "black"
                )
            ax.set_xticks(np.arange(len(names)) + 0.5)
            ax.set_xticklabels([design_label(n) for n in names], rotation=45, ha="right")
            ax.set_yticks(np.arange(n_seg) + 0.5)
            ax.set_yticklabels([f"segment {i}" for i in range(1, n_seg + 1)])
            ax.invert_yaxis()
            ax.set_title(label + ", base at the top, foot at the bottom")
            cb = fig.colorbar(mesh, ax=ax, pad=0.01, fraction=0.05)
            cb.ax.minorticks_off()
            cb.set_ticks([v for v in (1, 2, 5, 10, 20, 50, 100, 200, 500, 1000) if vals.min() <= v <= vals.max()])
            cb.ax.yaxis.set_major_formatter("{x:g}")
    return fig
