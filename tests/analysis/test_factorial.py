"""The factorial's table on a synthetic 2 x 2 of legs whose per-seed log
ratios are chosen so that every effect, exact sign-flip p and Holm
adjustment can be worked out by hand.

Legs A, B, C, D on six seeds; ln(leg / D) per seed is a, b, c, 0. The
contrasts' log ratios are then a, a - b, c, a - c, b. An exact sign-flip
test over 2^6 sign patterns gives p = 2k / 64 where k patterns reach the
observed sum: all positive k = 1 (0.03125); the two or three smallest
negative, each smaller than any positive, k = 4 (0.125) or 8 (0.25). In
each the paired t test's p is smaller, so p is the sign-flip p."""

import math

import numpy as np
import pandas as pd
import pytest

from mat_hopper.analysis.factorial import factorial_effects

A = (0.5, 0.6, 0.7, 0.8, 0.9, 1.0)  # claim (A vs D): all positive, mean 0.75
B = (-0.01, -0.02, 0.3, 0.4, 0.5, 0.6)  # B vs D: two smallest negative, mean 0.295
C = (-0.01, -0.02, -0.03, 0.3, 0.4, 0.5)  # C vs D: three smallest negative, mean 0.19
# A - B = (0.51, 0.62, 0.4, 0.4, 0.4, 0.4), mean 0.455; A - C = (0.51, 0.62, 0.73, 0.5, 0.5, 0.5), mean 0.56

CONTRASTS = {
    "claim": ("A", "D"),
    "f1": ("A", "B"),
    "f2": ("C", "D"),
    "f3": ("A", "C"),
    "f4": ("B", "D"),
}


def _means(drop=()):
    rows = []
    for leg, logs in {"A": A, "B": B, "C": C, "D": (0.0,) * 6}.items():
        for seed, v in enumerate(logs):
            if (leg, seed) not in drop and leg not in drop:
                # the same log ratios in both metrics, at different scales (m, W)
                rows.append({"leg": leg, "replicate": seed, "err_m": 0.05 * math.exp(v), "power_w": 300 * math.exp(v)})
    return pd.DataFrame(rows).set_index(["leg", "replicate"])


def _pct(mean_log):
    return 100 * (math.exp(mean_log) - 1)


def test_effects_holm_families_and_conclusions_by_hand():
    t = factorial_effects(_means(), CONTRASTS, metrics=("err_m", "power_w"), alone=("claim",))
    assert list(t.columns[:2]) == ["contrast", "metric"] and list(t.columns[-2:]) == ["p_holm", "conclusion"]
    assert list(t["contrast"]) == [c for c in CONTRASTS for _ in range(2)]
    assert list(t["metric"]) == ["err_m", "power_w"] * 5
    for metric in ("err_m", "power_w"):
        g = t[t["metric"] == metric].set_index("contrast")
        assert list(g["n_pairs"]) == [6] * 5
        np.testing.assert_allclose(
            g["pct_change"], [_pct(0.75), _pct(0.455), _pct(0.19), _pct(0.56), _pct(0.295)], rtol=1e-9
        )
        np.testing.assert_allclose(g["p"], [2 / 64, 2 / 64, 16 / 64, 2 / 64, 8 / 64], rtol=1e-9)
        # the claim alone: unadjusted. The four factorial contrasts of this metric, Holm by hand:
        # sorted p 1/32 (f1), 1/32 (f3), 1/8 (f4), 1/4 (f2) -> 4/32, max(4/32, 3/32), max(., 2/8), max(., 1/4)
        np.testing.assert_allclose(g["p_holm"], [1 / 32, 1 / 8, 1 / 4, 1 / 8, 1 / 4], rtol=1e-9)
        assert list(g["conclusion"]) == ["difference"] + ["not enough evidence"] * 4


def test_claim_in_the_family_when_not_alone():
    # five contrasts in one family: the claim's 1/32 ranks among the smallest, 5 x 1/32
    g = factorial_effects(_means(), CONTRASTS, metrics=("err_m",)).set_index("contrast")
    assert g.loc["claim", "p_holm"] == pytest.approx(5 / 32)
    assert g.loc["claim", "conclusion"] == "not enough evidence"


def test_unusable_runs_drop_their_pairs_and_an_absent_leg_stays_in_its_family():
    g = factorial_effects(_means(drop=[("C", 0)]), CONTRASTS, metrics=("err_m",), alone=("claim",))
    assert list(g["n_pairs"]) == [6, 6, 5, 5, 6]
    g = factorial_effects(_means(drop=["B"]), CONTRASTS, metrics=("err_m",), alone=("claim",)).set_index("contrast")
    assert g.loc[["f1", "f4"], "n_pairs"].tolist() == [0, 0]
    assert g.loc[["f1", "f4"], "pct_change"].isna().all() and g.loc[["f1", "f4"], "p_holm"].isna().all()
    # family of four, two untestable (p as 1): sorted 1/32 (f3), 1/4 (f2), 1, 1 -> f3 4/32, f2 max(4/32, 3/4)
    assert g.loc["f3", "p_holm"] == pytest.approx(4 / 32)
    assert g.loc["f2", "p_holm"] == pytest.approx(3 / 4)
    assert (g.loc[["f1", "f4"], "conclusion"] == "not enough evidence").all()


def test_errors_name_the_unknown_metric_and_contrast():
    with pytest.raises(ValueError, match="tracking_error_m"):
        factorial_effects(_means(), CONTRASTS, metrics=("tracking_error_m",))
    with pytest.raises(ValueError, match="headline"):
        factorial_effects(_means(), CONTRASTS, metrics=("err_m",), alone=("headline",))
