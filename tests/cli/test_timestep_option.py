"""--timestep, one option for every command that runs: seconds or 'auto',
read by one reader; a study records it in its key."""

import pytest

from mat_hopper.cli import build_parser, subcommand_parser
from mat_hopper.cli._options import timestep_arg
from mat_hopper.cli.optimize import config_from_args
from mat_hopper.core.timestep import AUTO


@pytest.mark.parametrize("command", ["simulate", "batch", "compare", "optimize"])
def test_every_running_command_has_the_option(command):
    sub = subcommand_parser(build_parser(command), command)
    assert any("--timestep" in a.option_strings for a in sub._actions)


def test_one_reader():
    assert timestep_arg(None) is None
    assert timestep_arg("AUTO") == AUTO
    assert timestep_arg("5e-5") == 5e-5
    for bad in ("fast", "1_0", "inf", "١e-4"):
        with pytest.raises(ValueError, match="--timestep"):
            timestep_arg(bad)


def test_a_study_at_auto_records_it_in_its_key():
    args = build_parser("optimize").parse_args(["optimize", "--study", "s", "--profile", "quick", "--timestep", "auto"])
    config = config_from_args(args, None)
    assert config.objective.profile.timestep_s == AUTO
    assert config.key()["objective"]["profile"]["timestep_s"] == AUTO
    plain = config_from_args(
        build_parser("optimize").parse_args(["optimize", "--study", "s", "--profile", "quick"]), None
    )
    assert plain.objective.profile.timestep_s == 1e-4 and plain.key() != config.key()
    # resuming without --timestep keeps the stored study's step
    resumed = config_from_args(build_parser("optimize").parse_args(["optimize", "--study", "s"]), config)
    assert resumed.objective.profile.timestep_s == AUTO


def test_a_bad_step_is_named_before_a_redundant_profile(capsys):
    """simulate with --profile and all three of --duration, --transient and
    --timestep refuses the redundant profile, but a bad value among them is
    the error a newcomer sees first."""
    from mat_hopper.cli import main

    common = ["simulate", "--design", "SS", "--profile", "quick", "--duration", "3", "--transient", "1"]
    assert main([*common, "--timestep", "-1e-4"]) == 2
    assert "--timestep must be in (0, 0.1] s" in capsys.readouterr().err
    assert main([*common, "--timestep", "1e-4"]) == 2
    assert "leave out --profile" in capsys.readouterr().err
