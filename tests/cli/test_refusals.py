"""The command line: every bad input is one line and exit code 2, found
before any simulation, and leaves nothing behind; every option acts or is
refused; run sizes are capped; signals and closed pipes end cleanly. Each
expected value is the right behaviour."""

from __future__ import annotations

import os
import re
import signal
import subprocess
import sys
import time

import numpy as np
import pandas as pd
import pytest
from _refusal import refused

from mat_hopper.cli import main
from mat_hopper.cli._checks import negative_list_argv, parse_list, parse_pair
from mat_hopper.cli.simulate import run_with_progress
from mat_hopper.core.materials import parse_design
from mat_hopper.core.sim import SimSettings, simulate
from mat_hopper.util.atomic import remove_stale_mp_dirs

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
ENV = {**os.environ, "PYTHONPATH": REPO + os.pathsep + os.environ.get("PYTHONPATH", "")}
ENV.pop("MAT_HOPPER_PROFILE", None)
# A run that takes many seconds: a check that fails fast proves it came first.
LONG = ["--duration", "3000", "--transient", "1"]


@pytest.fixture
def here(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    monkeypatch.delenv("MAT_HOPPER_PROFILE", raising=False)
    (tmp_path / "a_file").write_text("x")
    (tmp_path / "a_folder").mkdir()
    return tmp_path


def _made(root, before=("a_file", "a_folder")):
    return sorted(set(os.listdir(root)) - set(before))


# --- 1. output paths checked before any simulation -----------------------------


@pytest.mark.parametrize(
    "argv, text",
    [
        (["simulate", *LONG, "--csv", "a_file/x.csv"], "a_file is a file, not a folder"),
        (["simulate", *LONG, "--csv", "a_folder"], "--csv a_folder: is a folder"),
        (["render", "--seconds", "3000", "--video", "a_file/v.mp4"], "a_file is a file, not a folder"),
        (["render", "--tiles", "a_folder", "--seconds", "1"], "--tiles a_folder: is a folder"),
        (["reproduce", "--profile", "quick", "--cache", "a_file"], "--cache a_file: is a file, not a folder"),
        (["reproduce", "--profile", "quick", "--out", "a_file"], "--out a_file: is a file, not a folder"),
        (["reproduce", "--profile", "quick", "--out", "a_file/sub"], "a_file is a file, not a folder"),
    ],
)
def test_bad_output_paths_fail_before_any_work(here, capsys, argv, text):
    refused(argv, capsys, text)  # within 10 s: the 3000 s run never started
    assert _made(here) == []


def _read_only_folder(tmp_path):
    """A folder this process cannot write into: a chmod 555 folder, or, for
    root (who writes anywhere), a read-only mount such as /proc/sys."""
    if os.geteuid() != 0:
        ro = tmp_path / "ro"
        ro.mkdir()
        os.chmod(ro, 0o555)
        return str(ro)
    for path in ("/proc/sys", "/sys/fs"):
        if os.path.isdir(path) and not os.access(path, os.W_OK):
            return path
    pytest.skip("running as root without a read-only mount: no folder root cannot write")


@pytest.mark.parametrize(
    "argv, flag",
    [
        (["simulate", *LONG, "--csv", "{ro}/x.csv"], "--csv"),
        (["render", "--still", "{ro}/x.png"], "--still"),
        (["reproduce", "--profile", "quick", "--out", "{ro}/out", "--cache", "cache"], "--out"),
        (["reproduce", "--profile", "quick", "--out", "out", "--cache", "{ro}"], "--cache"),
    ],
)
def test_read_only_output_folder_is_refused_before_work(here, capsys, argv, flag):
    ro = _read_only_folder(here)
    before = sorted(os.listdir(ro))
    argv = [a.replace("{ro}", ro) for a in argv]
    refused(argv, capsys, "is not writable")
    assert sorted(os.listdir(ro)) == before and _made(here, ("a_file", "a_folder", "ro")) == []


# --- 2. run sizes ----------------------------------------------------------------


@pytest.mark.parametrize(
    "argv, text",
    [
        (["simulate", "--duration", "1e9"], "over the limit of 2e+09"),
        (["simulate", "--timestep", "1e-300"], "over the limit of 2e+09"),
        (["simulate", "--segments", "10000"], "--segments must be an integer in [1, 64]"),
        (["simulate", "--segments", "65"], "--segments must be an integer in [1, 64]"),
        (["render", "--start", "1e9", "--tiles", "x.png"], "over the limit of 2e+09"),
        (["render", "--seconds", "1e9", "--video", "x.mp4"], "over the limit of 2e+09"),
        (["render", "--segments", "10000", "--still", "x.png"], "--segments must be an integer in [1, 64]"),
        (["render", "--seconds", "-1", "--video", "x.mp4"], "--seconds must be > 0"),
        (["simulate", "--duration", "4000", "--transient", "1", "--timestep", "1e-6"], "4e+09 physics steps"),
    ],
)
def test_run_sizes_refused_before_work(here, capsys, argv, text):
    refused(argv, capsys, text)  # within 10 s
    assert _made(here) == []


def test_chunked_rollout_with_progress_is_bit_identical():
    design = parse_design("SS")
    s = SimSettings(duration_s=2.5, transient_s=0.5)
    chunked = run_with_progress(design, "forward", s, progress=True)
    whole = simulate(design, "forward", settings=s)
    assert np.array_equal(chunked.data, whole.data, equal_nan=True)
    assert np.array_equal(chunked.events, whole.events, equal_nan=True)


# --- 3. physical ranges -------------------------------------------------------------


@pytest.mark.parametrize(
    "argv, text",
    [
        (["--density", "1e30,1,1", "--modulus", "70,70,70"], "density of seg1 must be in [0.001, 30] g/cm^3"),
        (["--density", "1e-30,1,1", "--modulus", "70,70,70"], "density of seg1 must be in [0.001, 30] g/cm^3"),
        (["--density", "8", "--modulus", "1e-30"], "modulus of seg1 must be in [1e-06, 2000] GPa"),
        (["--density", "8", "--modulus", "1e30"], "modulus of seg1 must be in [1e-06, 2000] GPa"),
        (["--density", "0,1,2", "--modulus", "70,70,70"], "--density must be > 0 g/cm^3"),
    ],
)
def test_physical_ranges_named(here, capsys, argv, text):
    refused(["simulate", *LONG, *argv], capsys, text)
    assert "mjMINVAL" not in text


# --- 4. options act or are refused, parsed one way -----------------------------------


@pytest.mark.parametrize(
    "argv, text",
    [
        (["--density", "1,,2", "--modulus", "70,70,70"], "(an empty item)"),
        (["--density", "1,2,", "--modulus", "70,70,70"], "(an empty item)"),
        (["--density", "1,2,3", "--modulus", "70,,70,70"], "(an empty item)"),
        (["--density", "1,x,3", "--modulus", "70,70,70"], "--density must be comma-separated numbers"),
        (["--density", "1,2,3", "--modulus", "70,nan,70"], "not finite"),
        # argparse would answer "expected one argument": the value is a negative number list
        (["--density", "-1,2,3", "--modulus", "1,1,1"], "--density must be > 0 g/cm^3"),
        (["--density=-1,2,3", "--modulus", "1,1,1"], "--density must be > 0 g/cm^3"),
        (["--density", "1,2,3", "--modulus", "-70,70,70"], "--modulus must be > 0 GPa"),
        (["--sensor-timing", "soon"], "unknown sensor timing 'soon'"),
        (["--sensor-timing", "-3"], "--sensor-timing: must be in [0, 1000] physics steps, got '-3'"),
        (["--segment-mass", "blob"], "invalid choice: 'blob'"),
        (["--timestep", "fast"], "or 'auto'"),
        (["--bogus"], "unrecognized arguments: --bogus"),
        (["--duration", "ten"], "argument --duration: must be a decimal number"),
        (["--profile", "turbo"], "unknown profile 'turbo'"),
    ],
)
def test_simulate_options_refused_in_one_line(here, capsys, argv, text):
    refused(["simulate", *LONG, *argv], capsys, text)
    assert _made(here) == []


def test_unknown_profile_from_the_environment_is_refused(here, capsys, monkeypatch):
    monkeypatch.setenv("MAT_HOPPER_PROFILE", "turbo")
    refused(["simulate"], capsys, "unknown profile 'turbo' (from $MAT_HOPPER_PROFILE)")


def test_simulate_honours_the_profile_and_records_its_settings(here, capsys, monkeypatch):
    monkeypatch.setenv("MAT_HOPPER_PROFILE", "quick")
    argv = ["simulate", "--design", "Al", "--sensor-timing", "fresh", "--segment-mass", "capsule", "--csv", "h.csv"]
    assert main(argv) == 0
    out = capsys.readouterr().out
    assert "12 s (quick profile)" in out and "after 4 s" in out  # the quick profile: 12 s runs, 4 s transient
    t = pd.read_csv(here / "h.csv")
    assert (t.sensor_timing == "fresh").all() and (t.segment_mass == "capsule").all()
    assert (t.timestep_s == 1e-4).all() and (t.substeps == 1).all()
    assert t.t_start_s.min() >= 4.0 and t.t_end_s.max() <= 12.0


def test_timestep_auto_prints_and_records_the_chosen_step(here, capsys):
    argv = ["simulate", "--design", "SS", "--timestep", "auto", "--duration", "1", "--transient", "0.2"]
    assert main([*argv, "--csv", "h.csv"]) in (0, 1)
    out = capsys.readouterr().out
    # SS's spring bound puts the step below the 1e-4 s control period: 2 substeps of 5e-5 s
    assert "dt=5e-05 s (2 physics substeps per 0.0001 s control period)" in out
    t = pd.read_csv(here / "h.csv")
    assert list(t.columns[:7]) == [
        "design",
        "behaviour",
        "convention",
        "sensor_timing",
        "segment_mass",
        "timestep_s",
        "substeps",
    ]


def test_render_honours_timestep(here, capsys):
    """At 1e-3 s SS diverges in 0.009 s (simulate says UNSTABLE); the render
    must simulate that same run, not a stable one at 1e-4 s."""
    assert main(["simulate", "--timestep", "1e-3", "--duration", "1", "--transient", "0.1"]) == 1
    out = capsys.readouterr().out
    t_div = float(re.search(r"UNSTABLE: diverged at t = ([0-9.]+) s", out).group(1))
    assert t_div < 0.05
    argv = ["render", "--timestep", "1e-3", "--tile-start", "0", "--tiles", "t.png"]  # a 1 s run
    argv += ["--sensor-timing", "authors", "--segment-mass", "leg"]
    assert main(argv) == 1  # a diverged run exits 1 in every command; the tiles stop at it
    out = capsys.readouterr().out
    assert "dt=0.001 s" in out and f"diverged at t = {t_div:.4f} s" in out
    assert (here / "t.png").stat().st_size > 0


def test_one_list_parser():
    assert parse_list("1, 2.5,3e1", "--x") == [1.0, 2.5, 30.0]
    assert parse_list("8,rigid,RIGID", "--modulus", rigid=True) == [8.0, None, None]
    assert parse_pair("0.5,20", "--density-bounds") == (0.5, 20.0)
    for bad in ("1,,2", ",1", "1,", "", "a", "1,inf"):
        with pytest.raises(ValueError, match="--x must be comma-separated numbers"):
            parse_list(bad, "--x")
    with pytest.raises(ValueError, match="two numbers MIN,MAX"):
        parse_pair("1,2,3", "--density-bounds")
    argv = ["simulate", "--density", "-1,2", "--modulus", "-7", "--design", "-x", "--timestep", "1e-4"]
    assert negative_list_argv(argv, ("--density", "--modulus")) == [
        "simulate",
        "--density=-1,2",
        "--modulus=-7",
        "--design",
        "-x",
        "--timestep",
        "1e-4",
    ]


# --- 1. a failed command leaves nothing behind ------------------------------------


@pytest.mark.slow  # Dask tries the dead address for its full 20 s timeout
def test_unreachable_scheduler_leaves_no_folder(here, capsys):
    argv = ["reproduce", "--profile", "quick", "--experiments", "1", "--scheduler", "tcp://127.0.0.1:1"]
    argv += ["--out", "out", "--cache", "cache"]
    refused(argv, capsys, "cannot reach the Dask scheduler at 'tcp://127.0.0.1:1'", max_wall_s=60.0)
    assert _made(here) == []
    refused(["reproduce", "--profile", "quick", "--scheduler", "tcp://127.0.0.1:1"], capsys, "Dask", max_wall_s=60.0)
    assert _made(here) == []  # neither results/quick nor results/cache


# --- 5 and 9. signals, closed pipes, temp folders ---------------------------------


def test_closed_pipe_is_not_a_traceback(tmp_path):
    p = subprocess.Popen(
        [sys.executable, "-m", "mat_hopper", "simulate", "--duration", "3", "--transient", "1"],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        env=ENV,
        cwd=tmp_path,
    )
    p.stdout.close()  # `| head` that has gone away
    err = p.stderr.read().decode()
    p.wait(120)
    assert "Traceback" not in err and "BrokenPipeError" not in err, err
    assert p.returncode == 141


def test_sigterm_on_reproduce_leaves_no_temp_folder_nor_partial_file(tmp_path, short_tmp):
    """SIGTERM is handled like Ctrl-C: the pool stops, multiprocessing's
    pymp-* folder is removed, every cached file is whole."""
    tmp = short_tmp  # the fork server's socket lives here: a short path (conftest)
    env = {**ENV, "TMPDIR": str(tmp)}
    cmd = [sys.executable, "-m", "mat_hopper", "reproduce", "--profile", "quick", "--experiments", "1"]
    cmd += ["--out", str(tmp_path / "out"), "--cache", str(tmp_path / "cache"), "--no-progress", "--workers", "2"]
    p = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, env=env, text=True)
    # generous bounds: on a fresh checkout every pool worker compiles the
    # loop first, and under CI's load (4 test workers and the book's kernels
    # on 2 cores) the first result took over 120 s (CI stop 24 failed here)
    deadline = time.monotonic() + 900
    cache = tmp_path / "cache"
    # once the pool's workers run (the first result stored): a kill during the
    # pool's own start-up meets a CPython race (a worker still unpickling its
    # queue's semaphore when the parent removes it), not ours
    while not (cache.is_dir() and [n for n in os.listdir(cache) if n.endswith(".parquet") and n[0] != "."]):
        if p.poll() is not None or time.monotonic() > deadline:
            p.kill()
            out, err = p.communicate()
            pytest.fail(f"no result stored (exit {p.returncode}): {err[-2000:]}")
        time.sleep(0.1)
    assert [n for n in os.listdir(tmp) if n.startswith("pymp-")], "no multiprocessing temp folder to remove"
    p.send_signal(signal.SIGTERM)
    out, err = p.communicate(timeout=600)  # the pool finishes the runs under way
    assert p.returncode == 128 + signal.SIGTERM, err
    assert err.strip().splitlines()[-1] == "interrupted by SIGTERM", err
    assert [n for n in os.listdir(tmp) if n.startswith("pymp-")] == []
    import pyarrow.parquet as pq

    stored = os.listdir(cache)
    assert stored and not [f for f in stored if f.startswith(".")]  # finished results kept, no temp file
    for f in stored:
        pq.read_table(cache / f)  # whole files only


def test_stale_temp_folders_of_killed_runs_are_removed(tmp_path):
    import socket

    old = time.time() - 3600
    for name in ("pymp-empty", "pymp-deadsock", "pymp-live", "pymp-young", "pymp-files", "other"):
        (tmp_path / name).mkdir()
    dead = socket.socket(socket.AF_UNIX)
    dead.bind(str(tmp_path / "pymp-deadsock" / "listener-1"))
    dead.close()  # the file stays, nobody has it bound: a killed forkserver's
    live = socket.socket(socket.AF_UNIX)
    live.bind(str(tmp_path / "pymp-live" / "listener-2"))
    live.listen()
    (tmp_path / "pymp-files" / "data.bin").write_bytes(b"x")
    for name in ("pymp-empty", "pymp-deadsock", "pymp-live", "pymp-files", "other"):
        os.utime(tmp_path / name, (old, old))
    try:
        removed = remove_stale_mp_dirs(str(tmp_path))
    finally:
        live.close()
    assert sorted(os.path.basename(r) for r in removed) == ["pymp-deadsock", "pymp-empty"]
    assert sorted(os.listdir(tmp_path)) == ["other", "pymp-files", "pymp-live", "pymp-young"]


@pytest.mark.parametrize(
    "csv, text", [("a_folder", "--csv a_folder: is a folder"), ("a_file/x.csv", "a_file is a file, not a folder")]
)
def test_batch_csv_checked_before_work(here, capsys, csv, text):
    refused(["batch", "--designs", "SS,PVC", "--duration", "3000", "--transient", "1", "--csv", csv], capsys, text)
    assert _made(here) == []


@pytest.mark.parametrize(
    "args, text",
    [
        (["--conventions", "paper,,axial"], "(an empty item)"),
        (["--conventions", "paper,"], "(an empty item)"),
        (["--experiments", "3,,3"], "(an empty item)"),
        (["--experiments", "1,1"], "names an item twice"),
    ],
)
def test_reproduce_refuses_malformed_name_lists_before_work(args, text, tmp_path, capsys):
    """Malformed name lists are refused, never read as a full reproduction."""
    code = main(["reproduce", "--profile", "quick", "--out", str(tmp_path / "out"), *args])
    err = capsys.readouterr().err.strip()
    assert code == 2 and len(err.splitlines()) == 1 and text in err, err
    assert not (tmp_path / "out").exists()
