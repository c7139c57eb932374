"""How the runs ended, for reading: one cell per design and behaviour
("ok, N hops", "fell", "diverged at T s", "failed"), a paragraph on the
runs that did not end upright, and the failures told apart (numerical
blow-up, fall, fall then blow-up). Unperturbed runs (replicate -1) only;
times in s, heights in m.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ..core.behaviours import order_behaviours
from ..core.materials import order_designs
from ._columns import need_columns as _need


def outcome_table(runs: pd.DataFrame) -> pd.DataFrame:
    """How each run ended, designs as rows and behaviours as columns: "ok,
    N hops" (N scored hop cycles), "fell" (the body ended below 0.1 m),
    "diverged at T s" (numerical blow-up, simulated time) or "failed"
    (an error; see the runs table). Unperturbed runs only.

    Args:
        runs: a run-summary table (design, behaviour, status; n_hops, diverged_at_s and replicate where
            present).

    Returns:
        DataFrame of str, designs as index and behaviours as columns, each in the paper's order: "ok, N
        hops" ("ok" without an n_hops value), "diverged at T s" (T to two significant digits) or the
        run's status as written (e.g. "fallen", "failed", "diverged" without a time); nan where no run.

    Raises:
        ValueError: `runs` lacks a column design, behaviour or status.
    """
    need = ("design", "behaviour", "status")
    missing = [c for c in need if c not in runs.columns]
    if missing:
        raise ValueError(f"outcome_table needs columns {missing}")
    r = runs[runs["replicate"] == -1] if "replicate" in runs.columns else runs

    def cell(row) -> str:
        st = row["status"]
        if st == "ok":
            return f"ok, {int(row['n_hops'])} hops" if "n_hops" in row and pd.notna(row["n_hops"]) else "ok"
        if st == "diverged" and pd.notna(row.get("diverged_at_s", np.nan)):
            return f"diverged at {row['diverged_at_s']:.2g} s"
        return str(st)

    t = r.assign(outcome=r.apply(cell, axis=1)).pivot_table(
        index="design", columns="behaviour", values="outcome", aggfunc="first"
    )
    t = t.reindex(index=order_designs(t.index), columns=order_behaviours(t.columns))
    t.columns.name = None
    return t


def outcome_summary(runs: pd.DataFrame) -> str:
    """One paragraph on how the (unperturbed) runs ended: how many ended
    upright, then each design and behaviour that did not, with how
    (diverged at T s, fell, failed).

    Args:
        runs: a run-summary table, as for :func:`outcome_table`.

    Returns:
        str: "K of N runs ended upright." or "K of N runs ended upright; not: <design> <behaviour>:
        <outcome>; ...." (the behaviour left out where the table has only one), outcomes as in
        :func:`outcome_table`; N counts the design-behaviour cells that have a run.

    Raises:
        ValueError: `runs` lacks a column design, behaviour or status.
    """
    t = outcome_table(runs)
    cells = [(d, b, v) for d in t.index for b in t.columns if isinstance(v := t.loc[d, b], str)]
    bad = [(d, b, v) for d, b, v in cells if not v.startswith("ok")]
    one_behaviour = len(t.columns) == 1
    text = f"{len(cells) - len(bad)} of {len(cells)} runs ended upright"
    if not bad:
        return text + "."
    items = [f"{d}{'' if one_behaviour else ' ' + b}: {v}" for d, b, v in bad]
    return text + "; not: " + "; ".join(items) + "."


def failure_table(runs: pd.DataFrame) -> pd.DataFrame:
    """Every unperturbed run that did not end upright, told apart:
    ``numerical`` (the numbers blew up while the body was still up: a time
    step above the design's stable step, chapter 5), ``fell, then
    diverged`` (the body was already below 0.1 m, the paper's criterion,
    when the numbers blew up: the hopper failed first), ``fell`` (ended
    below 0.1 m without blowing up) or ``failed`` (an error). Columns:
    design, behaviour, kind, at_s (time of the blow-up, s; nan for a plain
    fall), ``numerically suspect`` (no blow-up, but a hop apex far above
    the target: corrupted numbers, :attr:`mat_hopper.core.rollout.Rollout.suspect`;
    at_s the apex's time). Columns:
    design, behaviour, kind, at_s (time of the blow-up or of the suspect
    apex, s; nan for a plain fall), final_base_z_m (the last recorded body height), n_hops.

    Args:
        runs: a run-summary table (design, behaviour, status, final_base_z_m; upright, diverged_at_s,
            n_hops and replicate where present; without ``upright`` a run is upright when its status is
            "ok").

    Returns:
        DataFrame, one row per unperturbed run whose status is not "ok" or that is not upright, with
        the columns above (at_s and final_base_z_m in s and m; n_hops 0 where missing). "Below 0.1 m"
        is not at or above :data:`mat_hopper.core.reference.STABLE_MIN_BASE_Z` (a nan height counts as
        below).

    Raises:
        ValueError: `runs` lacks a column design, behaviour, status or final_base_z_m, or lacks
            diverged_at_s while one of its unperturbed runs diverged (the message names the columns).
    """
    from ..core import reference as ref

    _need(runs, ("design", "behaviour", "status", "final_base_z_m"), "failure_table")
    r = runs[runs["replicate"] == -1] if "replicate" in runs.columns else runs
    upright = r["upright"].astype(bool) if "upright" in r.columns else r["status"] == "ok"
    bad = r[(r["status"] != "ok") | ~upright]
    if (bad["status"] == "diverged").any():  # the time of a blow-up: checked before any row is made
        _need(runs, ("diverged_at_s",), "failure_table (a run diverged)")
    rows = []
    for row in bad.itertuples(index=False):
        z = float(row.final_base_z_m)
        low = not (z >= ref.STABLE_MIN_BASE_Z)
        if row.status == "diverged":
            kind = "fell, then diverged" if low else "numerical"
            at = float(row.diverged_at_s)
        elif row.status == "failed":
            kind, at = "failed", np.nan
        elif row.status == "suspect":  # corrupted numbers without a blow-up (Rollout.suspect)
            kind, at = "numerically suspect", float(getattr(row, "suspect_at_s", np.nan))
        else:
            kind, at = "fell", np.nan
        rows.append(
            {
                "design": row.design,
                "behaviour": row.behaviour,
                "kind": kind,
                "at_s": at,
                "final_base_z_m": z,
                "n_hops": int(row.n_hops) if pd.notna(getattr(row, "n_hops", np.nan)) else 0,
            }
        )
    return pd.DataFrame(rows, columns=["design", "behaviour", "kind", "at_s", "final_base_z_m", "n_hops"])
