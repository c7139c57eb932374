"""The book's findings page, read from the recorded paper-profile results.

The paper profile's answers (60 s runs scored after 20 s, 10 paired seeds)
take hours on a small machine, so the book keeps them as records
(``book/records/``, each with how it was made in its README). This module
turns those records into what a reader asks first, "what leg should I
build?", without running a simulation:

- :func:`read_records`: the record files as tables (a clear error names a
  missing file or column);
- :func:`findings_table`: one row per paper claim, its verdict and the
  controls it was held against;
- :func:`paired_effects`: every numeric paired effect of the records
  (percent change of a design against its comparator, with its 95 %
  interval), one tidy table;
- :func:`design_answer`: the answer in plain sentences, every number in
  it read from the records;
- :func:`forest_plot`: every paired effect as an interval against the
  ±10 % equivalence margin.

Percent changes are of the design against its comparator (negative: the
design's value is lower), in %; intervals are the records' 95 % paired t
intervals. Nothing here switches the matplotlib backend: a new figure is a
``matplotlib.figure.Figure``.
"""

from __future__ import annotations

import numpy as np
import pandas as pd
from matplotlib import rc_context
from matplotlib.figure import Figure

from ..analysis.paired import DIFFERENCE, NO_DIFFERENCE, NOT_ENOUGH, conclusion
from ._records import (
    DEFAULT_DOMINANCE,
    EFFECT_COLUMNS,
    FINDINGS_COLUMNS,
    MARGIN_PCT,
    METRIC_LABELS,
    NOT_COMPARED,
    NOT_RECORDED,
    RECORD_FILES,
    REQUIRED_COLUMNS,
    WINDOW_COLUMN,
    cell_text,
    findings_table,
    metric_label,
    paired_effects,
    read_records,
    rigid_twin_summary,
    verdict_changes,
)
from .style import STYLE

__all__ = [
    "DEFAULT_DOMINANCE",
    "EFFECT_COLUMNS",
    "FINDINGS_COLUMNS",
    "MARGIN_PCT",
    "METRIC_LABELS",
    "NOT_COMPARED",
    "NOT_RECORDED",
    "RECORDED",
    "RECORD_FILES",
    "REQUIRED_COLUMNS",
    "WINDOW_COLUMN",
    "beside_record",
    "design_answer",
    "findings_table",
    "forest_plot",
    "paired_effects",
    "read_records",
    "rigid_twin_summary",
    "verdict_changes",
]


def _pct(x: float) -> str:
    return f"{x:+.1f} %"


def _effect(row) -> str:
    return f"{_pct(row.pct_change)} [{row.ci_low:+.1f}, {row.ci_high:+.1f}]"


def _beyond_margin(row) -> bool:
    """A difference whose whole interval lies outside the ±10 % margin."""
    return row.ci_low > MARGIN_PCT or row.ci_high < -MARGIN_PCT


def _same_mass_sentence(effects: pd.DataFrame) -> str:
    """Tracking error only (one metric, so no pooling of metrics), per kind
    of same-mass control: equivalent, differing beyond the margin (the whole
    interval outside it), differing within it, not enough evidence."""
    same = effects[effects["same_mass"] & (effects["metric"] == "tracking_error_m")]
    if same.empty:
        return ""
    parts = []
    for group, g in same.groupby("group", sort=False):
        differ = g[g["conclusion"] == DIFFERENCE]
        beyond = int(sum(_beyond_margin(r) for r in differ.itertuples()))
        parts.append(
            f"{group.split(': ', 1)[-1]}: {int((g['conclusion'] == NO_DIFFERENCE).sum())} of {len(g)} equivalent, "
            f"{beyond} beyond the margin, {len(differ) - beyond} within it, "
            f"{int((g['conclusion'] == NOT_ENOUGH).sum())} not enough evidence"
        )
    return (
        f"Tracking error against a control of the same leg mass, per kind of control (paired, ±{MARGIN_PCT:.0f} % "
        f"margin; a rigid twin differs from its design in the springs alone, a mass-matched or homogeneous leg in "
        f"density and modulus together): " + "; ".join(parts) + "."
    )


def _crossed_sentence(crossed: pd.DataFrame) -> str:
    tracking = crossed[crossed["metric"] == "tracking_error_m"].copy()
    tracking["conclusion"] = [
        conclusion(p, lo, hi) for p, lo, hi in zip(tracking["p_holm"], tracking["ci_low"], tracking["ci_high"])
    ]
    mod = tracking[tracking["contrast"].str.startswith("modulus")]
    dens = tracking[tracking["contrast"].str.startswith("densities")]
    if mod.empty or dens.empty:
        return ""

    def effects(rows):
        return " and ".join(f"{_effect(r)} ({r.contrast.replace('rho-', 'ρ-')})" for r in rows.itertuples())

    reading = ""
    if (mod["conclusion"] == NO_DIFFERENCE).all() and (dens["conclusion"] == DIFFERENCE).all():
        reading = ": the densities (the mass and its distribution together), not the modulus, carry the effect"
    elif (mod["conclusion"] == DIFFERENCE).any():
        reading = ": the modulus alone moves it too"
    return (
        f"On the crossed legs, changing the modulus alone moves tracking error by {effects(mod)}, "
        f"changing the densities alone by {effects(dens)}{reading}."
    )


def _ramp_sentence(optimizer: pd.DataFrame, dominance: str) -> str:
    """The validated gradients against the uniform leg of their mass; of those
    that beat it, how many survive validation, and the checks the rest fail."""
    rows = optimizer[optimizer["dominance"] == dominance]
    if rows.empty:
        return ""
    beats = rows["beats its mass-matched leg"].astype(str)
    wins = int((beats == "yes").sum())
    others = ", ".join(f"{int(n)} {v}" for v, n in beats[beats != "yes"].value_counts().items())
    dominated = rows["homogeneous legs of its mass dominating it"].map(lambda v: cell_text(v, "") != "")
    which, verb = ("none", "dominates") if wins == 0 else (f"{wins}", "dominates" if wins == 1 else "dominate")
    text = (
        f"On the ramp (the optimizer's objective, {dominance} rule), {which} of the {len(rows)} validated "
        f"gradients {verb} the uniform leg of its mass" + (f" ({others})" if others else "") + ", "
        f"and at least one homogeneous leg of the same mass dominates {int(dominated.sum())} of them."
    )
    winners = rows[beats == "yes"]
    if wins and "survives" in rows.columns:
        survive = int((winners["survives"].astype(str) == "True").sum())
        checks = [c for c in rows.columns if c.startswith("stable: ")]
        failed = sorted({c.removeprefix("stable: ") for c in checks if (winners[c].astype(str) == "False").any()})
        text += f" Of those {wins}, {survive} survive validation"
        if failed and survive < wins:
            text += f"; those that do not fell or diverged under the validation's checks: {', '.join(failed)}"
        text += "."
    return text


def _bending_sentence(crossed: pd.DataFrame, soft: pd.DataFrame | None = None) -> str:
    mod = crossed[crossed["contrast"].str.startswith("modulus")]
    dens = crossed[crossed["contrast"].str.startswith("densities")]
    if mod.empty or dens.empty:
        return ""

    def effects(rows, metric):
        r = rows[rows["metric"] == metric]
        return " and ".join(_effect(x) for x in r.itertuples())

    verdict = "no difference within the margin" if (mod["conclusion"] == NO_DIFFERENCE).all() else "a difference"
    sign = np.sign(dens.loc[dens["metric"] == "tracking_error_m", "pct_change"])
    reading = ""
    if soft is not None:
        soft_sign = np.sign(
            soft.loc[
                soft["contrast"].str.startswith("densities") & (soft["metric"] == "tracking_error_m"), "pct_change"
            ]
        )
        if len(sign) and len(soft_sign) and (sign.to_numpy() != soft_sign.to_numpy()[: len(sign)]).all():
            reading = (
                ": the densities' effect on ramp tracking reverses sign against the rigid legs on the soft contact "
                "(the convention, the contact and the step all differ, so which one reverses it is not separated)"
            )
    return (
        f"Where the leg can bend (hinge springs, a 1 ms contact, one step for the four legs), the modulus alone moves "
        f"tracking error by {effects(mod, 'tracking_error_m')} and hip power by {effects(mod, 'power_w')} "
        f"({verdict}); the densities alone move tracking error by {effects(dens, 'tracking_error_m')}{reading}."
    )


def _modulus_bending_sentence(sweeps: pd.DataFrame) -> str:
    swept = sweeps[np.isfinite(sweeps["modulus_gpa"].astype(float))]
    if swept.empty:
        return ""
    beyond = swept[swept["beyond_margin"].astype(bool)]
    toggles = ("leg_touch_toggles_per_switch", "against_touch_toggles_per_switch")
    recorded = set(toggles) <= set(sweeps.columns)

    def chatter(r) -> str:
        return (
            f", touchdown chatter {getattr(r, toggles[0]):.1f} against {getattr(r, toggles[1]):.1f}" if recorded else ""
        )

    named = "; ".join(
        f"{r.base} at {r.modulus_gpa:g} GPa against {r.against_gpa:g} GPa, {metric_label(r.metric)} {_effect(r)}"
        + chatter(r)
        for r in beyond.itertuples()
    )
    return (
        f"Hopping forward along the paper's modulus sweeps at equal mass, under bending on the stiff contact (one "
        f"step per base material), {len(beyond)} of {len(swept)} contrasts (a leg and a metric) move tracking error "
        f"or hip power beyond ±{MARGIN_PCT:g} %"
        + (f" ({named}{'; touch toggles per phase switch, leg against base' if recorded else ''})" if named else "")
        + (": where the chatter differs, the contact shares in the effect" if named and recorded else "")
        + "."
    )


def _contact_sentence(robust: pd.DataFrame) -> str:
    rows = robust[robust["variant"] == "stiff contact"]
    if rows.empty:
        return ""
    counts = rows["class"].value_counts()
    flips = rows[rows["class"] == "flips"]
    named = "; ".join(f"{r.quantity_id}: {_pct(r.default_pct)} to {_pct(r.value_pct)}" for r in flips.itertuples())
    changed = rows.loc[rows["class"] != "keeps", "quantity_id"].astype(str)
    ramp_tracking = changed.str.startswith("tracking") & changed.str.endswith("ramp")
    reading = ": the ramp's tracking claims rest on the soft contact" if len(changed) and ramp_tracking.all() else ""
    return (
        f"On a 1 ms contact instead of MuJoCo's default soft one (one unperturbed run per design, no interval; "
        f"'keeps' means the same sign within a factor 2), {int(counts.get('keeps', 0))} "
        f"of the {len(rows)} numbers the claims rest on keep, {int(counts.get('moves > 2x', 0))} move by more than "
        f"a factor 2 and {int(counts.get('flips', 0))} flip"
        + (f" ({named})" if named else "")
        + reading
        + "."
        + _apex_clause(robust)
    )


def _apex_clause(robust: pd.DataFrame) -> str:
    rows = robust[robust["variant"] == "apex above ground"]
    if rows.empty:
        return ""
    changed = rows[rows["class"] != "keeps"]
    named = "; ".join(
        f"{q} {c}: {_pct(d)} to {_pct(v)}"
        for q, c, d, v in zip(changed["quantity_id"], changed["class"], changed["default_pct"], changed["value_pct"])
    )
    return (
        f" With the apex measured above the ground instead of in world z, {len(rows) - len(changed)} of {len(rows)} "
        f"keep" + (f" ({named})" if named else "") + "."
    )


def _finer_step_text(claims: pd.DataFrame, crossed: pd.DataFrame | None) -> str:
    """Where a record reruns the headline at a finer step (the crossed
    legs), the two numbers side by side."""
    if crossed is None:
        return ""
    fine = crossed[crossed["contrast"].str.startswith("claim") & (crossed["metric"] == "tracking_error_m")]
    head = claims.loc[claims["claim_id"] == "headline_tracking", "ours"] if "claim_id" in claims.columns else []
    if fine.empty or len(head) == 0:
        return ""
    return (
        f" (where a record does, the crossed legs at a finer physics step, the headline's tracking is "
        f"{_effect(next(fine.itertuples()))} against {str(head.iloc[0]).split(' (')[0]} at the 1e-4 s step of the claims)"
    )


def _limits_sentence(claims: pd.DataFrame, crossed: pd.DataFrame | None = None) -> str:
    simulated = claims[claims["timestep_check"].notna()]
    unchecked = int((simulated["timestep_check"].astype(str) == "not checked").sum())
    if WINDOW_COLUMN in claims.columns:
        window = claims[WINDOW_COLUMN].astype(str)
        window_text = (
            f"{int(window.str.startswith('window-dependent').sum())} of them change verdict between the halves "
            f"of the scoring window ({int(window.str.startswith('stationary').sum())} stationary)"
        )
    else:
        window_text = (
            "whether each verdict holds over both halves of the scoring window is not recorded, so every verdict "
            "here is provisional"
        )
    step_text = _finer_step_text(claims, crossed)
    checks = simulated["timestep_check"].astype(str)
    if unchecked:
        step_claims = f"{unchecked} of the {len(simulated)} simulated claims were not rerun at a finer time step"
    else:
        moved = int(checks.str.startswith("moves").sum())
        step_claims = (
            f"of the {len(simulated)} simulated claims, rerun at a finer physics step, "
            f"{len(simulated) - moved} keep their runs within 10 % and {moved} move by more"
        )
    return (
        "These answers hold for one lumped model (rigid segments joined by springs), "
        "for the behaviours and controller recorded here, and not beyond them; "
        f"{step_claims}{step_text}, and {window_text}."
    )


def design_answer(records: dict[str, pd.DataFrame], *, dominance: str = DEFAULT_DOMINANCE) -> str:
    """What leg to build, in plain sentences generated from the records.

    Three findings (comparisons against same-mass controls inside the
    ±10 % margin; the crossed legs' modulus against density contrasts; on
    the ramp, whether a gradient dominates the uniform leg of its mass),
    then their limits. Every number in the text is read from `records`.

    Args:
        records: from :func:`read_records`.
        dominance: the optimizer record's domination rule to read
            (``margin``, the default, or ``significance``).

    Returns:
        The answer as one paragraph of plain text.
    """
    effects = paired_effects(records)
    sentences = [
        _same_mass_sentence(effects),
        _crossed_sentence(records["crossed"]),
        _ramp_sentence(records["optimizer"], dominance),
        _bending_sentence(records["crossed_bending"], records["crossed"]),
        _modulus_bending_sentence(records["modulus_bending"]),
        _contact_sentence(records["robustness_contact"]),
        _limits_sentence(records["claims"], records["crossed"]),
    ]
    return " ".join(s for s in sentences if s)


def _draw_group(ax, rows: pd.DataFrame, y: np.ndarray, colour) -> None:
    ax.hlines(y, rows["ci_low"], rows["ci_high"], colors=[colour], lw=1.2, gid="intervals")
    ax.scatter(rows["pct_change"], y, s=9, color=colour, zorder=3)


def forest_plot(records: dict[str, pd.DataFrame], ax=None, *, kinds=None):
    """Every numeric paired effect as a horizontal 95 % interval around its
    percent change, grouped by comparison kind, over a shaded ±10 %
    equivalence band. The x axis is linear inside ±10 % and logarithmic
    beyond (symlog), so that small and large effects both show.

    Args:
        records: from :func:`read_records`.
        ax: a matplotlib Axes to draw on; None (the default) for a new
            ``matplotlib.figure.Figure`` sized to the rows.
        kinds: the groups of :func:`paired_effects` to draw, in that
            order; None (the default) for every group.

    Returns:
        The Figure drawn on. Each group's intervals are one LineCollection
        with gid ``intervals`` (one segment per effect); the band a patch
        with gid ``margin-band``.

    Raises:
        ValueError: `kinds` names a group the records do not have.
    """
    import seaborn as sns

    effects = paired_effects(records)
    groups = list(dict.fromkeys(effects["group"])) if kinds is None else list(kinds)
    unknown = [g for g in groups if g not in set(effects["group"])]
    if unknown:
        raise ValueError(
            f"forest_plot: no effects of the kinds {unknown}; the records have {sorted(set(effects['group']))}"
        )
    colours = sns.color_palette("deep", len(groups))
    n_rows = sum(int((effects["group"] == g).sum()) for g in groups)
    with rc_context({**STYLE, "axes.grid.axis": "x"}):
        fig = None
        if ax is None:
            fig = Figure(figsize=(7.5, 0.8 + 0.105 * (n_rows + 1.5 * len(groups))), layout="constrained")
            ax = fig.add_subplot()
        ax.axvspan(
            -MARGIN_PCT, MARGIN_PCT, color="0.88", zorder=0, gid="margin-band", label=f"±{MARGIN_PCT:.0f} % margin"
        )
        ax.axvline(0, color="0.4", lw=0.7, zorder=1)
        ticks, labels, y0 = [], [], 0.0
        for g, colour in zip(groups, colours):
            rows = effects[effects["group"] == g]
            y = y0 + 1 + np.arange(len(rows))
            ax.text(
                0.005, y0, g, transform=ax.get_yaxis_transform(), ha="left", va="center", fontsize=7, fontweight="bold"
            )
            _draw_group(ax, rows, y, colour)
            ticks += list(y)
            labels += list(rows["label"])
            y0 = y[-1] + 1.5
        ax.set_xscale("symlog", linthresh=MARGIN_PCT, linscale=1.0)
        ax.set_xticks([-100, -50, -10, 0, 10, 50, 100, 200], ["−100", "−50", "−10", "0", "+10", "+50", "+100", "+200"])
        ax.set_xlim(-100, max(250.0, float(effects["ci_high"].max()) * 1.1))
        ax.set_yticks(ticks, labels, fontsize=5.5)
        ax.set_ylim(y0, -1)
        ax.set_xlabel("change against the comparator, % (95 % paired t interval)")
        ax.legend(loc="upper right", fontsize=7)
    return fig if fig is not None else ax.figure


RECORDED = "recorded, paper profile"  # the suffix of a recorded column beside this build's


def beside_record(built: pd.DataFrame, recorded: pd.DataFrame, key, columns) -> pd.DataFrame:
    """This build's verdicts beside the recorded paper-profile ones.

    A quick build's 2 seeds cannot reach a paired verdict ("untestable");
    the paper profile's 10 seeds can, and its results are kept in
    ``book/records/``. So every row of this build is shown with the
    recorded values of the same row, labelled as recorded (the records'
    README names the commit and machine that made them).

    Args:
        built: this build's table (e.g. :func:`mat_hopper.analysis.claims.claims_table`'s rows of one convention).
        recorded: the recorded table of the same rows (e.g. ``read_records(...)["claims"]``).
        key: the column (or list of columns) that identifies a row in both.
        columns: the columns to set side by side; each recorded one is named
            ``"<column> (recorded, paper profile)"``.

    Returns:
        A DataFrame: the key columns, then for each of `columns` this build's
        value and the recorded one ("not recorded" where the records lack the
        row or the column).

    Raises:
        ValueError: a key or column missing from `built`, or a key missing from `recorded`.
    """
    keys = [key] if isinstance(key, str) else list(key)
    columns = list(columns)
    missing = [c for c in keys + columns if c not in built.columns]
    if missing:
        raise ValueError(f"beside_record: this build's table has no column {missing}")
    if any(k not in recorded.columns for k in keys):
        raise ValueError(
            f"beside_record: the recorded table has no key column {[k for k in keys if k not in recorded.columns]}"
        )
    rec = recorded[keys + [c for c in columns if c in recorded.columns]].drop_duplicates(keys)
    rec = rec.rename(columns={c: f"{c} ({RECORDED})" for c in columns})
    out = built[keys + columns].merge(rec, on=keys, how="left")
    order = keys + [x for c in columns for x in (c, f"{c} ({RECORDED})")]
    for c in order:
        if c not in out.columns:
            out[c] = NOT_RECORDED
    return out[order].fillna({f"{c} ({RECORDED})": NOT_RECORDED for c in columns})
