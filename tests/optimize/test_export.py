"""Designs a user can take away (mat_hopper.optimize._export): a trial's
design as CSV and MJCF, and the round trip back to its metrics. Runs use a
2 s profile (tiny)."""

from __future__ import annotations

import shlex
from dataclasses import replace

import mujoco
import numpy as np
import optuna
import pandas as pd
import pytest

from mat_hopper.batch import designs_from_csv
from mat_hopper.cli import main
from mat_hopper.core.behaviours import behaviour
from mat_hopper.core.model import build_model
from mat_hopper.experiments.profiles import Profile, get_profile
from mat_hopper.optimize import (
    Objective,
    PoolEvaluator,
    RunOptions,
    SearchSpace,
    StudyConfig,
    create_or_load,
    default_url,
    evaluate,
    export_trial,
    leg_mass_kg,
    open_storage,
    run_loop,
)

optuna.logging.set_verbosity(optuna.logging.WARNING)
TINY = Profile("tiny", duration_s=2.0, transient_s=0.5)


def _study(folder, name, replicates, n_trials=3):
    config = StudyConfig(name, SearchSpace(), Objective(profile=TINY, replicates=replicates))
    folder.mkdir(exist_ok=True)
    url = default_url(name, str(folder))
    storage = open_storage(url)
    study = create_or_load(config, storage, sampler=optuna.samplers.RandomSampler(seed=1))
    study.enqueue_trial({"seg1_density_g_cm3": 3.3, "seg1_modulus_gpa": 12.5, "seg2_density_g_cm3": 1.7,
                         "seg2_modulus_gpa": 0.93, "seg3_density_g_cm3": 9.1, "seg3_modulus_gpa": 410.0})  # fmt: skip
    with PoolEvaluator(str(folder / "cache"), workers=1) as evaluator:
        run_loop(study, storage, config, evaluator, RunOptions(trials=n_trials, progress=False))
    return config, url, study


def test_export_round_trip_reproduces_the_trial(tmp_path, capsys):
    """The exported CSV gives the trial's design bit for bit: simulating it
    with the study's settings (K = 2 replicates) gives the trial's
    objectives and standard errors exactly."""
    config, url, study = _study(tmp_path, "rt", replicates=2, n_trials=4)
    number = max(t.number for t in study.get_trials(states=(optuna.trial.TrialState.COMPLETE,)))
    res = export_trial("rt", url, number, str(tmp_path / "out"))
    trial = study.trials[number]
    (design,) = designs_from_csv(res["csv"])
    original = config.space.design(trial.params)
    assert [(m.density_g_cm3, m.modulus_gpa) for m in design.segments] == [
        (m.density_g_cm3, m.modulus_gpa) for m in original.segments
    ]
    ev = evaluate(design, config.objective)
    assert tuple(ev.values) == tuple(trial.values)  # exactly: determinism
    assert ev.standard_errors[0] == trial.user_attrs["standard_error"]["tracking_error_m"]
    row = pd.read_csv(res["csv"]).iloc[0]
    assert row["trial"] == number and row["replicates"] == 2 and row["study"] == "rt"
    assert row["tracking_error_m"] == trial.values[0]
    assert row["leg_mass_kg"] == pytest.approx(leg_mass_kg(design, config.objective.segment_mass), rel=1e-15)

    # MJCF from MuJoCo's own writer: it compiles to the same masses; stiffness to 6 digits
    model = mujoco.MjModel.from_xml_path(res["mjcf"]["ramp"])
    ref = build_model(original, ramp_grade_deg=behaviour("ramp").ramp_grade_deg).model
    assert np.array_equal(model.body_mass, ref.body_mass)
    assert np.allclose(model.jnt_stiffness, ref.jnt_stiffness, rtol=5e-6, atol=0)  # half a unit of the 6th digit
    assert model.opt.timestep == config.objective.sim_settings(design=original).timestep_s
    # --replay of a replicated trial: the runs by seed, the standard errors, the same values
    assert main(["optimize", "--study", "rt", "--studies-dir", str(tmp_path), "--replay", str(number)]) == 0
    out = capsys.readouterr().out
    assert "(replicate seed 1000)" in out and "(replicate seed 1001)" in out and "standard errors" in out
    assert "matches the stored values exactly" in out


def test_export_cli_and_simulate_design_csv(tmp_path, capsys):
    """``optimize --export`` writes the files; ``simulate --design-csv``
    reads the CSV and, unperturbed, reproduces the trial's per-hop means."""
    studies = tmp_path / "studies"
    config, url, study = _study(studies, "cli", replicates=0, n_trials=1)
    trial = study.trials[0]
    out = tmp_path / "out"
    assert main(["optimize", "--study", "cli", "--studies-dir", str(studies), "--export", "0", "--out", str(out)]) == 0
    text = capsys.readouterr().out
    csv = out / "cli-trial0.csv"
    assert f"wrote {csv}" in text and (out / "cli-trial0-ramp.xml").exists()
    assert "simulate --design-csv" in text
    hops = tmp_path / "hops.csv"
    argv = ["simulate", "--design-csv", str(csv), "--behaviour", "ramp", "--duration", "2", "--transient", "0.5"]
    assert main([*argv, "--csv", str(hops), "--no-progress"]) == 0
    row = trial.user_attrs["result"]["per_behaviour"][0]
    assert row["n_hops"] > 0 and row["upright"]
    h = pd.read_csv(hops)
    assert len(h) == row["n_hops"]
    assert float(h["tracking_error_m"].mean()) == trial.values[0]  # the CSV round trip of repr floats: exact
    assert float(h["power_w"].mean()) == trial.values[1]


@pytest.mark.parametrize(
    "profile",
    [TINY, replace(get_profile("quick"), timestep_s="auto")],
    ids=["a profile of its own", "a named profile at the auto step"],
)
def test_the_printed_simulate_command_reproduces_the_trial(tmp_path, capsys, profile):
    """The ``simulate it:`` line of ``optimize --export`` carries every run
    setting the study holds apart from its named profile (a profile of its
    own: every one, no --profile): run as printed, it gives the trial's
    per-hop means exactly."""
    studies = tmp_path / "studies"
    config = StudyConfig("cmd", SearchSpace(), Objective(profile=profile, replicates=0))
    studies.mkdir()
    url = default_url("cmd", str(studies))
    study = create_or_load(config, open_storage(url), sampler=optuna.samplers.RandomSampler(seed=1))
    study.enqueue_trial({"seg1_density_g_cm3": 3.3, "seg1_modulus_gpa": 12.5, "seg2_density_g_cm3": 1.7,
                         "seg2_modulus_gpa": 0.93, "seg3_density_g_cm3": 9.1, "seg3_modulus_gpa": 410.0})  # fmt: skip
    with PoolEvaluator(str(studies / "cache"), workers=1) as evaluator:
        run_loop(study, open_storage(url), config, evaluator, RunOptions(trials=1, progress=False))
    out = tmp_path / "out"
    assert main(["optimize", "--study", "cmd", "--studies-dir", str(studies), "--export", "0", "--out", str(out)]) == 0
    (line,) = [x for x in capsys.readouterr().out.splitlines() if x.startswith("simulate it: ")]
    argv = shlex.split(line.removeprefix("simulate it: "))
    assert argv[:2] == ["mat-hopper", "simulate"]
    assert ("--profile" in argv) == (profile.name == "quick")
    hops = tmp_path / "hops.csv"
    assert main([*argv[1:], "--csv", str(hops), "--no-progress"]) == 0
    h = pd.read_csv(hops)
    trial = study.trials[0]
    assert len(h) == trial.user_attrs["result"]["per_behaviour"][0]["n_hops"] > 0
    assert float(h["tracking_error_m"].mean()) == trial.values[0]
    assert float(h["power_w"].mean()) == trial.values[1]


def test_export_errors(tmp_path, capsys):
    studies = tmp_path / "studies"
    _study(studies, "e", replicates=0, n_trials=1)
    assert main(["optimize", "--study", "e", "--studies-dir", str(studies), "--export", "99"]) == 2
    assert "no trial 99" in capsys.readouterr().err
    csv = tmp_path / "two.csv"
    csv.write_text("design,density_1,modulus_1\na,8,193\nb,2,3\n")
    assert main(["simulate", "--design-csv", str(csv), "--duration", "1", "--transient", "0.5"]) == 2
    assert "holds 2 designs" in capsys.readouterr().err


def test_export_of_a_study_the_storage_does_not_hold(tmp_path):
    storage = optuna.storages.InMemoryStorage()
    optuna.create_study(study_name="other", storage=storage)
    with pytest.raises(ValueError, match=r"no study 'missing'.*studies present: 'other'"):
        export_trial("missing", storage, 0, str(tmp_path / "out"))
    assert not (tmp_path / "out").exists()
