"""mat_hopper.util.parsing: check_positive, the one check of a setting that
must be a finite number > 0 (modes' gains, behaviours' periods, porosity);
parse_name's answer to an unknown name (the accepted ones, and the nearest)."""

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


# --- parse_name: an unknown name is answered with the nearest ---------------------------------------------

from mat_hopper.util.parsing import close_names, did_you_mean, parse_name  # noqa: E402

CONVENTIONS = ("paper", "axial", "bending", "axial+bending")


@pytest.mark.parametrize(
    "text, found",
    [
        ("rho_inc", ["rho-inc"]),  # other separators: that name alone
        ("RHO INC", ["rho-inc"]),
        ("rho/inc", ["rho-inc"]),
        ("rhoinc", ["rho-inc", "rho-dec"]),  # near spellings, best first
        ("kryptonite", []),
        ("", []),
        (None, []),
    ],
)
def test_close_names_reads_separators_then_spellings(text, found):
    assert close_names(text, ["rho-inc", "rho-dec", "SS"]) == found


def test_parse_name_suggests_the_nearest_after_the_accepted_names():
    with pytest.raises(ValueError, match=r"^unknown convention 'axail'; accepted: paper, .*; did you mean axial\?$"):
        parse_name("axail", CONVENTIONS, "convention")
    with pytest.raises(ValueError, match=r"; did you mean axial\+bending\?$"):
        parse_name("axial_bending", CONVENTIONS, "convention")
    with pytest.raises(
        ValueError, match=r"^unknown convention 'beam'; accepted: paper, axial, bending, axial\+bending$"
    ):
        parse_name("beam", CONVENTIONS, "convention")  # nothing close: no guess
    assert parse_name(" Axial+Bending ", CONVENTIONS, "convention") == "axial+bending"


def test_did_you_mean_names_up_to_three():
    assert did_you_mean("rho_inc", ["rho-inc", "rho-dec"]) == "did you mean rho-inc?"
    assert did_you_mean("rhoinc", ["rho-inc", "rho-dec"]) == "did you mean rho-inc or rho-dec?"
    assert did_you_mean("zzz", ["rho-inc"]) == ""


def test_a_count_that_is_not_a_number_asks_for_a_whole_number():
    """An option that takes a count says "whole number", not "decimal"."""
    from mat_hopper.util.parsing import parse_number

    with pytest.raises(ValueError, match=r"--segments must be a whole number \(e.g. 3, 12\), got 'abc'"):
        parse_number("abc", "--segments", integer=True)
    with pytest.raises(ValueError, match="must be a decimal number"):
        parse_number("abc", "--duration")


def test_parse_name_says_none_is_not_given_and_blank_is_empty():
    with pytest.raises(ValueError, match=r"convention is not given \(None\); accepted: "):
        parse_name(None, CONVENTIONS, "convention")
    with pytest.raises(ValueError, match="convention is empty; accepted: "):
        parse_name("  ", CONVENTIONS, "convention")


@pytest.mark.parametrize("value", [np.int64(3), np.int32(3), np.float32(0.5), np.float64(0.5), np.uint8(3)])
def test_numpy_scalars_are_numbers_everywhere_a_number_is_read(value):
    # np.arange and np.linspace give NumPy scalars: parse_number refused np.int64 and np.float32
    # ("must be a finite number, got np.int64(2)"), as did every isinstance(v, (int, float)) check
    from mat_hopper.core.controller import ControllerSettings
    from mat_hopper.core.perturbations import Perturbation
    from mat_hopper.util.parsing import is_real, parse_number

    assert is_real(value)
    assert parse_number(value, "duration_s", low=0) == float(value)
    assert Perturbation(start_offset_m=value).start_offset_m == value
    assert ControllerSettings(stance_kd=value).stance_kd == value


@pytest.mark.parametrize("value", [True, np.bool_(True), "2", None, [1.0]])
def test_a_bool_or_a_non_number_is_not_a_real_number(value):
    from mat_hopper.util.parsing import is_real

    assert not is_real(value)
