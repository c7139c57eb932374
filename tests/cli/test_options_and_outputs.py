"""Command-line faults, each as a kind with its examples and other doors.
Checks before any output; numbers through the one parser; messages that
name flags; no option or environment variable silently ignored; no output
over an input; a stage cut short says "stopped"; and the summaries' and
messages' wording."""

from __future__ import annotations

import os
import re
import signal
import subprocess
import sys
import time

import pytest
from _refusal import refused as _refused

from mat_hopper.cli import main

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
ENV = {**os.environ, "PYTHONPATH": REPO + os.pathsep + os.environ.get("PYTHONPATH", "")}
ENV.pop("MAT_HOPPER_PROFILE", None)
LONG = ["--duration", "3000", "--transient", "1"]  # minutes of work: a refusal that is fast came first
SHORT = ["--duration", "2", "--transient", "1"]  # where the fault ran the command: it ends (and the test fails)
DESIGN_TABLE = "density_1,density_2,density_3,modulus_1,modulus_2,modulus_3\n8,8,8,193,193,193\n"


@pytest.fixture
def here(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    for var in ("MAT_HOPPER_PROFILE", "MAT_HOPPER_MAX_STEPS", "MAT_HOPPER_CACHE"):
        monkeypatch.delenv(var, raising=False)
    return tmp_path


# --- 1. every option checked before any output ----------------------------------


@pytest.mark.parametrize(
    "argv, texts",
    [
        # e.g. the modes table, or render's design header, must not come first
        (["modes", "--sensor-timing", "late"], ("--sensor-timing", "'late'")),
        (["modes", "--sensor-timing", "2000"], ("--sensor-timing", "[0, 1000]")),
        (["modes", "--sensor-timing", "99999999999"], ("--sensor-timing", "[0, 1000]")),
        (["render", "--video", "v.mp4", "--seconds", "5", "--fps", "1000000"], ("--fps", "(0, 240]")),
        # other doors: render's behaviour after its header; a count of bending modes after the axial table
        (["render", "--still", "s.png", "--behaviour", "nope"], ("behaviour", "'nope'")),
        (["modes", "--convention", "axial+bending", "--modes", "4"], ("--modes 4",)),
        (["modes", "--convention", "bending", "--modes", "10"], ("--modes 10", "3 bending modes")),
        (["batch", "--designs", "SS", "--sensor-timing", "late", *LONG], ("--sensor-timing",)),
    ],
)
def test_every_option_is_checked_before_any_output(here, capsys, argv, texts):
    cap = _refused(argv, capsys, *texts)
    assert cap.out == ""
    assert os.listdir(here) == []


# --- 2. numbers: ASCII decimals, one parser ---------------------------------------


@pytest.mark.parametrize(
    "argv, texts",
    [
        # e.g. an Arabic-Indic 3 must not run as latency 3, nor a superscript 2 leak int()'s words
        (["simulate", "--sensor-timing", "٣", *SHORT], ("--sensor-timing", "'٣'")),
        (["simulate", "--sensor-timing", "²", *SHORT], ("--sensor-timing", "'²'")),
        # other doors: latency-L, a fraction, --timestep (float()), --size (int()), --leg-mass (float())
        (["simulate", "--sensor-timing", "latency-٣", *SHORT], ("--sensor-timing",)),
        (["simulate", "--sensor-timing", "1.5", *SHORT], ("--sensor-timing", "whole number")),
        (["simulate", "--timestep", "١e-4", *SHORT], ("--timestep", "decimal number")),
        (["simulate", "--timestep", "1_0e-5", *SHORT], ("--timestep", "decimal number")),
        (["render", "--still", "s.png", "--size", "٦٤٠x٤٨٠"], ("--size", "WIDTHxHEIGHT")),
        (["optimize", "--study", "s", "--trials", "1", "--profile", "quick", "--leg-mass", "٣"], ("--leg-mass",)),
    ],
)
def test_numbers_go_through_the_one_parser(here, capsys, argv, texts):
    _refused(argv, capsys, *texts)
    assert os.listdir(here) == []


def test_sensor_timing_names_and_latencies():
    from mat_hopper.cli._checks import sensor_timing_arg
    from mat_hopper.core.controller import SensorTiming

    assert [int(sensor_timing_arg(t)) for t in ("FRESH", " authors ", "latency-7", "7", "0")] == [0, 1, 7, 7, 0]
    t = SensorTiming(3)
    assert sensor_timing_arg(t) is t
    for bad in ("٣", "²", "latency-²", "0x1", "+", "", "1001", "latency-"):
        with pytest.raises(ValueError, match="^--sensor-timing"):
            sensor_timing_arg(bad)


def test_the_command_line_reads_no_number_behind_the_parser():
    """No isdigit() or int()/float() of typed text in mat_hopper/cli: numbers
    go through mat_hopper.util.parsing (argparse's type=int/float are replaced by
    it, see _checks.harden_parser)."""
    pattern = re.compile(r"\.isdigit\(|\.isnumeric\(|\b(?:int|float)\((?:(?:text|s|value)\b|args\.(?!func))")
    folder = os.path.join(REPO, "mat_hopper", "cli")
    for name in sorted(os.listdir(folder)):
        if name.endswith(".py"):
            with open(os.path.join(folder, name), encoding="utf-8") as f:
                for i, line in enumerate(f, 1):
                    assert not pattern.search(line), f"{name}:{i}: {line.strip()}"


# --- 3. messages name flags, not Python parameters ----------------------------------

PARAMETERS = re.compile(r"(?<![-\w$])(replicates|size|fps|risk|cvar_alpha|leg_mass_tolerance_kg|leg_mass)\b")


@pytest.mark.parametrize(
    "argv, text",
    [
        (["optimize", "--study", "s", "--replicates", "100000"], "--replicates must be an integer in [0, 64]"),
        (["render", "--still", "s.png", "--size", "100000x100000"], "--size must be between"),
        (["optimize", "--study", "s", "--risk", "cvar", "--cvar-alpha", "1.5"], "--cvar-alpha must be in [0, 1)"),
        (["optimize", "--study", "s", "--leg-mass-tolerance", "-1"], "--leg-mass-tolerance must be"),
        (["optimize", "--study", "s", "--leg-mass-tolerance", "0.1"], "--leg-mass-tolerance needs --leg-mass"),
        # other doors
        (["optimize", "--study", "s", "--risk", "cvar", "--replicates", "1"], "--risk cvar needs --replicates >= 2"),
        (["optimize", "--study", "s", "--risk", "worst"], "unknown --risk 'worst'"),
        (["optimize", "--study", "s", "--leg-mass", "steel"], "--leg-mass: a paper design"),
        (["render", "--video", "v.mp4", "--fps", "0"], "--fps must be in (0, 240]"),
        (["render", "--still", "s.png", "--size", "640 x"], "--size must be WIDTHxHEIGHT"),
    ],
)
def test_messages_name_the_flags_not_the_parameters(here, capsys, argv, text):
    cap = _refused(argv, capsys, text)
    assert not PARAMETERS.search(cap.err.split("error: ", 1)[1]), cap.err
    assert os.listdir(here) == []


# --- 4. no option, and no environment variable, silently ignored --------------------


@pytest.mark.parametrize(
    "argv, texts",
    [
        # each would otherwise exit 0, the option unused
        (["render", "--still", "s.png", "--fps", "60", "--seconds", "3"], ("--fps", "--still")),
        (["optimize", "--study", "s", "--trials", "1", "--profile", "quick", "--cvar-alpha", "0.5"], ("--cvar-alpha",)),
        (["optimize", "--study", "s", "--trials", "1", "--profile", "quick", "--render"], ("--render", "--replay")),
        (["optimize", "--report", "s", "--trials", "7", "--sampler", "gp", "--workers", "3"], ("--trials", "--report")),
        (["optimize", "--study", "s", "--export", "0", "--replay", "0", "--out", "ex"], ("--export", "--replay")),
        (["optimize", "--study", "s", "--export", "0", "--trials", "50"], ("--trials", "--export")),
        (
            ["optimize", "--study", "s", "--space", "catalogue", "--materials", "ti,SS", "--density-bounds", "1,2"],
            ("--density-bounds", "--space catalogue"),
        ),
        (
            ["optimize", "--study", "s", "--storage", "sqlite:///x.db", "--studies-dir", "o"],
            ("--storage", "--studies-dir"),
        ),
        # other doors
        (["render", "--tiles", "t.png", "--size", "100x100"], ("--size", "--tiles")),
        (["render", "--tiles", "t.png", "--seconds", "3"], ("--seconds", "--tiles")),
        (["render", "--video", "v.mp4", "--tile-start", "1"], ("--tile-start", "--video")),
        (["render", "--still", "s.png", "--start", "2"], ("--start", "--still")),
        (["render", "--still", "s.png", "--convention", "axial"], ("--convention", "--still")),
        (["render", "--still", "s.png", "--sensor-timing", "fresh"], ("--sensor-timing", "--still")),
        (["optimize", "--study", "s", "--trials", "1", "--materials", "Ti"], ("--materials", "--space")),
        (
            ["optimize", "--study", "s", "--trials", "1", "--modulus-bounds", "1,9", "--space", "catalogue"],
            ("--modulus",),
        ),
        (["optimize", "--study", "s", "--trials", "1", "--out", "o"], ("--out",)),
        (["optimize", "--study", "s", "--replay", "0", "--out", "o"], ("--out", "--replay")),
        (["optimize", "--report", "s", "--seed", "3"], ("--seed", "--report")),
        (["optimize", "--study", "s", "--replay", "0", "--convention", "axial"], ("--convention", "--replay")),
        (["optimize", "--study", "a", "--report", "b"], ("--study a", "--report b")),
        (["simulate", "--profile", "quick", "--timestep", "1e-4", *SHORT], ("--profile", "--duration")),
    ],
)
def test_options_that_would_be_ignored_are_refused_naming_the_pair(here, capsys, argv, texts):
    _refused(argv, capsys, *texts)
    assert os.listdir(here) == []


@pytest.mark.parametrize(
    "var, value, argv",
    [
        ("MAT_HOPPER_PROFILE", "", ["simulate", *SHORT]),  # ran the paper profile
        ("MAT_HOPPER_CACHE", " ", ["reproduce", "--out", "r"]),  # blamed --cache, never typed
        ("MAT_HOPPER_PROFILE", " ", ["batch", "--designs", "SS", *SHORT]),
        ("MAT_HOPPER_PROFILE", "", ["optimize", "--study", "s", "--trials", "1"]),
        ("MAT_HOPPER_MAX_STEPS", " ", ["batch", "--designs", "SS", *SHORT]),
    ],
)
def test_an_empty_environment_variable_is_refused_naming_it(here, capsys, monkeypatch, var, value, argv):
    monkeypatch.setenv(var, value)
    cap = _refused(argv, capsys, f"${var} is set but empty")
    assert "--cache" not in cap.err and "--profile" not in cap.err
    assert os.listdir(here) == []


# --- 5. an output never over an input -------------------------------------------------


@pytest.mark.parametrize("force", [[], ["--force"]])  # --force replaces outputs, never an input
def test_an_output_never_overwrites_an_input(here, capsys, force):
    (here / "d.csv").write_text(DESIGN_TABLE)
    os.symlink("d.csv", here / "link.csv")
    for argv in (
        ["batch", "--designs-csv", "d.csv", "--csv", "d.csv", *SHORT],
        ["simulate", "--design-csv", "d.csv", "--csv", "./d.csv", *SHORT],
        ["simulate", "--design-csv", "link.csv", "--csv", "sub/../d.csv", *SHORT],  # a symlink, a ..
        ["batch", "--designs-csv", "link.csv", "--csv", str(here / "d.csv"), *SHORT],
        ["render", "--design-csv", "d.png", "--still", "./d.png"],
    ):
        flag = "--designs-csv" if argv[0] == "batch" else "--design-csv"
        _refused([*argv, *force], capsys, "--still" if argv[0] == "render" else "--csv", flag, "overwrite")
    assert (here / "d.csv").read_text() == DESIGN_TABLE
    assert sorted(os.listdir(here)) == ["d.csv", "link.csv"]


def test_reproduce_refuses_results_inside_the_cache_folder(here, capsys, monkeypatch):
    """--out r/c --cache r: clearing the cache would delete the results. (A
    tiny step limit: were the check missing, the run is refused for its
    size, with other words, instead of starting.)"""
    monkeypatch.setenv("MAT_HOPPER_MAX_STEPS", "1")
    _refused(["reproduce", "--out", "r/c", "--cache", "r"], capsys, "--out", "inside --cache")
    _refused(["reproduce", "--out", "r/c/../c", "--cache", "./r/"], capsys, "inside --cache")
    monkeypatch.setenv("MAT_HOPPER_CACHE", "r")
    _refused(["reproduce", "--out", "r/c"], capsys, "inside $MAT_HOPPER_CACHE")
    assert os.listdir(here) == []


# --- 6. a stage cut short says so; a read-only use leaves no files ----------------------


def test_a_stage_cut_short_says_stopped_not_done():
    import io

    from mat_hopper.util.progress import StageLines

    log = io.StringIO()
    with pytest.raises(KeyboardInterrupt):  # the callers' pattern: close() in a finally
        bar = StageLines(total=100, desc="X", unit="sim s", file=log)
        try:
            bar.update(3)
            raise KeyboardInterrupt
        finally:
            bar.close()
    with pytest.raises(ValueError), StageLines(total=3, desc="Y", file=log):
        raise ValueError
    for _ in StageLines([1, 2, 3], desc="Z", file=log):
        break
    with StageLines(total=1, desc="W", file=log) as bar:
        bar.update(1)
    lines = log.getvalue().splitlines()
    assert [line.split(",")[0] for line in lines] == [
        *("X: started", "X: stopped", "Y: started", "Y: stopped"),
        *("Z: started", "Z: stopped", "W: started", "W: done"),
    ]
    assert lines[1].startswith("X: stopped, 3/100 sim s in ")


def test_sigterm_in_a_pipe_says_stopped_then_interrupted(tmp_path):
    """Never "X: done, 0/100 sim s" before "interrupted"."""
    cmd = [sys.executable, "-m", "mat_hopper", "simulate", "--duration", "1000", "--transient", "1"]
    p = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True, env=ENV, cwd=tmp_path)
    try:
        first = p.stderr.readline()  # the stage's first line: the run has started
        assert first.startswith("SS: started"), first
        time.sleep(1.0)
        p.send_signal(signal.SIGTERM)
        rest = p.stderr.read()
        assert p.wait(timeout=120) == 143
    finally:
        if p.poll() is None:
            p.kill()
    lines = rest.strip().splitlines()
    assert lines[-2].startswith("SS: stopped, ") and lines[-1] == "interrupted by SIGTERM", rest
    assert "done," not in rest


def test_export_leaves_no_wal_files_beside_the_study(here, capsys):
    import optuna

    from mat_hopper.experiments.profiles import Profile
    from mat_hopper.optimize import (
        Objective,
        PoolEvaluator,
        RunOptions,
        SearchSpace,
        StudyConfig,
        create_or_load,
        default_url,
        dispose,
        open_storage,
        run_loop,
    )

    optuna.logging.set_verbosity(optuna.logging.WARNING)
    config = StudyConfig("s", SearchSpace(), Objective(profile=Profile("tiny", duration_s=1.0, transient_s=0.5)))
    os.mkdir("studies")
    storage = open_storage(default_url("s", "studies"))
    with PoolEvaluator("cache", workers=1) as evaluator:
        run_loop(create_or_load(config, storage), storage, config, evaluator, RunOptions(trials=1, progress=False))
    dispose(storage)
    assert os.listdir("studies") == ["s.db"]  # the writer, closed, left no -wal/-shm
    assert main(["optimize", "--study", "s", "--export", "0", "--out", "ex"]) == 0
    assert "wrote ex/s-trial0.csv" in capsys.readouterr().out
    assert os.listdir("studies") == ["s.db"]


# --- 7. summaries and messages that say what they mean -------------------------------


def test_simulate_summary_labels_hip_power_and_the_work_of_all_actuators(here, capsys):
    """On static, "0 W" beside "32 J" read as a contradiction: the labels say why."""
    assert main(["simulate", "--design", "SS", "--behaviour", "static", *SHORT]) == 0
    out = capsys.readouterr().out
    line = next(x for x in out.splitlines() if x.startswith("power_w:"))
    assert line.startswith("power_w: hip actuators only (mean mechanical power)")
    assert "work of all three actuators (hips and leg slide)" in line and " J per hop" in line


def test_optimize_help_names_the_enqueued_paper_designs(capsys):
    from mat_hopper.optimize import PAPER_SEEDS, SearchSpace

    with pytest.raises(SystemExit):
        main(["optimize", "--help"])
    text = " ".join(capsys.readouterr().out.split())  # argparse wraps the lines
    seeds = [name for name, _ in SearchSpace().seeds()]
    assert len(seeds) == 8 and f"8 of {len(PAPER_SEEDS)} in the default continuous space" in text
    assert f"({', '.join(seeds)}; not MD" in text


def test_docs_name_only_test_paths_that_exist():
    """docs/optimizer.md pointed to tests/test_optimize.py after it moved."""
    names = [os.path.join("docs", n) for n in os.listdir(os.path.join(REPO, "docs")) if n.endswith(".md")]
    assert os.path.join("docs", "optimizer.md") in names
    for name in [*names, "README.md"]:
        with open(os.path.join(REPO, name), encoding="utf-8") as f:
            text = f.read()
        for path in re.findall(r"\btests/[\w./-]*[\w/]", text):
            assert os.path.exists(os.path.join(REPO, path.split("::")[0])), f"{name} names {path}"


def test_batch_warp_on_cpu_says_it_is_building_before_the_silence(tmp_path):
    """`batch --backend warp --device cpu` ran 90 s with no output: the
    building and compiling line comes first (a tiny run: the line, not the
    compilation, is under test)."""
    pytest.importorskip("mujoco_warp")
    cmd = [sys.executable, "-m", "mat_hopper", "batch", "--designs", "SS", "--backend", "warp", "--device", "cpu"]
    p = subprocess.run(
        [*cmd, "--duration", "0.02", "--transient", "0.01"],
        capture_output=True,
        text=True,
        env=ENV,
        cwd=tmp_path,
        timeout=900,
    )
    assert p.returncode == 0, p.stderr
    ours = [line for line in p.stderr.splitlines() if not line.startswith("Warp")]  # Warp's own CUDA notice
    assert ours[0].startswith("warp: building 1 world on cpu and compiling its kernels"), p.stderr
    assert any(line.startswith("warp x1: started") for line in ours[1:]), p.stderr
