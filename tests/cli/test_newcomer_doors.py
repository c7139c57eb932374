"""Doors a newcomer trial found: a near name or command answered with
"did you mean", no abbreviated option taken for another, a new output
folder said, render's and modes' options, and optimize's help and
refusals in the truth's words."""

from __future__ import annotations

import argparse

import pytest
from _refusal import refused

from mat_hopper.cli import COMMAND_HELP, build_parser, main, subcommand_parser
from mat_hopper.cli._checks import suggest_in
from mat_hopper.cli._options import AUTO_TIMESTEP_HELP
from mat_hopper.util.parsing import close_names


def _actions(command):
    return {s: a for a in subcommand_parser(build_parser(command), command)._actions for s in a.option_strings}


def test_a_unique_prefix_is_the_name_suggested():
    assert close_names("loss", ["authors", "loss-factor"]) == ["loss-factor"]
    assert close_names("a", ["ab", "ac"]) != ["ab"]  # two names start so: no prefix pick


@pytest.mark.parametrize(
    ("argv", "hint"),
    [
        (["simulat"], "did you mean simulate?"),
        (["simulate", "--damping", "loss"], "did you mean loss-factor?"),
        (["reproduce", "--convention", "paper"], "did you mean --conventions?"),
        (["compare", "--controls", "rigid,masss"], "did you mean mass?"),
        (["optimize", "--study", "s", "--trials", "1", "--sampler", "tpee"], "did you mean tpe?"),
        (["optimize", "--study", "s", "--trials", "1", "--ashby-classes", "metl"], "did you mean metal?"),
        (["optimize", "--study", "s", "--trials", "1", "--leg-mass", "SSS"], "did you mean SS?"),
        (["simulate", "--sensor-timing", "autors"], "did you mean authors?"),
        (["batch", "--designs", "SS", "--sensor-timing", "frsh"], "did you mean fresh?"),
    ],
)
def test_a_near_name_is_answered_with_did_you_mean(argv, hint, capsys):
    refused(argv, capsys, hint)


def test_no_subcommand_takes_an_abbreviated_option():
    parser = build_parser()
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    assert not parser.allow_abbrev and all(not p.allow_abbrev for p in sub.choices.values())
    assert set(COMMAND_HELP) <= set(sub.choices)


def test_a_library_list_error_gains_did_you_mean():
    text = "--controls: unknown control 'masss'; accepted: rigid, mass, inertia (or none)"
    assert suggest_in(text).endswith("; did you mean mass?")
    assert suggest_in("unknown control 'zzz'; accepted: rigid, mass") == "unknown control 'zzz'; accepted: rigid, mass"


def test_an_output_folder_made_is_said_once(tmp_path, capsys):
    out = tmp_path / "new" / "dir" / "modes.csv"
    assert main(["modes", "--csv", str(out)]) == 0
    err = capsys.readouterr().err
    assert (
        f"mat-hopper modes: note: --csv: created folders {tmp_path / 'new'}, {tmp_path / 'new' / 'dir'}" in err
        and err.count("note:") == 1
    )
    assert out.exists()


def test_modes_gives_a_graded_legs_stable_step_and_refuses_its_table(capsys):
    assert main(["modes", "--density", "1.39,4.43,8", "--modulus", "3,110,193"]) == 0
    out = capsys.readouterr().out
    assert "no modes table" in out and "analytic stable time step" in out
    refused(["modes", "--design", "PVC-Ti-SS", "--modes", "2"], capsys, "--modes is for a leg of one elastic")
    assert "run profile" in subcommand_parser(build_parser("modes"), "modes").description  # none: it runs nothing


def test_render_has_profile_and_no_progress_and_names_the_options_of_its_run(tmp_path, capsys):
    actions = _actions("render")
    assert "--profile" in actions and "--no-progress" in actions
    refused(["render", "--still", str(tmp_path / "s.png"), "--profile", "quick"], capsys, "--profile is for --video")
    cap = refused(["render", "--design", "SS", "--video", str(tmp_path / "r.gif"), "--start", "1e9", "--seconds", "1"],
                  capsys, "--start + --seconds")  # fmt: skip
    assert "--tile-start" not in cap.err


def test_optimize_replay_takes_no_progress_and_help_says_where_export_writes(tmp_path, capsys):
    argv = ["optimize", "--study", "none", "--replay", "0", "--no-progress", "--studies-dir", str(tmp_path)]
    cap = refused(argv, capsys, "no study 'none'")
    assert "is for a study run" not in cap.err
    actions = _actions("optimize")
    assert "default STUDIES_DIR, not the report's folder" in actions["--export"].help
    assert "--export's" in actions["--out"].help
    description = subcommand_parser(build_parser("optimize"), "optimize").description
    assert "--timestep auto" in description and "Exit status: 0 when the study reached its target" in description


def test_the_auto_step_help_says_the_control_period_may_shorten():
    assert "--sensor-timing latency-L" in AUTO_TIMESTEP_HELP and "flight loop" in AUTO_TIMESTEP_HELP


def test_the_python_api_takes_design_names_for_controls_and_names_auto():
    from mat_hopper.core.control_legs import inertia_matched, mass_matched, rigid_twin
    from mat_hopper.core.sim import SimSettings

    assert mass_matched("SS").name == "SS~mass" and rigid_twin("rho-inc").name == "rho-inc~rigid"
    assert inertia_matched("PVC-Ti-SS").name == "PVC-Ti-SS~inertia"
    with pytest.raises(ValueError, match="'auto'"):
        SimSettings(timestep_s="fast")


@pytest.mark.parametrize(
    "density, modulus, text",
    [
        ("2,7,8", "1,5", "--modulus 1,5 is two values (1.5 with a point would still leave 3 densities and 1 modulus)"),
        ("2,7", "3", "--density 2,7 is two values: for 2.7 write a point"),
    ],
)
def test_a_decimal_comma_hint_is_given_only_where_it_fixes_the_counts(capsys, density, modulus, text):
    from mat_hopper.cli import main

    assert main(["simulate", "--density", density, "--modulus", modulus]) == 2
    assert text in capsys.readouterr().err
