"""The book's records, read and tidied (the findings page's data half).

- :func:`read_records`: the record files of ``book/records/`` as tables (a
  clear error names a missing file or column);
- :func:`findings_table`: one row per paper claim, its verdict and the
  controls it was held against;
- :func:`paired_effects`: every numeric paired effect of the records
  (percent change of a design against its comparator, with its 95 %
  interval), one tidy table.

:mod:`mat_hopper.viz.findings` hands these on and builds the answer and
the forest plot from them. Percent changes are of the design against its
comparator (negative: the design's value is lower), in %.
"""

from __future__ import annotations

import re
from collections import Counter
from pathlib import Path

import numpy as np
import pandas as pd

from ..analysis.paired import EQUIVALENCE_MARGIN, conclusion

# Each record this page reads, by its key in :func:`read_records`' answer,
# with the columns the page needs from it.
RECORD_FILES = {
    "claims": "claims-paper.csv",
    "crossed": "crossed-legs-paper.csv",
    "optimizer": "optimizer-paper.csv",
    "optimizer_paired": "optimizer-paired-paper.csv",
    "stress": "stress-verdicts-paper.csv",
    "crossed_bending": "crossed-legs-bending-stiff-paper.csv",
    "robustness_contact": "robustness-paper.csv",
    "modulus_bending": "modulus-sweeps-bending-stiff-paper.csv",
    "claims_reseeded": "claims-seeds-10-19-paper.csv",  # the same claims on seeds 10-19
}
EFFECT_COLUMNS = ("pct_change", "ci_low", "ci_high")
REQUIRED_COLUMNS = {
    "claims": ("claim", "paper", "ours", "verdict", "timestep_check", "vs_rigid_twin", "beyond_mass"),
    "crossed": ("contrast", "metric", *EFFECT_COLUMNS, "p_holm"),
    "optimizer": ("design", "dominance", "beats its mass-matched leg", "homogeneous legs of its mass dominating it"),
    "optimizer_paired": ("design", "against", "kind", "objective", *EFFECT_COLUMNS, "p_holm"),
    "stress": ("gradient", "metric", "against", *EFFECT_COLUMNS, "p_holm"),
    "crossed_bending": ("contrast", "metric", *EFFECT_COLUMNS, "conclusion"),
    "robustness_contact": ("variant", "quantity_id", "value_pct", "default_pct", "class"),
    "modulus_bending": ("base", "modulus_gpa", "against_gpa", "metric", *EFFECT_COLUMNS, "beyond_margin"),
    "claims_reseeded": ("claim_id", "claim", "verdict", "stationarity", "beyond_mass"),
}
# The claims table's column for "stable over the scoring window"; the
# records do not carry it yet, and the page says so rather than guess.
WINDOW_COLUMN = "stationarity"
NOT_RECORDED = "not recorded"
NOT_COMPARED = "not compared"
MARGIN_PCT = 100 * EQUIVALENCE_MARGIN  # ±10 %: inside it a difference counts as none
DEFAULT_DOMINANCE = "margin"

METRIC_LABELS = {
    "tracking_error_m": "tracking error",
    "power_w": "hip power",
    "power_total_w": "total power",
    "hop_peak_stress_median_pa": "median hop peak stress",
    "peak_stress_pa": "largest peak stress",
    "fatigue_safety_factor": "fatigue safety factor",
}
FINDINGS_COLUMNS = (
    "claim",
    "paper",
    "ours",
    "verdict",
    "beyond the rigid twin",
    "beyond the mass-matched leg",
    "converged in time step",
    "stable over the scoring window",
)
_CONCLUSION = re.compile(r"\((difference|no difference|not enough evidence),")


def read_records(folder) -> dict[str, pd.DataFrame]:
    """The recorded paper-profile tables this page reads, from `folder`.

    Args:
        folder: the records folder (the repository's ``book/records``).

    Returns:
        A dict from each key of :data:`RECORD_FILES` to its table.

    Raises:
        FileNotFoundError: a record file is missing (its name and the folder
            are given).
        ValueError: a record lacks a column the page needs (named).
    """
    folder = Path(folder)
    out = {}
    for key, name in RECORD_FILES.items():
        path = folder / name
        if not path.is_file():
            raise FileNotFoundError(f"record {name} missing from {folder} (the findings page reads {key} from it)")
        table = pd.read_csv(path)
        missing = [c for c in REQUIRED_COLUMNS[key] if c not in table.columns]
        if missing:
            raise ValueError(f"record {name} lacks the columns {missing}")
        out[key] = table
    return out


def verdict_changes(
    first: pd.DataFrame,
    second: pd.DataFrame,
    key="claim_id",
    columns=("verdict", "stationarity", "beyond_mass"),
    labels=("stationarity",),
) -> pd.DataFrame:
    """Where two tables of the same rows disagree: e.g. the recorded claims
    on seeds 0-9 and on seeds 10-19, to show which verdicts another draw of
    the seeds changes.

    Args:
        first, second: the two tables (rows matched on `key`).
        key: the column naming a row in both.
        columns: the columns compared, as text.
        labels: of them, those compared by their label only, the text before
            its first " (" (a stationarity label, not the numbers behind it).

    Returns:
        DataFrame with columns key, ``column``, ``first``, ``second``: one row
        per differing cell, in `first`'s row order; rows only one table has,
        and cells "not run" in either, are left out.

    Raises:
        ValueError: `key` or a column missing from either table.
    """
    for name, t in (("first", first), ("second", second)):
        missing = [c for c in (key, *columns) if c not in t.columns]
        if missing:
            raise ValueError(f"verdict_changes: the {name} table has no column {missing}")
    other = second.set_index(key)

    def text(value, column) -> str:
        value = str(value)
        return value.split(" (")[0] if column in labels else value

    rows = []
    for _, r in first.iterrows():
        if r[key] not in other.index:
            continue
        for c in columns:
            a, b = text(r[c], c), text(other.loc[r[key], c], c)
            if a != b and "not run" not in (a, b):
                rows.append({key: r[key], "column": c, "first": a, "second": b})
    return pd.DataFrame(rows, columns=[key, "column", "first", "second"])


def cell_text(value, empty: str) -> str:
    """The record's text, or `empty` where the cell is blank."""
    if value is None or (isinstance(value, float) and np.isnan(value)) or str(value).strip() == "":
        return empty
    return str(value)


def rigid_twin_summary(cell) -> str:
    """A claim's comparisons against the rigid twin (the same segment masses
    without springs: what the moduli add), counted by their conclusion.

    Args:
        cell: the claims record's ``vs_rigid_twin`` text: one entry per
            comparison, each with its conclusion in brackets.

    Returns:
        E.g. "differs in 3 of 16 (12 no difference, 1 not enough evidence)";
        the text itself where it names no conclusion; "not compared" where
        blank.
    """
    text = cell_text(cell, NOT_COMPARED)
    counts = Counter(_CONCLUSION.findall(text))
    if not counts:
        return text
    rest = ", ".join(f"{n} {c}" for c, n in counts.items() if c != "difference")
    total = sum(counts.values())
    return f"differs in {counts['difference']} of {total}" + (f" ({rest})" if rest else "")


def findings_table(records: dict[str, pd.DataFrame]) -> pd.DataFrame:
    """One row per paper claim: the paper's number, ours, whether it was
    reproduced and whether the effect goes beyond the claim's controls.

    Args:
        records: from :func:`read_records` (its ``claims`` table is used).

    Returns:
        A DataFrame with the columns of :data:`FINDINGS_COLUMNS`, in the
        claims record's order: ``verdict`` as recorded (holds, partly,
        does not hold); ``beyond the rigid twin`` from
        :func:`rigid_twin_summary`; ``beyond the mass-matched leg`` the
        record's ``beyond_mass``; ``converged in time step`` its
        ``timestep_check``; ``stable over the scoring window`` its
        :data:`WINDOW_COLUMN` where recorded, else "not recorded". A blank
        cell reads "not compared" (controls) or "not recorded" (checks).
    """
    claims = records["claims"]
    window = claims[WINDOW_COLUMN] if WINDOW_COLUMN in claims.columns else pd.Series(np.nan, index=claims.index)
    return pd.DataFrame(
        {
            "claim": claims["claim"].astype(str),
            "paper": claims["paper"].astype(str),
            "ours": claims["ours"].astype(str),
            "verdict": claims["verdict"].astype(str),
            "beyond the rigid twin": [rigid_twin_summary(v) for v in claims["vs_rigid_twin"]],
            "beyond the mass-matched leg": [cell_text(v, NOT_COMPARED) for v in claims["beyond_mass"]],
            "converged in time step": [cell_text(v, NOT_RECORDED) for v in claims["timestep_check"]],
            "stable over the scoring window": [cell_text(v, NOT_RECORDED) for v in window],
        },
        columns=list(FINDINGS_COLUMNS),
    ).reset_index(drop=True)


def metric_label(name: str) -> str:
    return METRIC_LABELS.get(name, name)


def _label(design: str, against: str) -> str:
    design = design.replace("rho-", "ρ-")
    against = against.replace("rho-", "ρ-")
    if against.startswith(f"{design}~"):
        against = against[len(design) + 1 :]
    return f"{design} vs {against}"


def paired_effects(records: dict[str, pd.DataFrame]) -> pd.DataFrame:
    """Every numeric paired effect of the records, one row each.

    The crossed legs (chapter 9c: a modulus or the densities changed
    alone), the stress study's gradients against their mass-matched legs
    and titanium (chapter 8b) and the optimizer's validated designs against
    their controls and the paper's designs (chapter 9).

    Args:
        records: from :func:`read_records`.

    Returns:
        A DataFrame with columns ``group`` (the comparison kind),
        ``label`` (design, comparator and metric), ``metric``,
        ``pct_change``, ``ci_low``, ``ci_high`` (%), ``p_holm``,
        ``same_mass`` (True where the comparator has the design's leg
        mass: its rigid twin, mass-matched and homogeneous legs of its
        mass, a modulus changed alone) and ``conclusion`` (difference, no difference, not
        enough evidence: :func:`mat_hopper.analysis.paired.conclusion`,
        ±10 % margin), in group order.
    """
    parts = []
    crossed = records["crossed"]
    modulus = crossed["contrast"].str.startswith("modulus")
    kind = np.where(
        modulus,
        "crossed legs: modulus alone",
        np.where(
            crossed["contrast"].str.startswith("densities"), "crossed legs: densities alone", "crossed legs: claim"
        ),
    )
    parts.append(
        crossed.assign(
            group=kind,
            label=crossed["contrast"].str.replace("rho-", "ρ-") + ", " + crossed["metric"].map(metric_label),
            same_mass=modulus,
        )
    )
    stress = records["stress"]
    parts.append(
        stress.assign(
            group="stress: vs " + stress["against"],
            label=[
                f"{_label(g, a)}, {metric_label(m)}"
                for g, a, m in zip(stress["gradient"], stress["against"], stress["metric"])
            ],
            same_mass=stress["against"].eq("mass-matched"),
        )
    )
    opt = records["optimizer_paired"]
    parts.append(
        opt.assign(
            group="optimizer: vs " + opt["kind"].replace({"paper": "paper designs"}),
            label=[
                f"{_label(d, a)}, {metric_label(m)}" for d, a, m in zip(opt["design"], opt["against"], opt["objective"])
            ],
            metric=opt["objective"],
            same_mass=opt["kind"].isin(["mass-matched", "homogeneous", "rigid twin"]),
        )
    )
    cols = ["group", "label", "metric", *EFFECT_COLUMNS, "p_holm", "same_mass"]
    out = pd.concat([p[cols] for p in parts], ignore_index=True)
    for c in (*EFFECT_COLUMNS, "p_holm"):
        out[c] = pd.to_numeric(out[c], errors="coerce")
    out["conclusion"] = [conclusion(p, lo, hi) for p, lo, hi in zip(out["p_holm"], out["ci_low"], out["ci_high"])]
    return out
