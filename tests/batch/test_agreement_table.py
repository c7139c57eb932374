"""batch.agreement on hand-made tables: the differences and the verdicts,
worked out by hand."""

import math

import pandas as pd
import pytest

from mat_hopper.batch import agreement


def _t(rows):
    cols = ["design", "behaviour", "n_hops", "hop_height_m", "tracking_error_m", "power_w", "stable", "diverged_at_s"]
    return pd.DataFrame(rows, columns=cols)


REF = _t(
    [
        ["A", "forward", 40, 1.000, 0.020, 2.00, True, math.nan],
        ["B", "forward", 40, 1.000, 0.020, 2.00, True, math.nan],
        ["C", "forward", 0, math.nan, math.nan, math.nan, False, 0.4100],
        ["D", "forward", 0, math.nan, math.nan, math.nan, False, 0.4100],
        ["E", "forward", 40, 1.000, 0.020, 2.00, True, math.nan],
    ]
)
OTHER = _t(
    [
        ["A", "forward", 41, 1.008, 0.0218, 1.85, True, math.nan],  # +1 hop, +8 mm, +9 %, -7.5 %: agrees
        ["B", "forward", 40, 1.000, 0.0230, 2.00, True, math.nan],  # tracking +15 %: does not
        ["C", "forward", 0, math.nan, math.nan, math.nan, False, 0.4105],  # both diverge 0.5 ms apart
        ["D", "forward", 0, math.nan, math.nan, math.nan, False, 0.4200],  # 10 ms apart
        ["E", "forward", 0, math.nan, math.nan, math.nan, False, 0.3000],  # only one diverges
    ]
)


def test_differences_and_verdicts_by_hand():
    a = agreement(REF, OTHER)
    assert a["agrees"].tolist() == [True, False, True, False, False]
    assert a["hop_height_diff_m"][0] == pytest.approx(0.008)
    assert a["tracking_error_diff_pct"][0] == pytest.approx(9.0)
    assert a["power_diff_pct"][0] == pytest.approx(-7.5)
    assert a["tracking_error_diff_pct"][1] == pytest.approx(15.0)
    assert (a["n_hops"] - a["n_hops_ref"]).tolist() == [1, 0, 0, 0, -40]


def test_runs_without_scored_hops_compare_whole_run_means():
    ref = _t([["A", "forward", 0, math.nan, math.nan, math.nan, True, math.nan]] * 2)
    ref["run_tracking_error_m"], ref["run_power_w"] = 0.030, 1.0
    other = ref.copy()
    other["run_tracking_error_m"] = [0.0327, 0.0333]  # +9 % agrees, +11 % does not
    a = agreement(ref, other)
    assert a["agrees"].tolist() == [True, False]
    assert a["run_tracking_error_diff_pct"].tolist() == pytest.approx([9.0, 11.0])


def test_tables_of_other_designs_are_refused():
    with pytest.raises(ValueError, match="same designs"):
        agreement(REF, OTHER.iloc[::-1].reset_index(drop=True))
