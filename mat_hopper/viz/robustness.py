"""The robustness study at a glance: every quantity the paper's claims rest
on, under every variant of the settings, coloured by whether it keeps its
sign and size, moves more than 2x, or flips (:mod:`mat_hopper.analysis.robustness`).
Returns a ``matplotlib.figure.Figure`` (no backend switching).
"""

from __future__ import annotations

import numpy as np
import pandas as pd
from matplotlib import rc_context
from matplotlib.colors import ListedColormap
from matplotlib.figure import Figure
from matplotlib.patches import Patch, Rectangle

from ..analysis.robustness import CLASSES, FLIPS, KEEPS, MOVES, NO_VALUE
from .style import STYLE

CLASS_COLOURS = {KEEPS: "#cfe8cf", MOVES: "#f6c26b", FLIPS: "#e4572e", NO_VALUE: "#d9d9d9"}
DEFAULT_COLOUR = "#9ecae1"


def _cell_text(v: float) -> str:
    if not np.isfinite(v):
        return "–"
    return f"{v:+.0f}" if abs(v) < 1000 else f"{v:+.1e}"


def robustness_figure(table: pd.DataFrame, default: str = "authors"):
    """Rows: quantities (percent change of a design against its baseline);
    columns: the paper's figure, the default settings' value, then every
    variant. Cells show the value (%) coloured by its class against the
    default (light green keeps, orange moves > 2x, red flips, grey no
    value: a run diverged or fell). table: from
    :func:`mat_hopper.analysis.robustness.robustness_table`.

    Args:
        table: one row per quantity and variant, columns ``variant``,
            ``quantity_id`` (a row label), ``paper_pct`` (the paper's figure,
            %; the first row of each quantity is used), ``value_pct`` (%) and
            ``class`` (one of :data:`mat_hopper.analysis.robustness.CLASSES`;
            anything else is drawn as no value).
        default: the variant of the default settings, shown in its own
            column (a dash where the table has none); the other variants follow
            in table order.

    Returns:
        The ``matplotlib.figure.Figure``.

    Raises:
        ValueError: a required column is missing (named), or (pandas' pivot)
            a quantity with two rows of one variant.
    """
    need = ("variant", "quantity_id", "paper_pct", "value_pct", "class")
    missing = [c for c in need if c not in table.columns]
    if missing:
        raise ValueError(f"robustness_figure needs columns {missing}")
    quantities = list(dict.fromkeys(table["quantity_id"]))
    variants = [v for v in dict.fromkeys(table["variant"]) if v != default]
    values = table.pivot(index="quantity_id", columns="variant", values="value_pct").reindex(quantities)
    classes = table.pivot(index="quantity_id", columns="variant", values="class").reindex(quantities)
    paper = table.drop_duplicates("quantity_id").set_index("quantity_id")["paper_pct"].reindex(quantities)
    codes = {c: i for i, c in enumerate(CLASSES)}
    grid = np.array([[codes.get(classes.at[q, v], codes[NO_VALUE]) for v in variants] for q in quantities])
    cmap = ListedColormap([CLASS_COLOURS[c] for c in CLASSES])
    with rc_context(STYLE):
        fig = Figure(figsize=(2.2 + 0.78 * (len(variants) + 2), 0.9 + 0.3 * len(quantities)), layout="constrained")
        ax = fig.add_subplot()
        n = len(variants)
        ax.imshow(
            grid,
            cmap=cmap,
            vmin=-0.5,
            vmax=len(CLASSES) - 0.5,
            aspect="auto",
            extent=(1.5, n + 1.5, len(quantities) - 0.5, -0.5),
        )
        for i, q in enumerate(quantities):
            ax.add_patch(Rectangle((-0.5, i - 0.5), 1, 1, facecolor="#f2f2f2", edgecolor="none"))
            ax.text(
                0, i, _cell_text(float(paper[q])) if pd.notna(paper[q]) else "", ha="center", va="center", fontsize=7
            )
            ax.add_patch(Rectangle((0.5, i - 0.5), 1, 1, facecolor=DEFAULT_COLOUR, edgecolor="none"))
            d = values.at[q, default] if default in values.columns else np.nan
            ax.text(1, i, _cell_text(d), ha="center", va="center", fontsize=7, fontweight="bold")
            for j, v in enumerate(variants):
                ax.text(j + 2, i, _cell_text(values.at[q, v]), ha="center", va="center", fontsize=7)
        ax.set_xlim(-0.5, n + 1.5)
        ax.set_ylim(len(quantities) - 0.5, -0.5)
        ax.set_xticks(range(n + 2), ["paper", default, *variants], rotation=40, ha="right")
        ax.set_yticks(range(len(quantities)), quantities)
        ax.tick_params(length=0)
        for spine in ax.spines.values():
            spine.set_visible(False)
        ax.axvline(1.5, color="black", lw=0.8)
        ax.set_title("Percent change against the baseline, per setting (cells: value in %)", fontsize=9)
        handles = [Patch(facecolor=DEFAULT_COLOUR, label="default (authors' settings)")] + [
            Patch(facecolor=CLASS_COLOURS[c], label=c) for c in CLASSES
        ]
        fig.legend(handles=handles, loc="outside lower center", ncols=len(handles), fontsize=7, frameon=False)
    return fig
