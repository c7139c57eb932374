"""Sequential replication: paired seeds only where a verdict still needs them.

A family of paired comparisons (one Holm family, :mod:`mat_hopper.analysis.paired`)
is judged by the book's rule at fixed n: per comparison the paired effect
(:func:`~mat_hopper.analysis.paired.paired_effect`: t interval on the log
ratios, ``p`` the larger of the paired t and the exact sign-flip p), Holm
over the family (:func:`mat_hopper.physics.metrics.holm`), the sign-flip
floor's guard (:func:`~mat_hopper.analysis.paired.reachable` at the
family's fewest pairs) and the verdict words of
:func:`~mat_hopper.analysis.paired.conclusion`. This module evaluates that
same rule (it calls those functions; it does not restate the verdict) at a
growing number of seeds, and stops a comparison once more seeds cannot
change its verdict.

The rule (:func:`sequential_family`):

1. Start. Every comparison of a family of m starts at
   :func:`min_seeds` (m) seeds, the fewest with which the exact sign-flip
   test's smallest two-sided p, 2 / 2^n, can pass Holm's first step,
   m 2 / 2^n < alpha, i.e. n > 1 + log2(m / alpha) (6 for m = 1, 8 for
   m = 4, 10 for m = 16 at alpha = 0.05), or at the largest n, `max_n`
   (the profile's replicate count, 10 for ``paper``), if that is fewer.
   Seeds are taken in seed order, the same seeds for every comparison, so
   the runs stay paired by seed.
2. Look. Each comparison's effect at its own seeds; Holm over the family's
   p-values as they stand.
3. Stop, decided. A comparison stops when its verdict is decided and
   stays so whatever the open comparisons' further seeds bring:

   - ``no difference``: its interval lies inside the equivalence margin
     (the interval is its own; the family does not enter);
   - ``difference``: its Holm p is below alpha even with every other open
     comparison's p set to 1. Holm's adjusted p-values do not decrease
     when a raw p increases, so that is the largest Holm p the comparison
     can end with; a p that the family's later seeds could still push
     above alpha does not stop it.

4. Stop, cannot change. An undecided comparison stops early only where
   neither verdict can be reached at any n up to `max_n`, for any values
   of the seeds still to come:

   - ``difference`` unreachable: a lower bound on the exact sign-flip p at
     every n up to `max_n` is at least alpha (:func:`sign_flip_floor`:
     whatever the new pairs, the sign patterns of the present pairs that
     reach the observed statistic still count, twice); Holm's p is never
     below the raw p, and the raw p is never below the sign-flip p;
   - ``no difference`` unreachable: the narrowest t interval the present
     pairs allow at `max_n` (:func:`narrowest_half_width`: every new log
     ratio at the present mean, which adds nothing to the sum of squares)
     is wider than the margin.

   Both bounds assume the new values stay positive (the log-ratio method)
   and the t interval; a comparison on differences (a non-positive value)
   or under ``interval="bca"`` is never stopped early for this reason.
   Otherwise it stops at `max_n` (or when its seeds run out).
5. Else add the next `step` seeds (in seed order) to every open
   comparison, and look again.

The verdicts returned are the book's fixed-n rule applied once more to the
family with each comparison at the seeds it stopped with. By steps 3 and 4
a comparison that stopped early ends with the verdict it stopped on.

What the rule is not: the stop at a decided verdict is optional stopping.
Each look is the fixed-n test at its alpha, but over the looks of one
comparison (at most max_n - min_seeds + 1 of them: 3 for m = 4 at 10
seeds) the chance of a false ``difference`` is bounded by the looks times
alpha (a union bound), not by alpha. The replay of the recorded tables
(:func:`replay_family`) checks whether, there, any verdict differs from the
verdict at all seeds.

Two forms: :func:`replay_family` (and :func:`replay_families`) over a table
that already holds every seed, and :func:`sequential_family`, which asks a
callback for the pairs of the next seeds of the comparisons still open, so
that an experiment runs seeds only where needed.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Hashable, Mapping, Sequence

import numpy as np
import pandas as pd
from scipy import stats

from ..physics.metrics import holm
from ..util.parsing import parse_name
from . import paired

DECIDED, CANNOT_CHANGE, MAX_N = "decided", "cannot change", "max n"
STOPS = (DECIDED, CANNOT_CHANGE, MAX_N)
EXACT_PATTERNS_UP_TO = 12  # pairs; beyond, the sign-flip floor uses one pattern (weaker, still a bound)

Fetch = Callable[[Mapping[Hashable, Sequence[int]]], Mapping[Hashable, Sequence[tuple[float, float]]]]


def min_seeds(family_size: int, alpha: float = 0.05) -> int:
    """The fewest paired seeds n at which a family of `family_size`
    comparisons can reach Holm p < alpha with the exact sign-flip test:
    the smallest n with m 2 / 2^n < alpha, i.e. n > 1 + log2(m / alpha).

    Args:
        family_size: comparisons m in the Holm family (>= 1).
        alpha: significance level, in (0, 1).

    Returns:
        int: n (6 for m = 1, 8 for m = 4, 10 for m = 16 at alpha = 0.05).

    Raises:
        ValueError: a family size below 1 or an alpha outside (0, 1).

    >>> min_seeds(1), min_seeds(4), min_seeds(16)
    (6, 8, 10)
    """
    if isinstance(family_size, bool) or int(family_size) != family_size or family_size < 1:
        raise ValueError(f"family_size must be a whole number >= 1, got {family_size!r}")
    if not 0 < alpha < 1:
        raise ValueError(f"alpha must be in (0, 1), got {alpha!r}")
    n = max(1, math.floor(1 + math.log2(family_size / alpha)))
    while family_size * 2.0 / 2.0**n >= alpha:  # exact, whatever the rounding of log2
        n += 1
    while n > 1 and family_size * 2.0 / 2.0 ** (n - 1) < alpha:
        n -= 1
    return n


def sign_flip_floor(x, n_max: int) -> float:
    """A lower bound on the exact two-sided sign-flip p (the statistic the
    mean, as :func:`~mat_hopper.analysis.paired.sign_flip_p`) that the
    pairs `x` can reach at any n from len(x) to `n_max`, whatever the pairs
    added.

    With k new values of sum Y, every sign pattern s of the present pairs
    with |A_s + Y| >= |T + Y| (A_s the signed sum, T the observed one)
    reaches the observed statistic with the new signs all kept, and again
    with all of them flipped; so p >= 2 min_Y c(Y) / 2^(n + k), least at
    k = n_max - n. The minimum over Y is taken over every interval between
    the points where a pattern's comparison changes. Up to
    :data:`EXACT_PATTERNS_UP_TO` pairs every pattern is counted; beyond, only
    the observed pattern (c = 1), a weaker bound.

    Args:
        x: (n,) present paired log ratios (finite).
        n_max: the most pairs the comparison can have.

    Returns:
        float: the bound, in (0, 1]; the present p itself is not included.
    """
    x = np.asarray(x, dtype=float)
    n = len(x)
    k = max(0, int(n_max) - n)
    if n == 0:
        return 2.0 / 2.0**k if k else 1.0
    if n > EXACT_PATTERNS_UP_TO:
        return 2.0 / 2.0 ** (n + k)
    signs = 1 - 2 * ((np.arange(2**n)[:, None] >> np.arange(n)) & 1)
    a = signs @ x
    t = float(x.sum())
    slack = 1e-12 * (float(np.abs(x).sum()) + 1.0)  # count a pattern only where it clearly reaches
    if k == 0:  # no pair to come: the present patterns alone
        return float(min(1.0, np.sum(np.abs(a) >= abs(t) + slack) / 2.0**n))
    cuts = np.unique(-(a + t) / 2.0)
    big = 4.0 * (float(np.abs(a).max()) + abs(t) + 1.0)
    ys = np.concatenate(([cuts[0] - big], (cuts[:-1] + cuts[1:]) / 2.0, [cuts[-1] + big]))
    c = min(int(np.sum(np.abs(a + y) >= abs(t + y) + slack * (1.0 + abs(y)))) for y in ys)
    return float(min(1.0, 2.0 * max(c, 1) / 2.0 ** (n + k)))


def narrowest_half_width(x, n_max: int, confidence: float = paired.CONFIDENCE) -> float:
    """The narrowest half-width of the t interval of the mean of the pairs
    `x` at any n up to `n_max`, whatever the pairs added: the sum of squares
    about the mean cannot fall below the present one, S, so the half-width
    is at least t(n'-1) sqrt(S / ((n'-1) n')), which falls with n'.

    Args:
        x: (n,) present paired log ratios (n >= 2).
        n_max: the most pairs the comparison can have.
        confidence: of the interval.

    Returns:
        float: the bound, in the units of `x` (0 where the pairs do not spread).
    """
    x = np.asarray(x, dtype=float)
    n_end = max(len(x), int(n_max))
    s = float(np.sum((x - x.mean()) ** 2))
    return float(stats.t.ppf(0.5 + confidence / 2, n_end - 1)) * math.sqrt(s / ((n_end - 1) * n_end))


def _cannot_change(a, b, n_max: int, *, alpha: float, confidence: float, margin: float) -> bool:
    """Whether neither decided verdict can be reached by `n_max` pairs
    (module doc, step 4); False wherever the bounds do not apply."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    ok = np.isfinite(a) & np.isfinite(b)
    a, b = a[ok], b[ok]
    if len(a) < 2 or not ((a > 0).all() and (b > 0).all()):
        return False
    x = np.log(a / b)
    no_difference_out = 2 * narrowest_half_width(x, n_max, confidence) > math.log((1 + margin) / (1 - margin))
    return bool(no_difference_out and sign_flip_floor(x, n_max) >= alpha)


def family_verdicts(
    pairs: Mapping[Hashable, tuple],
    *,
    alpha: float = 0.05,
    confidence: float = paired.CONFIDENCE,
    interval: str = "t",
    margin=None,
) -> pd.DataFrame:
    """The book's fixed-n paired rule over one Holm family (module doc).

    Args:
        pairs: comparison key -> (values, baseline_values), the pairs as
            :func:`~mat_hopper.analysis.paired.paired_effect` takes them.
        alpha, confidence, interval, margin: as in :func:`~mat_hopper.analysis.paired.paired_effect`
            and :func:`~mat_hopper.analysis.paired.conclusion`.

    Returns:
        DataFrame: one row per comparison, in the order given: comparison,
        the paired effect's columns, p_holm, conclusion.
    """
    rows = [
        {"comparison": key, **paired.paired_effect(a, b, confidence=confidence, interval=interval)}
        for key, (a, b) in pairs.items()
    ]
    out = pd.DataFrame(rows)
    if len(out) == 0:
        return out
    out["p_holm"] = holm(out["p"].to_numpy(float))
    testable = paired.reachable(int(out["n_pairs"].min()), len(out), alpha)
    words = (
        paired.conclusion(p, lo, hi, alpha=alpha, margin=margin)
        for p, lo, hi in zip(out.p_holm, out.ci_low, out.ci_high)
    )
    out["conclusion"] = [w if testable or w != paired.DIFFERENCE else paired.NOT_ENOUGH for w in words]
    return out


def _locked(table: pd.DataFrame, open_: list[bool], alpha: float, margin) -> list[bool]:
    """Per comparison, whether its verdict at this look is decided for good
    (module doc, step 3): for an open one, its Holm p with every other open
    comparison's p set to 1."""
    p = table["p"].to_numpy(float)
    testable = paired.reachable(int(table["n_pairs"].min()), len(table), alpha)
    out = []
    for i, is_open in enumerate(open_):
        worst = np.where(np.asarray(open_) & (np.arange(len(p)) != i), 1.0, p)
        p_holm = float(holm(worst)[i]) if testable else math.nan
        word = paired.conclusion(p_holm, table.ci_low.iat[i], table.ci_high.iat[i], alpha=alpha, margin=margin)
        out.append(bool(is_open) and word in (paired.DIFFERENCE, paired.NO_DIFFERENCE))
    return out


def _check_args(keys, seeds, max_n, step, alpha, confidence) -> tuple[list, list, int]:
    """The driver's checks; returns the keys, the seeds and max_n."""
    keys, seeds = list(keys), list(seeds)
    if not keys:
        raise ValueError("keys must name at least one comparison")
    if len(set(keys)) != len(keys):
        raise ValueError(f"keys must be distinct, got {keys!r}")
    if len(set(seeds)) != len(seeds):
        raise ValueError(f"seeds must be distinct, got {seeds!r}")
    max_n = len(seeds) if max_n is None else max_n
    if isinstance(max_n, bool) or int(max_n) != max_n or not 2 <= max_n <= len(seeds):
        raise ValueError(f"max_n must be a whole number from 2 to the {len(seeds)} seeds given, got {max_n!r}")
    if isinstance(step, bool) or int(step) != step or step < 1:
        raise ValueError(f"step must be a whole number >= 1, got {step!r}")
    if not 0 < alpha < 1:
        raise ValueError(f"alpha must be in (0, 1), got {alpha!r}")
    if not 0 < confidence < 1:
        raise ValueError(f"confidence must be in (0, 1), got {confidence!r}")
    return keys, seeds, int(max_n)


def sequential_family(
    fetch: Fetch,
    keys: Sequence[Hashable],
    *,
    seeds: Sequence[int] | None = None,
    max_n: int | None = None,
    step: int = 1,
    alpha: float = 0.05,
    confidence: float = paired.CONFIDENCE,
    interval: str = "t",
    margin=None,
) -> pd.DataFrame:
    """Sequential replication of one Holm family (module doc), asking
    `fetch` for the pairs of the seeds each open comparison needs next.

    Args:
        fetch: called with {key: [seed, ...]} (the next seeds, in seed
            order, of the comparisons still open); returns {key: [(value,
            baseline_value), ...]}, one pair per seed asked, in that order
            (nan where a run is unusable: the pair is dropped, as in
            :func:`~mat_hopper.analysis.paired.paired_effect`).
        keys: the family's comparisons (its Holm size is their number).
        seeds: the seeds in the order they are run (default range(max_n)).
        max_n: the most seeds a comparison gets (default: every seed given;
            the profile's replicate count).
        step: seeds added to an open comparison at each look.
        alpha, confidence, interval, margin: the book's rule
            (:func:`family_verdicts`).

    Returns:
        DataFrame: one row per comparison in the order of `keys`: comparison,
        n_seeds (seeds used), stop (``decided``, ``cannot change`` or
        ``max n``), n_stop (the seeds at which it stopped, = n_seeds), the
        paired effect's columns, p_holm and conclusion of
        :func:`family_verdicts` over the seeds used.

    Raises:
        ValueError: no or repeated keys, repeated seeds, a max_n or step out
        of range, an alpha or confidence outside (0, 1), or a `fetch` answer
        that lacks a comparison asked or holds the wrong number of pairs.
    """
    if seeds is None:
        if max_n is None:
            raise ValueError("give seeds or max_n")
        seeds = range(int(max_n))
    keys, seeds, max_n = _check_args(keys, seeds, max_n, step, alpha, confidence)
    margin_f = paired.EQUIVALENCE_MARGIN if margin is None else float(margin)
    bounds_apply = parse_name(interval, paired.INTERVALS, "interval") == "t"
    values: dict = {k: ([], []) for k in keys}
    stop: dict = dict.fromkeys(keys)
    ask = {k: seeds[: min(min_seeds(len(keys), alpha), max_n)] for k in keys}
    while ask:
        _take(fetch, ask, values)
        table = family_verdicts(values, alpha=alpha, confidence=confidence, interval=interval, margin=margin)
        open_ = [stop[k] is None for k in keys]
        locked = _locked(table, open_, alpha, margin)
        for k, done in zip(keys, locked):
            n = len(values[k][0])
            if stop[k] is not None:
                continue
            if done:
                stop[k] = DECIDED
            elif n >= max_n:
                stop[k] = MAX_N
            elif bounds_apply and _cannot_change(
                *values[k], max_n, alpha=alpha, confidence=confidence, margin=margin_f
            ):
                stop[k] = CANNOT_CHANGE
        ask = {k: seeds[len(values[k][0]) : min(len(values[k][0]) + step, max_n)] for k in keys if stop[k] is None}
    table = family_verdicts(values, alpha=alpha, confidence=confidence, interval=interval, margin=margin)
    n_seeds = [len(values[k][0]) for k in keys]
    table.insert(1, "n_seeds", n_seeds)
    table.insert(2, "stop", [stop[k] for k in keys])
    table.insert(3, "n_stop", n_seeds)
    return table


def _take(fetch: Fetch, ask: Mapping, values: dict) -> None:
    """Ask `fetch` for the seeds in `ask` and append the pairs it returns."""
    got = fetch({k: list(s) for k, s in ask.items()})
    for k, s in ask.items():
        if k not in got:
            raise ValueError(f"fetch returned no pairs for comparison {k!r}")
        pairs = list(got[k])
        if len(pairs) != len(s):
            raise ValueError(f"fetch returned {len(pairs)} pairs for comparison {k!r}, asked for {len(s)} seeds")
        for a, b in pairs:
            values[k][0].append(float(a))
            values[k][1].append(float(b))


def replay_family(pairs: Mapping[Hashable, tuple], *, max_n: int | None = None, step: int = 1, **rule) -> pd.DataFrame:
    """:func:`sequential_family` over a table that already holds every seed.

    Args:
        pairs: comparison key -> (values, baseline_values), two pandas
            Series indexed by seed (a seed absent from either side is an
            unusable pair: nan).
        max_n: the most seeds a comparison gets (default: every seed present).
        step: seeds added at each look.
        **rule: alpha, confidence, interval, margin (:func:`family_verdicts`).

    Returns:
        DataFrame: as :func:`sequential_family`.

    Raises:
        ValueError: as :func:`sequential_family`, or values that are not two
        Series with one value per seed.
    """
    for key, ab in pairs.items():
        if len(ab) != 2 or not all(isinstance(s, pd.Series) and s.index.is_unique for s in ab):
            raise ValueError(f"pairs[{key!r}] must be two pandas Series indexed by seed, one value per seed")
    seeds = sorted(set().union(*(set(a.index) | set(b.index) for a, b in pairs.values()))) if pairs else []

    def fetch(ask):
        return {k: [(pairs[k][0].get(s, np.nan), pairs[k][1].get(s, np.nan)) for s in ss] for k, ss in ask.items()}

    return sequential_family(fetch, list(pairs), seeds=seeds, max_n=max_n, step=step, **rule)


def replay_families(families: Mapping[Hashable, Mapping[Hashable, tuple]], **kw) -> pd.DataFrame:
    """:func:`replay_family` over several Holm families, one after another.

    Args:
        families: family key -> the family's pairs (:func:`replay_family`).
        **kw: as :func:`replay_family`.

    Returns:
        DataFrame: the families' rows, a ``family`` column first.
    """
    parts = [replay_family(p, **kw).assign(family=[fam] * len(p)) for fam, p in families.items()]
    out = pd.concat(parts, ignore_index=True) if parts else pd.DataFrame()
    return out[["family", *[c for c in out.columns if c != "family"]]] if len(out) else out


def seeds_saved(result: pd.DataFrame, max_n: int) -> dict:
    """Seeds used against `max_n` for every comparison.

    Args:
        result: rows of :func:`sequential_family` or :func:`replay_families`.
        max_n: the fixed design's seeds per comparison.

    Returns:
        dict: comparisons, seeds_used, seeds_fixed (comparisons x max_n),
        seeds_saved, saved_fraction. Counts comparison-seeds: where
        comparisons share runs (one control for several designs), the runs
        saved are the union's, counted by the caller.
    """
    used = int(result["n_seeds"].sum())
    fixed = int(len(result) * max_n)
    return {
        "comparisons": len(result),
        "seeds_used": used,
        "seeds_fixed": fixed,
        "seeds_saved": fixed - used,
        "saved_fraction": (fixed - used) / fixed if fixed else math.nan,
    }
