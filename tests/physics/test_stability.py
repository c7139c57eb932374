"""Stable time step: the analytic spring-chain limit, the bisection against
it, the spec scan's consistency check, the map's agreement summary."""

import math

import numpy as np
import pandas as pd
import pytest

from mat_hopper.core import reference as ref
from mat_hopper.core.materials import LegDesign, parse_design, spring_stiffness
from mat_hopper.core.model import build_model
from mat_hopper.physics.stability import (
    StabilitySpec,
    agreement,
    controller_timestep,
    delayed_damping_factor,
    estimate_timestep,
    largest_stable_timestep,
    leg_chain,
    scan_consistent,
    spring_chain_wmax,
    try_timestep,
)


def test_spring_chain_matches_closed_forms():
    m1, m2, k = 3.0, 0.5, 1e6
    assert spring_chain_wmax([m1, m2], [k]) == pytest.approx(math.sqrt(k * (1 / m1 + 1 / m2)), rel=1e-12)
    # three equal masses, two equal springs (free-free): w^2 in {0, k/m, 3k/m}
    assert spring_chain_wmax([2.0] * 3, [k, k]) == pytest.approx(math.sqrt(3 * k / 2.0), rel=1e-12)
    with pytest.raises(ValueError, match="springs"):
        spring_chain_wmax([1.0, 2.0], [1.0, 2.0])
    with pytest.raises(ValueError, match="> 0"):
        spring_chain_wmax([1.0, 0.0], [1.0])


def test_leg_chain_lumps_the_model_bodies():
    ss = parse_design("SS")
    masses, springs = leg_chain(ss)
    assert len(masses) == 5 and len(springs) == 4
    assert sum(masses) == pytest.approx(build_model(ss).total_mass_kg, rel=1e-9)
    assert springs[:3] == [pytest.approx(spring_stiffness(193.0))] * 3
    assert springs[-1] == ref.FOOT_SPRING_STIFFNESS and masses[-1] == pytest.approx(ref.FOOT_MASS)
    md_masses, md_springs = leg_chain(parse_design("MD"))  # rigid: one body down to the foot spring
    assert md_springs == [ref.FOOT_SPRING_STIFFNESS] and len(md_masses) == 2
    # heavier legs allow larger steps, stiffer legs need smaller ones
    light = estimate_timestep(LegDesign.from_properties([1.4] * 3, [100.0] * 3))[1]
    heavy = estimate_timestep(LegDesign.from_properties([8.0] * 3, [100.0] * 3))[1]
    stiff = estimate_timestep(LegDesign.from_properties([1.4] * 3, [300.0] * 3))[1]
    assert stiff < light < heavy


def test_bisection_brackets_the_analytic_limit_of_a_stiff_one_segment_leg():
    """A 1-segment leg with a very stiff spring: the material spring sets
    the limit, 2 / w_max, and the measured bracket must sit around it."""
    leg = LegDesign.from_properties([2.0], [300.0])
    w, est = estimate_timestep(leg)
    m, k = leg_chain(leg)
    assert len(m) == 3 and k[0] == pytest.approx(spring_stiffness(300.0))
    assert w == pytest.approx(math.sqrt(k[0] * (1 / m[0] + 1 / m[1])), rel=0.01)  # the stiff pair dominates
    tries = []
    lo, hi = largest_stable_timestep(leg, tolerance=1.5, duration_s=1.0, tries=tries)
    assert lo < hi <= lo * 1.5
    assert est / 2.5 < lo and hi < est * 2.5
    start = min(est, controller_timestep(leg))
    assert [t["method"] for t in tries][0] == "bracket" and tries[0]["dt_s"] == pytest.approx(start)
    assert all(t["upright"] == (t["dt_s"] <= lo) for t in tries)  # monotone here
    assert not try_timestep(leg, hi * 1.5, duration_s=1.0)["upright"]


def test_bisection_edges_and_bad_input():
    md = parse_design("MD")  # no material springs: 1e-2 s is already stable over 0.5 s (falling)
    lo, hi = largest_stable_timestep(md, duration_s=0.5, bracket="ladder")
    assert lo == 1e-2 and math.isnan(hi)
    lo, hi = largest_stable_timestep(md, duration_s=0.5, dt_max=1e-3)  # analytic: stops at dt_max
    assert lo == 1e-3 or lo < hi <= 1e-3
    with pytest.raises(ValueError, match="dt_min"):
        largest_stable_timestep(md, dt_min=1e-2, dt_max=1e-3)
    with pytest.raises(ValueError, match="tolerance"):
        largest_stable_timestep(md, tolerance=1.0)
    with pytest.raises(ValueError, match="duration"):
        StabilitySpec(md, duration_s=0.0)


def test_scan_consistency_rule():
    ladder = np.geomspace(1e-3, 1e-5, 20)
    assert scan_consistent(2e-4, 2.4e-4, float(ladder[ladder <= 2e-4][0]))
    assert not scan_consistent(2e-4, 2.4e-4, 3e-4)  # a stable step above the unstable one
    assert not scan_consistent(2e-4, 2.4e-4, float(ladder[ladder <= 2e-4][2]))  # passed over stable steps
    assert scan_consistent(5e-3, math.nan, 1e-3)  # above the ladder: its first step
    assert scan_consistent(5e-6, 6e-6, math.nan) and not scan_consistent(5e-5, 6e-5, math.nan)
    assert scan_consistent(math.nan, 1e-6, math.nan)


def test_stability_task_summary_and_agreement():
    task = StabilitySpec(LegDesign.from_properties([8.0], [300.0]), duration_s=0.5, tolerance=1.5, scan=False)
    tries, s = task.compute()
    assert s["status"] == "ok" and len(tries) == s["n_tries"] and math.isnan(s["spec_timestep_s"])
    assert s["max_stable_timestep_s"] <= s["analytic_timestep_s"] * 2
    assert s["ratio_measured_to_analytic"] == pytest.approx(s["max_stable_timestep_s"] / s["analytic_timestep_s"])
    assert task.key() != StabilitySpec(task.design, duration_s=0.5, tolerance=1.25, scan=False).key()
    assert s["combined_timestep_s"] == min(s["analytic_timestep_s"], s["controller_timestep_s"])
    table = pd.DataFrame(
        {
            "max_stable_timestep_s": [1e-4, 2e-4, 4e-4, np.nan],
            "unstable_timestep_s": [1.2e-4, 2.4e-4, 5e-4, 1e-6],
            "analytic_timestep_s": [1.1e-4, 2.2e-4, 4.4e-4, 1e-4],
            "combined_timestep_s": [1.1e-4, 2.2e-4, 3e-4, 1e-4],
            "scan_consistent": [True, True, False, True],
        }
    )
    ag = agreement(table)
    a = {(e, q): v for e, q, v in ag[["estimate", "quantity", "value"]].itertuples(index=False)}
    assert a["spring", "n_designs"] == 4 and a["spring", "n_measured"] == 3
    assert a["spring", "loglog_pearson_r"] == pytest.approx(1.0) and a["spring", "loglog_slope"] == pytest.approx(1.0)
    assert a["spring", "median_ratio_measured_to_estimate"] == pytest.approx(1 / 1.1)
    assert a["spring", "fraction_estimate_in_bracket"] == 1.0
    assert a["combined", "fraction_estimate_in_bracket"] == pytest.approx(2 / 3)
    assert a["spec scan", "fraction_scan_consistent"] == 0.75


@pytest.mark.parametrize("latency, factor", [(0, 2.0), (1, 1.0), (2, 2 * math.cos(2 * math.pi / 5))])
def test_delayed_damping_factor_by_hand(latency, factor):
    """Roots of z^(L+1) - z^L + q = 0 on the unit circle (Levin & May 1976):
    L = 0 -> q < 2, L = 1 -> q < 1, L = 2 -> q < 2 cos(2 pi / 5) = 0.618."""
    assert delayed_damping_factor(latency) == pytest.approx(factor)
    q = factor * 0.999  # just inside: every root of the characteristic polynomial inside the unit circle
    assert np.abs(np.roots([1, -1] + [0] * (latency - 1) + [q] if latency else [1, -1 + q])).max() < 1
    q = factor * 1.001
    assert np.abs(np.roots([1, -1] + [0] * (latency - 1) + [q] if latency else [1, -1 + q])).max() > 1


def test_controller_limit_is_the_base_inertia_over_the_stance_rate_gain():
    """I / (K_d gear) under the authors' one-step-old gyro, 2 I / (K_d gear)
    when fresh; material-independent: the plateau of soft, heavy legs."""
    ss, soft = parse_design("SS"), LegDesign.from_properties([20.0] * 3, [4.0] * 3)
    limit = controller_timestep(ss)
    assert limit == pytest.approx(controller_timestep(soft))
    m = build_model(ss).model
    inertia = min(m.body_inertia[m.body("base").id])  # MuJoCo's own: the base's COM is at the hip
    assert limit == pytest.approx(inertia / (ref.STANCE_KD * ref.HIP_GEAR))
    assert controller_timestep(ss, sensor_timing="fresh") == pytest.approx(2 * limit)
    assert estimate_timestep(soft)[1] > 1.5 * limit  # the spring limit lies above: this one binds
    assert try_timestep(soft, 0.8 * limit, duration_s=1.0)["upright"]
    assert not try_timestep(soft, 1.5 * limit, duration_s=1.0)["upright"]


def test_analytic_bracket_agrees_with_the_ladder_in_fewer_tries():
    for design in (parse_design("PVC"), parse_design("SS")):
        a_tries, l_tries = [], []
        a = largest_stable_timestep(design, bracket="analytic", tries=a_tries)
        b = largest_stable_timestep(design, bracket="ladder", tries=l_tries)
        assert a[0] < a[1] and b[0] < b[1]
        assert a[0] < b[1] and b[0] < a[1]  # the two brackets overlap
        assert len(a_tries) < len(l_tries)
    with pytest.raises(ValueError, match="bracket"):
        largest_stable_timestep(parse_design("SS"), bracket="guess")


def test_stability_spec_names_any_case_share_the_key():
    d = LegDesign.from_properties([8.0], [300.0])
    mixed = StabilitySpec(d, duration_s=0.5, scan=False, bracket="Ladder", convention="Axial")
    plain = StabilitySpec(d, duration_s=0.5, scan=False, bracket="ladder", convention="axial")
    assert (mixed.bracket, mixed.convention) == ("ladder", "axial")
    assert mixed.key_dict()["bracket_factor"] == math.sqrt(10.0)
    assert mixed.key() == plain.key()
    with pytest.raises(ValueError, match="unknown bracket 'binary'; accepted: analytic, ladder"):
        StabilitySpec(d, bracket="binary")


@pytest.mark.parametrize(
    "density_g_cm3, modulus_gpa", [(1.4, 4.0), (8.0, 340.0), (1.4, 340.0), (8.0, 4.0), (3.5, 41.5)]
)
def test_estimated_steps_bound_the_steps_a_search_runs(density_g_cm3, modulus_gpa):
    """The plan's count of a stable-step search (the map's corners and
    middle, the paper profile's 2 s tries and scan) is at least the steps
    MuJoCo actually ran (each try to its end or its divergence), and not
    looser than 20 times."""
    leg = LegDesign.from_properties([density_g_cm3] * 3, [modulus_gpa] * 3)
    spec = StabilitySpec(leg, duration_s=2.0, tolerance=1.25, max_iter=10, scan=True)
    tries, _ = spec.compute()
    ran = sum((2.0 if math.isnan(t.diverged_at_s) else t.diverged_at_s) / t.dt_s for t in tries.itertuples())
    assert ran <= spec.estimated_steps() <= 20 * ran
