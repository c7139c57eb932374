"""The book's extra checks (mat_hopper.experiments.paper) and whole rollouts
through the runner's one cache (mat_hopper.experiments.runner.rollouts)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pandas as pd
import pytest

from mat_hopper import simulate
from mat_hopper.analysis import stats
from mat_hopper.analysis import tables as tab
from mat_hopper.core import reference as ref
from mat_hopper.experiments import paper, runner
from mat_hopper.experiments.profiles import Profile
from mat_hopper.viz import chapters

TINY = Profile("tiny", 0.6, 0.1, 1e-4, 1, 0.3, stability_tolerance=2.0, stability_max_iter=3)


def test_convention_stability_measures_both_conventions(tmp_path):
    t = paper.convention_stability(("MD", "SS"), TINY, cache_dir=tmp_path, workers=1)
    assert len(t) == 4 and set(t["convention"]) == {"paper", "axial"}
    ss = t[t["design"] == "SS"].set_index("convention")
    # the physical springs are about 20x stiffer: a smaller stable step
    assert ss.loc["axial", "material_spring_n_m"] > 10 * ss.loc["paper", "material_spring_n_m"]
    assert ss.loc["axial", "analytic_timestep_s"] < ss.loc["paper", "analytic_timestep_s"]
    assert ss.loc["axial", "max_stable_timestep_s"] < ss.loc["paper", "max_stable_timestep_s"]
    assert t.loc[t["design"] == "MD", "material_spring_n_m"].isna().all()
    fig = chapters.convention_figure(t)
    assert len(fig.axes) == 2
    again = paper.convention_stability(("MD", "SS"), TINY, cache_dir=tmp_path, workers=1)
    pd.testing.assert_frame_equal(t, again)


def test_rollouts_are_cached_bit_identical(tmp_path):
    rs = runner.rollouts(
        ["SS"], ["forward", "ramp"], TINY.sim_settings(), record_rate_hz=500, cache_dir=tmp_path, workers=1
    )
    assert [r.behaviour.name for r in rs] == ["forward", "ramp"]
    files = sorted(tmp_path.glob("rollout-*.parquet"))  # the runner's one cache
    assert len(files) == 2
    again = runner.rollouts(
        ["SS"], ["forward", "ramp"], TINY.sim_settings(), record_rate_hz=500, cache_dir=tmp_path, workers=1
    )
    fresh = simulate("SS", "ramp", settings=replace(TINY.sim_settings(), record_rate_hz=500.0))
    for r in (again[1], rs[1]):
        assert np.array_equal(r.data, fresh.data)
        assert np.array_equal(r.events, fresh.events, equal_nan=True)
        assert r.diverged_step == fresh.diverged_step and r.total_mass_kg == fresh.total_mass_kg
    assert rs[1].settings.record_rate_hz == 500
    fig = chapters.controller_figure(rs[0], window_s=(0.2, 0.5))
    assert len(fig.axes) == 8
    with pytest.raises(ValueError, match="window_s"):
        chapters.controller_figure(rs[0], window_s=(0.5, 0.2))
    with pytest.raises(ValueError, match="at least one"):
        runner.rollouts([], ["ramp"], TINY.sim_settings(), cache_dir=tmp_path)


def test_clock_drift_moves_the_path(tmp_path):
    t = paper.clock_drift(TINY, cache_dir=tmp_path, designs=("SS",), factors=(1.0, 2.0), workers=1)
    assert list(t["clock_factor"]) == [1.0, 2.0]
    assert np.allclose(t["speed_m_s"], [ref.SPEED_M_S, 2 * ref.SPEED_M_S])
    with pytest.raises(ValueError, match="factors"):
        paper.clock_drift(TINY, cache_dir=tmp_path, designs=("SS",), factors=(0.0,), workers=1)


def test_in_place_replicates_compare_on_run_means(tmp_path):
    prof = Profile("short", 4.0, 1.0, replicates=3)
    reps = paper.in_place_replicates(prof, cache_dir=tmp_path, workers=1)
    assert set(reps["behaviour"]) == {"static"}
    assert set(reps["design"]) == set(ref.MONO_MATERIALS)
    assert sorted(set(reps["replicate"])) == [-1, 0, 1, 2]
    # perturbed runs move sideways; the unperturbed one does not
    track = reps.groupby("replicate")["tracking_error_m"].max()
    assert track.loc[-1] < 1e-9 and (track.drop(-1) > 1e-5).all()
    t = tab.replicate_table(stats.compare_replicates(reps, "MD"))
    assert set(t["design"]) == set(ref.MONO_MATERIALS) - {"MD"}
    assert (t["n"] == 3).all() and t["change"].str.match(r"[+-]\d+ % \[").all()
    with pytest.raises(ValueError, match="replicates"):
        Profile("bad", 4.0, 1.0, replicates=-1)


def test_jerk_by_rate_subsamples(tmp_path):
    (r,) = runner.rollouts(["SS"], ["static"], TINY.sim_settings(), cache_dir=tmp_path, workers=1)
    t = tab.jerk_by_rate(r, rates_hz=(1000.0, 100.0))
    assert np.allclose(t["rate_hz"], [1000.0, 100.0])
    assert (t["mean_jerk_m_s3"] > 0).all()
    with pytest.raises(ValueError, match="record rate"):
        tab.jerk_by_rate(r, rates_hz=(5000.0,))


def test_axial_check_three_settings(tmp_path):
    hopping = Profile("hopping", 2.0, 0.3, 1e-4, 1, 0.3)  # long enough for a few scored hops
    out = paper.axial_check(hopping, cache_dir=tmp_path, designs=("MD", "SS"), timestep_s=1e-5, workers=1)
    assert out["timestep_s"] == 1e-5
    settings = set(out["runs"]["setting"])
    assert settings == {"paper, profile step", "paper, axial's steps", "axial, axial's steps"}
    small = out["runs"][out["runs"]["setting"] != "paper, profile step"]
    assert set(small["timestep_s"]) == {1e-5}
    # the rigid leg has no springs: one small-step run stands for both conventions
    md = out["runs"][out["runs"]["design"] == "MD"]
    assert len(md) == 3 and md["key"].nunique() == 2
    cmp = tab.setting_comparison(out["hops"], pairs=(("SS", "MD"),))
    assert sorted(cmp.index) == sorted(settings)
    assert list(cmp.columns) == ["tracking_error_m: SS vs MD", "power_w: SS vs MD"]
    assert np.isfinite(cmp.to_numpy()).all()
    with pytest.raises(ValueError, match="setting"):
        tab.setting_comparison(out["hops"].drop(columns="setting"))


def test_axial_check_auto_substeps(tmp_path):
    """With the profile's axial step 'auto' the stiff SS leg gets physics
    substeps of the 1e-4 s control period; the rigid MD leg needs none."""
    hopping = Profile("hopping", 1.0, 0.3, 1e-4, 1, 0.3)
    out = paper.axial_check(hopping, cache_dir=tmp_path, designs=("MD", "SS"), workers=1)
    runs = out["runs"].set_index(["design", "setting"])
    ss = runs.loc[("SS", "axial, axial's steps")]
    assert ss["substeps"] > 1 and ss["timestep_s"] * ss["substeps"] == pytest.approx(1e-4)
    assert runs.loc[("MD", "axial, axial's steps"), "substeps"] == 1
    assert ss["status"] == "ok"
