"""``mat-hopper reproduce``: its options refused before any work."""

import pytest
from _refusal import refused

from mat_hopper.cli import build_parser
from mat_hopper.core.materials import CONVENTIONS
from mat_hopper.experiments.paper import parse_experiments
from mat_hopper.experiments.profiles import PROFILES


def _refused(argv, capsys) -> str:
    return refused(argv, capsys).err


def test_all_cannot_be_combined_with_other_experiments(tmp_path, capsys):
    err = _refused(["reproduce", "--experiments", "all,1", "--out", str(tmp_path / "o")], capsys)
    assert "'all' cannot be combined" in err and "--experiments" in err
    with pytest.raises(ValueError, match="cannot be combined"):
        parse_experiments("1,ALL")


def test_help_lists_every_convention_the_command_runs():
    sub = build_parser("reproduce")._subparsers._group_actions[0].choices["reproduce"]
    text = next(a.help for a in sub._actions if "--conventions" in a.option_strings)
    assert all(c in text for c in CONVENTIONS)


def test_help_gives_each_profiles_replicates():
    """The --replicates help gave "3 quick" after the quick profile went to 2."""
    sub = build_parser("reproduce")._subparsers._group_actions[0].choices["reproduce"]
    text = next(a.help for a in sub._actions if "--replicates" in a.option_strings)
    assert "10 paper" in text and f"{PROFILES['quick'].replicates} quick" in text and "3 quick" not in text


@pytest.mark.parametrize(
    "extra, words",
    [
        (["--experiments", "stability", "--push-scale", "2"], "--push-scale"),
        (["--replicates", "0", "--push-scale", "2"], "--replicates 0"),
        (["--experiments", "stability", "--conventions", "axial"], "--conventions"),
        (["--experiments", "stability", "--replicates", "5"], "--replicates"),
        (["--experiments", "robustness", "--conventions", "axial"], "--conventions"),
    ],
)
def test_an_option_without_effect_on_the_experiments_is_refused(tmp_path, capsys, extra, words):
    err = _refused(["reproduce", *extra, "--out", str(tmp_path / "o")], capsys)
    assert words in err and "no effect" in err and "--experiments" in err
    assert not (tmp_path / "o").exists()
