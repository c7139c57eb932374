import numpy as np
import pandas as pd
import pytest

from mat_hopper.metrics import ALL_METRICS, compare, holm, hop_cycles, hop_table, run_summary, summarize
from mat_hopper.sim import simulate


@pytest.fixture(scope="module")
def rollout():
    return simulate("Al", "forward", duration=8.0, transient=3.0)


def test_hop_table_rows_are_scored_cycles(rollout):
    hops = hop_table(rollout)
    cyc = hop_cycles(rollout)
    assert len(hops) == len(cyc) >= 5
    assert (hops["t_start_s"] >= 3.0).all()
    assert np.allclose(hops["t_start_s"].to_numpy()[1:], hops["t_end_s"].to_numpy()[:-1])
    for m in ALL_METRICS:
        assert np.isfinite(hops[m]).all() and (hops[m] >= 0).all()
    assert list(hops.columns[:7]) == ["design", "behaviour", "convention", "sensor_timing", "hop", "t_start_s",
                                      "t_end_s"]
    assert (hops["sensor_timing"] == "authors").all()


def test_metrics_match_direct_computation(rollout):
    hops = hop_table(rollout)
    row = hops.iloc[2]
    t = rollout.time
    sel = (t >= row.t_start_s) & (t < row.t_end_s)
    assert row.hop_height_m == pytest.approx(rollout.base_pos[sel, 2].max())
    err = np.linalg.norm(rollout.base_pos[sel, :2] - rollout.desired_pos[sel], axis=1).mean()
    assert row.tracking_error_m == pytest.approx(err)
    p = np.hypot(*(600.0 * rollout.ctrl[sel, :2] * rollout.hip_rate[sel]).T).mean()   # gear 600, by hand
    assert row.power_w == pytest.approx(p)
    # the controller's own hop heights agree with the recorded maxima
    assert rollout.hop_heights_m[-3:] == pytest.approx(hops.hop_height_m.to_numpy()[-3:], abs=2e-3)


def test_longer_transient_scores_fewer_hops(rollout):
    assert len(hop_table(rollout, transient_s=6.0)) < len(hop_table(rollout))


def test_run_summary(rollout):
    s = run_summary(rollout)
    assert s["stable"] and s["n_hops"] >= 5
    assert s["distance_m"] > 0.1 and s["cost_of_transport"] > 0


def test_holm_against_hand_computation():
    p = [0.01, 0.04, 0.03, 0.005]
    # sorted 0.005*4=0.02, 0.01*3=0.03, 0.03*2=0.06, 0.04*1=0.04 -> monotone 0.06
    assert holm(p) == pytest.approx([0.03, 0.06, 0.06, 0.02])
    assert np.isnan(holm([np.nan, 0.1])[0])


def test_compare_percent_change_and_effect():
    rng = np.random.default_rng(0)
    rows = []
    for design, shift in (("base", 0.0), ("better", -0.5), ("same", 0.0)):
        for v in rng.normal(1.0 + shift, 0.05, 30):
            rows.append({"design": design, "behaviour": "forward", "tracking_error_m": v})
    table = compare(pd.DataFrame(rows), "base", metrics=("tracking_error_m",))
    better = table[table.design == "better"].iloc[0]
    same = table[table.design == "same"].iloc[0]
    assert better["pct_change"] == pytest.approx(-50, abs=5)
    assert better.effect_size == -1.0 and better.significant
    assert not same.significant
    with pytest.raises(ValueError, match="baseline"):
        compare(pd.DataFrame(rows), "nope")


def test_summarize_is_tidy(rollout):
    s = summarize(hop_table(rollout))
    assert set(s.metric) == {"hop_height_m", "tracking_error_m", "jerk_m_s3", "power_w"}
    assert {"mean", "median", "iqr", "n"} <= set(s.columns)


def test_compare_ignores_round_off_differences():
    rows = [{"design": "MD", "behaviour": "static", "tracking_error_m": v} for v in np.full(20, 1e-17)]
    rows += [{"design": "SS", "behaviour": "static", "tracking_error_m": 0.0} for _ in range(20)]
    row = compare(pd.DataFrame(rows), "MD", metrics=("tracking_error_m",)).iloc[0]
    assert row["p"] == 1.0 and not row["significant"]
