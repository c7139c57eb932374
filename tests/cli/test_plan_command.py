"""``mat-hopper plan``: the total line, the chapters in the toc's order, the
CSV, and bad input refused before any work."""

from __future__ import annotations

import pathlib
import re

import pandas as pd
from _refusal import refused

from mat_hopper.cli import main

ROOT = pathlib.Path(__file__).resolve().parents[2]
TOTAL = re.compile(r"^total: \d+ runs, (\S+) physics steps, \S+ core-hours \(estimated\)$")


def test_plan_prints_every_chapter_and_the_total_line(tmp_path, capsys):
    csv = tmp_path / "plan.csv"
    argv = ["plan", "--profile", "quick", "--cache", str(tmp_path / "cache"), "--csv", str(csv)]
    assert main([*argv, "--us-per-step", "5"]) == 0
    out = capsys.readouterr().out.strip().splitlines()
    assert TOTAL.match(out[-2]), out[-2]  # then the "wrote" line
    assert out[-1].startswith("wrote ") and "5 us per physics step" in "\n".join(out)
    table = pd.read_csv(csv)
    toc = re.findall(r"^\s*- file: notebooks/(\S+)\s*$", (ROOT / "_toc.yml").read_text(), flags=re.M)
    assert list(dict.fromkeys(table["chapter"])) == toc
    assert {"runs", "shared_with_earlier", "cached", "simulated_s", "physics_steps", "timesteps"} <= set(table)
    # an existing --csv is replaced only with --force
    refused(argv, capsys, "--csv", "file exists", "--force")
    assert main([*argv, "--force"]) == 0
    assert TOTAL.match(capsys.readouterr().out.strip().splitlines()[-2])


def test_plan_refuses_an_unknown_profile_with_the_nearest(capsys):
    refused(["plan", "--profile", "quik"], capsys, "unknown profile", "did you mean quick")


def test_plan_refuses_a_cost_per_step_that_is_not_positive(capsys):
    refused(["plan", "--profile", "quick", "--us-per-step", "0"], capsys, "--us-per-step")


def test_plan_refuses_force_without_an_output(capsys):
    refused(["plan", "--profile", "quick", "--force"], capsys, "--force is for --csv")


def test_a_cache_that_is_not_there_is_said_and_a_file_refused(tmp_path, capsys):
    from mat_hopper.cli import main

    missing = tmp_path / "typo" / "cache"
    assert main(["plan", "--profile", "quick", "--cache", str(missing)]) == 0
    assert f"note: --cache {missing} does not exist: no run is cached there" in capsys.readouterr().out
    assert not missing.exists()
    afile = tmp_path / "x.csv"
    afile.write_text("a\n")
    assert main(["plan", "--profile", "quick", "--cache", str(afile)]) == 2
    assert "is a file, not a folder" in capsys.readouterr().err
