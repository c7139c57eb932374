"""The envelope growth rate (mat_hopper.analysis.growth) against
exponentials worked out by hand."""

from __future__ import annotations

import math

import numpy as np
import pytest

from mat_hopper.analysis.growth import envelope_growth

T = np.arange(0.0, 10.0, 1e-3)


def test_a_pure_exponential_by_hand():
    # x = 1e-6 e^{2t}: each 0.25 s window's largest value is at its last sample,
    # so log env = 2 (window end - 1 ms) + log 1e-6, slope 2 exactly. It passes
    # 1e-2 where e^{2t} > 1e4, t > ln(1e4) / 2 = 4.605 s: inside window 18
    # (4.50-4.75 s). Windows 0..17 are fitted: from 0.249 s to 4.499 s, 4.25 s at
    # a rate of 2 is 8.5 / ln 10 = 3.6914 decades.
    fit = envelope_growth(T, 1e-6 * np.exp(2 * T), 0.25)
    assert fit.rate_per_s == pytest.approx(2.0, rel=1e-9)
    assert fit.passed_s == pytest.approx(4.5)
    assert fit.decades == pytest.approx(8.5 / math.log(10), rel=1e-9)


def test_an_oscillation_under_a_growing_envelope():
    # a 20 Hz carrier: every 0.31 s window holds a peak of |sin| within one
    # carrier period (50 ms) of its end, so the rate comes out within a few %
    x = 1e-9 * np.exp(0.8 * T) * np.sin(2 * np.pi * 20 * T)
    assert envelope_growth(T, x, 0.31).rate_per_s == pytest.approx(0.8, rel=0.03)
    # a decaying envelope: each window's largest value is at its first sample, slope -0.5 exactly
    assert envelope_growth(T, 1e-3 * np.exp(-0.5 * T), 0.31).rate_per_s == pytest.approx(-0.5, rel=1e-9)


def test_the_floor_skips_what_comes_before_the_mode_and_the_start_moves_the_windows():
    # round-off (1e-15) until 2 s, then a mode seeded at 1e-10 growing at 1.5 /s
    x = np.where(T < 2.0, 1e-15, 1e-10 * np.exp(1.5 * (T - 2.0)))
    assert envelope_growth(T, x, 0.25, floor=1e-12).rate_per_s == pytest.approx(1.5, rel=1e-9)
    # with no floor the round-off windows are fitted too: the jump of five decades
    # from them to the seed bends the line (2.47 /s here)
    assert abs(envelope_growth(T, x, 0.25).rate_per_s - 1.5) > 0.5
    assert envelope_growth(T, x, 0.25, start_s=2.0).rate_per_s == pytest.approx(1.5, rel=1e-9)


def test_too_few_windows_below_the_ceiling_give_nan():
    fit = envelope_growth(T, 1e-3 * np.exp(3 * T), 0.5)  # passes 1e-2 within the first second
    assert math.isnan(fit.rate_per_s) and math.isnan(fit.decades) and fit.passed_s == pytest.approx(0.5)
    assert math.isnan(envelope_growth(T, np.zeros_like(T), 0.5, floor=1e-12).rate_per_s)


@pytest.mark.parametrize("kwargs", [{"window_s": 0.0}, {"window_s": -1.0}, {"window_s": 1e-4}, {"window_s": np.inf}])
def test_bad_input_is_refused(kwargs):
    with pytest.raises(ValueError, match="window_s"):
        envelope_growth(T, T, **kwargs)
    with pytest.raises(ValueError, match="one length"):
        envelope_growth(T, T[:-1], 0.3)
    for bad in (np.array([]), np.zeros((3, 2))):
        with pytest.raises(ValueError, match="one length >= 2"):
            envelope_growth(bad, bad, 0.3)
    with pytest.raises(ValueError, match="increasing"):
        envelope_growth(T[::-1], T, 0.3)
    with pytest.raises(ValueError, match="start_s"):
        envelope_growth(T, T, 0.3, start_s=np.nan)
    for floor, ceiling in ((1e-2, 1e-2), (0.0, np.nan), (-1.0, 1.0)):
        with pytest.raises(ValueError, match="floor < ceiling"):
            envelope_growth(T, T, 0.3, floor=floor, ceiling=ceiling)


def test_a_nan_sample_is_skipped():
    x = 1e-6 * np.exp(2 * T)
    x[1234] = np.nan
    assert envelope_growth(T, x, 0.25).rate_per_s == pytest.approx(2.0, rel=1e-9)
