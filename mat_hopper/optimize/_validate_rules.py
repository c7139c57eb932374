"""The domination rule of a front's validation, and the verdicts it gives.

A comparator *dominates* a design when it is significantly better on at
least one objective (Holm within the comparator kind's family, and only
where an exact sign-flip test on n seeds could reach the threshold),
significantly worse on none, and, under the default ``margin`` rule
(:data:`DEFAULT_DOMINANCE`), the design's advantage beyond the ±10 %
equivalence margin is ruled out on every objective by its unadjusted 95 %
interval: superiority on one objective, non-inferiority on the rest. The
``significance`` rule drops the non-inferiority. Under ``margin`` the burden
of proof is on domination, so :func:`dominance_state` and
:func:`survival_state` also tell "not shown dominated" (``unresolved``)
apart from "shown not dominated". Used by :mod:`mat_hopper.optimize.validate`.
"""

from __future__ import annotations

import pandas as pd

from ..analysis import paired
from ..physics.metrics import holm
from ._objective import Objective
from ._validate_checks import ALPHA, DEFAULT_DOMINANCE, EQUIVALENCE_MARGIN, check_dominance
from ._validate_pairs import _compare, replicate_means


def _better_worse(rows: pd.DataFrame) -> tuple[bool, bool]:
    """(the design significantly better on some objective, significantly
    worse on some) in one comparison's rows (minimized objectives)."""
    sig = rows[rows["significant"]]
    return bool((sig["pct_change"] < 0).any()), bool((sig["pct_change"] > 0).any())


def _judged(rows: pd.DataFrame) -> pd.DataFrame:
    """One comparison's rows that can be judged: those with an effect and
    an interval (an objective without, e.g. a degenerate difference, is
    left out as :func:`_compare` leaves out a stress of a rigid leg)."""
    return rows.dropna(subset=["pct_change", "ci_low", "ci_high"])


def _dominates(rows: pd.DataFrame, rule: str, sign: int) -> bool:
    """In one comparison's rows (the design against one comparator, one row
    per objective, minimized), whether the comparator dominates the design
    (`sign` +1) or the design the comparator (`sign` -1), under `rule`
    (module doc): the loser significantly worse on one objective and on
    none significantly better; under ``margin``, also on every objective
    either significantly worse or with its advantage beyond the ±10 %
    margin ruled out by its unadjusted 95 % interval. Rows without an
    interval are left out (:func:`_judged`)."""
    rows = _judged(rows)
    sig = rows["significant"].fillna(False).to_numpy(bool)
    change = sign * rows["pct_change"].to_numpy(float)
    worse, better = sig & (change > 0), sig & (change < 0)
    if not worse.any() or better.any():
        return False
    if rule == "significance":
        return True
    loser_low = rows["ci_low"].to_numpy(float) if sign > 0 else -rows["ci_high"].to_numpy(float)
    return bool((worse | (loser_low > -100 * EQUIVALENCE_MARGIN)).all())


# how a comparator stands against a design (dominance_state, survival_state)
DOMINATED, UNRESOLVED, NOT_DOMINATED = "dominated", "unresolved", "not dominated"
UNTESTABLE, NOT_COMPARED = "untestable", "not compared"


def dominance_state(rows: pd.DataFrame) -> str:
    """Whether one comparator dominates a design, in three states, so that
    "not shown dominated" is never read as "shown not dominated".

    Args:
        rows: one comparison's rows of :func:`paired_table` (the design
            against one comparator, one row per objective; rows without an
            interval are left out).

    Returns:
        ``dominated`` under the ``margin`` rule (module doc); else ``not
        dominated`` where that is shown: the design's advantage on some
        objective is shown by its unadjusted 95 % interval (entirely below
        zero), or every interval lies inside the ±10 % margin (neither leg
        is better beyond it); else ``unresolved`` (nothing shown either
        way, e.g. wide intervals across zero, or the design worse on every
        objective short of Holm's threshold).
    """
    rows = _judged(rows)
    if _dominates(rows, "margin", +1):
        return DOMINATED
    low, high = rows["ci_low"].to_numpy(float), rows["ci_high"].to_numpy(float)
    m = 100 * EQUIVALENCE_MARGIN
    if len(rows) and ((high < 0).any() or ((low > -m) & (high < m)).all()):
        return NOT_DOMINATED
    return UNRESOLVED


def survival_state(table: pd.DataFrame, design: str) -> str:
    """A design's standing against the paper's designs
    (:func:`dominance_state` of each).

    Args:
        table: :func:`paired_table`'s table.
        design: the front design's name.

    Returns:
        ``not compared`` (no comparison with a paper design: an unknown
        name, or every paper design fell), else ``dominated`` if one paper
        design dominates it, else ``untestable`` if a comparison could not
        reach Holm's threshold, else ``unresolved`` if one paper design is,
        else ``not dominated`` (shown against every paper design in the
        table: one that fell where the design stood up is not in it,
        :func:`fallen_comparators`).
    """
    rows = table[(table["design"] == design) & (table["kind"] == "paper")] if len(table) else table
    if rows.empty:
        return NOT_COMPARED
    states = {dominance_state(r) for _, r in rows.groupby("against", sort=False)}
    if DOMINATED in states:
        return DOMINATED
    if not rows["testable"].fillna(False).astype(bool).all():
        return UNTESTABLE
    return UNRESOLVED if UNRESOLVED in states else NOT_DOMINATED


def dominated_by(table: pd.DataFrame, design: str, kinds=("paper",), rule: str = DEFAULT_DOMINANCE) -> list[str]:
    """The comparators of `kinds` that dominate `design` in a
    :func:`paired_table` (module doc).

    Args:
        table: :func:`paired_table`'s table.
        design: the front design's name.
        kinds: the comparator kinds considered (default ``("paper",)``;
            others: ``mass-matched``, ``rigid twin``, ``homogeneous``).
        rule: the domination rule, one of :data:`DOMINANCE_RULES`
            (default ``margin``: significantly better on one objective,
            worse on none, and non-inferior within ±10 % on every other).

    Returns:
        The comparators' names (the table's ``against``), in table order;
        empty when none dominates `design`.

    Raises:
        ValueError: an unknown `rule`.
    """
    check_dominance(rule)
    rows = table[(table["design"] == design) & table["kind"].isin(kinds)]
    return [against for against, r in rows.groupby("against", sort=False) if _dominates(r, rule, +1)]


YES, WORSE, TRADE_OFF, EQUIVALENT, NO_EVIDENCE = "yes", "worse", "trade-off", "equivalent", "no evidence"


def beats(table: pd.DataFrame, design: str, kind: str, rule: str = DEFAULT_DOMINANCE) -> str:
    """How `design` compares with its comparator of `kind` (Holm-significant
    comparisons): ``yes`` (the design dominates it under `rule`: better on
    an objective, worse on none, and under ``margin`` not worse beyond
    ±10 % on any), ``worse`` (it dominates the design), ``trade-off``
    (better on one, worse on another), ``equivalent`` (every interval
    inside the ±10 % margin), ``no evidence`` (none of these), ``untestable``
    (n seeds cannot reach Holm's threshold and the intervals leave the
    margin) or ``not run``. With several comparators of the kind (the
    homogeneous legs), the design must beat each one for ``yes``.

    Args:
        table: :func:`paired_table`'s table.
        design: the front design's name.
        kind: the comparator kind (``paper``, ``mass-matched``, ``rigid
            twin`` or ``homogeneous``).
        rule: the domination rule (:data:`DOMINANCE_RULES`; default ``margin``).

    Returns:
        One of ``not run`` (no rows), ``equivalent`` (checked first: every
        row's interval strictly inside the margin), ``untestable`` (some row
        not testable), then, over the comparators of the kind, ``worse`` if
        any is, else ``trade-off`` if any is, else ``no evidence`` if any
        is, else ``yes``.

    Raises:
        ValueError: an unknown `rule`.
    """
    check_dominance(rule)
    rows = table[(table["design"] == design) & (table["kind"] == kind)]
    if rows.empty:
        return "not run"
    m = 100 * EQUIVALENCE_MARGIN
    if ((rows["ci_low"] > -m) & (rows["ci_high"] < m)).all():
        return EQUIVALENT
    if not rows["testable"].all():
        return "untestable"
    states = []
    for _, r in rows.groupby("against", sort=False):
        better, worse = _better_worse(r)
        states.append(
            TRADE_OFF if better and worse
            else YES if _dominates(r, rule, -1)
            else WORSE if _dominates(r, rule, +1)
            else NO_EVIDENCE
        )  # fmt: skip
    for state in (WORSE, TRADE_OFF, NO_EVIDENCE):
        if state in states:
            return state
    return YES


def paper_best(
    runs: pd.DataFrame, objective: Objective, alpha: float = ALPHA, rule: str = DEFAULT_DOMINANCE
) -> list[str]:
    """The paper designs no other paper design dominates, paired by seed
    (Holm over each design's comparisons with the other eight; a design
    with none to compare with, where the others fell on some seed, counts
    as best).

    Args:
        runs: a validation's run table (:func:`validate_front`'s ``runs``).
        objective: the study's objective (its objectives are compared).
        alpha: the significance level (default :data:`ALPHA`, 0.05).
        rule: the domination rule (:data:`DOMINANCE_RULES`; default ``margin``).

    Returns:
        The names of the best paper designs, in the order of
        :func:`replicate_means`' index (sorted by name); designs without a
        complete replicate are not among them.

    Raises:
        ValueError: an unknown `rule`.
    """
    check_dominance(rule)
    means = replicate_means(runs, objective)
    names = [d for r, d in dict.fromkeys(means.index.droplevel("replicate")) if r == "paper"]
    best = []
    for a in names:
        rows = [
            {"against": b, "objective": o, **e}
            for b in names
            if b != a
            for o, e in _compare(means, ("paper", a), ("paper", b)).items()
        ]
        if not rows:  # no other paper design to compare with (the others fell on some seed)
            best.append(a)
            continue
        t = pd.DataFrame(rows)
        t["p_holm"] = holm(t["p"].to_numpy(float))
        t["significant"] = paired.reachable(int(t["n_pairs"].min()), len(t), alpha) & (t["p_holm"] < alpha)
        if not any(_dominates(g, rule, +1) for _, g in t.groupby("against")):
            best.append(a)
    return best
