"""Paired contrasts of a factorial of legs, with their Holm families and conclusions.

A factorial (e.g. the crossed legs of chapter 9c: mass distribution x
modulus, :mod:`mat_hopper.experiments.crossed_legs`) is read as contrasts,
each one leg against another on the same replicate seeds. Each contrast
and metric gets the paired effect of :func:`mat_hopper.analysis.paired.paired_effect`
(percent change of the geometric means, its t interval, p). The factorial's
contrasts of one metric are one Holm family: they answer one question
(which factor moves the metric). A contrast named in ``alone`` (the claim
the factorial explains) is a family of its own, its p unadjusted, as it
is tested in the claims table. The conclusion is
:func:`mat_hopper.analysis.paired.conclusion` on the Holm-adjusted p.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ..physics.metrics import holm
from . import paired


def _leg(run_means: pd.DataFrame, leg: str, metric: str) -> pd.Series:
    # a leg with no usable run has no rows: an empty side, so the contrast's pairs are none (NaNs)
    if leg not in run_means.index.get_level_values(0):
        return pd.Series(dtype=float)
    return run_means.xs(leg, level=0)[metric]


def factorial_effects(
    run_means: pd.DataFrame, contrasts: dict, metrics=("tracking_error_m", "power_total_w"), alone=()
) -> pd.DataFrame:
    """The factorial's table: one row per contrast and metric.

    Args:
        run_means: the usable runs' means, indexed by (leg label, replicate
            seed), one column per metric (units as the metric's, e.g. m, W).
            Runs dropped as unusable are simply absent: each contrast pairs
            only the seeds both legs have.
        contrasts: ``{label: (leg, against)}``, leg labels of `run_means`'
            first index level (e.g.
            :data:`mat_hopper.experiments.crossed_legs.CONTRASTS`).
        metrics: columns of `run_means` to compare, in the table's order
            within each contrast.
        alone: contrast labels that are each a Holm family of their own
            (``p_holm`` = ``p``); every other contrast is in its metric's family.

    Returns:
        DataFrame: contrast, metric, then the columns of
        :func:`~mat_hopper.analysis.paired.paired_effect` (n_pairs, method,
        pct_change, ci_low, ci_high in %, p, p_t, p_wilcoxon, ...), then
        p_holm and conclusion. A contrast with fewer than 2 pairs has NaN
        effects and counts in its family as untestable
        (:func:`~mat_hopper.physics.metrics.holm`).

    Raises:
        ValueError: a metric not in `run_means`, or a label in `alone` that
            is not a contrast.
    """
    missing = [m for m in metrics if m not in run_means.columns]
    if missing:
        raise ValueError(f"metrics not in the run means: {missing}; columns are {list(run_means.columns)}")
    unknown = [a for a in alone if a not in contrasts]
    if unknown:
        raise ValueError(f"alone names contrasts that are not in contrasts: {unknown}")
    table = pd.DataFrame(
        [
            {
                "contrast": label,
                "metric": m,
                **paired.paired_effect(_leg(run_means, a, m), _leg(run_means, c, m)),
            }
            for label, (a, c) in contrasts.items()
            for m in metrics
        ]
    )
    solo = table["contrast"].isin(list(alone))
    table["p_holm"] = np.nan
    table.loc[solo, "p_holm"] = table.loc[solo, "p"]
    for _, g in table[~solo].groupby("metric"):
        table.loc[g.index, "p_holm"] = holm(g["p"].to_numpy(float))
    table["conclusion"] = [
        paired.conclusion(p, lo, hi) for p, lo, hi in zip(table["p_holm"], table["ci_low"], table["ci_high"])
    ]
    return table
