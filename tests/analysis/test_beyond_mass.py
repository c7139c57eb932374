"""Beyond-mass verdicts and the attribution, on synthetic control runs."""

import numpy as np
import pandas as pd
import pytest

from mat_hopper.analysis import beyond_mass as bm
from mat_hopper.analysis.claims import claims_table


def _hops(rho_springs=1.0, rho_vs_mass=1.0, ss_vs_twin=1.0, n=6, rho_vs_ss=0.8):
    """Run means of SS, rho-inc, their controls and MD on shared seeds (tracking error, ramp).

    rho_springs: rho-inc against its rigid twin; ss_vs_twin: SS against its
    rigid twin; rho_vs_mass: rho-inc against its mass-matched leg."""
    rng = np.random.default_rng(0)
    seed = np.exp(rng.normal(0, 0.2, n))
    ss, rho = 0.5, 0.5 * rho_vs_ss
    legs = {  # design: (control_of, control, factor on tracking error, leg mass, com)
        "MD": ("MD", "none", 1.0, 1.9, 0.27),
        "SS": ("SS", "none", ss, 8.77, 0.215),
        "SS~rigid": ("SS", "rigid", ss / ss_vs_twin, 8.77, 0.215),
        "SS~mass": ("SS", "mass", ss, 8.77, 0.215),
        "rho-inc": ("rho-inc", "none", rho, 5.44, 0.264),
        "rho-inc~rigid": ("rho-inc", "rigid", rho / rho_springs, 5.44, 0.264),
        "rho-inc~mass": ("rho-inc", "mass", rho / rho_vs_mass, 5.44, 0.225),
        "rho-inc~inertia": ("rho-inc", "inertia", rho, 5.44, 0.264),
    }
    rows = []
    for name, (of, kind, f, m, com) in legs.items():
        for rep in range(n):
            v = 0.05 * f * seed[rep] * np.exp(rng.normal(0, 0.01))
            rows.append(
                {
                    "design": name,
                    "behaviour": "ramp",
                    "replicate": rep,
                    "control_of": of,
                    "control": kind,
                    "tracking_error_m": v,
                    "leg_mass_kg": m,
                    "leg_com_m": com,
                    "hip_inertia_kg_m2": 0.4,
                    "hop": 0,
                }
            )
    return pd.DataFrame(rows)


def test_an_elastic_baseline_is_judged_by_the_difference_in_differences_and_the_mass_matched_leg():
    # rho-inc's springs lower its error by 10 % against its twin, SS's do nothing, and
    # rho-inc beats a homogeneous leg of its own mass by 10 %: beyond mass on both (n = 8:
    # an exact sign-flip test reaches Holm's threshold in a family of 2)
    out = bm.claim_controls("headline_tracking", _hops(rho_springs=0.9, rho_vs_mass=0.9, n=8), None)
    assert out["beyond_mass"] == "yes (2 yes)"
    assert out["vs_mass_matched"].startswith("ramp rho-inc -") and "(difference" in out["vs_mass_matched"]
    f = bm.comparison_frame(_hops(rho_springs=0.9, n=8), "headline_tracking").set_index("comparison")
    assert f.loc["springs vs both rigid twins", "share"] == pytest.approx(np.log(0.9) / np.log(0.8), abs=0.03)
    assert f.loc["mass-matched", "pct_change"] == pytest.approx(0.0, abs=1.0)
    # the case: a homogeneous leg of rho-inc's mass beats rho-inc (rho-inc 10 % worse)
    worse = bm.claim_controls("headline_tracking", _hops(rho_springs=0.9, rho_vs_mass=1.1, n=8), None)
    assert worse["beyond_mass"] == "partly (1 yes, 1 the other way)"
    # both legs' springs do the same and the mass-matched leg does as well: all mass
    same = bm.claim_controls("headline_tracking", _hops(rho_springs=0.9, ss_vs_twin=0.9, n=8), None)
    assert same["beyond_mass"] == "no (2 equivalent)"
    # no claim effect to attribute
    none = bm.claim_controls("headline_tracking", _hops(rho_vs_ss=1.0, n=8), None)
    assert none["beyond_mass"].startswith("untestable (the claim's own effect")


def test_a_rigid_baseline_uses_the_twin_and_the_mass_matched_leg_with_a_fraction_rule():
    out = bm.claim_controls(
        "ramp_rho_inc_tracking", _hops(rho_springs=0.8, rho_vs_mass=1.0, n=8), None
    )  # n = 8: Holm over 2 reachable
    assert out["beyond_mass"] == "partly (1 yes, 1 equivalent)"  # the twin says yes, the mass-matched leg no
    assert out["vs_mass_matched"].startswith("ramp rho-inc") and "share left" in out["vs_mass_matched"]
    # SS is homogeneous: its mass-matched leg is itself (same physics key); its twin decides
    ss = bm.claim_controls("ramp_ss_tracking", _hops(ss_vs_twin=1.0), None)
    assert ss["vs_mass_matched"].startswith("homogeneous") and ss["beyond_mass"].startswith("no")
    assert bm.claim_controls("hop_height", _hops(), None) == dict.fromkeys(bm.CONTROL_COLUMNS, "")
    assert bm.claim_controls("headline_tracking", None, None)["beyond_mass"] == bm.NOT_RUN


def test_three_seeds_can_still_show_the_controls_reproduce_the_design():
    # no comparison can be significant at n = 3, but intervals inside the ±10 % margin
    # say the controls reproduce the design: evidence against "beyond mass", not a lack of it
    out = bm.claim_controls("headline_tracking", _hops(rho_springs=1.0, rho_vs_mass=1.0, n=3), None)
    assert out["beyond_mass"].startswith("no (every one of 2 comparisons within the ±10 % margin")


def test_too_few_seeds_cannot_reach_a_verdict():
    out = bm.claim_controls("headline_tracking", _hops(rho_springs=0.5, n=3), None)
    assert out["beyond_mass"].startswith("untestable (n = 3") and "0.5" in out["beyond_mass"]  # 2 x 0.25
    # six seeds reach p = 2/64 = 0.031, over Holm's 0.025 for the two comparisons
    assert bm.claim_controls("headline_tracking", _hops(rho_springs=0.5, n=6), None)["beyond_mass"].startswith(
        "untestable (n = 6"
    )


def test_a_small_claimed_effect_reproduced_by_its_controls_is_not_a_no():
    # at n = 3 with the controls inside the margin, "no" needs a claimed effect
    # larger than the margin (here rho-inc is 5 % better than SS: nothing to attribute)
    out = bm.claim_controls("headline_tracking", _hops(rho_vs_ss=0.95, n=3), None)
    assert out["beyond_mass"].startswith("untestable (n = 3")


def test_one_yes_where_the_claim_mostly_fails_is_not_yes():
    """A referee's case: the claim's own effect holds in one behaviour of
    four, and there beyond mass. The comparisons where it holds all say yes,
    but they are 2 of 8: too little effect to attribute, not a survivor."""
    parts = []
    for beh in ("static", "forward", "ramp", "circle"):
        h = _hops(rho_springs=0.8, rho_vs_mass=0.8, n=10, rho_vs_ss=0.7 if beh == "ramp" else 1.0)
        parts.append(h.assign(behaviour=beh))
    hops = pd.concat(parts, ignore_index=True).rename(columns={"tracking_error_m": "jerk_body_m_s3"})
    verdict = bm.claim_controls("jerk_gradient", hops, None)["beyond_mass"]
    body = verdict.split(" | ")[0]
    assert body.startswith("body, zero-phase: untestable (the claim's own effect holds in only 2 of its 8"), body
    assert "2 yes" in body and "6 no own effect" in body


def test_power_claims_get_one_verdict_per_formula():
    h = _hops()
    h["power_w"] = h["power_total_w"] = h["tracking_error_m"]
    out = bm.claim_controls("headline_power", h, None)
    assert out["beyond_mass"].startswith("paper formula: not run | hip: ") and "| total: " in out["beyond_mass"]


def test_share_left_has_fiellers_interval():
    x, y = np.array([0.1, 0.12, 0.08, 0.11]), np.array([0.2, 0.22, 0.19, 0.21])
    s = bm.share_left(x, y)
    assert s["share"] == pytest.approx(x.mean() / y.mean())
    assert s["share_low"] < s["share"] < s["share_high"]
    assert np.isnan(bm.share_left(x, np.array([0.1, -0.1, 0.05, -0.05]))["share_low"])  # no claim effect: unbounded


def test_claims_table_carries_the_beyond_mass_columns():
    t = claims_table(None, conventions=("paper",))
    assert set(bm.CONTROL_COLUMNS) <= set(t.columns) and "power_verdicts" in t.columns
    row = t.set_index("claim_id").loc["headline_tracking"]
    assert row["beyond_mass"] == bm.NOT_RUN and row["vs_rigid_twin"] == "not run"


def test_unusable_control_runs_are_dropped():
    h = _hops(rho_springs=0.9)
    h["experiment"], h["profile"], h["convention"] = "controls", "quick", "paper"
    t = claims_table(None, conventions=("paper",))
    bad = pd.DataFrame({"design": ["rho-inc"] * 6, "behaviour": "ramp", "replicate": range(6), "why": "fell over"})
    for c in ("experiment", "profile", "convention"):
        bad[c] = h[c].iloc[0]
    out = bm.beyond_mass_columns(t, h, bad=bad).set_index("claim_id").loc["headline_tracking"]
    assert out["beyond_mass"] == bm.NOT_RUN  # every rho-inc run dropped: nothing left to compare


def test_headline_sentence_names_masses_and_controls():
    s = bm.headline_sentence(_hops(rho_vs_mass=0.75, rho_springs=0.9))
    assert "5.44 kg" in s and "8.77 kg" in s and "its rigid twin" in s and "n = 6" in s and "beyond SS's springs" in s


def _sweeps(slope, n=6):
    """Experiment 2's modulus sweeps of two base materials at fixed density:
    tracking error ~ E^slope, replicate seeds shared."""
    rng = np.random.default_rng(1)
    rows = []
    for base, rho in (("PVC", 1.39), ("SS", 8.0)):
        for e in (1.0, 10.0, 100.0):
            for rep in range(n):
                v = 0.05 * e**slope * np.exp(rng.normal(0, 0.01))
                rows.append(
                    {"experiment": "exp2", "sweep_base": base, "sweep_property": "modulus", "density_g_cm3": rho,
                     "modulus_gpa": e, "replicate": rep, "behaviour": "forward", "tracking_error_m": v}
                )  # fmt: skip
    return pd.DataFrame(rows)


def test_the_low_modulus_claim_is_read_at_equal_mass():
    yes = bm.sweep_controls("low_modulus_tracks_worse", _sweeps(-0.1))
    assert yes["beyond_mass"].startswith("yes (2/2") and "PVC (equal mass): error ~ E^-0.10" in yes["vs_mass_matched"]
    flat = bm.sweep_controls("low_modulus_tracks_worse", _sweeps(0.0))
    assert flat["beyond_mass"].startswith("no (0/2")
    assert bm.sweep_controls("low_modulus_tracks_worse", None)["beyond_mass"] == bm.NOT_RUN
    assert bm.sweep_controls("density_over_modulus", _sweeps(-0.1))["beyond_mass"].startswith("n/a")


def test_claims_rows_carry_their_designs_mass_properties():
    # SS's leg: 8.77 kg by tests/core/test_control_legs.py's hand calculation (stub, six
    # half-segment capsules of radius 0.025 m at 8 g/cm^3, the foot's two capsules)
    text = bm.mass_property_text("headline_tracking")
    assert text.startswith("rho-inc ") and "; SS 8.77 kg" in text
    assert bm.mass_property_text("hop_height") == ""
    t = claims_table(None, conventions=("paper",)).set_index("claim_id")
    assert t.loc["headline_tracking", "mass_properties"] == text


def test_headline_sentence_gives_the_seeds_of_a_control_run_on_fewer():
    """The inertia-matched leg runs the figure seeds (3): its interval says so."""
    h = _hops(rho_vs_mass=0.75, rho_springs=0.9)
    h = h[(h["control"] != "inertia") | (h["replicate"] < 3)]
    s = bm.headline_sentence(h)
    assert "a leg of its mass and hip inertia" in s and "] (n = 3)" in s and "n = 6 paired seeds" in s
    assert "(n = " not in bm.headline_sentence(_hops(rho_vs_mass=0.75, rho_springs=0.9))
