"""A command a message prints runs as printed (shell-quoted, with the
options that find the same study), and a study that cannot run as asked
is answered in the options the user gives."""

from __future__ import annotations

import dataclasses
import shlex

import optuna
from optuna.trial import TrialState

from mat_hopper.cli import build_parser, main
from mat_hopper.cli._rerun import simulate_command
from mat_hopper.core.materials import parse_design
from mat_hopper.experiments.profiles import resolve_profile
from mat_hopper.optimize import SearchSpace, StudyConfig, create_or_load, default_url, open_storage
from mat_hopper.optimize._objective import RESULT_ATTR
from mat_hopper.optimize._study import RACING_ATTR


def _create(folder, name: str) -> optuna.Study:
    c = StudyConfig(name, SearchSpace(n_segments=3))
    ob = dataclasses.replace(c.objective, profile=resolve_profile("quick"), replicates=0, behaviours=("forward",))
    return create_or_load(StudyConfig(name, c.space, ob), open_storage(default_url(name, str(folder))))


def test_a_printed_simulate_command_reads_back_a_name_with_a_space():
    design = parse_design("rho=1.4 E=340")  # a map point's name, which simulate reads
    words = shlex.split(simulate_command(design, behaviour="forward"))
    args = build_parser("simulate").parse_args(words[1:])
    assert words[:2] == ["mat-hopper", "simulate"] and args.design == "rho=1.4 E=340"


def test_a_study_of_other_settings_names_the_options_that_differ(tmp_path, capsys):
    _create(tmp_path, "t1")
    argv = ["optimize", "--study", "t1", "--trials", "3", "--profile", "paper", "--replicates", "2"]
    assert main([*argv, "--studies-dir", str(tmp_path), "--workers", "1", "--no-progress"]) == 2
    err = capsys.readouterr().err
    assert "--profile (study has quick, asked paper), --replicates (study has 0, asked 2);" in err
    assert "stability_grid_size" not in err and "objective." not in err


def test_a_racing_study_resumed_without_race_is_told_to_give_race(tmp_path, capsys):
    _create(tmp_path, "r1").set_user_attr(RACING_ATTR, {"eta": 3})
    argv = ["optimize", "--study", "r1", "--trials", "9", "--studies-dir", str(tmp_path), "--workers", "1"]
    assert main([*argv, "--no-progress"]) == 2
    err = capsys.readouterr().err
    assert "give --race again" in err and "run_racing" not in err


def test_the_reports_export_hint_finds_the_same_study(tmp_path, capsys):
    folder = tmp_path / "my studies"
    folder.mkdir()
    study = _create(folder, "t1")
    trial = study.ask()  # the first queued paper design, scored by hand
    SearchSpace(n_segments=3).suggest(trial)
    trial.set_user_attr(RESULT_ATTR, {"feasible": True, "per_behaviour": [{"behaviour": "forward", "upright": True}]})
    study.tell(trial, [0.01, 1.0])
    for name in ("SS", "rho-inc"):  # stored baselines: nothing simulated
        study.set_user_attr(f"baseline:{name}", {"values": [0.02, 2.0], "left_out": None})
    out = tmp_path / "rep"
    assert main(["optimize", "--report", "t1", "--studies-dir", str(folder), "--out", str(out)]) == 0
    hint = next(line for line in capsys.readouterr().out.splitlines() if line.startswith("export a design: "))
    words = shlex.split(hint.removeprefix("export a design: "))
    assert words[words.index("--studies-dir") + 1] == str(folder)
    assert study.trials[0].state == TrialState.COMPLETE
