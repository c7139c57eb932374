"""A front's validation runs paired by seed: replicate means and paired comparisons.

Every front design is compared with each comparator (the paper's designs,
its mass-matched leg, its rigid twin, the homogeneous legs of its mass) on
each of the study's objectives, on the replicate seeds both ran
(:func:`mat_hopper.analysis.paired.paired_effect`: the log ratio of the
replicate means, its t interval, the paired t p), Holm-adjusted within one
family per comparator kind. A paper design that fell where the front design
stood up is left out of its survival family (:func:`fallen_comparators`).
Percent changes in %, objectives in their SI units. Used by
:mod:`mat_hopper.optimize.validate`.
"""

from __future__ import annotations

import pandas as pd

from ..analysis import paired
from ..core.materials import paper_designs
from ..experiments.runner import DIVERGED, FALLEN, OK
from ..physics.metrics import holm
from ..physics.run_metrics import METRICS
from ..util.keys import design_key
from ._objective import Objective
from ._validate_checks import ALPHA, CONFIDENCE, CONTROL_KINDS, HOMOGENEOUS, REPLICATE


def _summary_column(name: str) -> str:
    """The runs column of objective `name`: the run summary's
    (:attr:`~mat_hopper.physics.run_metrics.Metric.summary_column`; leg mass
    is the whole leg's there and in the objective alike)."""
    return METRICS[name].summary_column


def replicate_means(runs: pd.DataFrame, objective: Objective) -> pd.DataFrame:
    """Per (role, design, replicate): each of the objective's metrics
    (``objective.objectives``, read from its run-summary column) as the mean
    over the study's behaviours, from the replicate runs that ended well; a
    replicate that fell or diverged on any behaviour is missing (NaN). A
    stress metric of a leg with no modelled stress (rigid segments) is NaN,
    so that it is left out of the comparisons (:func:`_compare`).

    Args:
        runs: a validation's run table (columns role, design, replicate,
            behaviour, check, status and the objectives' summary columns).
        objective: the study's objective (its objectives and behaviours).

    Returns:
        A pandas DataFrame indexed by (role, design, replicate), one column
        per objective name (its units); only replicates with a run of
        status ``ok`` on every one of the study's behaviours have a row.
    """
    reps = runs[(runs["check"] == REPLICATE) & (runs["status"] == OK)]
    cols = {_summary_column(o): o for o in objective.objectives}
    g = reps.groupby(["role", "design", "replicate"])
    means = g[list(cols)].mean()
    complete = g["behaviour"].nunique() == len(objective.behaviours)
    return means[complete].rename(columns=cols)


def _compare(means: pd.DataFrame, a: tuple, b: tuple) -> dict:
    """Paired effects of design a against design b ((role, name) each) per
    objective (the columns of `means`), on the seeds both have; an objective
    that either design lacks altogether (a stress metric of a rigid leg) is
    left out."""
    out = {}
    for obj in means.columns:
        if means.loc[a][obj].isna().all() or means.loc[b][obj].isna().all():
            continue
        pair = pd.concat([means.loc[a][obj], means.loc[b][obj]], axis=1, join="inner").dropna()
        out[obj] = paired.paired_effect(pair.iloc[:, 0], pair.iloc[:, 1], confidence=CONFIDENCE)
    return out


def paired_table(
    runs: pd.DataFrame, objective: Objective, alpha: float = ALPHA, front: dict | None = None
) -> pd.DataFrame:
    """Every front design against each comparator (the paper's designs,
    its mass-matched leg, its rigid twin, the homogeneous legs of its
    mass), paired by seed (module doc).

    Args:
        runs: a validation's run table.
        objective: the study's objective (its objectives are compared).
        alpha: the significance level.
        front: {name: LegDesign} of the front designs (a paper design among
            them is not compared with itself).

    Returns:
        One row per front design, comparator and objective (a paper
        design that fell on one of the front design's seeds is left out:
        :func:`fallen_comparators`): design,
        against, kind (``paper``, ``mass-matched``, ``rigid twin``,
        ``homogeneous``),
        objective, n_pairs, pct_change, ci_low, ci_high (%: the design
        against the comparator; below 0: the design is lower, better), p,
        p_min, p_holm (Holm within the design's rows of one kind: one
        question's family), testable (an exact sign-flip test could reach
        Holm's threshold in that family), significant.
    """
    means = replicate_means(runs, objective)
    have = set(means.index.droplevel("replicate"))
    front_design = front or {}
    paper_key = {n: design_key(d) for n, d in paper_designs().items()}
    rows = []
    for name in runs.loc[runs["role"] == "front", "design"].unique():
        if ("front", name) not in have:
            continue
        own = design_key(front_design[name]) if name in front_design else None
        fell = set(fallen_comparators(runs, name))
        # the paper's designs, not the design itself (a paper gradient validated as a front design),
        # nor one that fell where this design stayed up (module doc: it cannot dominate it)
        comparators = [
            (("paper", p), p, "paper")
            for r, p in sorted(have)
            if r == "paper" and (own is None or paper_key.get(p) != own) and p not in fell
        ]
        comparators += [(("control", f"{name}~{k}"), f"{name}~{k}", v) for k, v in CONTROL_KINDS.items()]
        comparators += [
            (("control", c), c, HOMOGENEOUS)
            for r, c in sorted(have)
            if r == "control" and c.startswith(f"{name}~{HOMOGENEOUS} ")
        ]
        mine = []
        for key, label, kind in comparators:
            if key not in have:
                continue
            for obj, e in _compare(means, ("front", name), key).items():
                mine.append({"design": name, "against": label, "kind": kind, "objective": obj, **e})
        if not mine:
            continue
        rows.extend(_holm_by_kind(pd.DataFrame(mine), alpha))
    cols = ["design", "against", "kind", "objective", "n_pairs", "pct_change", "ci_low", "ci_high", "p", "p_min"]
    if not rows:
        return pd.DataFrame(columns=[*cols, "p_holm", "testable", "significant"])
    return pd.concat(rows, ignore_index=True)[[*cols, "p_holm", "testable", "significant"]]


def fallen_comparators(runs: pd.DataFrame, design: str) -> list[str]:
    """The paper designs that fell or diverged (runner status ``fallen`` or
    ``diverged``) in a replicate run on a seed where the front `design`
    stood up on every behaviour (module doc). A run that failed (raised) is
    missing data, not a fall: it leaves its comparator in, with fewer pairs.

    Args:
        runs: a validation's run table (role, design, check, replicate, status).
        design: the front design's name.

    Returns:
        Sorted names of those paper designs (empty where `design` has no
        replicate run, or none fell where it stood up).

    Raises:
        ValueError: `runs` not a pandas DataFrame, or lacking one of the
            columns named above.
    """
    need = ("role", "design", "check", "replicate", "status")
    if not isinstance(runs, pd.DataFrame) or not set(need) <= set(runs.columns):
        raise ValueError(f"runs must be a validation's run table, a DataFrame with columns {', '.join(need)}")
    reps = runs[runs["check"] == REPLICATE]
    mine = reps[(reps["role"] == "front") & (reps["design"] == design)]
    stood = mine.groupby("replicate")["status"].agg(lambda s: bool((s == OK).all()))
    seeds = set(stood[stood].index)
    fell = reps[(reps["role"] == "paper") & reps["status"].isin([FALLEN, DIVERGED])]
    return sorted(p for p, g in fell.groupby("design") if seeds & set(g["replicate"]))


def fallen_reasons(runs: pd.DataFrame, design: str) -> dict[str, str]:
    """Why each of :func:`fallen_comparators`' paper designs is left out:
    its first replicate run that fell or diverged on a seed where the front
    `design` stood, e.g. ``diverged at t = 0.0043 s (ramp, seed 3)`` or
    ``fell (ramp, seed 7)``.

    Args:
        runs: a validation's run table (as :func:`fallen_comparators`; a
            ``diverged_at_s`` column, when present, gives the time).
        design: the front design's name.

    Returns:
        {paper design: reason}, in the order of :func:`fallen_comparators`.
    """
    names = fallen_comparators(runs, design)
    reps = runs[runs["check"] == REPLICATE]
    mine = reps[(reps["role"] == "front") & (reps["design"] == design)]
    stood = mine.groupby("replicate")["status"].agg(lambda s: bool((s == OK).all()))
    seeds = set(stood[stood].index)
    out = {}
    for name in names:
        bad = reps[(reps["role"] == "paper") & (reps["design"] == name) & reps["status"].isin([FALLEN, DIVERGED])]
        r = bad[bad["replicate"].isin(seeds)].sort_values("replicate", kind="stable").iloc[0]
        where = f"{r['behaviour']}, seed {int(r['replicate'])}" if "behaviour" in r else f"seed {int(r['replicate'])}"
        t = r.get("diverged_at_s")
        if r["status"] == DIVERGED:
            out[name] = f"diverged at t = {float(t):.4g} s ({where})" if pd.notna(t) else f"diverged ({where})"
        else:
            out[name] = f"fell ({where})"
    return out


def _holm_by_kind(t: pd.DataFrame, alpha: float) -> list[pd.DataFrame]:
    """One front design's comparisons, Holm-adjusted within each question's
    family: its comparator kind (the paper's designs decide survival, each
    control kind its ``beats`` verdict). One family over every comparator
    would leave survival untestable at 10 seeds (30 comparisons x
    2 / 2^10 > 0.05)."""
    out = []
    for _, f in t.groupby("kind", sort=False):
        f = f.copy()
        f["p_holm"] = holm(f["p"].to_numpy(float))
        f["testable"] = paired.reachable(int(f["n_pairs"].min()), len(f), alpha)
        f["significant"] = f["testable"] & (f["p_holm"] < alpha)
        out.append(f)
    return out


def _paper_family(table: pd.DataFrame) -> int:
    """The largest survival family (a front design's comparisons with the paper's designs)."""
    paper_rows = table[table["kind"] == "paper"]
    return int(paper_rows.groupby("design").size().max()) if len(paper_rows) else 0
