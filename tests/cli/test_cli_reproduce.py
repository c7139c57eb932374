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


def test_a_reproduction_whose_runs_diverged_exits_1_and_says_so(tmp_path, capsys, monkeypatch):
    """The exit rule of simulate and compare: a run that diverged exits 1
    (the tables and claims still written); --help states it. The runs are
    counted from the run-summary table (stable False), the map's tries left
    out."""
    import pandas as pd

    import mat_hopper.cli.reproduce as cli
    from mat_hopper.cli import main
    from mat_hopper.experiments.reproduce import Reproduction, diverged_runs

    runs = pd.DataFrame(
        {"design": ["Ti", "SS", "MD"], "behaviour": ["forward"] * 3, "stable": [False, True, True],
         "upright": [False, False, True], "diverged_at_s": [0.0025, None, None], "status": ["diverged", "fallen", "ok"]}
    )  # fmt: skip
    assert diverged_runs("exp2", runs) == 1  # the fallen SS run ends upright-less, not diverged
    assert diverged_runs("stability", runs) == 0

    def fake(profile, experiments, out, **kwargs):
        return Reproduction("quick", out, wall_s={"exp2": 1.0}, failed={"exp2": 0}, diverged={"exp2": 1})

    monkeypatch.setattr(cli, "reproduce", fake)
    argv = ["reproduce", "--profile", "quick", "--experiments", "2", "--out", str(tmp_path / "o")]
    assert main([*argv, "--cache", str(tmp_path / "c"), "--no-progress"]) == 1
    assert "1 run diverged (exp2 1): exit status 1" in capsys.readouterr().out
    with pytest.raises(SystemExit):
        main(["reproduce", "--help"])
    assert "1 when a task failed or any run of experiments 1-3" in " ".join(capsys.readouterr().out.split())


def test_a_run_of_the_controls_alone_says_where_they_are_and_what_they_feed(tmp_path, capsys):
    """The controls judge no claim by themselves: their line names their
    tables and the claims' columns they feed, and asks for experiments 1-3."""
    from types import SimpleNamespace

    from mat_hopper.cli.reproduce import _controls_note

    _controls_note(SimpleNamespace(wall_s={"controls": 40.0, "figures": 2.0}, out_dir=str(tmp_path)))
    line = capsys.readouterr().out
    assert str(tmp_path / "controls_hops.csv") in line and "beyond_mass" in line
    assert "--experiments 1,2,3,controls" in line
    _controls_note(SimpleNamespace(wall_s={"exp1": 30.0, "controls": 40.0}, out_dir=str(tmp_path)))
    assert "--experiments" not in capsys.readouterr().out  # judged with experiment 1 already


def test_an_earlier_runs_files_left_beside_this_ones_are_named(tmp_path, capsys):
    """--force replaces what a run writes and removes nothing: the files of
    an earlier run that this one did not write are named."""
    from types import SimpleNamespace

    from mat_hopper.cli.reproduce import _earlier_outputs_note

    (tmp_path / "figures").mkdir()
    for name in ("exp1_hops.csv", "claims.csv", "claims.md", "figures/fig4.png"):
        (tmp_path / name).write_text("x")
    _earlier_outputs_note(SimpleNamespace(out_dir=str(tmp_path), files=[str(tmp_path / "exp1_hops.csv")]))
    out = capsys.readouterr().out
    assert "3 files" in out and "claims.csv" in out and "claims.md" in out and "figures/fig4.png" in out
    assert "exp1_hops.csv" not in out
    _earlier_outputs_note(SimpleNamespace(out_dir=str(tmp_path), files=[str(p) for p in tmp_path.rglob("*.*")]))
    assert capsys.readouterr().out == ""
