"""Paired inference on replicates that share their seeds.

Every design of an experiment runs the same replicate seeds
(:meth:`mat_hopper.core.perturbations.Perturbation.replicate`): replicate k of
design A and replicate k of its baseline saw the same start offset, tilt,
push and sensor noise. The runs are paired by construction, and a paired
comparison removes the seed's share of the spread. Per pair k, the log
ratio r_k = ln(a_k / b_k) of the two runs' means (the metrics are positive
and their effects multiplicative); where a value is not positive (a
tracking error of exactly 0 m in unperturbed static hopping), the pair's
difference a_k - b_k instead, the percent change then taken against the
baseline's mean (``method`` says which).

- effect: ``pct_change`` = 100 (exp(mean r) - 1), the ratio of geometric
  means; interval: Student t on the mean log ratio (``interval="t"``, the
  default: exact under normal log ratios, defined at any n >= 2), or BCa
  (``interval="bca"``, :func:`scipy.stats.bootstrap` on the pairs;
  unreliable below about 10 pairs, and degenerate when the pairs tie);
- test: ``p`` is the larger of two two-sided p-values, so a comparison
  is significant only where both tests reject: the paired t test on the
  log ratios (:func:`scipy.stats.ttest_1samp`, ``p_t``; it rests on the
  normality of a handful of log ratios) and the exact sign-flip test
  below (``p_perm``, distribution-free); the Wilcoxon signed-rank test
  (:func:`scipy.stats.wilcoxon`, exact) as a check, ``p_wilcoxon``, whose
  smallest reachable two-sided p with n pairs is 2 / 2^n
  (:func:`wilcoxon_smallest_p`: n = 3: 0.25, n = 6: 0.031, n = 10: 0.002);
  the exact sign-flip permutation test of the paired log ratios
  (:func:`scipy.stats.permutation_test`, ``permutation_type="samples"``,
  all 2^n sign patterns), ``p_perm``, distribution-free, with the same
  smallest reachable p 2 / 2^n (``p_min``): a verdict built on Holm over a
  family of m comparisons can only be reached where m * p_min < alpha
  (:func:`reachable`); where every pair is the same (no spread, the t test
  undefined) ``p`` is the permutation test's answer, not 0;
- conclusion (:func:`conclusion`): ``no difference`` when the whole
  interval lies inside the equivalence margin :data:`EQUIVALENCE_MARGIN`
  (+-10 %; a 95 % interval inside the margin is the two one-sided tests
  equivalence at 2.5 % per side, stricter than the standard TOST at 5 %,
  which a 90 % interval would give),
  even where a tiny effect is significant; else ``difference`` when
  Holm-adjusted p < alpha; otherwise ``not enough evidence``. "Does not hold" can then say whether the evidence is against
  a claim or merely missing.

Holm's correction runs over the comparisons of one claim (its own family),
not over every comparison of an experiment.
"""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
from scipy import stats

from ..physics.metrics import holm
from ..util.parsing import parse_name

EQUIVALENCE_MARGIN = 0.10  # +-10 %: inside it a difference counts as none
CONFIDENCE = 0.95
INTERVALS = ("t", "bca")
DIFFERENCE, NO_DIFFERENCE, NOT_ENOUGH = "difference", "no difference", "not enough evidence"
BCA_RESAMPLES = 9999


def wilcoxon_smallest_p(n_pairs: int) -> float:
    """Smallest two-sided exact Wilcoxon signed-rank p with n pairs: every
    sign the same, 2 / 2^n (nan for n < 1).

    Args:
        n_pairs: the number of pairs n.

    Returns:
        float: min(1, 2 / 2^n) (1.0 for n = 1), nan for n < 1.

    >>> wilcoxon_smallest_p(6)
    0.03125
    """
    return math.nan if n_pairs < 1 else min(1.0, 2.0 / 2.0**n_pairs)


def reachable(n_pairs: int, family_size: int = 1, alpha: float = 0.05) -> bool:
    """Whether a family of `family_size` comparisons of n paired seeds can
    reach Holm p < alpha with the exact sign-flip test (its smallest
    two-sided p is 2 / 2^n, Holm's first step multiplies it by the family
    size).

    Args:
        n_pairs: the number of paired seeds n.
        family_size: the number of comparisons m in the Holm family.
        alpha: significance level.

    Returns:
        bool: True where m * 2 / 2^n < alpha (:func:`wilcoxon_smallest_p`); False for n < 1.

    >>> reachable(3, 1), reachable(6, 1), reachable(6, 16), reachable(10, 16)
    (False, True, False, True)
    """
    p = wilcoxon_smallest_p(n_pairs)
    return bool(np.isfinite(p) and family_size * p < alpha)


def sign_flip_p(x) -> float:
    """Exact two-sided sign-flip permutation p of the mean of paired
    differences `x` (scipy.stats.permutation_test, every sign pattern).

    Args:
        x: (n,) paired differences (here log ratios or differences of run means), array-like.

    Returns:
        float: the p-value, at most 1; nan where `x` is empty.
    """
    x = np.asarray(x, dtype=float)
    if len(x) < 1:
        return math.nan
    res = stats.permutation_test((x,), np.mean, permutation_type="samples", n_resamples=np.inf)
    return float(min(1.0, res.pvalue))


def paired_effect(
    values, baseline_values, *, confidence: float = CONFIDENCE, interval: str = "t", seed: int = 0
) -> dict:
    """Paired effect of `values` against `baseline_values` (module doc).

    Args:
        values, baseline_values: (n,) run means. Two pandas Series are
            paired on their index (the replicate seed; only seeds in both
            count, so a run dropped from one side cannot shift the pairs);
            anything else pairs position k with position k.
        confidence: of the interval, in (0, 1).
        interval: ``t`` or ``bca``, any case.
        seed: of the BCa resampling (deterministic).

    Returns:
        dict: n_pairs, method (``log-ratio`` or ``difference``), pct_change,
        ci_low, ci_high (%), p (the larger of p_t and p_perm: significant
        only where both tests reject), p_t (paired t; the sign-flip p where
        the pairs do not spread), p_wilcoxon, p_min_wilcoxon, p_perm (exact
        sign-flip), p_min (its smallest reachable p, 2 / 2^n).
        NaNs where fewer than 2 finite pairs.

    Raises:
        ValueError: unequal lengths, a confidence outside (0, 1), an unknown
        interval, or two Series with a repeated index value (a seed twice).
    """
    if isinstance(values, pd.Series) and isinstance(baseline_values, pd.Series):
        if not (values.index.is_unique and baseline_values.index.is_unique):
            raise ValueError("paired Series must have one value per index value (seed); an index value repeats")
        values, baseline_values = values.align(baseline_values, join="inner")
    a, b = np.asarray(values, dtype=float), np.asarray(baseline_values, dtype=float)
    if a.shape != b.shape or a.ndim != 1:
        raise ValueError(f"values and baseline_values must be 1-D and paired, got shapes {a.shape} and {b.shape}")
    if not 0 < confidence < 1:
        raise ValueError(f"confidence must be in (0, 1), got {confidence!r}")
    interval = parse_name(interval, INTERVALS, "interval")
    ok = np.isfinite(a) & np.isfinite(b)
    a, b = a[ok], b[ok]
    n = len(a)
    out = {"n_pairs": n, "p_min_wilcoxon": wilcoxon_smallest_p(n), "p_min": wilcoxon_smallest_p(n)}
    nan = dict.fromkeys(("pct_change", "ci_low", "ci_high", "p", "p_t", "p_wilcoxon", "p_perm"), math.nan)
    if n < 2:
        return {**out, "method": "", **nan}
    log = bool((a > 0).all() and (b > 0).all())
    x = np.log(a / b) if log else a - b
    scale = 1.0 if log else float(np.mean(b))
    if not log and scale == 0:
        return {**out, "method": "difference", **nan}

    def to_pct(v):
        return 100.0 * np.expm1(v) if log else 100.0 * np.asarray(v) / scale

    m, sd = float(x.mean()), float(x.std(ddof=1))
    p_perm = sign_flip_p(x)
    if sd == 0:  # every pair the same: the t test is undefined; the sign-flip test answers (n = 2: 0.5)
        p = p_perm
        lo = hi = m
    else:
        p = float(stats.ttest_1samp(x, 0.0).pvalue)
        if interval == "t":
            half = float(stats.t.ppf(0.5 + confidence / 2, n - 1)) * sd / math.sqrt(n)
            lo, hi = m - half, m + half
        else:
            res = stats.bootstrap(
                (x,),
                np.mean,
                confidence_level=confidence,
                method="BCa",
                n_resamples=BCA_RESAMPLES,
                random_state=np.random.default_rng(seed),
            )
            lo, hi = float(res.confidence_interval.low), float(res.confidence_interval.high)
    nonzero = x[x != 0]
    p_w = float(stats.wilcoxon(nonzero).pvalue) if len(nonzero) else 1.0
    return {
        **out,
        "method": "log-ratio" if log else "difference",
        "pct_change": float(to_pct(m)),
        "ci_low": float(to_pct(lo)),
        "ci_high": float(to_pct(hi)),
        "p": max(p, p_perm),
        "p_t": p,
        "p_wilcoxon": p_w,
        "p_perm": p_perm,
    }


def share_left(x_control, x_claim, confidence: float = 0.95) -> dict:
    """The share of a claim's effect left against a control, mean ln(d/ctrl)
    / mean ln(d/base) over paired seeds, with Fieller's interval for a
    ratio of paired means (unbounded, nan, where the claim's own effect is
    not clearly away from 0 at this confidence).

    Args:
        x_control, x_claim: (n,) per-seed log ratios, paired.
        confidence: of the interval.

    Returns:
        dict: share, share_low, share_high.
    """
    x, y = np.asarray(x_control, float), np.asarray(x_claim, float)
    n = len(x)
    nan = {"share": np.nan, "share_low": np.nan, "share_high": np.nan}
    if n < 2 or y.mean() == 0:
        return nan
    t2 = stats.t.ppf(0.5 + confidence / 2, n - 1) ** 2
    mx, my = x.mean(), y.mean()
    c = np.cov(x, y, ddof=1) / n  # variances and covariance of the two means
    a = my**2 - t2 * c[1, 1]
    bq = mx * my - t2 * c[0, 1]
    cq = mx**2 - t2 * c[0, 0]
    disc = bq**2 - a * cq
    out = {"share": float(mx / my), "share_low": np.nan, "share_high": np.nan}
    if a > 0 and disc >= 0:  # a bounded interval
        out["share_low"], out["share_high"] = float((bq - disc**0.5) / a), float((bq + disc**0.5) / a)
    return out


def conclusion(p_holm: float, ci_low_pct: float, ci_high_pct: float, *, alpha: float = 0.05, margin=None) -> str:
    """``difference``, ``no difference`` or ``not enough evidence`` (module doc).

    Args:
        p_holm: Holm-adjusted p of the comparison.
        ci_low_pct, ci_high_pct: its interval (%).
        alpha: significance level.
        margin: equivalence margin as a fraction (default EQUIVALENCE_MARGIN).

    Returns:
        str.
    """
    margin = EQUIVALENCE_MARGIN if margin is None else float(margin)
    inside = np.isfinite(ci_low_pct) and np.isfinite(ci_high_pct) and -100 * margin < ci_low_pct <= ci_high_pct
    if inside and ci_high_pct < 100 * margin:
        return NO_DIFFERENCE  # equivalent, even where a tiny effect is significant
    if np.isfinite(p_holm) and p_holm < alpha:
        return DIFFERENCE
    return NOT_ENOUGH


def compare_paired(
    means: pd.DataFrame,
    baseline: str,
    *,
    by: str = "behaviour",
    metrics=("tracking_error_m",),
    group_columns=(),
    alpha: float = 0.05,
    confidence: float = CONFIDENCE,
    interval: str = "t",
    margin=None,
) -> pd.DataFrame:
    """Every design against `baseline`, paired on the ``replicate`` column.

    Args:
        means: one row per run (design, `by`, replicate, metric columns;
            :func:`mat_hopper.analysis.stats.replicate_means`).
        baseline: the baseline design's name.
        by: the grouping inside which designs are compared (behaviour).
        metrics: metric columns.
        group_columns: further columns that separate families (experiment,
            profile, convention): Holm runs within each family and metric.
        alpha, confidence, interval, margin: as in :func:`paired_effect`
            and :func:`conclusion`.

    Returns:
        DataFrame: group columns, `by`, design, baseline, metric, n, n_baseline,
        n_pairs, mean, mean_baseline, pct_change, ci_low, ci_high, method, p
        (:func:`paired_effect`'s: both tests must reject), p_t, p_wilcoxon,
        p_min_wilcoxon, p_perm, p_min, p_holm, significant, conclusion, paired.

    Raises:
        ValueError: no ``replicate`` column, or the baseline is absent.
    """
    if "replicate" not in means.columns:
        raise ValueError("compare_paired needs a 'replicate' column to pair runs on")
    if baseline not in set(means["design"]):
        raise ValueError(f"baseline {baseline!r} not among the designs: {sorted(set(means['design']))}")
    keys = list(group_columns)
    rows = []
    for fam, g in means.groupby(keys, sort=False) if keys else [((), means)]:
        fam = fam if isinstance(fam, tuple) else (fam,)
        for group, gg in g.groupby(by, sort=False):
            base = gg[gg["design"] == baseline]
            for design, dg in gg.groupby("design", sort=False):
                if design == baseline:
                    continue
                for m in metrics:
                    pair = dg[["replicate", m]].merge(base[["replicate", m]], on="replicate", suffixes=("", "_b"))
                    eff = paired_effect(pair[m], pair[f"{m}_b"], confidence=confidence, interval=interval)
                    rows.append(
                        {
                            **dict(zip(keys, fam)),
                            by: group,
                            "design": design,
                            "baseline": baseline,
                            "metric": m,
                            "n": len(dg),
                            "n_baseline": len(base),
                            "mean": float(dg[m].mean()),
                            "mean_baseline": float(base[m].mean()) if len(base) else math.nan,
                            **eff,
                        }
                    )
    out = pd.DataFrame(rows)
    if len(out) == 0:
        return out
    out["p_holm"] = math.nan
    for _, fam_rows in out.groupby([*keys, "metric"], sort=False):
        out.loc[fam_rows.index, "p_holm"] = holm(fam_rows["p"].to_numpy())
    # p already needs the sign-flip test to reject (paired_effect); the
    # reachability guard (m * p_min < alpha) says so for the family at once
    reachable = out.groupby([*keys, "metric"], sort=False)["p_min"].transform(lambda v: len(v) * v.max() < alpha)
    out["significant"] = (out["p_holm"] < alpha) & reachable.astype(bool)
    out["conclusion"] = [
        conclusion(p if sig else math.nan, lo, hi, alpha=alpha, margin=margin)
        for p, sig, lo, hi in zip(out.p_holm, out.significant, out.ci_low, out.ci_high)
    ]
    out["paired"] = True
    return out


MAX_SEEDS_ADVISED = 64  # the largest replicate count an "untestable" verdict advises


def min_replicates(family_size: int, alpha: float = 0.05) -> int | None:
    """The fewest paired seeds with which a family of `family_size`
    comparisons can reach Holm p < alpha (:func:`mat_hopper.analysis.paired.reachable`),
    or None beyond :data:`MAX_SEEDS_ADVISED`.

    Args:
        family_size: comparisons in the Holm family (>= 1).
        alpha: the family's significance level.

    Returns:
        The number of seeds (int), or None when more than MAX_SEEDS_ADVISED are needed.

    >>> min_replicates(1), min_replicates(5)
    (6, 8)
    """
    return next((n for n in range(2, MAX_SEEDS_ADVISED + 1) if reachable(n, family_size, alpha)), None)
