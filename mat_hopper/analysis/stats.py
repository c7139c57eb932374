"""Statistics of the results: summaries, comparisons against a baseline,
and replicate-level inference.

Two bases for a comparison of designs:

``hops`` (the paper's)
    every scored hop cycle of one run is a sample; the design's cycles are
    compared with the baseline's by a two-sided Mann-Whitney U test
    (:func:`mat_hopper.physics.metrics.compare_independent`), Holm-corrected over one family:
    one metric within one experiment, profile and stiffness convention
    (every design against the baseline on every behaviour: 16 comparisons
    for experiment 1), the family of one figure panel and of one claim.
``replicates``
    every replicate run is a sample: N runs per design and behaviour, each
    with its own seeded small perturbation
    (:meth:`mat_hopper.core.perturbations.Perturbation.replicate`), are reduced
    to one mean per run, and the designs are compared on these means: a
    Mann-Whitney U test across replicates (Holm-corrected over the family)
    and a percentile bootstrap confidence interval of the percent change.

Why replicates. Hop cycles of one deterministic run are not independent
samples: each cycle starts from the state the previous one left, the
controller adapts its thrust from the last hop, and a periodic gait repeats
almost the same cycle again and again. A p-value over hop cycles grows
smaller with the run's length, not with the evidence; it describes one run,
it does not infer anything about the design. Worse, our simulation is
deterministic and perfectly symmetric: in-place (static) hopping starts
upright above its target and nothing ever pushes it sideways, so it has no
lateral motion at all, and its tracking error is zero (or round-off) for
every design. We measured exactly 0.0 m for the stainless-steel leg hopping
in place, unperturbed. The spread of static-hopping tracking error that
the paper shows must come from perturbations its implementation introduced
without naming them: its desired path and its loop ran on the wall clock,
so every run saw a slightly different timing. Replicates replace these
accidental disturbances by small, documented, seeded ones (a few mm of
start offset, half a degree of tilt, one gentle push, sensor noise), and
they are how the book can still say something about in-place hopping, and
about any difference between designs that is larger than run-to-run noise.

Round-off. Values smaller in magnitude than ``ROUNDOFF`` (1e-9 in SI
units: 1 nm, 1 nW) count as exactly zero in every comparison. Unperturbed
static hopping gives MD a tracking error of 1e-17 m (round-off) and SS
exactly 0.0 m; compared as they are, a rank test calls that difference
"significant" (p = 3e-6 over 13 and 14 hop cycles of 14 s runs).

Test power with few replicates: with n replicates per design the smallest
two-sided Mann-Whitney p is 2 / C(2n, n) (n = 5: 0.0079; n = 6: 0.0022;
n = 10: 1.1e-5). Holm's correction multiplies the smallest p by the number
of comparisons in the family, so experiment 1's family of 16 comparisons
(4 materials x 4 behaviours, one metric) needs n >= 6 replicates before
any difference can be significant at 0.05, whatever its size. The
bootstrap interval does not depend on the family; read both.

The run-level helpers (family and run columns, unusable runs, replicate
selection, replicate means) live in the package-private ``_runs`` and are
re-exported here.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ..physics import metrics as _metrics
from ..physics.metrics import METRICS
from ..util.change import ROUNDOFF, percent_change
from ..util.parsing import parse_name
from ._runs import (
    FAMILY_COLUMNS,
    RUN_COLUMNS,
    SWEEP_COLUMNS,
    UNPERTURBED,
    _check_metrics,
    _families,
    _present,
    combine_experiments,
    drop_unusable,
    has_replicates,
    replicate_means,
    seconds,
    select_replicates,
    unusable_runs,
)

__all__ = [
    "BASES",
    "FAMILY_COLUMNS",
    "RUN_COLUMNS",
    "SWEEP_COLUMNS",
    "UNPERTURBED",
    "bootstrap_pct_change",
    "combine_experiments",
    "compare_designs",
    "compare_hops",
    "compare_replicates",
    "drop_unusable",
    "has_replicates",
    "replicate_means",
    "seconds",
    "select_replicates",
    "summary_table",
    "unusable_runs",
]

BASES = ("hops", "replicates")


def _compare_families(table: pd.DataFrame, baseline: str, by: str, metrics, alpha: float):
    """metrics.compare_independent per family and metric (one Holm correction each),
    family columns in front: a list of (family sub-table, result); families
    without the baseline are skipped."""
    frames = []
    for fam, g in _families(table):
        if baseline not in set(g["design"]):
            continue
        for m in metrics:
            v = pd.to_numeric(g[m], errors="coerce").astype(float)
            g = g.assign(**{m: v.where(~(v.abs() < ROUNDOFF), 0.0)})
            res = _metrics.compare_independent(g, baseline, by=by, metrics=(m,), alpha=alpha)
            for k, v in reversed(fam.items()):
                res.insert(0, k, v)
            frames.append((g, res))
    return frames


def summary_table(
    hops: pd.DataFrame,
    *,
    by=("design", "behaviour"),
    metrics=METRICS,
    baseline: str | None = "MD",
    replicate: int | None = UNPERTURBED,
) -> pd.DataFrame:
    """Mean, median and IQR of each metric per design and behaviour (per
    family), tidy, with the percent change of mean and median against the
    baseline design in the same family and behaviour (nan without one).

    Built on :func:`mat_hopper.physics.metrics.summarize`.

    Args:
        hops: a per-hop table.
        by: the grouping columns; the family columns present (experiment, profile, convention) are
            put in front.
        metrics: metric columns.
        baseline: the baseline design; None: no percent-change columns.
        replicate: the replicate id summarized (default the unperturbed run, -1; None: every row,
            :func:`select_replicates`).

    Returns:
        DataFrame, one row per group and metric. Columns: family columns, `by`, metric, n (hop
        cycles), mean, median, iqr and, with a baseline and ``design`` in `by`: mean_baseline,
        median_baseline, pct_change_mean, pct_change_median (%), baseline. Empty (without the baseline
        columns) when no row is left.

    Raises:
        ValueError: a metric that is not a column of `hops`.
    """
    metrics = _check_metrics(hops, metrics)
    hops = select_replicates(hops, replicate)
    fam = _present(hops, FAMILY_COLUMNS)
    by = tuple(c for c in fam if c not in by) + tuple(by)
    if len(hops) == 0:
        return pd.DataFrame(columns=[*by, "metric", "n", "mean", "median", "iqr"])
    out = _metrics.summarize(hops, by=by, metrics=metrics)
    if baseline is None or "design" not in by:
        return out
    keys = [c for c in by if c != "design"] + ["metric"]
    base = out[out["design"] == baseline][keys + ["mean", "median"]]
    base = base.rename(columns={"mean": "mean_baseline", "median": "median_baseline"})
    out = out.merge(base, on=keys, how="left")
    out["pct_change_mean"] = percent_change(out["mean"], out["mean_baseline"])
    out["pct_change_median"] = percent_change(out["median"], out["median_baseline"])
    out["baseline"] = baseline
    return out


def compare_hops(
    hops: pd.DataFrame,
    baseline: str = "MD",
    *,
    by: str = "behaviour",
    metrics=METRICS,
    alpha: float = 0.05,
    replicate: int | None = UNPERTURBED,
) -> pd.DataFrame:
    """The paper's comparison on hop cycles: every design against `baseline`
    per `by` group and metric (:func:`mat_hopper.physics.metrics.compare_independent`), one Holm
    family per metric, experiment, profile and convention. By default only
    the unperturbed run (replicate -1) is used; ``replicate=None`` pools all.

    Adds the family columns and ``basis = "hops"``.

    Metric values smaller in magnitude than ``ROUNDOFF`` count as 0 (module doc); families without
    the baseline are skipped.

    Args:
        hops: a per-hop table (design, `by`, the metric columns).
        baseline: the baseline design.
        by: the grouping inside which designs are compared.
        metrics: metric columns.
        alpha: significance level of the Holm-adjusted p.
        replicate: the replicate id compared (:func:`select_replicates`); None pools all.

    Returns:
        DataFrame: family columns, then the columns of :func:`mat_hopper.physics.metrics.compare_independent` (`by`,
        design, baseline, metric, n, n_baseline, mean, mean_baseline, pct_change, u, p, effect_size,
        p_holm, significant), then basis.

    Raises:
        ValueError: a metric that is not a column of `hops`; the baseline in no family; or from
            :func:`mat_hopper.physics.metrics.compare_independent` (no `by` column, alpha not in (0, 1)).
    """
    metrics = _check_metrics(hops, metrics)
    hops = select_replicates(hops, replicate)
    frames = [res for _, res in _compare_families(hops, baseline, by, metrics, alpha)]
    if not frames:
        raise ValueError(
            f"baseline {baseline!r} not among the designs of any family: "
            f"{sorted(set(hops['design'])) if len(hops) else []}"
        )
    out = pd.concat(frames, ignore_index=True)
    out["basis"] = "hops"
    return out


def bootstrap_pct_change(
    values, baseline_values, *, n_boot: int = 10000, confidence: float = 0.95, seed: int = 0
) -> tuple[float, float, float]:
    """Percent change of the mean of `values` against the mean of
    `baseline_values`, and its percentile bootstrap interval (%).

    Both samples are resampled independently with replacement `n_boot`
    times from ``numpy.random.default_rng(seed)`` (deterministic). Returns
    (pct_change, low, high); nan where a sample is empty or the baseline
    mean is 0; resamples whose baseline mean is 0 are dropped.

    Args:
        values: the design's samples (e.g. replicate means); non-finite values are dropped.
        baseline_values: the baseline's samples; non-finite values are dropped.
        n_boot: the number of bootstrap resamples.
        confidence: of the interval, in (0, 1).
        seed: of the resampling.

    Returns:
        tuple[float, float, float]: (pct_change, low, high), %. "0" is a baseline mean below
        ``ROUNDOFF`` in magnitude (:func:`mat_hopper.util.change.percent_change`); low and high are nan
        where every resample is dropped.

    Raises:
        ValueError: `confidence` not in (0, 1); `n_boot` below 1.
    """
    a = np.asarray(values, dtype=float)
    b = np.asarray(baseline_values, dtype=float)
    a, b = a[np.isfinite(a)], b[np.isfinite(b)]
    if not 0 < confidence < 1:
        raise ValueError(f"confidence must be in (0, 1), got {confidence!r}")
    if int(n_boot) < 1:
        raise ValueError(f"n_boot must be an integer >= 1, got {n_boot!r}")
    if len(a) == 0 or len(b) == 0:
        return (np.nan, np.nan, np.nan)
    pct = percent_change(a.mean(), b.mean())
    if not np.isfinite(pct):
        return (np.nan, np.nan, np.nan)
    rng = np.random.default_rng(seed)
    ma = a[rng.integers(0, len(a), (int(n_boot), len(a)))].mean(axis=1)
    mb = b[rng.integers(0, len(b), (int(n_boot), len(b)))].mean(axis=1)
    boots = percent_change(ma, mb)
    boots = boots[np.isfinite(boots)]
    if len(boots) == 0:
        return (pct, np.nan, np.nan)
    tail = 50.0 * (1.0 - confidence)
    lo, hi = np.percentile(boots, [tail, 100.0 - tail])
    return (pct, float(lo), float(hi))


def _shares_seeds(means: pd.DataFrame, baseline: str, by: str) -> bool:
    """True when every design's replicate ids equal the baseline's in each group
    (the runs are paired by seed)."""
    keys = _present(means, FAMILY_COLUMNS) + [by]
    for _, g in means.groupby(keys, sort=False):
        base = set(g.loc[g["design"] == baseline, "replicate"])
        if not base:
            continue
        for _, dg in g.groupby("design", sort=False):
            if set(dg["replicate"]) != base:
                return False
    return True


def compare_replicates(
    hops: pd.DataFrame,
    baseline: str = "MD",
    *,
    by: str = "behaviour",
    metrics=METRICS,
    alpha: float = 0.05,
    n_boot: int = 10000,
    confidence: float = 0.95,
    seed: int = 0,
    paired: str | bool = "auto",
) -> pd.DataFrame:
    """Designs against `baseline` on replicate means (see module doc).

    `hops` is a per-hop table with a ``replicate`` column (the unperturbed
    run, -1, is left out). paired: ``auto`` (default) pairs the runs by
    replicate seed when every design shares the baseline's seeds (they do in
    every experiment of the package), True requires it, False never pairs.

    Paired (:func:`mat_hopper.analysis.paired.compare_paired`): log ratios
    per seed, paired t test and t interval, Wilcoxon signed-rank as a
    check, a conclusion with the equivalence margin. Unpaired: n
    (replicates), means of replicate means, percent change with its
    bootstrap interval (``ci_low``, ``ci_high``, %), Mann-Whitney U across
    replicates, rank-biserial effect size. Either way raw and Holm-adjusted
    p (one family per metric, experiment, profile and convention; the
    claims re-correct within each claim), significance, ``basis =
    "replicates"`` and ``paired``.

    Args:
        hops: a per-hop table with a ``replicate`` column.
        baseline: the baseline design.
        by: the grouping inside which designs are compared.
        metrics: metric columns.
        alpha: significance level.
        n_boot: bootstrap resamples of the interval (unpaired only).
        confidence: of the interval, in (0, 1).
        seed: of the bootstrap (unpaired only).
        paired: ``auto``, True or False.

    Returns:
        DataFrame, one row per family, `by` group, design and metric. Paired: the columns of
        :func:`mat_hopper.analysis.paired.compare_paired` and basis. Unpaired: family columns and the
        columns of :func:`mat_hopper.physics.metrics.compare_independent`, then ci_low, ci_high, basis, paired (False).

    Raises:
        ValueError: a metric that is not a column of `hops`; no ``replicate`` column; no replicate run
            (replicate >= 0); the baseline without replicate runs; `paired` not ``auto``, True or False;
            ``paired=True`` where the designs do not share the baseline's seeds.
    """
    from .paired import compare_paired

    metrics = _check_metrics(hops, metrics)
    means = replicate_means(hops, metrics=metrics)
    if len(means) == 0:
        raise ValueError("no replicate runs (replicate >= 0) in the table")
    if baseline not in set(means["design"]):
        raise ValueError(
            f"baseline {baseline!r} has no replicate runs; designs with replicates: {sorted(set(means['design']))}"
        )
    if paired not in ("auto", True, False):
        raise ValueError(f"paired must be 'auto', True or False, got {paired!r}")
    shares = _shares_seeds(means, baseline, by)
    if paired is True and not shares:
        raise ValueError("paired=True but the designs do not share the baseline's replicate seeds")
    if paired is not False and shares:
        out = compare_paired(
            means,
            baseline,
            by=by,
            metrics=metrics,
            group_columns=_present(means, FAMILY_COLUMNS),
            alpha=alpha,
            confidence=confidence,
        )
        out["basis"] = "replicates"
        return out
    frames = []
    for g, res in _compare_families(means, baseline, by, metrics, alpha):
        lows, highs = [], []
        for row in res.to_dict("records"):
            grp = g[g[by] == row[by]]
            a = grp.loc[grp["design"] == row["design"], row["metric"]]
            b = grp.loc[grp["design"] == baseline, row["metric"]]
            _, lo, hi = bootstrap_pct_change(a, b, n_boot=n_boot, confidence=confidence, seed=seed)
            lows.append(lo)
            highs.append(hi)
        res["ci_low"], res["ci_high"] = lows, highs
        frames.append(res)
    out = pd.concat(frames, ignore_index=True)
    out["basis"] = "replicates"
    out["paired"] = False
    return out


def compare_designs(
    hops: pd.DataFrame,
    baseline: str = "MD",
    *,
    basis: str = "auto",
    by: str = "behaviour",
    metrics=METRICS,
    alpha: float = 0.05,
    **kwargs,
) -> pd.DataFrame:
    """Compare designs against `baseline` on ``basis`` "hops" (the paper's,
    unperturbed run), "replicates", or "auto" (replicates when every design
    and behaviour has at least 2, else hops). Extra keyword arguments go to
    :func:`compare_replicates` (n_boot, confidence, seed) or
    :func:`compare_hops` (replicate).

    Args:
        hops: a per-hop table.
        baseline: the baseline design.
        basis: ``hops``, ``replicates`` or ``auto`` (:func:`has_replicates`),
            any case.
        by: the grouping inside which designs are compared.
        metrics: metric columns.
        alpha: significance level.
        **kwargs: passed on to :func:`compare_replicates` or :func:`compare_hops`.

    Returns:
        DataFrame: :func:`compare_replicates`'s or :func:`compare_hops`'s table (its ``basis`` column
        says which).

    Raises:
        ValueError: `basis` not hops, replicates or auto; or from the comparison run.
    """
    basis = parse_name(basis, BASES + ("auto",), "basis")
    if basis == "auto":
        basis = "replicates" if has_replicates(hops) else "hops"
    if basis == "replicates":
        return compare_replicates(hops, baseline, by=by, metrics=metrics, alpha=alpha, **kwargs)
    return compare_hops(hops, baseline, by=by, metrics=metrics, alpha=alpha, **kwargs)
