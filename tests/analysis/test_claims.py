import math

import numpy as np
import pandas as pd
import pytest
from synthetic_results import results, stability_table

from mat_hopper.analysis import claims


def _verdicts(table, convention="paper"):
    t = table[table["convention"] == convention]
    return dict(zip(t["claim_id"], t["verdict"]))


@pytest.fixture(scope="module")
def paper_results():
    return results(convention="paper", n=20)


def test_constructed_to_hold(paper_results):
    """Synthetic results built with the paper's numbers: every claim holds;
    a convention without results is 'not run', never a number."""
    hops, runs = paper_results
    t = claims.claims_table(hops, runs, stability_table())
    assert list(t.columns[:5]) == ["claim_id", "claim", "paper", "ours", "verdict"]
    assert set(t["convention"]) == {"paper", "axial"}
    assert set(t["claim_id"]) == {c.claim_id for c in claims.CLAIMS}
    paper = _verdicts(t)
    assert all(v == claims.HOLDS for v in paper.values()), paper
    axial = t[t["convention"] == "axial"]
    assert (axial["verdict"] == claims.NOT_RUN).all() and (axial["ours"] == "not run").all()
    row = t[(t["convention"] == "paper") & (t["claim_id"] == "ramp_rho_inc_tracking")].iloc[0]
    assert row["paper"] == "-82 %" and row["ours"] == "-82 %"
    assert (t["profile"] == "quick").all()


def test_partly_and_does_not_hold():
    # SS on static only -30 %: every behaviour lower, not all by 55 %: partly.
    # rho-inc ramp tracking at +10 % vs MD: does not hold (wrong sign).
    hops, runs = results(n=20, tracking={"SS": 0.028})
    static_ss = (hops["design"] == "SS") & (hops["behaviour"] == "static")
    hops.loc[static_ss, "tracking_error_m"] *= 0.07 / 0.028
    ramp_inc = (hops["design"] == "rho-inc") & (hops["behaviour"] == "ramp")
    hops.loc[ramp_inc, "tracking_error_m"] *= 0.11 / 0.018
    v = _verdicts(claims.claims_table(hops, runs, conventions=("paper",)))
    assert v["tracking_ss_55"] == claims.PARTLY
    assert v["ramp_rho_inc_tracking"] == claims.FAILS
    assert v["headline_tracking"] == claims.FAILS  # rho-inc now tracks worse than SS
    assert v["ramp_ss_tracking"] == claims.HOLDS
    assert v["timestep_materials"] == claims.NOT_RUN  # no stability map given


def test_unstable_runs_are_not_testable_never_numbers(paper_results):
    hops, runs = paper_results
    ax_hops, ax_runs = results(convention="axial", n=20)
    bad = ax_runs["design"].isin(["SS", "Ti"])
    ax_runs.loc[bad, ["stable", "upright", "status", "diverged_at_s"]] = [False, False, "diverged", 0.0012]
    t = claims.claims_table(pd.concat([hops, ax_hops]), pd.concat([runs, ax_runs]), timestep_s=1e-4)
    ax = t[t["convention"] == "axial"].set_index("claim_id")
    assert ax.loc["tracking_ss_55", "verdict"] == claims.NOT_TESTABLE
    assert "SS unstable at dt=1e-4 s" in ax.loc["tracking_ss_55", "ours"]
    assert ax.loc["ramp_rho_inc_tracking", "verdict"] == claims.HOLDS  # MD and rho-inc are fine
    assert ax.loc["tracking_all_beat_md", "verdict"] == claims.PARTLY  # judged on PVC and Al only
    assert "unusable" in ax.loc["tracking_all_beat_md", "detail"]
    assert _verdicts(t)["tracking_ss_55"] == claims.HOLDS  # the paper convention untouched


def test_replicate_basis_is_used_when_present():
    hops, runs = results(n=6, replicates=3)
    t = claims.claims_table(hops, runs, conventions=("paper",))
    row = t.set_index("claim_id").loc["ramp_ss_tracking"]
    assert row["basis"] == "replicate means" and "CI" in row["detail"]
    assert t.set_index("claim_id").loc["density_over_modulus", "basis"] == "hop cycles (description only)"  # exp2: none


def test_a_count_over_hop_cycles_is_labelled_descriptive_never_significant(paper_results):
    """Hop cycles of one run are not independent samples (analysis.stats):
    on that basis a claim's count is a description, its rows never say
    "significantly"; on replicate means the same count is a test."""
    hops, runs = paper_results
    t = claims.claims_table(hops, runs, stability_table(), conventions=("paper",)).set_index("claim_id")
    described = t[t["basis"] == "hop cycles (description only)"]
    assert "tracking_all_beat_md" in described.index
    for column in ("ours", "stationarity"):
        assert not described[column].astype(str).str.contains("significant").any(), described[column]
    assert described.loc["tracking_all_beat_md", "ours"].startswith("16/16 lower, descriptive: Holm p < 0.05 over")


def test_match_percent_rule():
    assert claims.match_percent(-80.0, -82.0) == claims.HOLDS
    assert claims.match_percent(-30.0, -35.0) == claims.HOLDS  # within 10 points
    assert claims.match_percent(-40.0, -82.0) == claims.PARTLY
    assert claims.match_percent(-10.0, -82.0) == claims.FAILS  # under a quarter of the size
    assert claims.match_percent(5.0, -82.0) == claims.FAILS
    assert claims.match_percent(np.nan, -82.0) == claims.NOT_TESTABLE


def test_stability_claims_from_the_map():
    s = stability_table()
    v = _verdicts(claims.claims_table(None, None, s, conventions=("paper",)))
    assert v["timestep_materials"] == claims.HOLDS and v["timestep_trend"] == claims.HOLDS
    flipped = s.assign(max_stable_timestep_s=1e-7 / s["max_stable_timestep_s"])  # the trend reversed
    v = _verdicts(claims.claims_table(None, None, flipped, conventions=("paper",)))
    assert v["timestep_trend"] == claims.FAILS and v["timestep_materials"] == claims.FAILS


def test_writers_are_atomic_and_complete(tmp_path, paper_results):
    hops, runs = paper_results
    t = claims.claims_table(hops, runs, stability_table())
    md, csv = claims.write_claims(t, tmp_path / "out")
    text = open(md, encoding="utf-8").read()
    assert text.startswith("| claim | convention | paper | ours | verdict |")
    assert text.count("\n| ") >= len(t) and "Verdict rules:" in text
    back = pd.read_csv(csv)
    assert list(back["claim_id"]) == list(t["claim_id"]) and list(back["verdict"]) == list(t["verdict"])
    assert not [p for p in (tmp_path / "out").iterdir() if p.name.startswith(".tmp-")]


def test_bad_input():
    with pytest.raises(ValueError, match="convention"):
        claims.claims_table(None, conventions=("bent",))
    with pytest.raises(ValueError, match="basis"):
        claims.claims_table(None, basis="cycles")
    two = pd.concat([stability_table(), stability_table().assign(profile="paper")])
    with pytest.raises(ValueError, match="profile"):
        claims.claims_table(None, None, two)


def test_claim_numbers_are_the_papers():
    # typed from the paper's claims (docs/reference-hopper.md, "The paper's claims"):
    # ramp vs MD "rho-inc -82 % tracking at +123 % power; SS -72 % at +193 %";
    # headline "about -35 % tracking error, -23 % power"; SS "by at least 55 %"
    paper = {c.claim_id: c.paper for c in claims.CLAIMS}
    assert (paper["ramp_rho_inc_tracking"], paper["ramp_rho_inc_power"]) == ("-82 %", "+123 %")
    assert (paper["ramp_ss_tracking"], paper["ramp_ss_power"]) == ("-72 %", "+193 %")
    assert (paper["headline_tracking"], paper["headline_power"]) == ("-35 %", "-23 %")
    assert paper["tracking_ss_55"] == "<= -55 % on every behaviour"
    assert paper["timestep_materials"] == "PVC 1e-3 s, Al 1e-4 s, SS 1e-4 s"


def test_smallest_reachable_p_by_hand():
    # n = 6 against 6: the most extreme ranking has probability 1 / C(12, 6) = 1 / 924 each way
    assert claims.smallest_p(6) == pytest.approx(2 / 924)
    assert claims.smallest_p(6, 16) == pytest.approx(0.0346, abs=1e-4)
    assert claims.smallest_p(3, 4) == pytest.approx(0.4)  # 4 x 2 / 20: the quick profile cannot reach 0.05
    assert math.isnan(claims.smallest_p(0))


def test_timestep_check_names_the_runs_that_move():
    base = pd.DataFrame(
        {
            "design": ["MD", "MD", "SS", "SS"],
            "behaviour": ["ramp"] * 4,
            "replicate": [-1] * 4,
            "tracking_error_m": [0.02, 0.02, 0.01, 0.01],
            "power_w": [1.0] * 4,
        }
    )
    fine = base.assign(tracking_error_m=[0.05, 0.05, 0.0105, 0.0105])  # MD +150 %, SS +5 %
    text = claims.timestep_check("ramp_ss_tracking", base, fine, "2e-5 s")
    assert text.startswith("moves > 10 % at 2e-5 s") and "MD ramp tracking_error_m +150 %" in text
    assert "SS" not in text
    assert claims.timestep_check("ramp_ss_power", base, fine, "2e-5 s").startswith("converged")
    assert claims.timestep_check("ramp_ss_power", base, None, "2e-5 s") == "not checked"


def test_one_sensor_timing_per_table():
    hops = pd.DataFrame({"design": ["MD", "SS"], "behaviour": ["forward"] * 2, "sensor_timing": ["authors", "fresh"]})
    with pytest.raises(ValueError, match="sensor timings"):
        claims.claims_table(hops)


def test_paired_verdicts_need_a_reachable_sign_flip_threshold():
    # 3 shared seeds: an exact sign-flip test reaches p >= 0.25, x 16 for Holm: no verdict, however large t is
    hops, runs = results(n=6, replicates=3)
    row = claims.claims_table(hops, runs, conventions=("paper",)).set_index("claim_id").loc["tracking_all_beat_md"]
    assert row["verdict"] == claims.NOT_TESTABLE and "sign-flip" in row["ours"] and "n = 3" in row["ours"]


def test_percent_claims_details_say_not_enough_evidence_where_no_verdict_is_reachable():
    # SS 55 % lower than MD on every behaviour: a family of 4 at 3 seeds (p >= 0.25 x 4):
    # however clear the t test, no comparison of the family may read "difference"
    hops, runs = results(n=6, replicates=3)
    row = claims.claims_table(hops, runs, conventions=("paper",)).set_index("claim_id").loc["tracking_ss_55"]
    assert "difference" not in row["detail"].replace("no difference", "")
    # with 10 seeds the same family is testable (2 / 2^10 x 4 = 0.008)
    hops, runs = results(n=6, replicates=10)
    row = claims.claims_table(hops, runs, conventions=("paper",)).set_index("claim_id").loc["tracking_ss_55"]
    assert "paired, n = 10: difference" in row["detail"]


def test_conventions_and_basis_any_case():
    s = stability_table()
    mixed = claims.claims_table(None, None, s, conventions=("Paper",), basis="AUTO")
    plain = claims.claims_table(None, None, s, conventions=("paper",), basis="auto")
    pd.testing.assert_frame_equal(mixed, plain)
    assert set(mixed["convention"]) == {"paper"}
    with pytest.raises(ValueError, match="unknown stiffness convention 'radial'"):
        claims.claims_table(None, None, s, conventions=("radial",))


def test_a_ratio_to_mds_zero_tracking_in_place_is_undefined_not_judged():
    """Unperturbed, MD hops in place with a tracking error of round-off
    (2.5e-17 m): SS's percent change against it has no value, so static is
    named undefined with why and the verdict comes from the other three."""
    hops, runs = results(n=20)
    static = hops["behaviour"] == "static"
    hops.loc[static & (hops["design"] == "MD"), "tracking_error_m"] = 2.5e-17
    hops.loc[static & (hops["design"] == "SS"), "tracking_error_m"] = 1.0e-17
    row = claims.claims_table(hops, runs, conventions=("paper",)).set_index("claim_id").loc["tracking_ss_55"]
    assert row["ours"].startswith("static undefined (MD tracks exactly in place")
    assert "nan" not in row["ours"] and "static: undefined: MD tracks exactly in place" in row["detail"]
    assert row["verdict"] == claims.PARTLY  # forward, ramp and circle hold; static cannot
