"""The claims table's stationarity column: each claim judged again on each
half of the scored window."""

import pandas as pd
from synthetic_results import results

from mat_hopper.analysis import claims
from mat_hopper.analysis.stationarity import (
    NOT_CHECKED,
    is_window_dependent,
    stationarity,
    window_halves,
    window_midpoint_s,
)


def test_halves_split_the_scored_window_at_its_midpoint():
    hops = pd.DataFrame({"t_start_s": [20.0, 30.0, 39.0, 50.0], "t_end_s": [21.0, 31.0, 40.0, 60.0]})
    assert window_midpoint_s(hops) == 40.0  # (20 + 60) / 2
    first, second = window_halves(hops)
    assert list(first["t_start_s"]) == [20.0, 30.0, 39.0] and list(second["t_start_s"]) == [50.0]
    assert window_halves(hops.iloc[0:0]) is None and window_halves(pd.DataFrame({"x": [1]})) is None


def test_cells_name_both_halves():
    assert stationarity("holds", "holds") == "stationary (holds | holds)"
    cell = stationarity("holds", "does not hold", "-80 %", "+5 %")
    assert is_window_dependent(cell) and "first half: holds, -80 %" in cell and "second half: does not hold" in cell
    assert stationarity("", "holds") == NOT_CHECKED and not is_window_dependent(NOT_CHECKED)


def _row(table, claim_id):
    return table[(table["convention"] == "paper") & (table["claim_id"] == claim_id)].iloc[0]


def test_a_settled_claim_is_stationary_and_a_drifting_one_window_dependent():
    """Synthetic results that hold in every cycle are stationary; make
    rho-inc's ramp tracking worse than MD's in the second half only, and
    the whole-window verdict may still hold while the column says the
    claim depends on the window."""
    hops, runs = results(n=20)
    t = claims.claims_table(hops, runs, conventions=("paper",))
    assert _row(t, "ramp_rho_inc_tracking")["stationarity"] == "stationary (holds | holds)"
    assert (t.loc[~t["claim_id"].str.startswith("timestep"), "stationarity"].str.startswith("stationary")).all()
    assert (t.loc[t["claim_id"].str.startswith("timestep"), "stationarity"] == "").all()

    late = hops["t_start_s"] >= window_midpoint_s(hops)
    inc = (hops["design"] == "rho-inc") & (hops["behaviour"] == "ramp")
    drifted = hops.copy()
    drifted.loc[inc & late, "tracking_error_m"] *= 0.11 / 0.018  # worse than MD, second half only
    t2 = claims.claims_table(drifted, runs, conventions=("paper",))
    cell = _row(t2, "ramp_rho_inc_tracking")["stationarity"]
    assert is_window_dependent(cell), cell
    assert "first half: holds" in cell and "second half: does not hold" in cell
    assert _row(t2, "ramp_ss_tracking")["stationarity"].startswith("stationary")  # the other claims untouched


def test_check_window_off_and_in_the_markdown():
    hops, runs = results(n=10)
    t = claims.claims_table(hops, runs, conventions=("paper",), check_window=False)
    assert (t.loc[~t["claim_id"].str.startswith("timestep"), "stationarity"] == NOT_CHECKED).all()
    assert "stationarity" in claims.to_markdown(t).splitlines()[0]
