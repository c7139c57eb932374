"""Confirming a study's front on seeds of its own before it is validated.

A front design is kept because its replicate means looked good on the
search's seeds (1000 ..). Validation judges it once, on seeds 0 .. 9.
Confirmation makes the same judgement again, on seeds of its own
(:data:`CONFIRMATION_SEED_START` ..: apart from validation's 0 .. and the
search's 1000 ..), as a replication study follows a discovery; where the
two disagree, the verdict measures the seeds more than the design.
Measured on the racing benchmark's ten fronts (97 designs whose runs all
ended upright, quick profile, ramp, 10 seeds each way; 2026-12-03):

- under the ``significance`` rule (the one before ``margin``), the two
  disjoint seed sets gave different verdicts for 26 of the 97 (Cohen's
  kappa 0.46);
- under the ``margin`` rule, for 6 of the 97; confirmation confirmed 91,
  and 90 of them survived validation.

So under the default rule confirmation buys little and costs much (below);
it is kept as the check that replicates a verdict, and for rules or
objectives where verdicts are less stable. Its steps:

1. every front design and every paper design runs the study's
   behaviours on ``replicates`` confirmation seeds (only the replicates:
   none of validation's other checks or controls);
2. each front design is compared with each paper design, paired by seed
   on each objective (:func:`mat_hopper.optimize.validate.paired_table`:
   log ratio of replicate means, t interval, paired t p, Holm over the
   design's comparisons with the paper's designs, significant only where an
   exact sign-flip test could reach Holm's threshold);
3. a design is *confirmed* when every replicate ran upright and no paper
   design dominates it (validation's rule,
   :data:`~mat_hopper.optimize.validate.DEFAULT_DOMINANCE`), exactly
   validation's survival rule on other seeds.

The confirmed designs go on to validation, which judges them on seeds
0 .. the confirmation never saw, so the confirmation's selection does not
bias the surviving fraction measured there. The cost is simulated
seconds: ``replicates`` runs per behaviour of each front design, and the
same for the nine paper designs (a fixed cost per objective, which a
cache shares between studies of the same objective). On the quick profile
a front of 6 costs 6 x 10 x 12 s = 720 s and the paper designs 1080 s,
against the 687-745 s the benchmark's racing studies spent searching.
"""

from __future__ import annotations

import numbers

import numpy as np
import pandas as pd

from ..core.behaviours import behaviour as get_behaviour
from ..core.materials import paper_designs
from ..experiments.runner import OK, RunSpec
from ._objective import Objective
from .validate import ALPHA, DEFAULT_DOMINANCE, REPLICATE, check_dominance, dominated_by, run_paired

__all__ = [
    "CONFIRMATION_SEED_START",
    "DEFAULT_CONFIRMATION_SEEDS",
    "MAX_CONFIRMATION_SEEDS",
    "confirm_front",
    "confirmation_tasks",
    "confirmation_verdicts",
]

CONFIRMATION_SEED_START = 2000  # apart from validation's seeds 0.. and the search's 1000.. (SEARCH_SEED_START)
DEFAULT_CONFIRMATION_SEEDS = 10  # the fewest reaching Holm's 0.05 in 18 comparisons; 27 (3 objectives) need 11
MAX_CONFIRMATION_SEEDS = 1000  # seeds 2000..2999: never the search's (at most 1000..1063) nor validation's (0..)


def confirmation_tasks(front: dict, objective: Objective, replicates: int, paper: dict | None = None) -> list:
    """RunSpecs of the confirmation: each front and paper design on the
    study's behaviours, on seeds ``CONFIRMATION_SEED_START`` ..
    ``CONFIRMATION_SEED_START + replicates - 1``.

    Args:
        front: {name: LegDesign} of the front designs.
        objective: the study's objective (profile, behaviours, settings).
        replicates: seeds per design and behaviour (not checked here).
        paper: {name: LegDesign} of the designs compared against; None (the
            default) for :func:`mat_hopper.core.materials.paper_designs`.

    Returns:
        A list of RunSpec labelled role (``front`` or ``paper``), design,
        behaviour, check (``replicate``), replicate (the seed), control_of
        and control (both ""), the labels
        :func:`mat_hopper.optimize.validate.paired_table` reads.
    """
    paper = paper_designs() if paper is None else paper
    tasks = []
    for role, designs in (("front", front), ("paper", paper)):
        for name, d in designs.items():
            for b in objective.behaviours:
                for seed in range(CONFIRMATION_SEED_START, CONFIRMATION_SEED_START + replicates):
                    settings = objective.sim_settings(objective.profile.replicate(seed), d)
                    labels = {"role": role, "design": name, "behaviour": b, "check": REPLICATE, "replicate": seed}
                    tasks.append(RunSpec(d, get_behaviour(b), settings, {**labels, "control_of": "", "control": ""}))
    return tasks


def confirmation_verdicts(runs: pd.DataFrame, table: pd.DataFrame, rule: str = DEFAULT_DOMINANCE) -> pd.DataFrame:
    """Judge each front design of a confirmation (module doc).

    Args:
        runs: the confirmation's run table (role, design, replicate,
            behaviour, check, status and the objectives' summary columns).
        table: :func:`~mat_hopper.optimize.validate.paired_table` of those runs.
        rule: the domination rule
            (:data:`~mat_hopper.optimize.validate.DOMINANCE_RULES`; default ``margin``).

    Returns:
        A pandas DataFrame, one row per front design in order of first
        appearance: design, stable (every replicate run ended upright,
        runner status ``ok``), dominated by (comma-separated paper designs),
        testable (its comparisons with the paper's designs could reach
        Holm's threshold), confirmed (True, False, or ``"untestable"`` for
        a stable design whose comparisons are not testable).

    Raises:
        ValueError: an unknown `rule`.
    """
    check_dominance(rule)
    rows = []
    for design, g in runs[runs["role"] == "front"].groupby("design", sort=False):
        mine = table[(table["design"] == design) & (table["kind"] == "paper")]
        testable = bool(len(mine)) and bool(mine["testable"].all())
        stable = bool((g["status"] == OK).all())
        dom = dominated_by(table, design, rule=rule)
        confirmed = (not dom) if testable else "untestable"
        rows.append({"design": design, "stable": stable, "dominated by": ", ".join(dom),
                     "testable": testable, "confirmed": confirmed if stable else False})  # fmt: skip
    return pd.DataFrame(rows, columns=["design", "stable", "dominated by", "testable", "confirmed"])


def confirm_front(
    front: dict,
    objective: Objective,
    *,
    replicates: int = DEFAULT_CONFIRMATION_SEEDS,
    cache_dir=None,
    workers: int | None = None,
    progress: bool = False,
    alpha: float = ALPHA,
    dominance: str = DEFAULT_DOMINANCE,
) -> dict:
    """Confirm the `front` designs against the paper's on confirmation seeds (module doc).

    Args:
        front: {name: LegDesign}.
        objective: the study's objective (profile, behaviours, objectives).
        replicates: confirmation seeds per design (an int >= 2; default
            :data:`DEFAULT_CONFIRMATION_SEEDS`, 10: with fewer, 9 paper
            designs x 2 objectives cannot reach Holm's threshold and every
            design is ``untestable``).
        cache_dir, workers, progress: the runner's.
        alpha: the significance level of the paired comparisons.
        dominance: the domination rule (validation's; default ``margin``).

    Returns:
        dict: ``runs`` (the runner's summary, one row per run, with the
        labels of :func:`confirmation_tasks`), ``paired`` (the front
        designs against the paper's: :func:`~mat_hopper.optimize.validate.paired_table`),
        ``verdicts`` (design, stable, dominated by, testable, confirmed:
        True, False or ``"untestable"``), ``confirmed`` ({name: LegDesign}
        of the designs confirmed), ``simulated_s`` (the simulated seconds
        of every confirmation run, the paper designs' included; s) and
        ``front_simulated_s`` (those of the front designs' runs only; s)
        and ``dominance`` (the rule).

    Raises:
        ValueError: `replicates` not an integer in [2, 1000], or an unknown
            `dominance` (checked before any run).
        RuntimeError: a confirmation run raised (not a fall: that is a result).
    """
    if isinstance(replicates, bool) or not isinstance(replicates, numbers.Integral):
        raise ValueError(f"replicates must be an integer >= 2, got {replicates!r}")
    if not 2 <= replicates <= MAX_CONFIRMATION_SEEDS:
        raise ValueError(f"replicates must be an integer >= 2 and <= {MAX_CONFIRMATION_SEEDS}, got {replicates!r}")
    check_dominance(dominance)
    tasks = confirmation_tasks(front, objective, int(replicates))
    runs, table = run_paired(tasks, objective, front, "confirmation",
                             cache_dir=cache_dir, workers=workers, progress=progress, alpha=alpha)  # fmt: skip
    ver = confirmation_verdicts(runs, table, dominance)
    keep = set(ver.loc[ver["confirmed"].astype(str) == "True", "design"])
    durations = np.array([t.settings.duration_s for t in tasks], float)
    is_front = np.array([t.labels["role"] == "front" for t in tasks], bool)
    return {
        "runs": runs,
        "paired": table,
        "verdicts": ver,
        "confirmed": {k: v for k, v in front.items() if k in keep},
        "simulated_s": float(durations.sum()),
        "front_simulated_s": float(durations[is_front].sum()),
        "dominance": dominance,
    }
