"""Objectives as a setting (an objective may be any metric of the table):
the named table, its parsing, the default's unchanged key, a
three-objective study and its report, validation and the warp refusal."""

from __future__ import annotations

import os

import numpy as np
import optuna
import pandas as pd
import pytest
from optuna.trial import TrialState

from mat_hopper.cli import main
from mat_hopper.core.materials import paper_designs
from mat_hopper.experiments.profiles import Profile
from mat_hopper.optimize import (
    METRICS,
    OBJECTIVES,
    Objective,
    RunOptions,
    SearchSpace,
    StudyConfig,
    check_objectives_vary,
    create_or_load,
    evaluate,
    front_table,
    hypervolume,
    leg_mass_kg,
    open_storage,
    parse_objectives,
    run_study,
    write_report,
)
from mat_hopper.optimize._batch import check_unperturbed
from mat_hopper.optimize.report import hypervolume_2d
from mat_hopper.optimize.validate import replicate_means

optuna.logging.set_verbosity(optuna.logging.WARNING)
TINY = Profile("tiny", duration_s=2.0, transient_s=0.5)
THREE = ("tracking_error_m", "power_total_w", "leg_mass_kg")


@pytest.fixture(autouse=True)
def own_cache(tmp_path, monkeypatch):
    monkeypatch.setenv("MAT_HOPPER_CACHE", str(tmp_path / "cache"))


def test_the_table_names_its_units_and_the_required_metrics():
    for name in ("tracking_error_m", "power_w", "power_total_w", "energy_per_hop_j", "peak_stress_pa"):
        assert name in METRICS
    assert {"damage_per_hop", "leg_mass_kg"} <= set(METRICS)
    for m in METRICS.values():
        assert m.unit and m.label and m.summary_column
        assert m.unit == "1" or m.name.endswith("_" + m.unit.lower())  # the unit is in the name
    assert OBJECTIVES == ("tracking_error_m", "power_w")


def test_default_objective_keeps_the_key_it_had_before_the_setting(tmp_path):
    """A default objective's key has no ``objectives`` entry (the key a study
    stored before the setting existed), equals the key of the default given
    explicitly, and such a study resumes; other objectives are another study."""
    default = Objective(replicates=0, profile=TINY)
    explicit = Objective(replicates=0, profile=TINY, objectives=("Tracking_Error_M", "POWER_W"))
    assert "objectives" not in default.key()
    assert default.key() == explicit.key() and explicit.objectives == OBJECTIVES
    assert Objective.from_key(default.key()) == default
    three = Objective(replicates=0, profile=TINY, objectives=THREE)
    assert three.key()["objectives"] == list(THREE) and Objective.from_key(three.key()) == three

    # the fields of an unperturbed objective's key before the setting (and before noise-aware scores)
    before = {"behaviours", "profile", "convention", "hop_height_target_m", "hop_height_tolerance_m"}
    assert set(default.key()) == before | {"segment_mass", "leg_material_length_m"}
    storage = open_storage(f"sqlite:///{tmp_path}/k.db")
    study = create_or_load(StudyConfig("k", SearchSpace(), default), storage)
    assert study.user_attrs["mat_hopper_config"]["objective"] == default.key()
    assert study.metric_names == list(OBJECTIVES) and len(study.directions) == 2
    create_or_load(StudyConfig("k", SearchSpace(), explicit), storage)  # resumes: no config change
    with pytest.raises(ValueError, match="other settings.*objectives"):
        create_or_load(StudyConfig("k", SearchSpace(), three), storage)


# The default objective's key as studies stored it (the paper profile, convention paper).
DEFAULT_KEY = {
    "behaviours": ["ramp"],
    "profile": {
        "name": "paper",
        "duration_s": 60.0,
        "transient_s": 20.0,
        "timestep_s": 0.0001,
        "stability_grid_size": 20,
        "stability_duration_s": 2.0,
        "stability_tolerance": 1.25,
        "stability_max_iter": 10,
        "stability_scan": True,
        "record_rate_hz": 1000.0,
        "convention": "paper",
        "axial_timestep_s": "auto",
        "replicates": 10,
        "sensor_timing": "authors",
        "segment_mass": "leg",
        "push_scale": 1.0,
        "substep_studies": True,
    },
    "convention": "paper",
    "hop_height_target_m": 1.0,
    "hop_height_tolerance_m": 0.05,
    "segment_mass": "leg",
    "leg_material_length_m": 0.3,
    "replicates": 4,
    "replicate_seed_start": 1000,
}


def test_objective_takes_every_run_setting_from_its_profile(monkeypatch):
    """convention and segment_mass left out are the profile's (both alike);
    given, they override it; the default objective's key is unchanged."""
    from dataclasses import replace

    from mat_hopper.experiments.profiles import PROFILES

    monkeypatch.delenv("MAT_HOPPER_PROFILE", raising=False)
    assert Objective().key() == DEFAULT_KEY and list(Objective().key()) == list(DEFAULT_KEY)
    axial = replace(TINY.for_convention("axial"), segment_mass="capsule")
    ob = Objective(replicates=0, profile=axial)
    assert (ob.convention, ob.segment_mass) == ("axial", "capsule")
    s = ob.sim_settings(design=paper_designs()["SS"])
    assert (s.convention, s.segment_mass, s.substeps) == ("axial", "capsule", 8)
    given = Objective(replicates=0, profile=axial, convention="Paper", segment_mass="LEG")
    assert (given.convention, given.segment_mass) == ("paper", "leg")
    assert given.sim_settings().convention == "paper" and given.sim_settings().timestep_s == 1e-4
    assert Objective.from_key(ob.key()) == ob and Objective.from_key(given.key()) == given
    assert Objective(profile="quick").profile is PROFILES["quick"]
    monkeypatch.setenv("MAT_HOPPER_PROFILE", "quick")
    assert Objective().profile is PROFILES["quick"]  # the API's entry point reads the variable
    with pytest.raises(ValueError, match="profile must be a Profile"):
        Objective(profile=3)


@pytest.mark.parametrize(
    "value, text",
    [
        ("tracking_error_m,bogus", "unknown objectives 'bogus'; accepted: tracking_error_m, power_w, power_total_w"),
        ("power_w", "give 2 or 3 metrics, got 1"),
        ("power_w,POWER_W", "each metric at most once"),
        ("power_w,tracking_error_m,leg_mass_kg,damage_per_hop", "got 4"),
        ("power_w,", "objectives is empty"),
    ],
)
def test_unknown_or_bad_objectives_are_refused_by_the_api(value, text):
    with pytest.raises(ValueError, match=text) as e:
        Objective(objectives=value)
    assert "\n" not in str(e.value)
    assert parse_objectives(" Power_Total_W ,leg_mass_KG") == ("power_total_w", "leg_mass_kg")


def test_unknown_objective_is_refused_by_the_cli_in_one_line(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    code = main(["optimize", "--study", "bad", "--trials", "5", "--objectives", "tracking_error_m,speed_m_s"])
    err = capsys.readouterr().err.strip()
    assert code == 2 and len(err.splitlines()) == 1
    assert "unknown --objectives 'speed_m_s'; accepted: tracking_error_m, power_w" in err
    assert "leg_mass_kg" in err
    assert not (tmp_path / "studies").exists()  # nothing was made


def test_help_documents_the_metrics(capsys):
    with pytest.raises(SystemExit):
        main(["optimize", "--help"])
    out = " ".join(capsys.readouterr().out.split())
    for name in METRICS:
        assert name in out
    assert "bending convention" in out


def test_total_power_includes_the_thrust_work():
    """power_total_w counts all three actuators, the thrust included: at least the hip power."""
    ob = Objective(replicates=0, profile=TINY, objectives=("power_w", "power_total_w"))
    ev = evaluate(paper_designs()["SS"], ob)
    hip, total = ev.values
    assert ev.objective_names == ("power_w", "power_total_w")
    assert total >= hip > 0
    assert total > 5 * hip  # the thrust does most of the work
    row = ev.per_behaviour[0]
    assert set(METRICS) <= set(row)  # every run scores the whole table
    assert row["leg_mass_kg"] == ev.leg_mass_kg == leg_mass_kg(paper_designs()["SS"], "leg")


def test_three_objective_study_completes_with_three_values_per_front_trial(tmp_path):
    name = "three"
    config = StudyConfig(name, SearchSpace(), Objective(replicates=0, profile=TINY, objectives=THREE))
    opts = RunOptions(trials=4, workers=1, batch_size=4, studies_dir=str(tmp_path / "studies"), progress=False)
    res = run_study(config, opts)
    assert res.finished
    url = opts.storage_url(name)
    study = optuna.load_study(study_name=name, storage=open_storage(url))
    assert study.metric_names == list(THREE) and len(study.directions) == 3
    complete = study.get_trials(deepcopy=False, states=(TrialState.COMPLETE,))
    assert len(complete) == 4
    for t in complete:
        assert len(t.values) == 3
        assert set(t.user_attrs["standard_error"]) == set(THREE)
        for r in t.user_attrs["result"]["per_behaviour"]:
            assert r["power_total_w"] >= r["power_w"]
        assert t.values[2] == pytest.approx(t.user_attrs["result"]["leg_mass_kg"])
    rep = write_report(name, open_storage(url), str(tmp_path / "report"))
    for p in rep["paths"].values():
        assert os.path.getsize(p) > 0
    front = rep["pareto"]
    assert len(front) >= 1  # SS, the first enqueued design, hops within tolerance on this profile
    assert list(front.columns[3:6]) == list(THREE)
    assert all(len(b) == 3 for b in rep["baselines"].values())
    best = {t.number for t in study.best_trials}
    feasible = rep["trials"][(rep["trials"].state == "COMPLETE") & rep["trials"].feasible]
    assert set(front["trial"]) == best & set(feasible["trial"])
    assert front[list(THREE)].notna().all().all()
    table = front_table(front)
    assert {"tracking error (mm)", "total power (W)", "leg mass (kg)"} <= set(table.columns)
    assert rep["hypervolume"]["hypervolume"].iloc[-1] > 0 and len(rep["reference"]) == 3


def test_hypervolume_in_two_and_three_objectives():
    assert hypervolume([[0, 0, 0]], [1, 1, 1]) == pytest.approx(1.0)
    # two boxes: 0.25 + 0.5 - their overlap 0.125
    assert hypervolume([[0, 0.5, 0.5], [0.5, 0, 0]], [1, 1, 1]) == pytest.approx(0.625)
    assert hypervolume([[2, 0, 0]], [1, 1, 1]) == 0.0 and hypervolume(np.empty((0, 3)), [1, 1, 1]) == 0.0
    rng = np.random.default_rng(0)
    pts = rng.random((12, 3))
    grid = rng.random((200_000, 3))  # Monte Carlo check of the slicing
    dominated = (pts[None, :, :] <= grid[:, None, :]).all(axis=2).any(axis=1)
    assert hypervolume(pts, [1, 1, 1]) == pytest.approx(dominated.mean(), abs=0.01)
    pts2 = rng.random((9, 2))
    assert hypervolume(pts2, [1, 1]) == hypervolume_2d(pts2, [1, 1])
    # a constant third objective scales the 2-D area by its distance to the reference
    flat = np.column_stack([pts2, np.full(9, 0.25)])
    assert hypervolume(flat, [1, 1, 1]) == pytest.approx(0.75 * hypervolume(pts2, [1, 1]))


def test_warp_refuses_what_it_cannot_compute_in_one_line():
    stress = Objective(replicates=0, objectives="tracking_error_m,peak_stress_pa")
    with pytest.raises(ValueError, match="computes only tracking_error_m, power_w, leg_mass_kg.*peak_stress_pa") as e:
        check_unperturbed(stress)
    assert "\n" not in str(e.value)
    check_unperturbed(Objective(replicates=0, objectives="power_w,leg_mass_kg"))  # both computed


def test_static_alone_refuses_only_objectives_zero_by_symmetry():
    with pytest.raises(ValueError, match="zero by symmetry"):
        check_objectives_vary(Objective(behaviours="static", objectives="tracking_error_m,power_total_w"))
    check_objectives_vary(Objective(behaviours="static", objectives="power_total_w,leg_mass_kg"))


def test_validation_reads_each_objective_from_its_run_summary_column():
    runs = pd.DataFrame(
        {
            "role": ["front"] * 2 + ["control"] * 2,
            "design": ["a", "a", "a~rigid", "a~rigid"],
            "replicate": [0, 1, 0, 1],
            "behaviour": ["ramp"] * 4,
            "check": ["replicate"] * 4,
            "status": ["ok"] * 4,
            "mean_power_total_w": [40.0, 42.0, 41.0, 43.0],
            "peak_stress_pa": [2e6, 3e6, np.nan, np.nan],  # a rigid twin has no modelled stress
            "leg_mass_kg": [3.0, 3.0, 3.0, 3.0],
        }
    )
    ob = Objective(objectives="power_total_w,peak_stress_pa,leg_mass_kg")
    means = replicate_means(runs, ob)
    assert list(means.columns) == ["power_total_w", "peak_stress_pa", "leg_mass_kg"]
    assert means.loc[("front", "a", 1), "power_total_w"] == 42.0
    from mat_hopper.optimize.validate import _compare

    effects = _compare(means, ("front", "a"), ("control", "a~rigid"))
    assert set(effects) == {"power_total_w", "leg_mass_kg"}  # stress left out: the twin has none
