import os
import subprocess
import sys

import pandas as pd
import pytest

from mat_hopper.cli import main

REQUIRED = ["design", "behaviour", "hop", "t_start_s", "hop_height_m", "tracking_error_m", "jerk_m_s3", "power_w"]


@pytest.mark.parametrize(
    "args, name",
    [
        (["--design", "ss"], "SS"),
        (["--design", "PVC-Ti-SS"], "PVC-Ti-SS"),
        (["--design", "rho-inc"], "rho-inc"),
        (["--design", "rho-dec"], "rho-dec"),
        (["--density", "1.39,4.43,8", "--modulus", "70,70,70"], None),
    ],
)
def test_simulate_every_design_form(tmp_path, args, name, capsys):
    out = tmp_path / "hops.csv"
    rc = main(["simulate", *args, "--behavior", "forward", "--duration", "5", "--transient", "2", "--csv", str(out)])
    assert rc == 0
    table = pd.read_csv(out)
    assert set(REQUIRED) <= set(table.columns) and len(table) >= 2
    if name:
        assert (table.design == name).all()
    assert "hop cycles scored" in capsys.readouterr().out


@pytest.mark.parametrize(
    "args, message",
    [
        (["--design", "kryptonite"], "unknown material"),
        (["--behaviour", "moonwalk"], "unknown behaviour"),
        (["--convention", "beam"], "convention"),
        (["--density", "1,0,3", "--modulus", "4,4,4"], "density"),
        (["--density", "1,2,3", "--modulus", "4,nan,4"], "modulus"),
        (["--density", "1,2,3", "--modulus", "-4,4,4"], "modulus"),
        (["--timestep", "0"], "timestep"),
        (["--duration", "10"], "duration"),
        (["--segments", "0"], "--segments must be"),
    ],
)
def test_bad_input_one_line_exit_2_no_file(tmp_path, capsys, args, message):
    """In this process (the package's import paid once per worker, not 3-20 s
    per case under load); :func:`test_bad_input_in_a_fresh_interpreter`
    runs one case as a user does."""
    out = tmp_path / "hops.csv"
    capsys.readouterr()
    try:
        rc = main(["simulate", *args, "--csv", str(out)])
    except SystemExit as e:  # argparse's errors
        rc = e.code
    err = capsys.readouterr().err
    assert rc == 2, err
    lines = err.strip().splitlines()
    assert len(lines) == 1 and message in lines[0], err
    assert not out.exists() and os.listdir(tmp_path) == []


def test_bad_input_in_a_fresh_interpreter(tmp_path):
    """``python -m mat_hopper`` with a bad option: one line, exit 2, nothing
    else printed at import, no file."""
    out = tmp_path / "hops.csv"
    p = subprocess.run(
        [sys.executable, "-m", "mat_hopper", "simulate", "--design", "SS", "--duration", "-5", "--csv", str(out)],
        capture_output=True,
        text=True,
    )
    assert p.returncode == 2 and p.stdout == "", p.stderr
    assert len(p.stderr.strip().splitlines()) == 1 and "--duration" in p.stderr, p.stderr
    assert os.listdir(tmp_path) == []
