"""simulate, batch and render say a run that is numerically suspect (no
divergence, but a hop apex far above the target: corrupted numbers) in one
line and exit 1 as for a diverged run; simulate says a fall without
divergence."""

import pytest

from mat_hopper.cli import main

RUN = ["--duration", "3", "--transient", "1", "--no-progress"]


def test_simulate_says_a_suspect_run_and_exits_1(capsys):
    """Ti in 4 segments at the default 1e-4 s (its analytic bound 1.02e-4 s)."""
    assert main(["simulate", "--design", "Ti", "--segments", "4", "--behaviour", "forward", *RUN]) == 1
    lines = [x for x in capsys.readouterr().out.splitlines() if x.startswith("SUSPECT: ")]
    assert len(lines) == 1 and "hop apex of 1.90 m at t = 2.347 s" in lines[0] and "--timestep auto" in lines[0]


def test_simulates_csv_says_how_the_run_ended_in_every_row(tmp_path, capsys):
    """A suspect run's rows carry when it turned suspect; a clean run's are empty (as batch's CSV)."""
    import pandas as pd

    bad, good = tmp_path / "ti4.csv", tmp_path / "ss.csv"
    main(["simulate", "--design", "Ti", "--segments", "4", "--behaviour", "forward", *RUN, "--csv", str(bad)])
    main(["simulate", "--design", "SS", "--behaviour", "forward", *RUN, "--csv", str(good)])
    rows, clean = pd.read_csv(bad), pd.read_csv(good)
    assert {"diverged_at_s", "fell_at_s", "suspect_at_s"} <= set(rows.columns)
    assert ((rows["suspect_at_s"] - 2.347).abs() < 5e-4).all() and rows["diverged_at_s"].isna().all()
    assert clean[["diverged_at_s", "fell_at_s", "suspect_at_s"]].isna().all().all()


def test_simulate_of_the_papers_steel_is_not_suspect(capsys):
    assert main(["simulate", "--design", "SS", "--behaviour", "forward", *RUN]) == 0
    out = capsys.readouterr().out
    assert "SUSPECT" not in out and "FELL" not in out


def test_simulate_says_a_fall_without_divergence(capsys):
    argv = ["simulate", "--density", "8,8,8", "--modulus", "260,260,260", "--behaviour", "ramp"]
    assert main([*argv, "--duration", "6", "--transient", "1", "--no-progress"]) == 1  # also suspect
    out = capsys.readouterr().out
    assert "FELL: the hopper fell (base tilted past 60 deg at t = 4.339 s)" in out


def test_batch_marks_a_suspect_design_in_its_table_and_its_lines(tmp_path, capsys):
    csv = tmp_path / "designs.csv"
    csv.write_text(
        "density_1,density_2,density_3,density_4,modulus_1,modulus_2,modulus_3,modulus_4\n"
        + "4.43," * 4
        + "120," * 3
        + "120\n"
    )
    assert main(["batch", "--designs-csv", str(csv), "--behaviour", "forward", *RUN]) == 1
    out = capsys.readouterr().out
    assert "suspect" in out.splitlines()[1].split()  # the table's column
    assert "1 of 1 design numerically suspect" in out and "try --timestep auto" in out


@pytest.mark.parametrize("command", ["simulate", "batch", "render"])
def test_the_exit_status_rule_names_suspect_runs(capsys, command):
    with pytest.raises(SystemExit):
        main([command, "--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert "1 when any diverged or is numerically suspect" in text
