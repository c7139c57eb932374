"""A run that stood but scored no hop cycle (a window shorter than a
cycle) is said, with what to change: not an empty table without a word,
nor "use more replicates"."""

from mat_hopper.cli import main
from mat_hopper.experiments.compare import untestable

SHORT = ["--duration", "1.5", "--transient", "1", "--no-progress"]


def test_simulate_says_why_no_cycle_was_scored(capsys):
    assert main(["simulate", "--design", "SS", *SHORT]) == 0
    out = capsys.readouterr().out
    assert "0 hop cycles scored" in out and "no hop cycle was scored between 1 and 1.5 s" in out
    assert "give a longer --duration" in out


def test_batch_says_it_for_its_designs(capsys):
    main(["batch", "--designs", "SS,Ti", *SHORT])
    assert "2 of 2 designs: no hop cycle was scored between 1 and 1.5 s" in capsys.readouterr().out


def test_compare_does_not_ask_for_seeds_that_cannot_help(capsys):
    assert main(["compare", "--design", "rho-inc", "--baseline", "SS", "--replicates", "2", *SHORT]) == 1
    out = capsys.readouterr().out
    assert "no hop cycle was scored" in out and "--replicates 8" not in out and "p >= nan" not in out
    assert untestable(0, 4) == "untestable: no paired seed has a scored hop cycle"
