"""mat_hopper.util.change: the one percent change and its round-off floor (hand-worked values)."""

import math

import numpy as np
import pytest

from mat_hopper.util.change import ROUNDOFF, percent_change


def test_percent_change_by_hand():
    assert percent_change(110.0, 100.0) == pytest.approx(10.0)
    assert percent_change(20.0, -40.0) == pytest.approx(150.0)  # relative to |baseline|: 60 / 40
    assert percent_change(0.5, 2.0) == pytest.approx(-75.0)
    assert type(percent_change(1.0, 2.0)) is float  # a float for scalars
    np.testing.assert_allclose(percent_change([1, 3], [2, 2]), [-50.0, 50.0])


def test_a_baseline_that_is_nothing_gives_nan():
    assert ROUNDOFF == 1e-9
    assert math.isnan(percent_change(1.0, 0.0))
    assert math.isnan(percent_change(1.0, 5e-10))  # below the round-off floor (SI units)
    assert percent_change(2e-9, 1e-9) == pytest.approx(100.0)  # at the floor: a value
    assert math.isnan(percent_change(1.0, math.inf)) and math.isnan(percent_change(1.0, math.nan))
    assert percent_change(1.0, 0.01, floor=0.1) != percent_change(1.0, 0.01)  # the floor is a parameter
    out = percent_change([1.0, 1.0], [0.0, 4.0])
    assert math.isnan(out[0]) and out[1] == pytest.approx(-75.0)
