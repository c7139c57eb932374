"""Bad input: each kind of fault refused with one line, exit 2, before any
work or file, on every command that takes the input."""

import os

import pytest

from tests.cli._refusal import refused

QUICK_STUDY = ["--trials", "1", "--profile", "quick", "--behaviour", "forward", "--replicates", "0"]


def _left(root) -> list[str]:
    return sorted(os.path.relpath(os.path.join(d, f), root) for d, ds, fs in os.walk(root) for f in fs + ds)


# --- 1, 2, 3: optimize checks its cache, device and backend options before the study is made ---------------


@pytest.mark.parametrize(
    "env, argv, texts",
    [
        (
            "",
            ["--study", "s1", *QUICK_STUDY, "--workers", "1", "--studies-dir", "st", "--batch-size", "1"],
            ("$MAT_HOPPER_CACHE is set but empty",),
        ),
        (None, ["--study", "wd", *QUICK_STUDY, "--backend", "warp", "--device", "foo"], ("--device 'foo'", "cuda:N")),
        (
            None,
            ["--study", "w2", *QUICK_STUDY, "--backend", "warp", "--workers", "2"],
            ("--workers is for --backend mujoco",),
        ),
        (None, ["--study", "r", *QUICK_STUDY, "--backend", "warp", "--race"], ("--race runs on --backend mujoco",)),
    ],
)
def test_optimize_refuses_before_its_storage_is_made(env, argv, texts, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    if env is not None:
        monkeypatch.setenv("MAT_HOPPER_CACHE", env)
    refused(["optimize", *argv], capsys, *texts)
    assert _left(tmp_path) == []  # no studies/NAME.db, no st/, no cache folder


@pytest.mark.parametrize("command", ["optimize", "reproduce"])
def test_a_bad_cache_from_the_environment_is_named_as_such(command, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "file").write_text("")
    monkeypatch.setenv("MAT_HOPPER_CACHE", str(tmp_path / "file" / "x"))
    argv = ["optimize", "--study", "s2", *QUICK_STUDY] if command == "optimize" else ["reproduce", "--profile", "quick"]
    _, err = refused(argv, capsys, "$MAT_HOPPER_CACHE", "is a file, not a folder")
    assert "--cache" not in err
    assert _left(tmp_path) == ["file"]


# --- 4: --export / --replay of a queued trial name its state ----------------------------------------------------


@pytest.mark.parametrize("flag", ["--export", "--replay"])
def test_a_trial_that_has_not_run_is_named_by_its_state(flag, tmp_path, capsys):
    from mat_hopper.optimize import RunOptions, StudyConfig, create_or_load, dispose

    options = RunOptions(studies_dir=str(tmp_path))
    storage = options.open("base")
    create_or_load(StudyConfig("base"), storage)  # the paper's designs queued, none run
    dispose(storage)
    _, err = refused(
        ["optimize", "--study", "base", flag, "5", "--studies-dir", str(tmp_path)],
        capsys,
        "trial 5 has not run yet",
        "WAITING",
    )
    assert "parameters lack" not in err
    assert _left(tmp_path) == ["base.db"]


# --- 5: a run shorter than one control period is refused, with the numbers --------------------------------------


@pytest.mark.parametrize(
    "argv, texts",
    [
        (["simulate", "--design", "SS", "--behaviour", "static", "--duration", "1e-300", "--transient", "0"],
         ("--duration must be at least one control period", "0.0001 s", "1e-300 s")),
        (["simulate", "--design", "SS", "--behaviour", "static", "--duration", "1e-5", "--transient", "0"],
         ("--duration must be at least one control period", "1e-05 s")),
        (["simulate", "--design", "SS", "--convention", "axial", "--timestep", "auto", "--duration", "5e-5",
          "--transient", "0"], ("--duration", "one control period", "8 x --timestep")),
        (["batch", "--designs", "SS", "--duration", "1e-9", "--transient", "0", "--workers", "1"],
         ("--duration must be at least one control period", "1e-09 s")),
        (["batch", "--designs", "SS", "--stability", "--stability-duration", "1e-9", "--workers", "1"],
         ("--stability-duration must be at least", "0.001 s", "1e-09 s")),
        (["render", "--design", "SS", "--video", "v.gif", "--seconds", "1e-9"],
         ("--seconds must be at least one control period", "1e-09 s")),
    ],
)  # fmt: skip
def test_a_run_shorter_than_one_step_is_refused(argv, texts, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    refused([*argv, "--csv", "tiny.csv"] if argv[0] != "render" else argv, capsys, *texts)
    assert _left(tmp_path) == []


def test_the_library_refuses_a_run_of_no_step():
    from mat_hopper.core.sim import SimSettings

    with pytest.raises(ValueError, match="duration must be at least one control period, 0.0001 s"):
        SimSettings(duration_s=1e-5, transient_s=0.0)
    with pytest.raises(ValueError, match=r"4 x timestep 2\.5e-05 s"):
        SimSettings(duration_s=5e-5, transient_s=0.0, timestep_s=2.5e-5, substeps=4)
    assert SimSettings(duration_s=1e-4, transient_s=0.0).n_steps == 1


# --- 6: simulate and render keep the run-size limit ($MAT_HOPPER_MAX_STEPS) ------------------------------------


@pytest.mark.parametrize(
    "value, texts",
    [
        ("", ("$MAT_HOPPER_MAX_STEPS is set but empty",)),
        ("abc", ("$MAT_HOPPER_MAX_STEPS", "decimal")),
        ("-1", ("$MAT_HOPPER_MAX_STEPS must be >= 1",)),
        ("0", ("$MAT_HOPPER_MAX_STEPS must be >= 1",)),
        ("1e3", ("physics steps in all", "above the limit of 1e+03 ($MAT_HOPPER_MAX_STEPS)")),
    ],
)
@pytest.mark.parametrize("command", ["simulate", "render"])
def test_simulate_and_render_keep_the_step_limit(command, value, texts, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("MAT_HOPPER_MAX_STEPS", value)
    argv = ["simulate", "--duration", "1", "--transient", "0", "--csv", "h.csv"]
    if command == "render":
        argv = ["render", "--video", "v.gif", "--seconds", "1"]
    refused(argv, capsys, *texts)
    assert _left(tmp_path) == []


# --- 7, 8, 9: one value per segment; messages in the command line's words, with the right counts ---------------


@pytest.mark.parametrize(
    "argv, texts",
    [
        (["modes", "--density", "1,1", "--modulus", "70"], ("one value per segment (got 2 and 1)",)),
        (["modes", "--density", "1", "--modulus", "70,70,70,70,70"], ("one value per segment (got 1 and 5)",)),
        (["simulate", "--density", "1,1", "--modulus", "70"], ("one value per segment (got 2 and 1)",)),
        (["render", "--density", "1", "--modulus", "70,70", "--still", "s.png"], ("one value per segment",)),
        (["simulate", "--density", "1,2,3", "--modulus", "1e-7,70,70"], ("or rigid",)),
        (["simulate", "--design", "SS", "--density", "1", "--modulus", "2"],
         ("give either --design or --density with --modulus, not both",)),
        (["optimize", "--study", "s", *QUICK_STUDY, "--max-yield-fraction", "0"], ("(0, 10]", "leave the option out")),
        (["optimize", "--study", "s", *QUICK_STUDY, "--min-hops-to-failure", "0"], ("[1, 1e+20]", "leave the option out")),
    ],
)  # fmt: skip
def test_design_lists_and_messages_in_the_command_lines_words(argv, texts, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    _, err = refused(argv, capsys, *texts)
    assert "or None" not in err and "(with --modulus/--density)" not in err
    assert _left(tmp_path) == []


def test_design_table_messages_list_the_names_and_count_the_tables_segments(tmp_path, capsys):
    from mat_hopper.batch._designs import RECORD_COLUMNS

    extra = tmp_path / "extra.csv"
    extra.write_text("density_1,modulus_1,colour\n1,70,red\n")
    _, err = refused(["simulate", "--design-csv", str(extra)], capsys, "'colour'", *RECORD_COLUMNS, "power_total_w")
    assert "RECORD_COLUMNS" not in err
    short = tmp_path / "shortrow.csv"
    short.write_text("design,density_1,density_2,density_3,modulus_1,modulus_2,modulus_3\nA,1.39,4.43\n")
    _, err = refused(["simulate", "--design-csv", str(short)], capsys, "modulus_1 is empty", "of the table's 3")
    assert "a row's 2 segments" not in err


# --- 10: help says what the code does, its defaults and ranges from the constants -------------------------------


def _help(capsys, *argv) -> str:
    from mat_hopper.cli import main

    with pytest.raises(SystemExit):
        main([*argv, "--help"])
    return " ".join(capsys.readouterr().out.split())


def test_help_states_defaults_and_ranges(capsys):
    from mat_hopper.core.behaviours import DEFAULT_BEHAVIOUR
    from mat_hopper.core.materials import DEFAULT_CONVENTION, MAX_SEGMENTS
    from mat_hopper.optimize import MAX_SEGMENTS as MAX_OPT_SEGMENTS

    assert "empty or 'rigid'" not in _help(capsys, "batch")
    for command in ("simulate", "render"):
        text = _help(capsys, command)
        assert f"(default {DEFAULT_BEHAVIOUR})" in text and f"(default {DEFAULT_CONVENTION})" in text
    assert f"segments per leg, 1 to {MAX_OPT_SEGMENTS}" in _help(capsys, "optimize")
    assert f"1 to {MAX_SEGMENTS}" in _help(capsys, "modes")


# --- B3: an MP4 size the encoder would pad is refused before any rendering -----------------------------------


@pytest.mark.parametrize("size, padded", [("641x480", "648x480"), ("100x100", "104x104")])
def test_an_mp4_size_the_encoder_would_pad_is_refused(size, padded, tmp_path, monkeypatch, capsys):
    """641x480 came out 648x480 while render printed 641x480 (H.264's 8-pixel
    blocks, imageio-ffmpeg's macro_block_size); a .gif keeps any size."""
    monkeypatch.chdir(tmp_path)
    refused(
        ["render", "--design", "SS", "--video", "v.mp4", "--size", size, "--seconds", "0.1"], capsys, padded, ".gif"
    )
    assert _left(tmp_path) == []
