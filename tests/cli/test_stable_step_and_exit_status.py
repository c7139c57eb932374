"""Every command that runs (or plans runs of) a leg compares its time step
with the leg's analytic stable step before any work, in one warning line
naming --timestep auto; and every command states the one exit-status rule:
1 when any run asked for diverged."""

import argparse

import pytest

from mat_hopper.cli import main


def _help(capsys, command: str) -> str:
    with pytest.raises(SystemExit) as e:
        main([command, "--help"])
    assert e.value.code == 0
    return " ".join(capsys.readouterr().out.split())  # argparse wraps the lines


@pytest.mark.parametrize("command", ["simulate", "batch", "render"])
def test_each_command_states_the_exit_status_rule(capsys, command):
    text = _help(capsys, command)
    assert "Exit status: 0 when every run ended without numerical divergence; 1 when any diverged" in text
    assert "--timestep auto" in text


def test_modes_warns_when_the_default_step_is_above_the_bound(capsys):
    assert main(["modes", "--design", "WC", "--convention", "paper"]) == 0
    out = capsys.readouterr().out
    lines = [x for x in out.splitlines() if x.startswith("warning: at the default step")]
    assert (
        len(lines) == 1 and "the physics step 0.0001 s is above this leg's analytic stable step 9.52e-05 s" in lines[0]
    )
    assert "try --timestep auto (3 physics substeps" in lines[0]
    assert main(["modes", "--design", "SS", "--convention", "paper"]) == 0
    assert "warning: at the default step" not in capsys.readouterr().out


def test_reproduce_names_the_designs_above_their_bound_before_any_work(capsys):
    """Experiment 2's sweeps hold designs whose springs' bound lies under the protocol's 1e-4 s step."""
    from mat_hopper.cli.reproduce import _warn_stable_step
    from mat_hopper.experiments.profiles import PROFILES

    _warn_stable_step(PROFILES["quick"], argparse.Namespace(experiments="2", conventions="paper"))
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("mat-hopper reproduce: warning: 6 designs run above their analytic")
    assert "exp2 SS E=1000" in err[0] and "--timestep auto" in err[0]
    # the command it names is one simulate runs: a sweep's design by its lists, never "--design D"
    command = err[0].split("`")[1]
    assert command == "mat-hopper simulate --density 2.0,2.0,2.0 --modulus 120.0,120.0,120.0 --timestep auto"
    _warn_stable_step(PROFILES["quick"], argparse.Namespace(experiments="1,stability", conventions="paper,axial"))
    assert capsys.readouterr().err == ""  # the paper's materials at 1e-4 s, axial at auto; the scan left out


def test_batch_advises_auto_only_where_it_would_change_the_step(tmp_path, capsys):
    """A heavy leg (19 g/cm^3, 120 GPa) falls at 9.4 s and then diverges:
    its automatic step is the 1e-4 s it ran at, so batch does not advise
    --timestep auto for it (it did, and auto gave the same run). The fall
    is named with its time, as Rollout.fell_at_s gives it, and the command
    that says why is one simulate runs: the CSV's design has no name
    simulate knows, so its --density and --modulus."""
    from mat_hopper.cli import main

    designs = tmp_path / "heavy.csv"
    designs.write_text(
        "design,density_1,density_2,density_3,modulus_1,modulus_2,modulus_3\nheavy,19,19,19,120,120,120\n"
    )
    argv = ["batch", "--designs-csv", str(designs), "--duration", "12", "--transient", "4", "--no-progress"]
    assert main(argv) == 1
    out = capsys.readouterr().out
    assert "1 of 1 design diverged (heavy fell at t = 9.393 s, then diverged at t = 11.0553 s)" in out
    assert "--timestep auto would not change their step" in out and "try " not in out
    assert "--design D" not in out
    command = out.split("`")[1]
    assert command.startswith("mat-hopper simulate --density 19.0,19.0,19.0 --modulus 120.0,120.0,120.0 ")
    assert main([*command.split()[1:], "--no-progress"]) == 1  # it runs, and says why
    assert "UNSTABLE: the hopper fell (base tilted past 60 deg at t = 9.393 s)" in capsys.readouterr().out


def test_a_command_named_in_a_message_gives_the_same_design():
    """simulate's flags for a design read back as its segments: by name
    where simulate knows it (a single material at 5 segments with
    --segments), else by exact --density and --modulus lists."""
    from mat_hopper.cli import build_parser, subcommand_parser
    from mat_hopper.cli._rerun import design_flags
    from mat_hopper.cli.simulate import design_from_args
    from mat_hopper.core.materials import LegDesign, parse_design

    designs = [
        parse_design("rho-inc"),
        parse_design("SS", n_segments=5),
        LegDesign.from_properties([1.0 / 3, 2.0], [None, 4.0], name="SS"),  # a CSV's row that borrowed a name
    ]
    assert [design_flags(d)[:2] for d in designs] == [
        ["--design", "rho-inc"],
        ["--design", "SS"],
        ["--density", "0.3333333333333333,2.0"],
    ]
    for d in designs:
        args = subcommand_parser(build_parser("simulate"), "simulate").parse_args(design_flags(d))
        assert design_from_args(args).segments == d.segments


def test_batch_names_a_design_that_fell_without_diverging(capsys):
    """A fall alone (the base tilted past 60 deg, the numbers finite) is
    named with its time below the table; the exit status stays 0 (as
    simulate's); the warp backend, which does not track the tilt, says so."""
    import pandas as pd

    from mat_hopper.cli.batch import _diverged_note, _fallen_note

    table = pd.DataFrame(
        {"design": ["a", "b", "c"], "stable": [True, True, False], "upright": [False, True, False],
         "fell_at_s": [7.25, float("nan"), 3.5], "diverged_at_s": [None, None, 4.0]}
    )  # fmt: skip
    assert _fallen_note(table).startswith("1 of 3 designs fell over (a at t = 7.250 s;")
    assert "c fell at t = 3.500 s, then diverged at t = 4.0000 s" in _diverged_note(table, False)
    warp = table.assign(fell_at_s=float("nan"))
    assert "a (when: not tracked)" in _fallen_note(warp)
