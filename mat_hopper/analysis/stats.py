"""Statistics of the results: summaries, comparisons against a baseline,
and replicate-level inference.

Two bases for a comparison of designs:

``hops`` (the paper's)
    every scored hop cycle of one run is a sample; the design's cycles are
    compared with the baseline's by a two-sided Mann-Whitney U test
    (:func:`mat_hopper.physics.metrics.compare`), Holm-corrected over one family:
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
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ..physics import metrics as _metrics
from ..physics.metrics import ALL_METRICS, METRICS
from ..util.change import ROUNDOFF, percent_change
from ..util.parsing import parse_name


def _compare_families(table: pd.DataFrame, baseline: str, by: str, metrics, alpha: float):
    """metrics.compare per family and metric (one Holm correction each),
    family columns in front: a list of (family sub-table, result); families
    without the baseline are skipped."""
    frames = []
    for fam, g in _families(table):
        if baseline not in set(g["design"]):
            continue
        for m in metrics:
            v = pd.to_numeric(g[m], errors="coerce").astype(float)
            g = g.assign(**{m: v.where(~(v.abs() < ROUNDOFF), 0.0)})
            res = _metrics.compare(g, baseline, by=by, metrics=(m,), alpha=alpha)
            for k, v in reversed(fam.items()):
                res.insert(0, k, v)
            frames.append((g, res))
    return frames


# Columns that split results into independent families (one Holm correction,
# one baseline each) when they are present in a table.
FAMILY_COLUMNS = ("experiment", "profile", "convention")
# Columns that identify one run in a per-hop table.
RUN_COLUMNS = FAMILY_COLUMNS + ("design", "behaviour", "replicate")
SWEEP_COLUMNS = ("sweep_base", "sweep_property", "density_g_cm3", "modulus_gpa")
UNPERTURBED = -1  # replicate id of the unperturbed run
BASES = ("hops", "replicates")


def _present(table: pd.DataFrame, columns) -> list[str]:
    return [c for c in columns if c in table.columns]


def _check_metrics(table: pd.DataFrame, metrics) -> tuple[str, ...]:
    metrics = tuple(metrics)
    missing = [m for m in metrics if m not in table.columns]
    if missing:
        raise ValueError(
            f"metrics {missing} are not columns of the table; accepted: "
            f"{[m for m in ALL_METRICS if m in table.columns]}"
        )
    return metrics


def _families(table: pd.DataFrame):
    """(dict of family values, sub-table) for each family in the table."""
    fam = _present(table, FAMILY_COLUMNS)
    if not fam:
        yield {}, table
        return
    for key, g in table.groupby(fam, sort=True, dropna=False):
        key = key if isinstance(key, tuple) else (key,)
        yield dict(zip(fam, key)), g


def seconds(x: float) -> str:
    """A duration in s, short: 0.5, 12.9, 1e-4, 2.5e-3.

    Args:
        x: the duration, s.

    Returns:
        str: three significant digits for 0.01 <= |x| < 1e4, else two significant digits (a trailing
        zero dropped) and an unpadded exponent ("2.5e-3", "1e-4"); 0, nan and inf as ``format(x, "g")``.
    """
    if not np.isfinite(x) or x == 0:
        return f"{x:g}"
    if 0.01 <= abs(x) < 1e4:
        return f"{x:.3g}"
    mant, exp = f"{x:.1e}".split("e")
    mant = mant.rstrip("0").rstrip(".")
    return f"{mant}e{int(exp)}"


def unusable_runs(runs: pd.DataFrame | None, timestep_s: float | None = None) -> pd.DataFrame:
    """The runs of a run-summary table that diverged numerically, fell over
    (not upright at the end) or failed, with a reason in ``why`` ("unstable
    at dt=1e-4 s, diverged at t=2.5e-3 s", "fell over", "failed"). Uses the
    columns status, stable, upright, diverged_at_s and timestep_s where
    present (else the `timestep_s` argument, s).

    Args:
        runs: a run-summary table (one row per run), or None.
        timestep_s: the runs' physics step, s, named in ``why`` where `runs` has no ``timestep_s``
            column; None: not named.

    Returns:
        DataFrame, one row per unusable run. Columns: design, behaviour, experiment, profile,
        convention, replicate, key, the sweep columns (:data:`SWEEP_COLUMNS`), why; columns `runs`
        lacks are nan. A run is diverged where status is "diverged" or ``stable`` is false, fallen
        where status is "fallen" or ``upright`` is false (a missing stable or upright value counts as
        false), failed where status is "failed". Empty (those columns) for None or an empty table.
    """
    cols = ["design", "behaviour", "experiment", "profile", "convention", "replicate", "key", *SWEEP_COLUMNS, "why"]
    if runs is None or len(runs) == 0:
        return pd.DataFrame(columns=cols)
    status = runs["status"].astype(str) if "status" in runs.columns else pd.Series("", index=runs.index)
    stable = (
        runs["stable"].fillna(False).astype(bool) if "stable" in runs.columns else pd.Series(True, index=runs.index)
    )
    upright = (
        runs["upright"].fillna(False).astype(bool) if "upright" in runs.columns else pd.Series(True, index=runs.index)
    )
    diverged = (status == "diverged") | ~stable
    failed = status == "failed"
    fallen = ~diverged & ~failed & ((status == "fallen") | ~upright)
    why = pd.Series("", index=runs.index, dtype=object)
    for i in runs.index[diverged]:
        dt = runs.at[i, "timestep_s"] if "timestep_s" in runs.columns else timestep_s
        at = runs.at[i, "diverged_at_s"] if "diverged_at_s" in runs.columns else None
        text = "unstable" + (f" at dt={seconds(float(dt))} s" if dt is not None and np.isfinite(float(dt)) else "")
        if at is not None and pd.notna(at):
            text += f", diverged at t={seconds(float(at))} s"
        why[i] = text
    why[fallen] = "fell over"
    why[failed] = "failed"
    bad = runs[diverged | fallen | failed].assign(why=why[diverged | fallen | failed])
    for c in cols:
        if c not in bad.columns:
            bad[c] = np.nan
    return bad[cols].reset_index(drop=True)


def drop_unusable(hops: pd.DataFrame, bad: pd.DataFrame | None) -> pd.DataFrame:
    """The per-hop rows of usable runs only: rows of the runs in `bad` (from
    :func:`unusable_runs`) are dropped, matched by the runner's ``key``
    column where both have it, else by experiment, profile, convention,
    design, behaviour, replicate and sweep point. A diverged run keeps the hop cycles it
    scored before diverging; they are not results.

    Args:
        hops: a per-hop table.
        bad: :func:`unusable_runs`'s table, or None. Only the matching columns that `hops` has and
            that are filled in every row of `bad` are used.

    Returns:
        DataFrame: the rows of `hops` not in a run of `bad` (original index kept); `hops` itself where
        `bad` is None or either table is empty.
    """
    if bad is None:
        return hops
    if len(bad) == 0 or len(hops) == 0:
        return hops
    if "key" in hops.columns and bad["key"].notna().all():
        return hops[~hops["key"].isin(set(bad["key"]))]
    keys = [
        c
        for c in (
            "experiment",
            "profile",
            "convention",
            "design",
            "behaviour",
            "replicate",
            "density_g_cm3",
            "modulus_gpa",
        )
        if c in hops.columns and bad[c].notna().all()
    ]
    marker = bad[keys].drop_duplicates().assign(_bad=True)
    m = hops.merge(marker, on=keys, how="left")
    return hops[~m["_bad"].fillna(False).to_numpy(bool)]


def select_replicates(hops: pd.DataFrame, replicate: int | None = UNPERTURBED) -> pd.DataFrame:
    """Rows of one replicate id (default: the unperturbed run, -1); all rows
    when `replicate` is None or the table has no ``replicate`` column.

    Args:
        hops: a per-hop table.
        replicate: the replicate id to keep (-1: the unperturbed run), or None.

    Returns:
        DataFrame: the rows whose ``replicate`` equals `replicate`, or `hops` itself.
    """
    if replicate is None or "replicate" not in hops.columns:
        return hops
    return hops[hops["replicate"] == replicate]


def combine_experiments(hops: pd.DataFrame, experiments=None) -> pd.DataFrame:
    """Rows of several experiments as one comparison family (e.g. the
    gradients of experiment 3 beside MD and SS of experiment 1): every
    design and behaviour (per profile and convention) is taken from the
    first experiment in `experiments` (default: sorted) that has it, and the
    ``experiment`` column becomes their names joined by "+".

    Args:
        hops: a per-hop table with an ``experiment`` column.
        experiments: experiment names in order of precedence (compared as str); None: every
            experiment of the table, sorted.

    Returns:
        DataFrame: a copy of the kept rows (rows of experiments not named dropped), ``experiment`` set
        to e.g. "exp1+exp3"; `hops` itself where it has no ``experiment`` column or is empty.
    """
    if "experiment" not in hops.columns or len(hops) == 0:
        return hops
    exps = [
        str(e) for e in (experiments if experiments is not None else sorted(hops["experiment"].astype(str).unique()))
    ]
    t = hops[hops["experiment"].astype(str).isin(exps)]
    rank = t["experiment"].astype(str).map({e: i for i, e in enumerate(exps)})
    keys = _present(t, ("profile", "convention", "design", "behaviour"))
    first = rank.groupby([t[k] for k in keys], dropna=False).transform("min")
    out = t[rank == first].copy()
    out["experiment"] = "+".join(exps)
    return out


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
    per `by` group and metric (:func:`mat_hopper.physics.metrics.compare`), one Holm
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
        DataFrame: family columns, then the columns of :func:`mat_hopper.physics.metrics.compare` (`by`,
        design, baseline, metric, n, n_baseline, mean, mean_baseline, pct_change, u, p, effect_size,
        p_holm, significant), then basis.

    Raises:
        ValueError: a metric that is not a column of `hops`; the baseline in no family; or from
            :func:`mat_hopper.physics.metrics.compare` (no `by` column, alpha not in (0, 1)).
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


def replicate_means(hops: pd.DataFrame, *, metrics=ALL_METRICS, include_unperturbed: bool = False) -> pd.DataFrame:
    """One row per run: the mean of each metric over its scored hop cycles
    and ``n_hops``. Run keys: the family columns, design, behaviour,
    replicate and, where present, the sweep columns. The unperturbed run
    (replicate -1) is left out unless `include_unperturbed`.

    Args:
        hops: a per-hop table with a ``replicate`` column.
        metrics: metric columns to average; those not in `hops` are skipped.
        include_unperturbed: keep the unperturbed run (replicate -1).

    Returns:
        DataFrame, one row per run: the run keys, n_hops, the mean of each metric. Empty (those
        columns) when no row is left.

    Raises:
        ValueError: `hops` has no ``replicate`` column.
    """
    if "replicate" not in hops.columns:
        raise ValueError("replicate_means needs a 'replicate' column (int, -1 for the unperturbed run)")
    metrics = tuple(m for m in metrics if m in hops.columns)
    if not include_unperturbed:
        hops = hops[hops["replicate"] != UNPERTURBED]
    keys = _present(hops, RUN_COLUMNS + SWEEP_COLUMNS)
    if len(hops) == 0:
        return pd.DataFrame(columns=[*keys, "n_hops", *metrics])
    grouped = hops.groupby(keys, sort=True, dropna=False)
    out = grouped[list(metrics)].mean()
    out.insert(0, "n_hops", grouped.size())
    return out.reset_index()


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
        columns of :func:`mat_hopper.physics.metrics.compare`, then ci_low, ci_high, basis, paired (False).

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


def has_replicates(hops: pd.DataFrame, min_replicates: int = 2) -> bool:
    """True when every run key of the table has at least `min_replicates`
    perturbed replicates (replicate >= 0).

    Args:
        hops: a per-hop table.
        min_replicates: the fewest replicates each run key needs.

    Returns:
        bool: True where every combination of the family columns, design and behaviour present has at
        least `min_replicates` distinct replicate ids other than -1; False without a ``replicate``
        column, for an empty table, or without perturbed rows.
    """
    if "replicate" not in hops.columns or len(hops) == 0:
        return False
    reps = hops[hops["replicate"] != UNPERTURBED]
    if len(reps) == 0:
        return False
    keys = _present(hops, FAMILY_COLUMNS + ("design", "behaviour"))
    counts = reps.groupby(keys)["replicate"].nunique()
    all_keys = hops.groupby(keys).size().index
    return len(counts) == len(all_keys) and int(counts.min()) >= min_replicates


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
