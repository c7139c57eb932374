"""``mat-hopper compare``: refusals before any work, and the table it prints and writes."""

import pandas as pd
import pytest
from _refusal import refused

from mat_hopper.cli import main

SHORT = ["--profile", "quick", "--duration", "2", "--transient", "1"]


@pytest.mark.parametrize(
    "args, texts",
    [
        (["--baseline", "kryptonite"], ("--baseline", "unknown material 'kryptonite'")),
        (["--baseline", "SS,ss"], ("--baseline", "name the same design")),
        (["--baseline", "SS,,Ti"], ("--baseline", "an empty item")),
        (["--controls", "rigid,twin"], ("--controls", "unknown control 'twin'", "rigid, mass, inertia")),
        (["--controls", "mass,mass"], ("--controls", "named twice")),
        (["--controls", "none", "--baseline", "none"], ("--baseline and --controls are both none",)),
        (["--replicates", "1"], ("--replicates must be an integer >= 2",)),
        (["--timestep", "fast"], ("--timestep", "'auto'")),
    ],
)
def test_bad_input_is_one_line_before_any_run(tmp_path, capsys, args, texts):
    cap = refused(["compare", "--design", "rho-inc", *SHORT, "--cache", str(tmp_path / "c"), *args], capsys, *texts)
    assert cap.err.startswith("mat-hopper compare: error: ")
    assert not (tmp_path / "c").exists()  # no run, no cache folder left behind


def test_csv_writes_the_paired_table_and_two_seeds_are_untestable(tmp_path, capsys):
    """The quick profile's 2 seeds: the verdicts say the comparison is
    untestable and how many seeds would do; the CSV holds one row per
    comparator with the paired columns, every leg at one time step."""
    out = tmp_path / "compare.csv"
    argv = ["compare", "--design", "rho-inc", "--baseline", "MD", "--controls", "none", *SHORT, "--timestep", "auto"]
    argv += ["--workers", "1", "--cache", str(tmp_path / "cache"), "--csv", str(out), "--no-progress"]
    assert main(argv) == 0
    printed = capsys.readouterr().out
    assert "every leg at dt=5e-05 s" in printed and f"wrote 1 rows to {out}" in printed
    # the header names the replicates' protocol and where this run's push falls: inside its own scored window
    assert "replicate protocol authors, each seed's push drawn in " in printed
    table = pd.read_csv(out)
    assert table["comparator"].tolist() == ["MD"] and table["n_pairs"].tolist() == [2]
    assert table["timestep_s"].tolist() == [5e-5] and table["seeds"].tolist() == ["0 1"]
    verdicts = [table[f"{m}_verdict"].iloc[0] for m in ("tracking_error_m", "power_w", "hop_height_m")]
    assert "untestable with n = 2 seeds; use --replicates 6 or more" in verdicts
    assert "untestable with n = 2 seeds; use --replicates 6 or more" in printed
    assert "with n = 2 seeds no difference can be significant here" in printed
    assert {"power_w_pct_change", "power_w_ci_low", "power_w_ci_high", "power_w_p_holm"} <= set(table.columns)
    # a second call: every run from the cache
    assert main([*argv[:-3], "--no-progress"]) == 0
    assert "4 runs (4 from the cache, 0 computed)" in capsys.readouterr().out


def test_a_diverging_comparator_is_warned_of_before_and_exits_1(tmp_path, capsys):
    """CFRP's paper springs diverge at the 1e-4 s step: compare names it
    on stderr before any run, leaves it out with why, and exits 1 (a run
    asked for diverged), though the other comparator's table is printed."""
    argv = ["compare", "--design", "SS", "--baseline", "CFRP,Ti", "--controls", "none", *SHORT, "--replicates", "2"]
    argv += ["--workers", "1", "--cache", str(tmp_path / "cache"), "--no-progress"]
    assert main(argv) == 1
    cap = capsys.readouterr()
    assert "mat-hopper compare: warning: CFRP (baseline): the physics step 0.0001 s is above" in cap.err
    assert "--timestep auto" in cap.err and "SS (design)" not in cap.err and "Ti (baseline)" not in cap.err
    assert "left out: CFRP (baseline, seeds 0 1): unstable at dt=1e-4 s" in cap.out
    assert "comparator" in cap.out and "Ti" in cap.out
