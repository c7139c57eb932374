"""compare_design: a design against baselines and its controls, paired on
shared seeds, at one time step, through the cached runner."""

import math

import numpy as np
import pandas as pd
import pytest

from mat_hopper.analysis.paired import DIFFERENCE, reachable
from mat_hopper.core.materials import LegDesign
from mat_hopper.core.sim import sim_settings
from mat_hopper.experiments.compare import (
    COMPARE_METRICS,
    compare_design,
    min_replicates,
    paired_table,
    plan_compare,
    untestable,
)
from mat_hopper.experiments.profiles import Profile

TINY = Profile("tiny", 2.0, 1.0, replicates=3, stability_grid_size=2, substep_studies=False)


@pytest.fixture(scope="module")
def cache(tmp_path_factory):
    return tmp_path_factory.mktemp("compare-cache")


@pytest.fixture(scope="module")
def table(cache):
    return compare_design(
        "rho-inc", baselines="SS", controls=("mass",), profile=TINY, timestep_s="auto", cache_dir=cache, workers=1
    )


def test_one_row_per_comparator_with_paired_columns(table, cache):
    assert table["comparator"].tolist() == ["SS", "rho-inc~mass"]
    assert table["role"].tolist() == ["baseline", "control"]
    assert (table["n_pairs"] == 3).all() and (table["seeds"] == "0 1 2").all()
    for m in COMPARE_METRICS:
        for c in ("pct_change", "ci_low", "ci_high", "p", "p_holm", "verdict", "mean", "mean_comparator"):
            assert f"{m}_{c}" in table.columns
        assert (table[f"{m}_ci_low"] <= table[f"{m}_pct_change"]).all()
        assert (table[f"{m}_pct_change"] <= table[f"{m}_ci_high"]).all()
        assert (table[f"{m}_p_holm"] >= table[f"{m}_p"]).all()
        # 3 seeds, a family of 2: no difference can be significant, and the verdict says so
        assert not (table[f"{m}_verdict"] == DIFFERENCE).any()
        assert not (table[f"{m}_verdict"] == "not enough evidence").any()
    assert "untestable with n = 3 seeds; use --replicates 7 or more" in set(table["power_w_verdict"])
    assert table.attrs["left_out"] == [] and table.attrs["n_computed"] == 6 + 3
    again = compare_design(
        "rho-inc", baselines="SS", controls=("mass",), profile=TINY, timestep_s="auto", cache_dir=cache, workers=1
    )
    assert again.attrs["n_computed"] == 0 and again.attrs["n_cached"] == 9  # the second call loads every run
    pd.testing.assert_frame_equal(again, table)


def test_one_time_step_for_every_leg_under_auto(table):
    """rho-inc's automatic step (5e-5 s, 2 substeps) is finer than MD's
    (1e-4 s) and its rigid twin's: every leg runs at rho-inc's."""
    own = {d: sim_settings(d, duration_s=2.0, transient_s=1.0, timestep_s="auto").timestep_s for d in ("rho-inc", "MD")}
    assert own["rho-inc"] < own["MD"]
    plan = plan_compare("rho-inc", baselines="MD", controls="rigid", profile=TINY, timestep_s="auto")
    assert plan.finest == "rho-inc" and plan.timestep_s == own["rho-inc"] and plan.substeps == 2
    assert {t.design.name for t in plan.tasks} == {"rho-inc", "MD", "rho-inc~rigid"}
    for t in plan.tasks:
        seed = t.labels["replicate"]
        assert t.settings == plan.settings[seed]  # the same settings (step, seed's perturbation) for every leg
    assert plan.settings[0].perturbation != plan.settings[1].perturbation
    assert (table["timestep_s"] == own["rho-inc"]).all() and table.attrs["timestep_s"] == own["rho-inc"]


def test_a_diverged_comparator_is_left_out_and_named(cache):
    """Ti's axial springs diverge at 1e-4 s: no row for Ti, named with why;
    MD (rigid) is compared."""
    rigid_steel = LegDesign.from_properties([8.0] * 3, [None] * 3)
    out = compare_design(
        rigid_steel,
        baselines=("MD", "Ti"),
        controls=(),
        profile=TINY,
        timestep_s=1e-4,
        convention="axial",
        cache_dir=cache,
        workers=1,
    )
    assert out["comparator"].tolist() == ["MD"]
    (ti,) = out.attrs["left_out"]
    assert ti["leg"] == "Ti" and ti["role"] == "baseline" and ti["seeds"] == [0, 1, 2]
    assert "unstable at dt=1e-4 s" in ti["why"] and ti["all"]


def test_identical_and_unbuildable_comparators_are_named_not_run():
    plan = plan_compare("SS", baselines="MD,SS", controls="rigid,mass", profile=TINY)
    assert [c.name for c in plan.comparators] == ["MD", "SS~rigid"]
    named = {e["leg"]: e["why"] for e in plan.left_out}
    assert set(named) == {"SS", "SS~mass"} and all("same leg as the design" in w for w in named.values())
    assert {t.design.name for t in plan.tasks} == {"SS", "MD", "SS~rigid"}


def test_nothing_left_to_compare_is_refused_before_any_run():
    """Every comparator the design itself: known before any run, so a refusal
    naming why, not runs of the design alone and "nothing to compare"."""
    with pytest.raises(ValueError, match="nothing to compare.*rho-inc: the same leg as the design"):
        plan_compare("rho-inc", baselines="rho-inc", controls="none", profile=TINY)
    with pytest.raises(ValueError, match="nothing to compare.*MD~rigid: the same leg"):
        plan_compare("MD", baselines="none", controls="rigid", profile=TINY)


@pytest.mark.parametrize(
    "kw, match",
    [
        ({"baselines": "kryptonite"}, "baselines: unknown material 'kryptonite'"),
        ({"baselines": "SS,ss"}, "baselines: 'SS' and 'ss' name the same design"),
        ({"baselines": "SS,,Ti"}, "baselines must be comma-separated names"),
        ({"controls": "rigid,twin"}, "controls: unknown control 'twin'"),
        ({"controls": "mass,Mass"}, "controls: 'mass' is named twice"),
        ({"baselines": "none", "controls": ()}, "at least one comparator"),
        ({"replicates": 1}, "replicates must be an integer >= 2"),
        ({"replicates": 3.0}, "replicates must be an integer >= 2"),
        ({"behaviour": "moonwalk"}, "unknown behaviour"),
    ],
)
def test_bad_arguments_are_named_before_any_run(kw, match):
    with pytest.raises(ValueError, match=match):
        plan_compare("rho-inc", profile=TINY, **kw)


def test_untestable_verdict_names_the_replicates_needed():
    assert untestable(2, 1) == "untestable with n = 2 seeds; use --replicates 6 or more"
    for m in (1, 2, 5, 16):
        k = min_replicates(m)
        assert reachable(k, m) and not reachable(k - 1, m)


def _summary(plan, effect: float, spread: float) -> pd.DataFrame:
    """A run summary for `plan` (no simulation): the design's run means
    `effect` x the comparators', with a seeded spread per run."""
    rng = np.random.default_rng(0)
    rows = []
    for t in plan.tasks:
        seed = t.labels["replicate"]
        scale = (effect if t.labels["role"] == "design" else 1.0) * math.exp(rng.normal(0.0, spread))
        rows.append({**t.labels, "status": "ok", "stable": True, "upright": True, "key": t.key(), "error": ""})
        rows[-1].update({f"mean_{m}": scale * (1.0 + 0.01 * seed) for m in COMPARE_METRICS})
    return pd.DataFrame(rows)


def test_two_seeds_say_untestable_and_enough_seeds_find_the_difference():
    """The quick profile's 2 seeds cannot make a difference significant (the
    exact sign-flip p is at least 0.5): the verdict says so plainly; with 8
    seeds a consistent +30 % is a difference."""
    two = plan_compare("rho-inc", baselines="SS", controls="mass", profile=TINY, replicates=2)
    out = paired_table(_summary(two, 1.3, 0.02), two)
    assert (out["power_w_verdict"] == "untestable with n = 2 seeds; use --replicates 7 or more").all()
    eight = plan_compare("rho-inc", baselines="SS", controls="mass", profile=TINY, replicates=8)
    out = paired_table(_summary(eight, 1.3, 0.02), eight)
    assert (out["power_w_verdict"] == DIFFERENCE).all()
    assert out["power_w_pct_change"].to_numpy() == pytest.approx([30.0, 30.0], abs=5.0)


def test_a_diverged_seed_of_the_design_drops_from_every_pair():
    plan = plan_compare("rho-inc", baselines="SS", controls="mass", profile=TINY, replicates=4)
    summary = _summary(plan, 1.3, 0.02)
    bad = (summary["role"] == "design") & (summary["replicate"] == 1)
    summary.loc[bad, ["status", "stable", "upright"]] = ["diverged", False, False]
    out = paired_table(summary, plan)
    assert (out["n_pairs"] == 3).all() and (out["seeds"] == "0 2 3").all()
    (left,) = out.attrs["left_out"]
    assert left["leg"] == "rho-inc" and left["role"] == "design" and left["seeds"] == [1] and not left["all"]


def test_a_shortened_run_draws_its_push_from_its_own_window():
    """`--duration 6 --transient 1` on the paper profile: the push falls in
    this run's scored window (1.5-3.5 s), not in the profile's (24-40 s),
    where it would never act; and the runs take the profile's protocol."""
    from dataclasses import replace

    from mat_hopper.core.perturbations import push_window_s
    from mat_hopper.experiments.profiles import get_profile

    paper = get_profile("paper")
    plan = plan_compare(
        "rho-inc", baselines="SS", controls="none", profile=paper, replicates=2, duration_s=6.0, transient_s=1.0
    )
    for s in plan.settings:
        assert s.perturbation.push_window_s == push_window_s(1.0, 6.0) == (1.5, 3.5)
        assert s.replicate_protocol == paper.replicate_protocol
    settled = replace(paper, replicate_protocol="branch-settled")
    plan = plan_compare(
        "rho-inc", baselines="SS", controls="none", profile=settled, replicates=2, duration_s=6.0, transient_s=1.0
    )
    assert {s.replicate_protocol for s in plan.settings} == {"branch-settled"}
