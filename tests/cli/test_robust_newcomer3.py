"""A third newcomer's bad input (this round's sixth session): each kind of
fault refused with one line, exit 2, before any work or file, on every
command that takes the input."""

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
    from mat_hopper.optimize import RunOptions, StudyConfig, dispose
    from mat_hopper.optimize._study import create_or_load

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
