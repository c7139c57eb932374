"""The command line's contract: run sizes, prompt signals, no silent
ignores, one way to read names and numbers, strict design tables, checks
before work, two outputs on one path. Each kind has a typical case and at
least one other door; the expected values are the right behaviour."""

from __future__ import annotations

import importlib
import os
import pty
import select
import signal
import subprocess
import sys
import time

import pandas as pd
import pytest
from _refusal import refused as _refused

from mat_hopper.cli import COMMAND_HELP, build_parser, main
from mat_hopper.core.sim import RolloutRunner, SimSettings, loop_chunk_steps

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
ENV = {**os.environ, "PYTHONPATH": REPO + os.pathsep + os.environ.get("PYTHONPATH", "")}
ENV.pop("MAT_HOPPER_PROFILE", None)
LONG = ["--duration", "3000", "--transient", "1"]  # a run of many minutes: a check that fails fast came first


@pytest.fixture
def here(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    monkeypatch.delenv("MAT_HOPPER_PROFILE", raising=False)
    monkeypatch.delenv("MAT_HOPPER_MAX_STEPS", raising=False)
    return tmp_path


# --- 1. work the machine cannot finish ----------------------------------------


def test_reproduce_replicates_100000_refused_naming_size_and_flag(here, capsys):
    """Refused at once, not left to sit silent while memory grows."""
    _refused(["reproduce", "--replicates", "100000", "--out", "out"], capsys, "--replicates 100000", "physics steps")
    assert os.listdir(here) == []


@pytest.mark.parametrize(
    "argv, texts",
    [
        (["batch", "--map", "100", "--stability", "--stability-duration", "100"], ("--map", "physics steps")),
        (["batch", "--designs", "SS,Ti", "--duration", "1e5", "--timestep", "1e-6"], ("--duration", "--timestep")),
        (["optimize", "--study", "s", "--trials", "100000000"], ("--trials 100000000", "physics steps")),
        (["reproduce", "--workers", "100000"], ("--workers", "[1, 256]")),
        (["batch", "--designs", "SS", "--workers", "5000"], ("--workers", "[1, 256]")),
        (["optimize", "--study", "s", "--trials", "5", "--workers", "1000"], ("--workers", "[1, 256]")),
    ],
)
def test_every_command_refuses_work_beyond_the_limit(here, capsys, argv, texts):
    _refused(argv, capsys, *texts)
    assert os.listdir(here) == []


def test_the_limit_is_documented_and_can_be_raised(here, capsys, monkeypatch):
    from mat_hopper.util.limits import LIMIT_ENV, MAX_TOTAL_STEPS, check_total_steps

    assert check_total_steps(MAX_TOTAL_STEPS, "x") == MAX_TOTAL_STEPS
    with pytest.raises(ValueError, match=r"--replicates 7: about 3e\+10 physics steps"):
        check_total_steps(3e10, "--replicates 7")
    monkeypatch.setenv(LIMIT_ENV, "1e11")
    assert check_total_steps(3e10, "x") == 3e10
    monkeypatch.setenv(LIMIT_ENV, "lots")
    with pytest.raises(ValueError, match=LIMIT_ENV):
        check_total_steps(1, "x")


def test_the_paper_reproduction_is_within_the_limit():
    from mat_hopper.experiments.paper import parse_experiments
    from mat_hopper.experiments.reproduce import planned_steps
    from mat_hopper.util.limits import MAX_TOTAL_STEPS

    names = parse_experiments("1,2,3,stability,robustness")
    steps = planned_steps("paper", names, ("paper", "axial"), 6)
    assert 1e9 < steps < MAX_TOTAL_STEPS / 3


# --- 2. signals at any time step ----------------------------------------------


def _read_until(fd, text: bytes, timeout_s: float) -> bytes:
    """What the pty shows until `text` (or its end, or the timeout)."""
    got, deadline = b"", time.monotonic() + timeout_s
    while text not in got and time.monotonic() < deadline:
        ready, _, _ = select.select([fd], [], [], 0.05)
        if ready:
            try:
                got += os.read(fd, 4096)
            except OSError:  # the child closed it
                break
    return got


def test_sigterm_on_a_tiny_time_step_simulate_acts_within_a_second(tmp_path):
    """SIGTERM on `simulate --timestep 1e-7` is answered promptly. stderr
    is a terminal (a pty, 120 columns), so the progress bar says when the
    loop runs; the command then answers the signal within a second
    ("interrupted by SIGTERM", exit 143). The process's exit after that is
    the interpreter's teardown, bounded loosely."""
    import fcntl
    import struct
    import termios

    master, slave = pty.openpty()
    fcntl.ioctl(slave, termios.TIOCSWINSZ, struct.pack("HHHH", 24, 120, 0, 0))
    cmd = [sys.executable, "-m", "mat_hopper", "simulate", "--timestep", "1e-7", "--duration", "100"]
    p = subprocess.Popen(cmd + ["--transient", "1"], stdout=subprocess.PIPE, stderr=slave, env=ENV, cwd=tmp_path)
    os.close(slave)
    try:
        assert b"simulated s" in _read_until(master, b"simulated s", 120)  # the bar: the loop is running
        time.sleep(0.5)
        t0 = time.monotonic()
        p.send_signal(signal.SIGTERM)
        err = _read_until(master, b"interrupted", 30)
        answered = time.monotonic() - t0
        p.wait(30)
        exited = time.monotonic() - t0
    finally:
        if p.poll() is None:
            p.kill()
        os.close(master)
    assert b"interrupted by SIGTERM" in err
    assert p.returncode == 128 + signal.SIGTERM
    assert answered < 1.0, f"{answered:.2f} s"
    assert exited < 5.0, f"{exited:.2f} s"


KILLER = (
    "import os, signal, sys, time; time.sleep(float(sys.argv[2])); print(time.time(), flush=True); "
    "os.kill(int(sys.argv[1]), signal.SIGINT)"
)


@pytest.mark.parametrize("n_segments, timestep_s", [(3, 1e-7), (64, 1e-6)])
def test_ctrl_c_reaches_the_python_api_within_a_second(n_segments, timestep_s):
    """Another door: the library's own rollout (every command's), Ctrl-C
    from another process (a thread could not run: the compiled loop holds
    the GIL). The loop returns between chunks of steps, so
    KeyboardInterrupt is raised well within a second."""
    from mat_hopper.core.materials import parse_design

    design = parse_design("SS", n_segments=n_segments)
    # long enough to outlast the 1 s wait many times over (about 2e6 steps, tens
    # of seconds), short enough that a lost signal cannot hang the suite
    settings = SimSettings(duration_s=2e6 * timestep_s, timestep_s=timestep_s, transient_s=0.0, record_rate_hz=100.0)
    run = RolloutRunner(design, "forward", settings)
    run.advance(10)  # compiled, model built
    # a pytest-xdist worker ignores SIGINT: this process gets Python's own handler for the test
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    killer = subprocess.Popen(
        [sys.executable, "-c", KILLER, str(os.getpid()), "1.0"], stdout=subprocess.PIPE, text=True
    )
    try:
        with pytest.raises(KeyboardInterrupt):
            run.advance()
        caught = time.time()
    finally:
        signal.signal(signal.SIGINT, previous)
        sent = float(killer.stdout.readline())
        killer.wait(10)
    assert caught - sent < 1.0, f"{caught - sent:.2f} s"
    assert 0 < run.step < run.settings.n_steps and run.diverged_step < 0
    assert loop_chunk_steps(n_segments) == (20_000 if n_segments == 3 else 1000)  # steps, not simulated time


# --- 3. every option acts or is refused; empty values are errors --------------


@pytest.mark.parametrize(
    "argv, texts",
    [
        (["simulate", "--design", "Ti", "--density", "8,8,8", "--modulus", "193,193,193"], ("--design", "--density")),
        (["optimize", "--study", "s", "--storage", ""], ("--storage", "empty value")),
        (["simulate", "--segments", "5", "--density", "8,8,8", "--modulus", "193,193,193"], ("--segments",)),
        (["modes", "--design", "SS", "--modulus", "193,193,193", "--density", "8,8,8"], ("--design", "--modulus")),
        (["render", "--still", "", "--tiles", "t.png"], ("--still", "empty value")),
        (["batch", "--designs", "SS", "--backend", "warp", "--device", " "], ("--device", "empty value")),
        (["reproduce", "--cache", ""], ("--cache", "empty value")),
    ],
)
def test_conflicting_and_empty_options_are_refused(here, capsys, argv, texts):
    _refused([*argv, *LONG] if argv[0] == "simulate" else argv, capsys, *texts)
    assert os.listdir(here) == []


# --- 4. design tables, read strictly -------------------------------------------


@pytest.mark.parametrize(
    "table, text",
    [
        ("density_1,density_2,density_3,modulus_1,modulus_2,modulus_3\n1,2,,70,70,193\n", "density_3 is empty"),
        ("density_1,modulus_1\n1,\n", "modulus_1 is empty (write rigid"),
        ("density_1,density_1,modulus_1\n1,2,70\n", "density_1 appears more than once"),
        ("design,density_1,modulus_1\na,1,70\nA,2,70\n", "design name 'A' is also row 1's"),
        ("density_1,modulus_1,modulas_2\n1,70,3\n", "unknown column 'modulas_2'"),
        ("density_1,modulus_1\n1,inf\n", "write rigid"),
        ("density_1,modulus_1\n1_0,70\n", "density_1 must be a decimal number"),
        ("density_1,modulus_1\n99,70\n", "density"),
        ("design,density_1,modulus_1\n,1,70\n", "the design cell is empty"),
    ],
)
def test_design_tables_are_read_strictly(here, capsys, table, text):
    (here / "d.csv").write_text(table)
    _refused(["batch", "--designs-csv", "d.csv", *LONG], capsys, text)


def test_design_table_round_trip_and_short_rows():
    from mat_hopper.batch import designs_from_frame, designs_to_frame
    from mat_hopper.core.materials import LegDesign, parse_design

    designs = [parse_design("rho-inc"), LegDesign.from_properties([1.0, 2.0], [None, 4.0], name="half")]
    back = designs_from_frame(designs_to_frame(designs))
    assert [d.moduli_gpa for d in back] == [d.moduli_gpa for d in designs]
    assert [d.n_segments for d in back] == [3, 2]


def test_simulate_csv_carries_the_design_properties(here, capsys):
    assert main(["simulate", "--design", "Ti", "--duration", "3", "--transient", "0.5", "--csv", "t.csv"]) == 0
    hops = pd.read_csv("t.csv")
    from mat_hopper.core.control_legs import mass_properties
    from mat_hopper.core.materials import parse_design

    ti = parse_design("Ti")
    cols = list(hops.columns)
    at = cols.index("substeps") + 1  # after the run settings
    props = [*(f"density_{i}" for i in (1, 2, 3)), *(f"modulus_{i}" for i in (1, 2, 3))]
    assert cols[at : at + 6] == props and cols.count("leg_mass_kg") == 1
    assert (hops["density_2"] == ti.densities_g_cm3[1]).all() and (hops["modulus_3"] == ti.moduli_gpa[2]).all()
    assert hops["leg_mass_kg"].iloc[0] == pytest.approx(mass_properties(ti).leg_mass_kg)


# --- 5. outputs checked before any work -----------------------------------------


def test_modes_csv_folder_fails_before_printing_the_table(here, capsys):
    """`modes --csv .` is refused before the table is printed."""
    cap = _refused(["modes", "--csv", "."], capsys, "--csv")
    assert cap.out == ""


def test_render_unknown_file_type_names_its_flag_before_work(here, capsys):
    _refused(["render", "--video", "clip.avi", "--seconds", "3000"], capsys, "--video", ".avi")
    _refused(["render", "--tiles", "t.bmp", "--seconds", "3000"], capsys, "--tiles", ".bmp")


# --- 6. one reading of names and numbers; messages name flags --------------------


def test_render_start_names_the_flags_not_the_parameter(here, capsys):
    """`render --start 1e6` names the flags, not the parameter duration_s."""
    cap = _refused(["render", "--start", "1e6", "--video", "v.mp4"], capsys, "--start + --seconds")
    assert "duration_s" not in cap.err


@pytest.mark.parametrize(
    "argv, texts",
    [
        (["simulate", "--modulus", "inf,70,70", "--density", "1,1,1"], ("--modulus", "write rigid")),
        (["simulate", "--duration", "١٢"], ("--duration", "decimal number")),
        (["simulate", "--duration", "1_000"], ("--duration", "decimal number")),
        (["simulate", "--duration", "nan"], ("--duration", "finite")),
        (["batch", "--designs", "SS", "--timestep", "0x10"], ("--timestep", "decimal number")),
        (["simulate", "--timestep", "1e-12", "--duration", "100"], ("--duration", "--timestep")),
        (["optimize", "--study", "s", "--trials", "2.5"], ("--trials", "whole number")),
        (["simulate", "--segments", "100"], ("--segments must be",)),
        (["simulate", "--sensor-timing", "late"], ("--sensor-timing",)),
        (["optimize", "--study", "s", "--density-bounds", "5,1"], ("--density-bounds",)),
        (["modes", "--modes", "4"], ("--modes 4", "3 axial modes")),
        (["modes", "--modes", "0"], ("--modes must be",)),
    ],
)
def test_numbers_are_ascii_decimals_and_errors_name_flags(here, capsys, argv, texts):
    cap = _refused(argv, capsys, *texts)
    assert "duration_s" not in cap.err and "timestep_s" not in cap.err


def test_names_are_case_insensitive_everywhere(here, capsys):
    """--convention PAPER is accepted, as --design ss is."""
    assert (
        main(
            [
                "simulate",
                "--convention",
                "PAPER",
                "--design",
                "ss",
                "--behaviour",
                "STATIC",
                "--duration",
                "0.3",
                "--transient",
                "0.1",
            ]
        )
        == 0
    )
    assert "convention=paper" in capsys.readouterr().out
    assert main(["modes", "--convention", "Axial", "--segment-mass", "LEG"]) == 0
    assert "convention axial" in capsys.readouterr().out


def test_one_parser_for_names_numbers_and_url_schemes():
    from mat_hopper.core.materials import LegDesign, check_convention
    from mat_hopper.optimize import storage_file
    from mat_hopper.util.parsing import normalize_url, parse_name, parse_number

    assert parse_name(" PAPER ", ("paper", "axial"), "--convention") == "paper"
    assert check_convention("Axial") == "axial" and SimSettings(convention="AXIAL").convention == "axial"
    with pytest.raises(ValueError, match="--convention"):
        parse_name("", ("paper",), "--convention")
    assert parse_number("2e-4", "x") == 2e-4 and parse_number(" -1.5 ", "x") == -1.5
    assert parse_number("rigid", "x", rigid=True) is None and parse_number("RIGID", "x", rigid=True) is None
    for bad in ("inf", "-Infinity", "nan", "1_0", "0x1f", "١", "1e999", "", "1,5", "½"):
        with pytest.raises(ValueError, match="^x "):
            parse_number(bad, "x")
    with pytest.raises(ValueError, match="write rigid"):
        parse_number(float("inf"), "modulus", rigid=True)
    with pytest.raises(ValueError, match=r"in \[1, 3\]"):
        parse_number("4", "x", low=1, high=3)
    # --modulus inf: refused by the CLI and the API alike; "rigid" works in both
    assert LegDesign.from_properties([1, 1], [70, "rigid"]).moduli_gpa == (70.0, None)
    with pytest.raises(ValueError):
        LegDesign.from_properties([1], [float("inf")])
    assert normalize_url("SQLite:///a/B.db") == "sqlite:///a/B.db"
    assert storage_file("SQLITE:///x.db") == os.path.abspath("x.db")
    assert storage_file("Journal:///tmp/j.log") == "/tmp/j.log"


def test_parse_design_reads_back_the_names_the_tool_writes():
    from mat_hopper.core.materials import LegDesign, parse_design

    d = LegDesign.from_properties([1.5, 8.0], [70.0, None])
    assert parse_design(d.name).densities_g_cm3 == d.densities_g_cm3
    assert parse_design(d.name).moduli_gpa == d.moduli_gpa
    assert parse_design("rho=8 E=193").moduli_gpa == (193.0,) * 3
    with pytest.raises(ValueError, match="DENSITY/MODULUS"):
        parse_design("custom(1,2)")


# --- 7. the Python API keeps its contract -----------------------------------------


def test_compare_refuses_alpha_outside_0_1():
    """alpha=2 is refused (it would mark p = 0.051 significant)."""
    from mat_hopper.physics.metrics import compare

    hops = pd.DataFrame(
        {"design": ["A"] * 5 + ["B"] * 5, "behaviour": "forward", "hop_height_m": [1, 2, 3, 4, 5, 2, 3, 4, 5, 6.0]}
    )
    for alpha in (2, 0, 1, -0.1, True, "0.05"):
        with pytest.raises(ValueError, match="alpha"):
            compare(hops, "A", metrics=("hop_height_m",), alpha=alpha)
    with pytest.raises(ValueError, match="'jerk_m_s3'"):
        compare(hops, "A", metrics=("jerk_m_s3",))
    with pytest.raises(ValueError, match="hops must be"):
        compare(hops.to_dict(), "A")
    assert len(compare(hops, "A", metrics=("hop_height_m",))) == 1


@pytest.mark.parametrize(
    "call, name",
    [
        (lambda: importlib.import_module("mat_hopper.physics.metrics").hop_table(None), "rollout"),
        (lambda: importlib.import_module("mat_hopper.physics.metrics").run_summary({}), "rollout"),
        (lambda: importlib.import_module("mat_hopper.core.sim").simulate("SS", "forward", settings=1), "settings"),
        (lambda: importlib.import_module("mat_hopper.core.sim").SimSettings(convention="stiff"), "convention"),
    ],
)
def test_api_misuse_is_a_value_error_naming_the_argument(call, name):
    with pytest.raises(ValueError, match=name):
        call()


# --- 8. stiff springs and other first stumbles ---------------------------------------


def test_help_imports_nothing_heavy_and_lists_every_command():
    code = (
        "import sys; from mat_hopper.cli import main\n"
        "try:\n    main(['--help'])\nexcept SystemExit:\n    pass\n"
        "heavy = [m for m in ('mujoco', 'numba', 'pandas', 'optuna', 'matplotlib', 'scipy') if m in sys.modules]\n"
        "print('HEAVY', heavy)"
    )
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=ENV, timeout=60)
    assert "HEAVY []" in p.stdout, p.stdout + p.stderr
    shown = " ".join(p.stdout.split())  # argparse wraps the lines
    for name, line in COMMAND_HELP.items():
        assert f"{name} {line}" in shown


def test_command_help_lines_are_the_modules_own():
    parser = build_parser()  # every command in full
    sub = next(a for a in parser._actions if a.dest == "command")
    listed = {c.dest: c.help for c in sub._choices_actions}
    assert listed == COMMAND_HELP


@pytest.mark.parametrize("convention", ["axial", "axial+bending"])
def test_stiff_divergence_suggests_timestep_auto(here, capsys, convention):
    """axial, and the bending conventions: each gets the hint."""
    code = main(["simulate", "--design", "Ti", "--convention", convention, "--duration", "0.05", "--transient", "0.01"])
    out = capsys.readouterr().out
    assert code == 1 and "UNSTABLE" in out and "--timestep auto" in out


# --- 9. two outputs, one path --------------------------------------------------------


def test_render_refuses_two_outputs_on_one_path(here, capsys):
    """Tiles and still on one path are refused (not one overwriting the other)."""
    _refused(["render", "--tiles", "same.png", "--still", "same.png"], capsys, "--tiles and --still", "same.png")
    _refused(["render", "--tiles", "a/x.png", "--still", "a/../a/x.png"], capsys, "--tiles and --still")
    assert os.listdir(here) == []


def test_reproduce_refuses_one_folder_for_results_and_cache(here, capsys):
    _refused(["reproduce", "--out", "r", "--cache", "r/"], capsys, "--out and --cache")
    assert os.listdir(here) == []


def test_progress_is_a_bar_on_a_terminal_and_lines_elsewhere(monkeypatch):
    import io

    from tqdm import tqdm

    from mat_hopper.util import progress

    log = io.StringIO()
    with progress.progress_bar(total=3, desc="exp1", unit="run", file=log) as bar:
        bar.update(2)
        monkeypatch.setattr(progress, "LINE_EVERY_S", 0.0)  # a long stage: a line while it runs
        bar.update(1)
    lines = log.getvalue().splitlines()
    assert lines[0] == "exp1: started, 0/3 run" and lines[-1].startswith("exp1: done, 3/3 run in ")
    assert any("3/3 run after" in line for line in lines) and "\r" not in log.getvalue()
    assert list(progress.progress_bar([1, 2], desc="render", file=io.StringIO())) == [1, 2]

    class Terminal(io.StringIO):
        def isatty(self):
            return True

    bar = progress.progress_bar(total=3, file=Terminal())
    assert isinstance(bar, tqdm) and not bar.disable
    bar.close()
    assert progress.progress_bar(total=3, file=Terminal(), enabled=False).disable


def test_batch_in_a_pipe_prints_a_line_per_stage(here, capsys):
    assert main(["batch", "--designs", "SS", "--duration", "0.3", "--transient", "0.1", "--workers", "1"]) == 0
    err = capsys.readouterr().err.splitlines()
    assert err[0] == "mujoco: started, 0/1 design" and err[-1].startswith("mujoco: done, 1/1 design")


def test_csv_dash_is_standard_output(here, capsysbinary):
    assert main(["modes", "--csv", "-"]) == 0
    cap = capsysbinary.readouterr()
    out = cap.out.decode()
    assert (
        out.splitlines()[0] == "mode,chain_hz,rod_hz,error_pct,kind" and len(out.splitlines()) == 4
    )  # 3 segments: 3 modes
    assert "wrote 3 rows to standard output" in cap.err.decode()
    assert os.listdir(here) == []


def test_importances_need_sampled_trials_not_the_enqueued_paper_designs():
    import optuna

    from mat_hopper.optimize.report import enough_for_importances, importances

    optuna.logging.set_verbosity(optuna.logging.WARNING)
    study = optuna.create_study(directions=["minimize", "minimize"])
    dist = optuna.distributions.FloatDistribution(0.0, 1.0)
    for i in range(8):  # a --trials 8 study: the paper designs only
        t = optuna.trial.create_trial(
            params={"x": i / 8}, distributions={"x": dist}, values=[i, 8 - i], user_attrs={"paper_design": f"d{i}"}
        )
        study.add_trial(t)
    assert not enough_for_importances(study) and importances(study).empty
    for i in range(4):
        study.add_trial(optuna.trial.create_trial(params={"x": 0.1 * i}, distributions={"x": dist}, values=[i, 1]))
    assert enough_for_importances(study)


@pytest.mark.slow  # a one-trial study: about 15 s
def test_optimize_report_hint_names_the_studies_dir(here, capsys):
    argv = ["optimize", "--study", "s", "--trials", "1", "--profile", "quick", "--workers", "1"]
    assert main([*argv, "--studies-dir", "elsewhere", "--no-progress", "--behaviour", "forward"]) == 0
    hint = next(line for line in capsys.readouterr().out.splitlines() if line.startswith("report:"))
    assert hint == "report: mat-hopper optimize --report s --studies-dir elsewhere"


def test_importances_plot_keeps_every_label_inside_the_figure():
    import io

    import optuna

    from mat_hopper.viz.study import importances_figure

    optuna.logging.set_verbosity(optuna.logging.WARNING)
    study = optuna.create_study(directions=["minimize", "minimize"], sampler=optuna.samplers.RandomSampler(seed=0))
    names = [f"seg{i}_{p}" for i in (1, 2, 3) for p in ("density_g_cm3", "modulus_gpa")]
    study.optimize(lambda t: [sum(t.suggest_float(n, 0.1, 10.0, log=True) for n in names), t.number], n_trials=12)
    fig = importances_figure(study, "a study: forward, quick profile, 3 segments")
    fig.savefig(io.BytesIO(), format="png")  # laid out as the report writes it
    box = fig.bbox
    for ax in fig.axes:
        for label in [*ax.get_yticklabels(), ax.title, ax.xaxis.label]:
            if label.get_text():
                e = label.get_window_extent()
                assert e.x0 >= box.x0 - 1 and e.x1 <= box.x1 + 1 and e.y0 >= box.y0 - 1 and e.y1 <= box.y1 + 1, label
        if ax.get_legend() is not None:
            e = ax.get_legend().get_window_extent()
            assert e.x0 >= box.x0 - 1 and e.x1 <= box.x1 + 1


def test_claims_only_for_the_conventions_asked_for(tmp_path, monkeypatch):
    """claims.md listed 16 'axial ... not run' rows nobody asked for."""
    from mat_hopper.analysis import claims
    from mat_hopper.experiments import reproduce as rp
    from mat_hopper.viz import figures

    seen = {}
    monkeypatch.setattr(figures, "write_figures", lambda tables, out: [])
    monkeypatch.setattr(claims, "write_claims", lambda table, out: [])
    real = claims.claims_table

    def spy(*args, **kwargs):
        seen["conventions"] = tuple(kwargs["conventions"])
        return real(*args, **kwargs)

    monkeypatch.setattr(claims, "claims_table", spy)
    rep = rp.Reproduction("quick", str(tmp_path), conventions=("paper",))
    rp._figures_and_claims(rep, log=lambda *a: None)
    assert seen["conventions"] == ("paper",)
    assert set(rep.tables["claims"]["convention"]) == {"paper"}


def test_batch_divergence_under_stiff_springs_names_a_way_out(here, capsys):
    """A batch diverging under stiff springs names a way out."""
    code = main(["batch", "--designs", "Ti", "--convention", "axial", "--duration", "0.05", "--transient", "0.01"])
    out = capsys.readouterr().out
    assert code == 1 and "1 of 1 design diverged" in out and "try --timestep auto" in out  # a diverged run: exit 1


def test_ctrl_c_during_start_up_is_one_line_and_exit_130(monkeypatch, capsys):
    """An interrupt while the command's modules load (before its run) is
    answered as one mid-run: "interrupted", exit 128 + SIGINT's 2."""
    import mat_hopper.cli as cli

    def slow_imports(command=None):
        raise KeyboardInterrupt

    monkeypatch.setattr(cli, "build_parser", slow_imports)
    assert cli.main(["simulate", "--design", "SS"]) == 130
    assert capsys.readouterr().err == "interrupted\n"
