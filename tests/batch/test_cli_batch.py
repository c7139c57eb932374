"""``mat-hopper batch``: both backends write one row per design; bad input
and a missing mujoco-warp are one-line errors with exit code 2."""

import subprocess
import sys

import pandas as pd
import pytest

from mat_hopper.batch import RESULT_COLUMNS, BatchSettings, designs_from_csv, designs_to_frame, evaluate_cpu
from mat_hopper.cli import main
from mat_hopper.cli.batch import EVENT_COLUMNS, SETTING_COLUMNS
from mat_hopper.core.materials import LegDesign, parse_design
from mat_hopper.core.sim import simulate
from mat_hopper.physics.metrics import run_summary


def _cli(*args, env_code: str = ""):
    """The CLI in a fresh interpreter: what a user sees, import-time output included."""
    code = f"import sys\n{env_code}\nfrom mat_hopper.cli import main\nsys.exit(main({list(args)!r}))"
    return subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)


def _main(capsys, *args) -> tuple[int, str]:
    """The CLI in this process, (exit code, stderr): the package's import is
    paid once per test worker, not once per case (a fresh interpreter costs
    3-20 s under load; :func:`test_bad_input_in_a_fresh_interpreter` keeps
    one such case)."""
    capsys.readouterr()
    try:
        rc = main(list(args))
    except SystemExit as e:  # argparse's errors
        rc = e.code
    return rc, capsys.readouterr().err


def test_mujoco_backend_rows_are_cpu_rollouts(tmp_path, capsys):
    out = tmp_path / "out.csv"
    rc = main(
        [
            "batch",
            "--designs",
            "MD,PVC",
            "--behaviour",
            "forward",
            "--duration",
            "3",
            "--transient",
            "0.4",
            "--timestep",
            "2e-4",
            "--backend",
            "mujoco",
            "--workers",
            "1",
            "--quiet",
            "--csv",
            str(out),
        ]
    )
    assert rc == 0
    table = pd.read_csv(out)
    props = [f"density_{i}" for i in (1, 2, 3)] + [f"modulus_{i}" for i in (1, 2, 3)] + ["leg_mass_kg"]
    assert list(table.columns) == ["design", *props, *RESULT_COLUMNS[1:], *SETTING_COLUMNS, *EVENT_COLUMNS]
    assert table[list(EVENT_COLUMNS)].isna().all().all()  # neither diverged nor fell
    assert [d.name for d in designs_from_csv(out)] == ["MD", "PVC"]  # the table reads back as designs
    assert list(table.density_1) == [parse_design(n).densities_g_cm3[0] for n in ("MD", "PVC")]
    assert (table["behaviour"] == "forward").all() and (table["sensor_timing"] == "authors").all()
    assert list(table.design) == ["MD", "PVC"]
    for _, row in table.iterrows():  # each row is that design's own CPU rollout, summarised by metrics.py
        s = run_summary(simulate(row.design, "forward", 3.0, 2e-4, transient_s=0.4))
        assert row.n_hops == s["n_hops"] and row.n_hops >= 1 and bool(row.stable) == s["stable"]
        assert row.hop_height_m == pytest.approx(s["mean_hop_height_m"], rel=1e-9)
        assert row.tracking_error_m == pytest.approx(s["mean_tracking_error_m"], rel=1e-9)
        assert row.power_w == pytest.approx(s["mean_power_w"], rel=1e-9)
    assert "2 designs on forward" in capsys.readouterr().out


def test_designs_csv_round_trip_and_parallel_cpu(tmp_path):
    designs = [
        parse_design("rho-inc"),
        LegDesign.from_properties([1.0, 2.0], [None, 4.0], name="half-rigid"),
        parse_design("MD"),
    ]
    path = tmp_path / "designs.csv"
    designs_to_frame(designs).to_csv(path, index=False)
    back = designs_from_csv(path)
    assert [d.name for d in back] == ["rho-inc", "half-rigid", "MD"]
    assert [d.densities_g_cm3 for d in back] == [d.densities_g_cm3 for d in designs]
    assert [d.moduli_gpa for d in back] == [d.moduli_gpa for d in designs]
    s = BatchSettings(duration_s=1.0, timestep_s=1e-3, transient_s=0.2)
    serial = evaluate_cpu(back, "static", s, workers=1)
    parallel = evaluate_cpu(back, "static", s, workers=2)
    pd.testing.assert_frame_equal(serial, parallel)


@pytest.mark.parametrize(
    "args, message",
    [
        (["--designs", "kryptonite"], "unknown material"),
        (["--designs", "SS", "--behaviour", "moonwalk"], "unknown behaviour"),
        (["--designs", "SS", "--timestep", "0"], "timestep"),
        (["--designs", "SS", "--duration", "10"], "duration"),
        (["--designs", "SS", "--device", "cuda"], "--device is for --backend warp"),
        (["--designs", "SS", "--workers", "0"], "--workers"),
        (["--designs-csv", "no/such/file.csv"], "--designs-csv no/such/file.csv: no such file"),
        (["--designs", "SS", "--sensor-timing", "late"], "unknown sensor timing"),
        (["--map", "0", "--stability"], "--map must be in [1, 100]"),
        (["--map", "2", "--stability", "--duration", "3"], "--duration: not used by --stability"),
        (["--designs", "SS", "--stability", "--behaviour", "ramp"], "--behaviour: not used by --stability"),
        (["--designs", "SS", "--stability", "--stability-duration", "0"], "--stability-duration must be > 0"),
        (["--designs", "SS", "--map", "2"], "not allowed with argument"),
        (["--designs", "SS,,PVC"], "(an empty item)"),
        (["--designs", "SS", "--stability-duration", "0.5"], "--stability-duration is for --stability"),
        (["--designs", "SS", "--max-batch", "5"], "--max-batch is for --backend warp"),
        (["--designs", "SS", "--backend", "warp", "--workers", "2"], "--workers is for --backend mujoco"),
        (["--designs", "SS", "--behaviour", ""], "argument --behaviour/--behavior: empty value"),
        (["--designs", "SS", "--profile", "bogus"], "unknown profile 'bogus'"),
        # argparse alone would answer "expected one argument" for an exponent form
        (["--designs", "SS", "--duration", "-1e3"], "duration must be"),
        (["--designs", "SS", "--timestep", "-1e-4"], "timestep"),
        (["--map", "2", "--stability", "--stability-duration", "-1e-3"], "--stability-duration must be > 0"),
        (["--designs", "SS", "--timestep", "fast"], "or 'auto'"),
        (["--designs", "SS", "--backend", "warp", "--timestep", "auto"], "--timestep auto is for --backend mujoco"),
        (["--designs", "SS", "--stability", "--timestep", "auto"], "--timestep: not used by --stability"),
    ],
)
def test_bad_input_one_line_exit_2_no_file(tmp_path, capsys, args, message):
    out = tmp_path / "out.csv"
    rc, err = _main(capsys, "batch", *args, "--csv", str(out))
    assert rc == 2, err
    lines = err.strip().splitlines()
    assert len(lines) == 1 and message in lines[0], err
    assert not out.exists()


def test_bad_input_in_a_fresh_interpreter(tmp_path):
    """The same, as a user runs it: nothing else printed at import."""
    out = tmp_path / "out.csv"
    p = _cli("batch", "--designs", "SS", "--duration", "-1e3", "--csv", str(out))
    assert p.returncode == 2 and p.stdout == "", p.stderr
    lines = p.stderr.strip().splitlines()
    assert len(lines) == 1 and "duration must be" in lines[0], p.stderr
    assert not out.exists()


@pytest.mark.parametrize(
    "content, message",
    [
        ("design,density_1,modulus_1\nx,abc,4\n", "density_1 must be a decimal number"),
        ("density_1,density_2,modulus_1\n1.4,2,70\n", "no column modulus_2"),  # not silently rigid
        ("density_1\n1.4\n", "no column modulus_1"),
        ("design,density_1,modulus_1\nx,1.4,70,99\n", "a row has more fields than the header"),
        ("", "not a CSV table of designs (empty file)"),
        ("density_0,modulus_0\n1,2\n", "density_1..density_N without gaps"),
        ("design,density_1,modulus_1,colour,notes\na,8,200,red,x\n", "unknown column 'colour', 'notes'"),
        ("design,density_1,modulus_1\na,8,200\nb,8.0,200\n", "design 'b' is the same leg as row 1 ('a')"),
    ],
)
def test_bad_designs_csv(tmp_path, capsys, content, message):
    path = tmp_path / "d.csv"
    path.write_text(content)
    rc, err = _main(capsys, "batch", "--designs-csv", str(path))
    assert rc == 2 and message in err and len(err.strip().splitlines()) == 1, err


def test_missing_mujoco_warp_is_a_one_line_error(tmp_path):
    out = tmp_path / "out.csv"
    p = _cli(
        "batch",
        "--designs",
        "PVC",
        "--backend",
        "warp",
        "--device",
        "cpu",
        "--csv",
        str(out),
        env_code="sys.modules['mujoco_warp'] = None   # as if not installed",
    )
    assert p.returncode == 2, p.stderr
    lines = p.stderr.strip().splitlines()
    assert len(lines) == 1 and "mujoco-warp" in lines[0] and "Traceback" not in p.stderr, p.stderr
    assert not out.exists()


def test_warp_backend_cli_on_cpu_device(tmp_path):
    pytest.importorskip("mujoco_warp")
    out = tmp_path / "out.csv"
    p = _cli(
        "batch",
        "--designs",
        "PVC,Nylon",
        "--behaviour",
        "forward",
        "--duration",
        "0.2",
        "--transient",
        "0.1",
        "--timestep",
        "2e-4",
        "--backend",
        "warp",
        "--device",
        "cpu",
        "--csv",
        str(out),
    )
    assert p.returncode == 0, p.stderr
    table = pd.read_csv(out)
    results = [c for c in table.columns if c in RESULT_COLUMNS]  # after each design's properties
    assert results == list(RESULT_COLUMNS) and list(table.design) == ["PVC", "Nylon"]
    assert {"density_1", "modulus_1", "leg_mass_kg"} <= set(table.columns)
    assert table.stable.all() and (table.n_hops == 0).all()  # 0.2 s: still falling, no hop yet
    assert "sim s" not in p.stderr  # no progress bar where stderr is no terminal (a log, a pipe)
    p = _cli(
        "batch",
        "--designs",
        "PVC",
        "--backend",
        "warp",
        "--device",
        "nosuch",
        "--duration",
        "0.2",
        "--transient",
        "0.1",
    )
    assert p.returncode == 2 and p.stderr.strip().splitlines() == [
        "mat-hopper batch: error: --device 'nosuch': unknown device; accepted: cpu, cuda or cuda:N"
    ]


def test_stability_scan_of_the_map_designs(tmp_path):
    """--map N gives the map's N x N mono-material designs (docs/reference-hopper.md:
    densities 1.39-8 g/cm^3 and moduli 4-340 GPa, log-spaced, rounded to 0.1);
    --stability writes each design's first upright step of the ladder, the
    value stability.spec_scan gives for the same design."""
    from mat_hopper.physics.stability import spec_scan

    out = tmp_path / "map.csv"
    rc = main(["batch", "--map", "2", "--stability", "--stability-duration", "0.5", "--quiet", "--csv", str(out)])
    assert rc == 0
    t = pd.read_csv(out)
    assert t["density_g_cm3"].tolist() == [1.4, 1.4, 8.0, 8.0] and t["modulus_gpa"].tolist() == [4.0, 340.0] * 2
    rho8_e4 = LegDesign.from_properties([8.0], [4.0] * 3)
    assert t["spec_timestep_s"][2] == pytest.approx(spec_scan(rho8_e4, duration_s=0.5))


def test_sensor_timing_reaches_the_runs(tmp_path):
    """At 2e-4 s the authors' timing (latency 1) is stable for PVC and a
    latency of 2 steps is not: the stance damping's delayed-feedback limit
    c(L) I / (K_d gear) is 2.1e-4 s at L = 1 and 1.3e-4 s at L = 2
    (mat_hopper.physics.stability)."""
    args = ["batch", "--designs", "PVC", "--duration", "0.6", "--transient", "0.1", "--timestep", "2e-4", "--quiet"]
    stable = {}
    for timing in ("authors", "2"):
        out = tmp_path / f"{timing}.csv"
        code = main([*args, "--sensor-timing", timing, "--csv", str(out)])
        stable[timing] = bool(pd.read_csv(out)["stable"][0])
        assert code == (0 if stable[timing] else 1)  # a diverged run exits 1, its table written
    assert stable == {"authors": True, "2": False}


def test_profile_sets_the_run_lengths_and_a_csv_is_replaced(tmp_path, monkeypatch):
    """$MAT_HOPPER_PROFILE (or --profile) gives the runs their length, the
    CSV records it, and running the same command again replaces the CSV."""
    out = tmp_path / "out.csv"
    monkeypatch.setenv("MAT_HOPPER_PROFILE", "quick")
    args = ["batch", "--designs", "MD", "--timestep", "1e-3", "--quiet", "--csv", str(out)]
    # MD diverges at 1e-3 s (above the controller's 2.1e-4 s limit): exit 1, the table written all the same
    assert main(args) == 1
    first = pd.read_csv(out)
    assert first["duration_s"][0] == 12.0 and first["transient_s"][0] == 4.0  # the quick profile's
    out.write_text("stale\n")
    assert main(args) == 2  # an existing output is replaced only with --force
    assert out.read_text() == "stale\n"
    assert main([*args, "--force"]) == 1  # replaced
    assert pd.read_csv(out).equals(first)


def test_a_csv_where_nothing_can_be_written_is_refused_before_work(capsys):
    """/proc accepts no new file even for root (os.access says it may): the
    folder is tried before any simulation."""
    rc = main(["batch", "--designs", "SS", "--duration", "600", "--csv", "/proc/out.csv"])
    err = capsys.readouterr().err.strip().splitlines()
    assert rc == 2 and len(err) == 1 and "nothing can be written in folder /proc" in err[0]


@pytest.mark.parametrize(
    "designs, message",
    [
        ("SS, ss", "'SS' and 'ss' name the same design (SS)"),  # not SS run twice
        ("rho-inc,RHO-INC ", "'rho-inc' and 'RHO-INC' name the same design (rho-inc)"),
        ("SS,Ti,SS-SS-SS", "'SS' and 'SS-SS-SS' are the same leg"),
        ("PVC-Ti-SS,pvc_ti/ss", "name the same design (PVC-Ti-SS)"),
    ],
)
def test_designs_naming_one_design_twice_are_refused(tmp_path, monkeypatch, capsys, designs, message):
    from mat_hopper.batch import parse_design_list

    with pytest.raises(ValueError, match="give each design once"):
        parse_design_list(designs)
    monkeypatch.chdir(tmp_path)
    assert main(["batch", "--designs", designs, "--duration", "3000", "--transient", "1", "--csv", "o.csv"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and message in err and "--designs" in err, err
    assert not (tmp_path / "o.csv").exists()
    assert [d.name for d in parse_design_list("SS,SS-Ti,Ti")] == ["SS", "SS-Ti", "Ti"]


@pytest.mark.parametrize(
    "command, flag", [("batch", "--designs-csv"), ("simulate", "--design-csv"), ("render", "--design-csv")]
)
@pytest.mark.parametrize("what", ["folder", "missing"])
def test_a_designs_csv_that_is_no_file_names_the_option(tmp_path, capsys, command, flag, what):
    path = tmp_path if what == "folder" else tmp_path / "missing.csv"
    still = ["--still", str(tmp_path / "s.png")] if command == "render" else []
    rc, err = _main(capsys, command, flag, str(path), *still)
    assert rc == 2 and flag in err and str(path) in err and len(err.strip().splitlines()) == 1, err


@pytest.mark.parametrize("device", ["tpu", "cuda:x", "gpu"])
def test_an_unknown_warp_device_is_one_line_before_any_work(capsys, device):
    rc, err = _main(capsys, "batch", "--designs", "SS", "--backend", "warp", "--device", device)
    assert rc == 2 and len(err.strip().splitlines()) == 1, err
    assert "--device" in err and "cpu, cuda or cuda:N" in err and "building" not in err


def test_timestep_auto_gives_each_design_its_substeps_and_a_diverged_run_exits_1(tmp_path, capsys):
    """WC's springs' bound (9.52e-05 s) lies under the authors' 1e-4 s step: the batch warns of it
    before any run, WC diverges 5 ms in and the batch exits 1; at --timestep auto each design runs
    at its own substeps (SS 2, WC 3), none diverges, exit 0."""
    out = tmp_path / "out.csv"
    argv = ["batch", "--designs", "SS,WC", "--behaviour", "forward", "--duration", "2", "--transient", "1"]
    argv += ["--workers", "1", "--quiet"]
    assert main([*argv, "--csv", str(out)]) == 1
    cap = capsys.readouterr()
    warned = [line for line in cap.err.splitlines() if "warning" in line]
    assert len(warned) == 1 and warned[0].startswith("mat-hopper batch: warning: WC: the physics step 0.0001 s")
    assert "--timestep auto" in warned[0]
    assert "1 of 2 designs diverged (WC at t = 0.00" in cap.out and "try --timestep auto" in cap.out
    table = pd.read_csv(out)  # still written
    assert list(table.stable) == [True, False] and list(table.substeps) == [1, 1]
    auto = tmp_path / "auto.csv"
    assert main([*argv, "--timestep", "auto", "--csv", str(auto)]) == 0
    cap = capsys.readouterr()
    assert (
        "warning" not in cap.err and "diverged" not in cap.out and "--timestep auto (dt=3.33e-05 to 5e-05 s" in cap.out
    )
    table = pd.read_csv(auto)
    assert list(table.stable) == [True, True] and list(table.substeps) == [2, 3]
    assert list(table.timestep_s) == pytest.approx([5e-5, 1e-4 / 3])
    # the rows are those designs' own runs at auto
    s = run_summary(simulate("WC", "forward", 2.0, "auto", transient_s=1.0))
    assert table.n_hops[1] == s["n_hops"] and table.hop_height_m[1] == pytest.approx(s["mean_hop_height_m"], rel=1e-9)


def test_the_api_refuses_auto_on_warp_and_runs_it_on_mujoco():
    from mat_hopper.batch import design_settings, evaluate

    with pytest.raises(ValueError, match="auto_timestep is for backend='mujoco'"):
        evaluate(["SS"], "static", BatchSettings(duration_s=0.2, transient_s=0.0), backend="warp", auto_timestep=True)
    s = design_settings("SS", BatchSettings(duration_s=0.2, transient_s=0.0), auto_timestep=True)
    assert (s.timestep_s, s.substeps) == (5e-5, 2)


def test_segment_mass_reaches_the_runs_as_simulate_takes_it(tmp_path, capsys):
    """--segment-mass, shared with simulate and compare: under capsule a
    2-segment leg carries the authors' per-capsule density, whose leg mass
    mass_properties gives (a different mass from leg's at 2 segments)."""
    from mat_hopper.core.control_legs import mass_properties

    designs = tmp_path / "two.csv"
    designs.write_text("design,density_1,density_2,modulus_1,modulus_2\ntwo,8,8,193,193\n")
    out = tmp_path / "out.csv"
    argv = ["batch", "--designs-csv", str(designs), "--duration", "0.5", "--transient", "0.2", "--quiet"]
    assert main([*argv, "--segment-mass", "capsule", "--csv", str(out)]) == 0
    assert "segment mass capsule" in capsys.readouterr().out
    row = pd.read_csv(out).iloc[0]
    design = designs_from_csv(designs)[0]
    assert row["segment_mass"] == "capsule"
    assert row["leg_mass_kg"] == pytest.approx(mass_properties(design, "capsule").leg_mass_kg, rel=1e-12)
    assert mass_properties(design, "capsule").leg_mass_kg != pytest.approx(mass_properties(design, "leg").leg_mass_kg)
