"""mat_hopper.util.parsing.check_positive: the one check of a setting that must
be a finite number > 0 (modes' gains, behaviours' periods, porosity)."""

import math

import numpy as np
import pytest

from mat_hopper.util.parsing import check_positive


@pytest.mark.parametrize("value", [2, 2.5, np.float32(0.5), np.int64(3), 1e-300])
def test_numbers_above_zero_come_back_as_floats(value):
    x = check_positive(value, "gear")
    assert type(x) is float and x == float(value)


@pytest.mark.parametrize("value", [0, -1.0, math.nan, math.inf, True, "2", None])
def test_bad_values_name_the_argument_and_range(value):
    with pytest.raises(ValueError, match=r"^dt_s must be a finite number > 0 s, got "):
        check_positive(value, "dt_s", unit="s")


def test_an_upper_bound_is_inclusive_and_named():
    assert check_positive(1.0, "safety", high=1.0) == 1.0
    with pytest.raises(ValueError, match=r"safety must be in \(0, 1\], got 1.5"):
        check_positive(1.5, "safety", high=1.0)
