"""Paired inference on shared replicate seeds."""

import numpy as np
import pandas as pd
import pytest
from scipy import stats as sps

from mat_hopper.analysis import paired, stats
from mat_hopper.physics.metrics import holm


def _runs(effect=1.05, n=6, seed_spread=0.3, noise=0.005):
    """Replicate means where each seed moves both designs a lot (shared) and
    the design effect is a small factor on top."""
    rng = np.random.default_rng(1)
    seed_factor = np.exp(rng.normal(0, seed_spread, n))
    rows = []
    for rep in range(n):
        for design, f in (("base", 1.0), ("new", effect)):
            v = 0.02 * seed_factor[rep] * f * np.exp(rng.normal(0, noise))
            rows.append({"design": design, "behaviour": "forward", "replicate": rep, "tracking_error_m": v})
    return pd.DataFrame(rows)


def test_paired_effect_is_the_t_interval_of_log_ratios():
    t = _runs()
    a = t[t.design == "new"].tracking_error_m.to_numpy()
    b = t[t.design == "base"].tracking_error_m.to_numpy()
    e = paired.paired_effect(a, b)
    x = np.log(a / b)
    ci = sps.ttest_1samp(x, 0.0).confidence_interval(0.95)  # scipy's own interval
    assert e["method"] == "log-ratio" and e["n_pairs"] == 6
    assert e["pct_change"] == pytest.approx(100 * (np.exp(x.mean()) - 1))
    assert e["ci_low"] == pytest.approx(100 * np.expm1(ci.low)) and e["ci_high"] == pytest.approx(
        100 * np.expm1(ci.high)
    )
    assert e["p_t"] == pytest.approx(sps.ttest_rel(np.log(a), np.log(b)).pvalue)
    assert e["p"] == max(e["p_t"], e["p_perm"])  # both tests must reject
    assert e["p_min_wilcoxon"] == pytest.approx(sps.wilcoxon(np.arange(1.0, 7.0)).pvalue)


def test_pairing_finds_what_the_unpaired_test_cannot():
    t = _runs(effect=1.05)
    a = t[t.design == "new"].tracking_error_m
    b = t[t.design == "base"].tracking_error_m
    assert sps.mannwhitneyu(a, b).pvalue > 0.3  # the seeds' spread hides a 5 % effect
    e = paired.paired_effect(a.to_numpy(), b.to_numpy())
    assert e["p_t"] < 0.001 and 3 < e["pct_change"] < 7
    # every one of the 6 pairs goes the same way: the sign-flip test's floor, 2 / 2^6
    assert e["p"] == e["p_perm"] and e["p"] == pytest.approx(2 / 2**6)


def test_conclusions_separate_no_difference_from_no_evidence():
    same = _runs(effect=1.0, noise=0.005)
    out = paired.compare_paired(same, "base")
    assert out["conclusion"].iloc[0] == paired.NO_DIFFERENCE
    noisy = _runs(effect=1.0, n=3, noise=0.3)
    assert paired.compare_paired(noisy, "base")["conclusion"].iloc[0] == paired.NOT_ENOUGH
    assert paired.compare_paired(_runs(effect=1.3), "base")["conclusion"].iloc[0] == paired.DIFFERENCE
    assert paired.conclusion(0.5, -12.0, 3.0) == paired.NOT_ENOUGH


def test_bca_interval_and_differences_for_zero_values():
    t = _runs(n=12)
    a, b = t[t.design == "new"].tracking_error_m.to_numpy(), t[t.design == "base"].tracking_error_m.to_numpy()
    e = paired.paired_effect(a, b, interval="bca")
    assert e["ci_low"] < e["pct_change"] < e["ci_high"]
    z = paired.paired_effect(np.array([0.0, 0.1, 0.2]), np.array([0.1, 0.1, 0.3]))
    assert z["method"] == "difference"
    with pytest.raises(ValueError, match="paired"):
        paired.paired_effect([1, 2], [1, 2, 3])
    with pytest.raises(ValueError, match="interval"):
        paired.paired_effect([1, 2], [1, 2], interval="normal")


def test_compare_replicates_pairs_shared_seeds():
    t = _runs(effect=1.05)
    hops = t.assign(hop=0)
    out = stats.compare_replicates(hops, "base", metrics=("tracking_error_m",))
    assert out["paired"].all() and out["significant"].all()
    unpaired = stats.compare_replicates(hops, "base", metrics=("tracking_error_m",), paired=False)
    assert not unpaired["paired"].any() and not unpaired["significant"].any()
    lonely = hops[~((hops.design == "new") & (hops.replicate == 0))]
    assert not stats.compare_replicates(lonely, "base", metrics=("tracking_error_m",))["paired"].any()
    with pytest.raises(ValueError, match="share"):
        stats.compare_replicates(lonely, "base", metrics=("tracking_error_m",), paired=True)


def test_sign_flip_floor_and_identical_pairs():
    e = paired.paired_effect([2.0, 2.0], [1.0, 1.0])  # identical log ratios: no evidence at n = 2
    assert e["p"] == pytest.approx(0.5) and e["p_perm"] == pytest.approx(0.5)
    e3 = paired.paired_effect([2.0, 3.0, 2.5], [1.0, 1.0, 1.0])
    assert e3["p_perm"] == pytest.approx(0.25) and e3["p_min"] == pytest.approx(0.25)  # 2 / 2^3
    assert not paired.reachable(3) and paired.reachable(6) and not paired.reachable(6, 16)


def test_significance_needs_a_reachable_sign_flip_threshold():
    """A clear 30 % effect on 3 seeds: the t test's p is tiny, but the exact
    sign-flip test's smallest p is 2 / 2^3 = 0.25 (hand count: 8 sign
    patterns, the two extreme ones), so nothing can be called significant;
    on 6 seeds 2 / 64 = 0.031 < 0.05 is reachable for a family of one."""
    small = paired.compare_paired(_runs(effect=1.3, n=3), "base").iloc[0]
    assert small["p_t"] < 0.01 and small["p_min"] == pytest.approx(0.25)
    assert small["p_holm"] == pytest.approx(0.25)  # p needs the sign-flip test too: its floor
    assert not small["significant"] and small["conclusion"] == paired.NOT_ENOUGH
    six = paired.compare_paired(_runs(effect=1.3, n=6), "base").iloc[0]
    assert six["p_min"] == pytest.approx(2 / 64) and six["significant"] and six["conclusion"] == paired.DIFFERENCE


def test_interval_name_any_case():
    a, b = [1.10, 1.21, 1.05, 1.30], [1.0, 1.0, 1.0, 1.0]
    assert paired.paired_effect(a, b, interval="T") == paired.paired_effect(a, b, interval="t")
    with pytest.raises(ValueError, match="unknown interval 'z'; accepted: t, bca"):
        paired.paired_effect(a, b, interval="z")


def test_p_needs_both_the_t_test_and_the_sign_flip_test():
    """A referee's case: nine log ratios near -0.15 and one at +0.006, n = 10.
    The t test gives p = 3e-5; the exact sign-flip test counts the sign
    patterns whose mean is at least as far from 0: all ten signs as they are
    and flipped (2), and the one pattern with only the +0.006 flipped, whose
    mean is larger (2 more): 4 / 2^10 = 0.0039. In a Holm family of 16 the t
    test alone would give 16 x 3e-5 < 0.05; the sign-flip test 16 x 0.0039 =
    0.0625 does not reject, and neither does p."""
    x = np.array([-0.15, -0.16, -0.14, -0.15, -0.155, -0.145, -0.15, -0.152, -0.148, 0.006])
    e = paired.paired_effect(np.exp(x), np.ones(10))
    assert e["p_t"] < 1e-4
    assert e["p_perm"] == pytest.approx(4 / 2**10)
    assert e["p"] == e["p_perm"]
    assert holm([e["p"]] + [1.0] * 15)[0] > 0.05


def test_series_pair_on_their_seeds_not_their_positions():
    """Seed 1 dropped from the design's runs: position pairing would set its
    seed 2 against the baseline's seed 1."""
    design = pd.Series([1.1, 2.2], index=[0, 2])
    base = pd.Series([1.0, 5.0, 2.0], index=[0, 1, 2])
    e = paired.paired_effect(design, base)
    assert e["n_pairs"] == 2 and e["pct_change"] == pytest.approx(10.0)
    with pytest.raises(ValueError, match="repeats"):
        paired.paired_effect(pd.Series([1.0, 2.0], index=[0, 0]), pd.Series([1.0, 2.0], index=[0, 1]))
