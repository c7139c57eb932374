"""The paper's claims beside ours, per chapter of the book: which claims a
chapter discusses (:data:`CHAPTER_CLAIMS`), the claims table built from a
reproduction's result tables, and the rule behind each verdict
(:mod:`mat_hopper.analysis.claims`).
"""

from __future__ import annotations

import pandas as pd

from ..core.materials import CONVENTIONS

CHAPTER_CLAIMS = {
    "mono": ("hop_height", "tracking_all_beat_md", "tracking_ss_55", "power_higher_dynamic", "power_ss_max"),
    "one_property": ("density_over_modulus", "low_modulus_tracks_worse"),
    "gradients": (
        "ramp_rho_inc_tracking",
        "ramp_rho_inc_power",
        "ramp_ss_tracking",
        "ramp_ss_power",
        "headline_tracking",
        "headline_power",
    ),
    "stability": ("timestep_materials", "timestep_trend"),
}


def _concat(tables: dict, suffix: str) -> pd.DataFrame | None:
    frames = [
        t
        for name, t in sorted(tables.items())
        if name.startswith("exp") and name.endswith(suffix) and t is not None and len(t)
    ]
    return pd.concat(frames, ignore_index=True) if frames else None


def claims_for(
    tables: dict, chapter: str | None = None, *, conventions=None, columns=("claim", "paper", "ours", "verdict")
) -> pd.DataFrame:
    """The paper's claims beside ours (:func:`mat_hopper.analysis.claims.claims_table`)
    from a reproduction's tables (``exp*_hops``, ``exp*_runs``,
    ``stability``, ``controls_hops`` where present), for one chapter (a key of :data:`CHAPTER_CLAIMS`) or all
    (None). conventions: default those present in the tables. columns:
    which to keep (None: all).

    Args:
        tables: result tables by name (``exp1_hops``, ``exp1_runs``, ..., ``stability``,
            ``robustness_hops`` for the time-step check, ``controls_hops``, ``controls_runs``); the
            ``exp*_hops`` and ``exp*_runs`` tables are concatenated.
        chapter: a key of :data:`CHAPTER_CLAIMS`, or None: every claim.
        conventions: the stiffness conventions; None: those present in the tables (``paper`` where
            none is).
        columns: the columns kept; None: all.

    Returns:
        DataFrame, one row per claim and convention (a chapter's claims in :data:`CHAPTER_CLAIMS`'s
        order), index reset.

    Raises:
        ValueError: an unknown chapter; or from :func:`mat_hopper.analysis.claims.claims_table`.
    """
    from . import claims

    if chapter is not None and chapter not in CHAPTER_CLAIMS:
        raise ValueError(f"chapter must be one of {', '.join(CHAPTER_CLAIMS)} or None, got {chapter!r}")
    hops, runs, stab = _concat(tables, "_hops"), _concat(tables, "_runs"), tables.get("stability")
    if conventions is None:
        present = set()
        for t in (hops, runs, stab):
            if t is not None and "convention" in t.columns:
                present |= set(t["convention"].dropna().astype(str))
        conventions = [c for c in CONVENTIONS if c in present] or ["paper"]
    from .robustness import FINE_LABEL, fine_step_hops

    fine = fine_step_hops(tables.get("robustness_hops"))
    table = claims.claims_table(
        hops,
        runs,
        stab,
        conventions=tuple(conventions),
        fine_hops=fine,
        fine_label=FINE_LABEL,
        controls=tables.get("controls_hops"),  # the beyond-mass columns, where the controls ran
        control_runs=tables.get("controls_runs"),  # their unusable runs dropped
    )
    if chapter is not None:
        ids = CHAPTER_CLAIMS[chapter]
        table = table[table["claim_id"].isin(ids)]
        table = (
            table.assign(_o=table["claim_id"].map({c: i for i, c in enumerate(ids)}))
            .sort_values(["_o", "convention"], kind="stable")
            .drop(columns="_o")
        )
    table = table.reset_index(drop=True)
    return table if columns is None else table[[c for c in columns if c in table.columns]]


def claim_rules() -> pd.DataFrame:
    """The rule behind each claim's verdict (:data:`mat_hopper.analysis.claims.CLAIMS`):
    columns claim, rule.

    Returns:
        DataFrame, one row per claim in :data:`mat_hopper.analysis.claims.CLAIMS`'s order.
    """
    from . import claims

    return pd.DataFrame([{"claim": c.claim, "rule": c.rule} for c in claims.CLAIMS])
