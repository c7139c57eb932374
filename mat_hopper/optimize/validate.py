"""Validating a study's Pareto front: which designs survive a harder look?

A study scores each design on the search's seeds, at the paper's time
step, under one stiffness convention; a front built that way can hold
designs that win by luck or by a numerical artefact. Each front design is
therefore run again (:class:`~mat_hopper.experiments.runner.RunSpec`
through :func:`~mat_hopper.experiments.runner.run_grid`: the one cache and
pool) under every check of :data:`CHECKS`: the nominal run, seeded
replicates on seeds 0..n-1 (never the search's 1000..), every other
behaviour, a 2e-5 s physics step with and without the 1e-4 s control
period, and the axial springs. Its controls (mass-matched leg, rigid twin,
homogeneous legs of its mass) and the paper's nine designs run the same
replicates, so every comparison is paired by seed, on each objective,
Holm-adjusted per comparator kind, and significant only where an exact
sign-flip test on n seeds can reach Holm's threshold (2 objectives x 9
paper designs need 10 seeds).

A design survives when every run ends upright and no paper design that
stood where it stood (:func:`fallen_comparators`) dominates it: is
significantly better on one objective, worse on none and, under the
default ``margin`` rule (:data:`DEFAULT_DOMINANCE`), not beaten beyond
±10 % on any. Where n seeds cannot reach the threshold survival is
``untestable``, not granted. :func:`survival_state` tells "not shown
dominated" from "shown not dominated"; :func:`answer` says whether a
surviving gradient beats the homogeneous leg of its mass. The method in
full: docs/optimizer.md, "Front validation". The checks, the pairing and
the rule live in ``_validate_checks``, ``_validate_pairs`` and
``_validate_rules``; this module re-exports their public names.
"""

from __future__ import annotations

import numbers

import numpy as np
import pandas as pd

from ..core.behaviours import BEHAVIOUR_NAMES
from ..experiments.runner import FAILED, OK, run_grid
from ._objective import Objective
from ._scoring import leg_mass_kg
from ._validate_checks import (
    ALPHA,
    AXIAL,
    BEHAVIOUR,
    CHECKS,
    CONFIDENCE,
    CONTROL_KINDS,
    DEFAULT_DOMINANCE,
    DOMINANCE_RULES,
    EQUIVALENCE_MARGIN,
    FINE_CONTROL,
    FINE_PLAIN,
    HOMOGENEOUS,
    HOMOGENEOUS_MODULI_GPA,
    NOMINAL,
    REPLICATE,
    check_dominance,
    check_settings,
    homogeneous_legs,
    is_gradient,
    validation_tasks,
)
from ._validate_pairs import _compare as _compare  # re-exported: tests pair replicate means with it
from ._validate_pairs import _paper_family, fallen_comparators, fallen_reasons, paired_table, replicate_means
from ._validate_rules import (
    DOMINATED,
    EQUIVALENT,
    NO_EVIDENCE,
    NOT_COMPARED,
    NOT_DOMINATED,
    TRADE_OFF,
    UNRESOLVED,
    UNTESTABLE,
    WORSE,
    YES,
    beats,
    dominance_state,
    dominated_by,
    paper_best,
    survival_state,
)

__all__ = [
    "ALPHA",
    "AXIAL",
    "BEHAVIOUR",
    "CHECKS",
    "CONFIDENCE",
    "CONTROL_KINDS",
    "DEFAULT_DOMINANCE",
    "DOMINANCE_RULES",
    "DOMINATED",
    "EQUIVALENCE_MARGIN",
    "EQUIVALENT",
    "FINE_CONTROL",
    "FINE_PLAIN",
    "HOMOGENEOUS",
    "HOMOGENEOUS_MODULI_GPA",
    "NOMINAL",
    "NOT_COMPARED",
    "NOT_DOMINATED",
    "NO_EVIDENCE",
    "REPLICATE",
    "TRADE_OFF",
    "UNRESOLVED",
    "UNTESTABLE",
    "WORSE",
    "YES",
    "answer",
    "beats",
    "check_dominance",
    "check_settings",
    "dominance_state",
    "dominated_by",
    "fallen_comparators",
    "fallen_reasons",
    "homogeneous_legs",
    "is_gradient",
    "paired_table",
    "paper_best",
    "PAIRED_RECORD_COLUMNS",
    "RECORD_COLUMNS",
    "RECORD_FLOAT_FORMAT",
    "record_tables",
    "replicate_means",
    "run_paired",
    "survival_state",
    "validate_front",
    "validation_tasks",
    "verdicts",
]


def _applicable_checks(g: pd.DataFrame) -> tuple:
    """The checks of :data:`CHECKS` that apply to one front design's runs
    `g`: all of them, less ``behaviour`` where the study's own behaviours
    (those of its runs under the other checks) already cover every one of
    :data:`~mat_hopper.core.behaviours.BEHAVIOUR_NAMES`: then no other behaviour
    is left to run, and the check is vacuous."""
    own = set(g.loc[g["check"] != BEHAVIOUR, "behaviour"])
    if set(BEHAVIOUR_NAMES) <= own:
        return tuple(c for c in CHECKS if c != BEHAVIOUR)
    return CHECKS


def verdicts(runs: pd.DataFrame, table: pd.DataFrame, rule: str = DEFAULT_DOMINANCE) -> pd.DataFrame:
    """One row per front design: stable under each check (True/False),
    stable everywhere, the paper designs that dominate it, whether that
    could be tested at its n, survives, and whether it beats its
    mass-matched leg and its rigid twin (:func:`beats`).

    Args:
        runs: a validation's run table (role, design, behaviour, check,
            status, ...).
        table: :func:`paired_table`'s table of those runs.
        rule: the domination rule (:data:`DOMINANCE_RULES`; default ``margin``).

    Returns:
        A pandas DataFrame, one row per front design in order of first
        appearance: design, ``stable: <check>`` for each of :data:`CHECKS`
        (False where the check has no run; ``stable: behaviour`` True,
        vacuously, where the study itself ran every behaviour of
        :data:`~mat_hopper.core.behaviours.BEHAVIOUR_NAMES`, so that no other
        is left), ``stable everywhere`` (stable under every check that
        applies: over the behaviours the study ran, and the others),
        ``dominated by`` (comma-separated paper designs), ``paper designs
        left out (fell)`` (:func:`fallen_comparators`), ``paper designs
        left out (why)`` (each with its first run that fell or diverged
        there, :func:`fallen_reasons`), ``survives``
        (True, False, or ``"untestable"`` where a stable design's
        comparisons with the paper's designs, survival's Holm family, are
        not all testable or there are none), ``against the paper's designs``
        (:func:`survival_state`: ``dominated``, ``unresolved``, ``not
        dominated`` shown, ``untestable`` or ``not compared``, so that a
        survivor nothing was shown against is told apart from one shown
        not dominated),
        ``beats its mass-matched leg`` and ``beats its rigid twin`` (:func:`beats`), and
        ``homogeneous legs of its mass dominating it`` (comma-separated
        ``E=<GPa>`` labels).

    Raises:
        ValueError: an unknown `rule`.
    """
    check_dominance(rule)
    front = runs[runs["role"] == "front"]
    rows = []
    for design, g in front.groupby("design", sort=False):
        row = {"design": design}
        applicable = _applicable_checks(g)
        for check in CHECKS:
            sel = g[g["check"] == check]
            if check not in applicable:  # no other behaviour to run: vacuously stable
                row[f"stable: {check}"] = True
                continue
            row[f"stable: {check}"] = bool(len(sel)) and bool((sel["status"] == OK).all())
        row["stable everywhere"] = all(row[f"stable: {c}"] for c in applicable)
        mine = table[(table["design"] == design) & (table["kind"] == "paper")]  # survival's family
        testable = bool(len(mine)) and bool(mine["testable"].all())
        dom = dominated_by(table, design, rule=rule)
        row["dominated by"] = ", ".join(dom)
        row["paper designs left out (fell)"] = ", ".join(fallen_comparators(runs, design))
        row["paper designs left out (why)"] = "; ".join(f"{p}: {w}" for p, w in fallen_reasons(runs, design).items())
        row["survives"] = (row["stable everywhere"] and not dom) if testable else "untestable"
        row["against the paper's designs"] = survival_state(table, design)
        if not row["stable everywhere"]:
            row["survives"] = False
        row["beats its mass-matched leg"] = beats(table, design, "mass-matched", rule)
        row["beats its rigid twin"] = beats(table, design, "rigid twin", rule)
        homog = dominated_by(table, design, kinds=(HOMOGENEOUS,), rule=rule)
        row["homogeneous legs of its mass dominating it"] = ", ".join(h.rsplit(" ", 1)[-1] for h in homog)
        rows.append(row)
    return pd.DataFrame(rows)


def run_paired(tasks: list, objective: Objective, front: dict, what: str, **options) -> tuple:
    """Run `tasks` through the runner's cache and pool and pair the front
    designs' replicates with their comparators (:func:`paired_table`).

    Args:
        tasks: RunSpecs labelled as :func:`validation_tasks` labels them.
        objective: the study's objective.
        front: {name: LegDesign} of the front designs.
        what: what the runs are, e.g. ``validation`` (the progress bar and errors say it).
        **options: ``cache_dir``, ``workers``, ``progress`` (the runner's)
            and ``alpha`` (the paired comparisons' level).

    Returns:
        (the runner's summary, one row per run; :func:`paired_table` of it).

    Raises:
        RuntimeError: a run raised (not a fall: that is a result).
    """
    res = run_grid(tasks, options.get("cache_dir"), workers=options.get("workers"),
                   progress=options.get("progress", False), desc=f"front {what}")  # fmt: skip
    runs = res.summary
    if res.n_failed:
        bad = runs[runs["status"] == FAILED]
        raise RuntimeError(f"{len(bad)} {what} run(s) failed: {'; '.join(bad['error'].astype(str).unique()[:3])}")
    return runs, paired_table(runs, objective, options.get("alpha", ALPHA), front)


def validate_front(
    front: dict,
    objective: Objective,
    *,
    replicates: int | None = None,
    cache_dir=None,
    workers: int | None = None,
    progress: bool = False,
    alpha: float = ALPHA,
    dominance: str = DEFAULT_DOMINANCE,
) -> dict:
    """Run every check (module doc) of the `front` designs, their controls
    and the paper's replicates, and judge them.

    Args:
        front: {name: LegDesign}.
        objective: the study's objective (profile, behaviours, settings).
        replicates: seeds per design (an int >= 2; default the profile's).
        cache_dir, workers, progress: the runner's.
        alpha: the significance level of the paired comparisons.
        dominance: the domination rule (:data:`DOMINANCE_RULES`; default
            ``margin``, module doc), recorded in the result.

    Returns:
        dict: ``runs`` (one row per run: role, design, behaviour, check,
        replicate, control_of, control, the runner's summary), ``paired``
        (:func:`paired_table`), ``paper_best`` (names), ``verdicts``
        (:func:`verdicts`), ``survivors`` ({name: LegDesign}) and
        ``surviving_fraction`` (survivors over the front; NaN where
        survival is untestable), ``dominance`` (the rule) and
        ``replicates`` (the seeds per design, n).

    Raises:
        ValueError: `replicates` not an integer, or fewer than 2, or an
            unknown `dominance` (checked before any run).
        RuntimeError: a validation run raised (not a fall: that is a result).
    """
    if replicates is not None and (isinstance(replicates, bool) or not isinstance(replicates, numbers.Integral)):
        raise ValueError(f"replicates must be an integer >= 2, got {replicates!r}")
    n = objective.profile.replicates if replicates is None else int(replicates)
    if n < 2:
        raise ValueError(f"validating a front needs at least 2 replicates per design, got {n}")
    check_dominance(dominance)
    runs, table = run_paired(validation_tasks(front, objective, n), objective, front, "validation",
                             cache_dir=cache_dir, workers=workers, progress=progress, alpha=alpha)  # fmt: skip
    ver = verdicts(runs, table, dominance)
    keep = set(ver.loc[ver["survives"].astype(str) == "True", "design"]) if len(ver) else set()
    testable = len(ver) and not (ver["survives"].astype(str) == "untestable").any()
    return {
        "runs": runs,
        "paired": table,
        "paper_best": paper_best(runs, objective, alpha, dominance),
        "verdicts": ver,
        "survivors": {k: v for k, v in front.items() if k in keep},
        "surviving_fraction": len(keep) / len(ver) if testable else np.nan,
        "dominance": dominance,
        "replicates": n,
    }


# The columns of book/records/optimizer-paper.csv: verdicts (less the free-text reasons), the rule and the leg.
RECORD_COLUMNS = (
    "design",
    "dominance",
    "searched",
    *(f"stable: {c}" for c in CHECKS),
    "stable everywhere",
    "dominated by",
    "paper designs left out (fell)",
    "survives",
    "against the paper's designs",
    "beats its mass-matched leg",
    "beats its rigid twin",
    "homogeneous legs of its mass dominating it",
    "densities_g_cm3",
    "moduli_gpa",
    "leg_mass_kg",
    "profile",
    "n_seeds",
)
# How the records write floats (pandas' to_csv float_format): 6 significant digits.
RECORD_FLOAT_FORMAT = "%.6g"
# The columns of book/records/optimizer-paired-paper.csv: paired_table's.
PAIRED_RECORD_COLUMNS = ("design", "against", "kind", "objective", "n_pairs", "pct_change", "ci_low", "ci_high",
                         "p", "p_min", "p_holm", "testable", "significant")  # fmt: skip


def _joined(values) -> str:
    """Per-segment values as the records write them: 4 significant digits,
    ';'-joined, base to foot; a rigid segment's modulus (None) as ``rigid``."""
    return ";".join("rigid" if v is None else f"{v:.4g}" for v in values)


def record_tables(validation: dict, legs: dict, objective: Objective, searched=(),
                  rules=DOMINANCE_RULES) -> tuple[pd.DataFrame, pd.DataFrame]:  # fmt: skip
    """A validation as the book's record tables (``optimizer-paper.csv`` and
    ``optimizer-paired-paper.csv``): its verdicts under each domination rule
    from the same runs (no run repeated), and its paired comparisons.

    Args:
        validation: :func:`validate_front`'s result (``verdicts``,
            ``paired``, ``dominance``, ``replicates``; ``runs`` where a rule
            other than its own is asked).
        legs: the {name: LegDesign} validated.
        objective: the study's objective (its profile and segment mass).
        searched: the names of the study's new designs (the others are the paper's).
        rules: the domination rules, one block of rows each, in this order.

    Returns:
        (verdicts, paired). verdicts: one row per rule and validated design,
        :data:`RECORD_COLUMNS`: the rule (``dominance``), ``searched``
        (bool), the verdicts' columns (:func:`verdicts`, less its reasons
        in words), ``densities_g_cm3`` (g/cm^3) and ``moduli_gpa`` (GPa)
        per segment, base to foot, ';'-joined at 4 significant digits,
        ``leg_mass_kg`` (kg, the objective's segment mass), ``profile``
        (its name) and ``n_seeds``. paired: :func:`paired_table`'s rows,
        :data:`PAIRED_RECORD_COLUMNS` (they do not depend on the rule).
        The records write both with ``float_format=RECORD_FLOAT_FORMAT``.

    Raises:
        ValueError: an unknown rule, or a rule other than the validation's
            asked of a validation without its ``runs``.
    """
    own, searched = validation["dominance"], set(searched)
    blocks = []
    for rule in rules:
        check_dominance(rule)
        if rule == own:
            ver = validation["verdicts"]
        elif "runs" in validation:
            ver = verdicts(validation["runs"], validation["paired"], rule)
        else:
            raise ValueError(f"the {rule} rule needs the validation's runs (it was judged under {own})")
        if ver.empty:  # nothing validated: no rows
            continue
        ver = ver.copy()
        ver.insert(1, "dominance", rule)
        ver.insert(2, "searched", ver["design"].isin(searched))
        ver["densities_g_cm3"] = [_joined(legs[d].densities_g_cm3) for d in ver["design"]]
        ver["moduli_gpa"] = [_joined(legs[d].moduli_gpa) for d in ver["design"]]
        ver["leg_mass_kg"] = [leg_mass_kg(legs[d], objective.segment_mass) for d in ver["design"]]
        ver["profile"] = objective.profile.name
        ver["n_seeds"] = validation["replicates"]
        blocks.append(ver.reindex(columns=list(RECORD_COLUMNS)))
    out = pd.concat(blocks, ignore_index=True) if blocks else pd.DataFrame(columns=list(RECORD_COLUMNS))
    return out, validation["paired"].reindex(columns=list(PAIRED_RECORD_COLUMNS)).reset_index(drop=True)


def answer(validation: dict, front: dict) -> str:
    """The chapter's plain answer from a validation's numbers.

    Args:
        validation: :func:`validate_front`'s result.
        front: the {name: LegDesign} validated.

    Returns:
        How many front designs survive, and for each surviving gradient how
        it compares with a homogeneous leg of its own mass: its
        mass-matched leg (:func:`beats`, with the paired intervals) and the
        homogeneous legs of its mass across moduli (which of them dominate
        it). A gradient beats the homogeneous leg of equal mass when it
        beats its mass-matched leg and none of the homogeneous legs
        dominates it.
    """
    ver, table = validation["verdicts"], validation["paired"]
    rule = validation.get("dominance", DEFAULT_DOMINANCE)
    n_front = len(ver)
    if n_front == 0:
        return "The front held no design to validate."
    if np.isnan(validation["surviving_fraction"]):
        n = int(table["n_pairs"].min()) if len(table) else 0
        return (
            f"Survival is untestable here: {n} seeds cannot bring an exact sign-flip test under Holm's threshold "
            f"for the {_paper_family(table)} comparisons with the paper's designs; run the paper profile "
            "(10 seeds)."
        )
    head = f"{len(validation['survivors'])} of {n_front} designs survive validation."
    grads = [n for n, d in validation["survivors"].items() if is_gradient(d)]
    if not grads:
        return head + " No surviving design is a gradient."
    parts, k = [], 0
    for name in grads:
        rows = table[(table["design"] == name) & (table["kind"] == "mass-matched")]
        said = "; ".join(
            f"{r.objective} {r.pct_change:+.1f} % [{r.ci_low:+.1f}, {r.ci_high:+.1f}]" for r in rows.itertuples()
        )
        v = beats(table, name, "mass-matched", rule)
        homog = [h.rsplit(" ", 1)[-1] for h in dominated_by(table, name, kinds=(HOMOGENEOUS,), rule=rule)]
        k += v == YES and not homog
        parts.append(
            f"{name}: against its mass-matched leg {v} ({said}); "
            + (
                f"dominated by the homogeneous legs of its mass at {', '.join(homog)}"
                if homog
                else "no homogeneous leg of its mass dominates it"
            )  # fmt: skip
        )
    verdict = "Yes" if k else "No"
    return (
        head
        + f" {verdict}: {k} of {len(grads)} surviving gradients beat the homogeneous leg of equal mass "
        + "(better than their mass-matched leg, and dominated by no homogeneous leg of their mass). "
        + " | ".join(parts)
    )
