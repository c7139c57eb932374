"""Tables for reading (mat_hopper.analysis.tables), on synthetic results with
known answers and on the compiled model."""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
import pytest
from synthetic_results import results

from mat_hopper.analysis import tables as tab
from mat_hopper.core import reference as ref
from mat_hopper.core.materials import spring_stiffness
from mat_hopper.viz import chapters


@pytest.fixture(scope="module")
def synthetic():
    return results(n=20)


def test_joint_table():
    j = tab.joint_table("SS").set_index("joint")
    assert np.isclose(j.loc["mat_spring_1", "stiffness"], spring_stiffness(193.0))
    assert j.loc["spring", "stiffness"] == ref.FOOT_SPRING_STIFFNESS
    assert j.loc["hip_y", "type"] == "hinge" and np.isclose(j.loc["hip_y", "range_high"], math.radians(70))
    assert "mat_spring_1" not in tab.joint_table("MD")["joint"].values


def test_pct_change_and_metric_tables(synthetic):
    hops, _ = synthetic
    exp1 = hops[hops["experiment"] == "exp1"]
    t = tab.pct_change_table(exp1, "tracking_error_m")
    assert list(t.index) == ["PVC", "Al", "Ti", "SS"]
    assert list(t.columns) == ["static", "forward", "ramp", "circle"]
    assert abs(t.loc["SS", "ramp"] - (0.028 / 0.10 - 1) * 100) < 3  # set by construction (3 % noise)
    zero = exp1.assign(tracking_error_m=np.where(exp1["design"] == "MD", 1e-17, exp1["tracking_error_m"]))
    assert tab.pct_change_table(zero, "tracking_error_m").isna().all().all()  # % of round-off: none
    vs_ss = tab.pct_change_table(hops[hops["experiment"] == "exp3"], "power_w", baseline="SS")
    assert "SS" not in vs_ss.index and abs(vs_ss.loc["rho-inc", "ramp"] - (2.23 / 2.93 - 1) * 100) < 3
    m = tab.metric_table(exp1, "hop_height_m")
    assert ((m - 1.0).abs() < 0.01).all().all()
    mm = tab.metric_table(exp1, "tracking_error_m", "median", scale=1e3)
    assert abs(mm.loc["MD", "forward"] - 100) < 5
    with pytest.raises(ValueError, match="stat"):
        tab.metric_table(exp1, "power_w", "max")


def test_outcome_table():
    runs = pd.DataFrame(
        {
            "design": ["SS", "SS", "MD"],
            "behaviour": ["ramp", "static", "static"],
            "replicate": [-1, -1, -1],
            "status": ["diverged", "ok", "fallen"],
            "n_hops": [3, 40, 10],
            "diverged_at_s": [12.5, np.nan, np.nan],
        }
    )
    t = tab.outcome_table(runs)
    assert list(t.index) == ["MD", "SS"] and list(t.columns) == ["static", "ramp"]
    assert t.loc["SS", "ramp"] == "diverged at 12 s"
    text = tab.outcome_summary(runs)
    assert text.startswith("1 of 3 runs ended upright; not: ")
    assert "SS ramp: diverged at 12 s" in text and "MD static: fallen" in text
    ok = runs.assign(status="ok")
    assert tab.outcome_summary(ok) == "3 of 3 runs ended upright."
    assert t.loc["SS", "static"] == "ok, 40 hops" and t.loc["MD", "static"] == "fallen"
    with pytest.raises(ValueError, match="status"):
        tab.outcome_table(runs.drop(columns="status"))


def test_sweep_spans(synthetic):
    hops, _ = synthetic
    s = tab.sweep_spans(hops[hops["experiment"] == "exp2"]).set_index(["sweep_base", "sweep_property"])
    # by construction density moves tracking error strongly, modulus little
    for base in ref.SWEEPS:
        assert s.loc[(base, "density"), "span"] > s.loc[(base, "modulus"), "span"]
    assert s.loc[("Ti", "density"), "at_max"] == min(ref.SWEEPS["Ti"]["density"])  # lightest tracks worst
    assert s.loc[("Ti", "density"), "n_points"] == len(ref.SWEEPS["Ti"]["density"])


def test_order_effect_and_starred(synthetic):
    hops, _ = synthetic
    exp3 = hops[hops["experiment"] == "exp3"]
    t = tab.order_effect(exp3)
    assert set(t["pair"]) == {"rho-dec vs rho-inc", "SS-Ti-PVC vs PVC-Ti-SS"}
    row = t[(t["pair"] == "rho-dec vs rho-inc") & (t["behaviour"] == "ramp") & (t["metric"] == "tracking_error_m")]
    assert abs(row["pct_change"].iloc[0] - (0.04 / 0.018 - 1) * 100) < 10 and bool(row["significant"].iloc[0])
    wide = tab.starred(t)
    assert list(wide.columns) == ["static", "forward", "ramp", "circle"]
    assert wide.loc[("rho-dec vs rho-inc", "tracking_error_m"), "ramp"].endswith("*")
    with pytest.raises(ValueError, match="both"):
        tab.order_effect(exp3[exp3["design"] != "rho-dec"])


def test_claims_for_chapters(synthetic):
    hops, runs = synthetic
    tables = {f"{e}_hops": hops[hops["experiment"] == e] for e in ("exp1", "exp2", "exp3")}
    tables.update({f"{e}_runs": runs[runs["experiment"] == e] for e in ("exp1", "exp2", "exp3")})
    from mat_hopper.analysis import claims

    known = {c.claim_id for c in claims.CLAIMS}
    for ids in tab.CHAPTER_CLAIMS.values():
        assert set(ids) <= known
    every = tab.claims_for(tables, None, columns=None)
    assert set(every["claim_id"]) == known
    mono = tab.claims_for(tables, "mono", columns=None)
    assert list(mono["claim_id"]) == list(tab.CHAPTER_CLAIMS["mono"])
    assert list(tab.claims_for(tables, "gradients").columns) == ["claim", "paper", "ours", "verdict"]
    ramp = mono = tab.claims_for(tables, "gradients", columns=None).set_index("claim_id")
    assert ramp.loc["ramp_rho_inc_tracking", "verdict"] == "holds"  # -82 % by construction
    with pytest.raises(ValueError, match="chapter"):
        tab.claims_for(tables, "nope")


def test_power_formula_and_defects_figure(synthetic):
    hops, _ = synthetic
    p = tab.power_formula_table(hops[hops["experiment"] == "exp1"])
    assert list(p.index) == ["real hip power (ours)", "the authors' formula"]
    assert abs(p.loc["real hip power (ours)", "ramp"] - (2.93 - 1) * 100) < 10
    clock = pd.DataFrame({"design": ["MD", "MD"], "clock_factor": [1.0, 2.0], "mean_tracking_error_m": [0.06, 0.1]})
    assert len(chapters.defects_figure(clock, p).axes) == 2
    rules = tab.claim_rules()
    assert len(rules) == len(tab.claims_for({"exp1_hops": hops[hops["experiment"] == "exp1"]}, None))


def test_jerk_by_rate_raw_and_metric_by_hand():
    """A hand-made record at 1 kHz: vertical acceleration a = 2 t (m/s^2),
    so every finite difference is exactly 2 m/s^3; the metric's channel
    jerk_z holds -3 m/s^3, so its mean |jerk| is 3 at every rate."""
    from mat_hopper.core.behaviours import behaviour
    from mat_hopper.core.materials import parse_design
    from mat_hopper.core.rollout import Rollout
    from mat_hopper.core.sim import CHANNELS, C, SimSettings

    t = np.arange(2001) * 1e-3
    data = np.zeros((len(t), len(CHANNELS)))
    data[:, C["t"]], data[:, C["az"]], data[:, C["jerk_z"]] = t, 2.0 * t, -3.0
    settings = SimSettings(duration_s=2.0, transient_s=0.5, timestep_s=1e-4)
    r = Rollout(parse_design("SS"), behaviour("forward"), settings, data, np.zeros((0, 3)), -1, 1.0, ())
    j = tab.jerk_by_rate(r, rates_hz=(1000.0, 100.0))
    assert list(j["rate_hz"]) == pytest.approx([1000.0, 100.0])
    assert list(j["raw_jerk_m_s3"]) == pytest.approx([2.0, 2.0])
    assert list(j["metric_jerk_m_s3"]) == pytest.approx([3.0, 3.0])
    assert list(j["mean_jerk_m_s3"]) == list(j["raw_jerk_m_s3"])
    assert len(chapters.jerk_rate_figure({"SS": j}).axes) == 1


def test_leg_mass_table_by_hand():
    # a 0.1 m segment at 1 g/cm^3 weighs 0.327 kg with its end caps
    # (docs/reference-hopper.md): three of them 0.982 kg; at 8 g/cm^3, 8 times that.
    runs = pd.DataFrame({"design": ["MD-like", "SS"], "densities_g_cm3": ["1/1/1", "8/8/8"], "replicate": [-1, -1]})
    t = tab.leg_mass_table(runs)
    assert t["leg_mass_kg"].tolist() == pytest.approx([3 * 0.327, 24 * 0.327], rel=2e-3)


def test_failure_table_tells_numerical_from_falls():
    runs = pd.DataFrame(
        {
            "design": ["A", "B", "C", "D"],
            "behaviour": ["forward"] * 4,
            "replicate": [-1] * 4,
            "status": ["ok", "diverged", "diverged", "fallen"],
            "upright": [True, False, False, False],
            "diverged_at_s": [np.nan, 0.0012, 9.4, np.nan],
            "final_base_z_m": [0.9, 1.2, 0.01, 0.05],
            "n_hops": [10, 0, 8, 3],
        }
    )
    f = tab.failure_table(runs).set_index("design")
    assert list(f.index) == ["B", "C", "D"]
    assert f.loc["B", "kind"] == "numerical" and f.loc["B", "at_s"] == 0.0012
    assert f.loc["C", "kind"] == "fell, then diverged" and f.loc["C", "at_s"] == 9.4
    assert f.loc["D", "kind"] == "fell" and np.isnan(f.loc["D", "at_s"])


def test_failure_table_without_diverged_at_s_names_the_column():
    runs = pd.DataFrame(
        {
            "design": ["A", "B"],
            "behaviour": ["forward"] * 2,
            "status": ["ok", "diverged"],
            "final_base_z_m": [0.9, 1.2],
        }
    )
    with pytest.raises(ValueError, match=r"failure_table.*needs columns \['diverged_at_s'\]"):
        tab.failure_table(runs)
    # no diverged run: the time of a blow-up is not needed
    f = tab.failure_table(runs.assign(status=["ok", "fallen"], final_base_z_m=[0.9, 0.05]))
    assert list(f["kind"]) == ["fell"]
    with pytest.raises(ValueError, match=r"needs columns \['behaviour', 'final_base_z_m'\]"):
        tab.failure_table(runs.drop(columns=["behaviour", "final_base_z_m"]))


def test_tables_name_missing_columns():
    with pytest.raises(ValueError, match=r"replicate_table needs columns \['design', 'n'"):
        tab.replicate_table(pd.DataFrame({"metric": ["power_w"], "pct_change": [1.0]}))
    with pytest.raises(ValueError, match=r"starred needs columns \['significant'\]"):
        tab.starred(pd.DataFrame({"pair": ["x"], "metric": ["m"], "behaviour": ["forward"], "pct_change": [1.0]}))
    hops = pd.DataFrame({"setting": ["a", "a"], "design": ["MD", "SS"], "power_w": [1.0, 2.0]})
    with pytest.raises(ValueError, match=r"setting_comparison needs columns \['tracking_error_m'\]"):
        tab.setting_comparison(hops)
    with pytest.raises(ValueError, match=r"setting_comparison needs columns \['design'\]"):
        tab.setting_comparison(hops.drop(columns="design"), metrics=("power_w",))


def _linear_record(rate_hz=1000.0, n=2001):
    """A hand-made record at `rate_hz` (as in the test above)."""
    from mat_hopper.core.behaviours import behaviour
    from mat_hopper.core.materials import parse_design
    from mat_hopper.core.rollout import Rollout
    from mat_hopper.core.sim import CHANNELS, C, SimSettings

    t = np.arange(n) / rate_hz
    data = np.zeros((len(t), len(CHANNELS)))
    data[:, C["t"]], data[:, C["az"]], data[:, C["jerk_z"]] = t, 2.0 * t, -3.0
    settings = SimSettings(duration_s=2.0, transient_s=0.5, timestep_s=1e-4)
    return Rollout(parse_design("SS"), behaviour("forward"), settings, data, np.zeros((0, 3)), -1, 1.0, ())


@pytest.mark.parametrize("rate", [1500.0, 1999.0, 1001.0])
def test_jerk_by_rate_refuses_a_rate_above_the_record_rate(rate):
    # between 1x and 2x the 1 kHz record rate: subsampling cannot give it
    # (it used to be lowered to 1000 Hz without a word)
    with pytest.raises(ValueError, match=r"exceeds the record rate 1000 Hz; possible rates: 1000 Hz divided by"):
        tab.jerk_by_rate(_linear_record(), rates_hz=(100.0, rate))


@pytest.mark.parametrize(
    ("rates", "text"),
    [
        ((0.0,), "must be a finite number > 0"),
        ((-10.0,), "must be a finite number > 0"),
        ((float("nan"),), "must be a finite number > 0"),
        ((), "at least one rate"),
        (100.0, "rates_hz must be numbers"),
        ((1e-3,), "leaves fewer than 3 samples"),
    ],
)
def test_jerk_by_rate_refuses_bad_rates(rates, text):
    with pytest.raises(ValueError, match=text):
        tab.jerk_by_rate(_linear_record(), rates_hz=rates)


def test_jerk_by_rate_rounds_a_rate_below_the_record_rate_to_a_whole_step():
    # 1 kHz / 3 = 333.33 Hz is the nearest possible rate to 300 Hz
    j = tab.jerk_by_rate(_linear_record(), rates_hz=(300.0, 1000.0))
    assert list(j["rate_hz"]) == pytest.approx([1000.0 / 3, 1000.0])
