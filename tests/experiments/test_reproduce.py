"""``mat-hopper reproduce``: bad input fails before any work; a tiny
profile runs end to end (tables, figures, claims) and then from the cache."""

import pandas as pd
import pytest

from mat_hopper.cli import main
from mat_hopper.experiments.profiles import Profile
from mat_hopper.experiments.reproduce import reproduce

TINY = Profile("tiny", 2.5, 0.5, 1e-4, 2, 0.5, stability_tolerance=1.5, stability_scan=False, replicates=0)


@pytest.mark.parametrize(
    "args, message",
    [
        (["--experiments", "1,9"], "unknown experiment"),
        (["--workers", "-1"], "workers"),
        (["--workers", "0"], "workers"),
        (["--workers", "2", "--scheduler", "tcp://127.0.0.1:1"], "not both"),
        (["--profile", "fast"], "unknown profile"),
        (["--replicates", "-3"], "replicates"),
        (["--conventions", "paper,beam"], "convention"),
        # a push no study asks (1e9), and its other spellings
        (["--push-scale", "1e9"], "--push-scale must be a finite number in [0, 100]"),
        (["--push-scale", "100.5"], "--push-scale must be a finite number in [0, 100]"),
        (["--push-scale", "-1"], "--push-scale must be a finite number in [0, 100]"),
        # two spellings of one experiment: refused naming both, not run once in silence
        (["--experiments", "4,stability"], "'4' and 'stability' are both stability"),
        (["--experiments", "1,EXP1"], "'1' and 'EXP1' are both exp1"),
        (["--experiments", "robust, robustness"], "names an item twice"),
    ],
)
def test_bad_input_is_a_one_line_error_before_any_work(tmp_path, capsys, args, message):
    out, cache = tmp_path / "out", tmp_path / "cache"
    rc = main(["reproduce", "--out", str(out), "--cache", str(cache), "--no-progress", *args])
    err = capsys.readouterr().err
    assert rc == 2 and message in err and len(err.strip().splitlines()) == 1
    assert not out.exists() and not cache.exists()


def test_tiny_reproduction_writes_tables_figures_claims(tmp_path):
    out, cache = tmp_path / "out", tmp_path / "cache"
    lines = []
    rep = reproduce(TINY, "1,stability", str(out), workers=2, cache_dir=str(cache), progress=False, log=lines.append)
    for name in ("exp1_hops", "exp1_runs", "stability", "stability_tries", "stability_agreement"):
        assert (out / f"{name}.csv").is_file()
    runs = pd.read_csv(out / "exp1_runs.csv")
    assert len(runs) == 20 and set(runs["profile"]) == {"tiny"} and set(runs["status"]) == {"ok"}
    hops = pd.read_csv(out / "exp1_hops.csv")
    assert {"experiment", "profile", "design", "behaviour", "replicate", "tracking_error_m"} <= set(hops.columns)
    stab = pd.read_csv(out / "stability.csv")
    assert len(stab) == 4 and stab["max_stable_timestep_s"].notna().all()
    assert (out / "claims.md").is_file() and (out / "claims.csv").is_file()
    assert any(f.endswith(".png") for f in rep.files)
    assert rep.computed == {"exp1": 20, "stability": 4} and not any(rep.failed.values())
    again = reproduce(
        TINY, ["exp1"], str(out), workers=1, cache_dir=str(cache), progress=False, figures=False, log=lines.append
    )
    assert again.computed == {"exp1": 0}
    pd.testing.assert_frame_equal(
        again.tables["exp1_runs"].reset_index(drop=True), rep.tables["exp1_runs"].reset_index(drop=True)
    )
    assert any("20 cached" in line for line in lines)


def test_axial_convention_runs_beside_paper_at_its_own_time_step(tmp_path):
    out, cache = tmp_path / "out", tmp_path / "cache"
    one = Profile("one", 1.5, 0.5, 1e-4, 2, 0.5, axial_timestep_s=2e-5, replicates=0)
    assert one.for_convention("axial").timestep_s == 2e-5 and one.for_convention("paper") is one
    rep = reproduce(
        one,
        "1",
        str(out),
        workers=2,
        cache_dir=str(cache),
        progress=False,
        conventions="paper,axial",
        log=lambda *a: None,
    )
    runs = rep.tables["exp1_runs"]
    assert len(runs) == 40
    assert dict(runs.groupby("convention")["timestep_s"].first()) == {"axial": 2e-5, "paper": 1e-4}
    claims = rep.tables["claims"]
    assert set(claims["convention"]) == {"paper", "axial"}


def test_replicates_default_to_the_profile_and_become_the_claims_basis(tmp_path):
    two = Profile("two", 2.5, 0.5, 1e-4, 2, 0.5, replicates=2)
    rep = reproduce(
        two, "1", str(tmp_path / "out"), workers=2, cache_dir=str(tmp_path / "c"), progress=False, log=lambda *a: None
    )
    runs = rep.tables["exp1_runs"]
    assert len(runs) == 20 * 3 and sorted(set(runs["replicate"])) == [-1, 0, 1]
    claims = rep.tables["claims"].query("convention == 'paper'").set_index("claim_id")
    row = claims.loc["ramp_ss_tracking"]
    assert row["basis"] == "replicate means" and row["n_replicates"] == 2
    assert row["sensor_timing"] == "authors" and row["timestep_check"] == "not checked"


@pytest.mark.slow
def test_robustness_study_end_to_end(tmp_path):
    """The study's every variant on a tiny profile: tables written, the
    default's value against each variant's classified, and the claims'
    time-step check fed from the finer-physics runs."""
    tiny = Profile("tiny", 2.0, 0.5, 1e-4, 2, 0.5, replicates=1)
    rep = reproduce(
        tiny,
        "1,3,robustness",
        str(tmp_path / "out"),
        workers=2,
        cache_dir=str(tmp_path / "c"),
        progress=False,
        log=lambda *a: None,
    )
    table = rep.tables["robustness"]
    assert set(table["variant"]) >= {"authors", "fresh", "latency-5", "axial", "2e-5 s physics", "replicate 0"}
    assert set(table["class"]) <= {"keeps", "moves > 2x", "flips", "no value"}
    assert (table.loc[table["variant"] == "authors", "class"].isin(["keeps", "no value"])).all()
    # latency 5 diverges at 1e-4 s: no values
    assert (table.loc[table["variant"] == "latency-5", "class"] == "no value").all()
    claims = rep.tables["claims"].query("convention == 'paper'").set_index("claim_id")
    assert claims.loc["ramp_ss_tracking", "timestep_check"] != "not checked"
    assert (tmp_path / "out" / "robustness_summary.csv").is_file()


def test_planned_steps_count_the_controls_as_they_run():
    # The controls run at least 2 replicates, and the profile's number when
    # given 0: the plan extrapolated from 0 and 1 replicates came out negative.
    from mat_hopper.experiments.paper import parse_experiments
    from mat_hopper.experiments.profiles import PROFILES
    from mat_hopper.experiments.reproduce import _tasks, planned_steps, task_steps

    names = parse_experiments("1,controls")
    for r in (0, 1, 4):
        exact = sum(task_steps(t) for ts in _tasks(PROFILES["quick"], names, ("paper",), r).values() for t in ts)
        assert planned_steps("quick", names, ("paper",), r) == pytest.approx(exact)


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"workers": 2, "scheduler": "tcp://127.0.0.1:1"}, "not both"),
        ({"scheduler": 42}, "scheduler must be an address like tcp://host:8786"),
        ({"scheduler": "  "}, "scheduler address is empty"),
    ],
)
def test_library_scheduler_checks_come_before_the_results_folder(tmp_path, kwargs, message):
    out, cache = tmp_path / "out", tmp_path / "cache"
    with pytest.raises(ValueError, match=message):
        reproduce(TINY, "1", str(out), cache_dir=str(cache), progress=False, figures=False, log=None, **kwargs)
    assert not out.exists() and not cache.exists()


def test_help_lists_every_accepted_experiment_spelling(capsys):
    # every spelling accepted (e.g. "--experiments 4", the stability map) is in --help
    from mat_hopper.experiments.paper import EXPERIMENT_SPELLINGS, experiment_name

    with pytest.raises(SystemExit):
        main(["reproduce", "--help"])
    text = " ".join(capsys.readouterr().out.split())  # argparse wraps lines
    for key, spellings in EXPERIMENT_SPELLINGS.items():
        for sp in spellings:
            assert experiment_name(sp.upper()) == key
            assert sp in text, sp
    assert "stability (4, stab)" in text and ", or all;" in text
