"""Chapter 8b's verdicts on the stress pairs: does a gradient change the
loads at equal mass, or the life against a real homogeneous leg?

:func:`stress_verdicts` reads the runs of
:func:`mat_hopper.experiments.stress_pairs.stress_pair_tasks` (one
summary row per run): per convention, paired on the seed, each gradient
against its mass-matched leg (a hop's median peak stress, the run's peak
stress) and against titanium (a hop's median peak stress, the fatigue
safety factor), with Holm over the four gradients of each comparison and
the sign-flip floor deciding what the seeds can show
(:mod:`mat_hopper.analysis.paired`).
"""

from __future__ import annotations

import pandas as pd

from ..physics.metrics import holm
from . import paired

# (metric, control): the loads, a hop's peak (median over the run's hops)
# first and the run's maximum (an extreme that follows one hard landing)
# beside it; the life against titanium's own S-N curve.
COMPARISONS = (
    ("hop_peak_stress_median_pa", "mass-matched"),
    ("hop_peak_stress_median_pa", "titanium"),
    ("peak_stress_pa", "mass-matched"),
    ("fatigue_safety_factor", "titanium"),
)


def usable_pairs(runs: pd.DataFrame) -> pd.DataFrame:
    """The runs that count: status ``ok`` with at least two scored hops (a
    run that diverged or fell keeps the hops before, which are not results).

    Args:
        runs: run summaries (``status``, ``n_hops`` columns).

    Returns:
        The rows of `runs` that count, in their order.
    """
    return runs[(runs["status"] == "ok") & (runs["n_hops"] >= 2)]


def stress_verdicts(runs: pd.DataFrame, n_seeds: int) -> pd.DataFrame:
    """Paired verdicts of every gradient against its controls (module doc).

    Args:
        runs: the stress pairs' run summaries (labels convention, gradient,
            leg, replicate; the metric columns of :data:`COMPARISONS`).
        n_seeds: the seeds run per leg (a pair lacking either run is
            dropped and counted in ``pairs_dropped``).

    Returns:
        tidy DataFrame, one row per convention, gradient, metric and
        control: pairs_dropped, :func:`paired.paired_effect`'s columns
        (pct_change of the gradient against the control, ci_low, ci_high,
        p, n_pairs, ...), p_holm and conclusion.
    """
    ok = usable_pairs(runs)
    rows = []
    for conv, conv_runs in ok.groupby("convention", sort=False):
        wide = conv_runs.pivot_table(
            index=["gradient", "replicate"], columns="leg", values=sorted({m for m, _ in COMPARISONS})
        )
        for metric, control in COMPARISONS:
            for name, grp in wide.groupby(level="gradient", sort=False):
                if (metric, control) not in grp.columns or (metric, "gradient") not in grp.columns:
                    continue
                both = grp[[(metric, "gradient"), (metric, control)]].dropna()
                e = paired.paired_effect(both.iloc[:, 0], both.iloc[:, 1])  # paired on the seed
                row = {"convention": conv, "gradient": name, "metric": metric, "against": control}
                rows.append({**row, "pairs_dropped": n_seeds - e["n_pairs"], **e})
    verdicts = pd.DataFrame(rows)
    if verdicts.empty:
        return verdicts
    for _, g in verdicts.groupby(["convention", "metric", "against"], sort=False):
        verdicts.loc[g.index, "p_holm"] = holm(g["p"].to_numpy(float))
        testable = paired.reachable(int(g["n_pairs"].min()), len(g))
        verdicts.loc[g.index, "conclusion"] = [
            c if testable or c != paired.DIFFERENCE else paired.NOT_ENOUGH
            for c in (
                paired.conclusion(p, lo, hi) for p, lo, hi in zip(verdicts.loc[g.index, "p_holm"], g.ci_low, g.ci_high)
            )
        ]
    return verdicts
