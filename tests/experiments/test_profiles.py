"""Run profiles (mat_hopper.experiments.profiles): their keys, their run
settings held once as SimSettings fields, and the one reader of
$MAT_HOPPER_PROFILE."""

import ast
import pickle
from dataclasses import FrozenInstanceError, fields, replace
from pathlib import Path

import pytest

from mat_hopper.core.sim import SETTING_NAMES, SimSettings
from mat_hopper.core.timestep import AUTO
from mat_hopper.experiments.profiles import (
    PROFILE_ENV,
    PROFILE_KEYS,
    PROFILES,
    RUN_SETTINGS,
    Profile,
    get_profile,
    resolve_profile,
)

# The keys of the shipped profiles as optimizer studies and result caches
# recorded them before the run settings moved into Profile.run: literal, so
# that a change to Profile cannot move them unseen.
PAPER_KEY = {
    "name": "paper",
    "duration_s": 60.0,
    "transient_s": 20.0,
    "timestep_s": 0.0001,
    "stability_grid_size": 20,
    "stability_duration_s": 2.0,
    "stability_tolerance": 1.25,
    "stability_max_iter": 10,
    "stability_scan": True,
    "record_rate_hz": 1000.0,
    "convention": "paper",
    "axial_timestep_s": "auto",
    "replicates": 10,
    "sensor_timing": "authors",
    "segment_mass": "leg",
    "push_scale": 1.0,
    "substep_studies": True,
}
QUICK_KEY = {
    **PAPER_KEY,
    "name": "quick",
    "duration_s": 12.0,
    "transient_s": 4.0,
    "stability_grid_size": 4,
    "stability_duration_s": 1.0,
    "stability_tolerance": 1.5,
    "replicates": 2,
    "substep_studies": False,
}
PAPER, QUICK = PROFILES["paper"], PROFILES["quick"]


def test_key_dicts_are_todays_in_their_order():
    for profile, want in ((PAPER, PAPER_KEY), (QUICK, QUICK_KEY)):
        got = profile.key_dict()
        assert got == want and list(got) == list(want) == list(PROFILE_KEYS)
        assert [type(v) for v in got.values()] == [type(v) for v in want.values()]  # 60.0 stays a float


def test_a_key_rebuilds_an_equal_profile():
    for p in (
        PAPER,
        QUICK,
        PAPER.for_convention("bending"),
        QUICK.for_convention("axial"),
        replace(QUICK, push_scale=2.0),
        Profile("x", 3, 1, sensor_timing=2, segment_mass="Capsule"),
    ):
        q = Profile(**p.key_dict())
        assert q == p and hash(q) == hash(p) and q.key_dict() == p.key_dict()
        assert pickle.loads(pickle.dumps(p)) == p  # sent to worker processes
    assert PAPER != QUICK and PAPER.for_convention("bending").timestep_s == AUTO


def test_run_settings_are_held_once_as_simsettings_fields():
    own = {f.name for f in fields(Profile)}
    assert not own & set(SETTING_NAMES), "a Profile field copies a SimSettings field"
    assert set(RUN_SETTINGS) <= set(SETTING_NAMES) and "run" in own
    assert tuple(QUICK.run) == RUN_SETTINGS
    assert {k: getattr(QUICK, k) for k in RUN_SETTINGS} == dict(QUICK.run)
    s = QUICK.sim_settings()
    assert {k: getattr(s, k) for k in RUN_SETTINGS} == dict(QUICK.run)
    with pytest.raises(TypeError):
        QUICK.run["duration_s"] = 1.0  # read-only
    with pytest.raises(FrozenInstanceError):
        QUICK.replicates = 3
    with pytest.raises(AttributeError):
        QUICK.duration_s = 1.0


def test_replace_and_run_override():
    q = replace(QUICK, duration_s=8.0, transient_s=2.0)
    assert (q.duration_s, q.transient_s, q.timestep_s, q.replicates, q.name) == (8.0, 2.0, 1e-4, 2, "quick")
    assert replace(QUICK, run={**QUICK.run, "record_rate_hz": 250.0}).record_rate_hz == 250.0
    from_settings = Profile("s", run=SimSettings(duration_s=3.0, transient_s=1.0, convention="Axial"))
    assert (from_settings.duration_s, from_settings.convention) == (3.0, "axial")
    assert Profile("s", 5.0, run={"duration_s": 3.0, "transient_s": 1.0}).duration_s == 5.0  # by name wins
    assert QUICK.sim_settings(segment_mass="capsule").segment_mass == "capsule"


@pytest.mark.parametrize(
    "kwargs",
    [
        {"duration_s": 5.0, "transient_s": 10.0},
        {"duration_s": 5.0, "transient_s": 1.0, "convention": "twisted"},
        {"duration_s": 5.0, "transient_s": 1.0, "record_rate_hz": 0.0},
        {"duration_s": 5.0, "transient_s": 1.0, "segment_mass": "heavy"},
        {"duration_s": 5.0, "transient_s": 1.0, "sensor_timing": "late"},
        {"duration_s": 5.0, "transient_s": 1.0, "timestep_s": 0.5},
    ],
)
def test_run_settings_are_checked_by_simsettings_with_its_words(kwargs):
    with pytest.raises(ValueError) as by_settings:
        SimSettings(**kwargs)
    with pytest.raises(ValueError) as by_profile:
        Profile("x", **kwargs)
    assert str(by_profile.value) == str(by_settings.value)


def test_what_only_a_profile_refuses():
    assert Profile("x", 4.0, 1.0, "AUTO").timestep_s == AUTO
    with pytest.raises(ValueError, match="timestep_s must be a number"):
        Profile("x", 4.0, 1.0, "fast")
    with pytest.raises(ValueError, match="run: unknown setting"):
        Profile("x", run={"duration_s": 4.0, "transient_s": 1.0, "damping": "authors"})
    with pytest.raises(TypeError, match="transient_s"):
        Profile("x", 4.0)
    with pytest.raises(ValueError, match="profile name"):
        Profile("", 4.0, 1.0)


def test_resolve_profile_reads_the_variable_and_get_profile_never(monkeypatch):
    monkeypatch.setenv(PROFILE_ENV, "quick")
    assert resolve_profile() is QUICK and resolve_profile("paper") is PAPER and resolve_profile(QUICK) is QUICK
    monkeypatch.setenv(PROFILE_ENV, "turbo")
    with pytest.raises(ValueError, match=r"unknown profile 'turbo' \(from \$MAT_HOPPER_PROFILE\)"):
        resolve_profile()
    assert get_profile(" Quick ") is QUICK and get_profile(PAPER) is PAPER  # below the entry points
    with pytest.raises(ValueError, match="none given"):
        get_profile(None)
    with pytest.raises(ValueError, match="unknown profile 'fast'; accepted: paper, quick"):
        get_profile("fast")
    monkeypatch.setenv(PROFILE_ENV, " ")
    with pytest.raises(ValueError, match="MAT_HOPPER_PROFILE is set but empty"):
        resolve_profile()
    monkeypatch.delenv(PROFILE_ENV)
    assert resolve_profile() is PAPER


def test_below_the_entry_points_nothing_reads_the_variable(monkeypatch):
    """Task builders, plans and the objective given a profile never look at
    $MAT_HOPPER_PROFILE (a read of this value would raise)."""
    from mat_hopper.analysis.robustness import variants
    from mat_hopper.experiments import controls, convergence, robustness
    from mat_hopper.experiments.paper import ControlsStudy, RobustnessStudy, StabilityMap, experiment_1, experiment_3
    from mat_hopper.experiments.reproduce import planned_steps
    from mat_hopper.optimize import Objective

    monkeypatch.setenv(PROFILE_ENV, "turbo")
    assert {t.labels["profile"] for t in experiment_1().tasks("quick")} == {"quick"}
    assert len(StabilityMap().tasks("quick")) == 16 and experiment_3().tasks(QUICK)
    assert RobustnessStudy().tasks("quick") and ControlsStudy().tasks("quick")
    assert convergence.tasks("quick", designs=("SS",), behaviours=("forward",))
    assert controls.control_tasks("quick", designs=("SS",), behaviours=("static",), replicates=2)
    assert robustness.tasks("quick", variants(replicates=0, timesteps=False))
    assert planned_steps("quick", ["exp1"], ("paper",), 0) > 0
    assert Objective(profile="quick").profile is QUICK
    with pytest.raises(ValueError, match="turbo"):  # an entry point does read it
        Objective()


def _reads_of_the_variable(tree) -> list[str]:
    """Functions (by name) holding a call or subscript that names PROFILE_ENV
    or "MAT_HOPPER_PROFILE" (os.environ.get, env_value, os.environ[...])."""
    out = []

    def names_it(node) -> bool:
        return (isinstance(node, ast.Name) and node.id == "PROFILE_ENV") or (
            isinstance(node, ast.Constant) and node.value == PROFILE_ENV
        )

    for fn in ast.walk(tree):
        if not isinstance(fn, (ast.FunctionDef, ast.AsyncFunctionDef)):
            continue
        for node in ast.walk(fn):
            if isinstance(node, ast.Call) and any(names_it(a) for a in node.args):
                func = node.func
                called = func.attr if isinstance(func, ast.Attribute) else getattr(func, "id", "")
                if called in ("env_value", "get", "getenv", "pop", "setdefault"):
                    out.append(fn.name)
            elif isinstance(node, ast.Subscript) and names_it(node.slice):
                out.append(fn.name)
    return out


def test_resolve_profile_is_the_only_reader_of_the_variable():
    pkg = Path(__file__).resolve().parents[2] / "mat_hopper"
    readers = {
        f"{path.relative_to(pkg).as_posix()}:{fn}"
        for path in pkg.rglob("*.py")
        for fn in _reads_of_the_variable(ast.parse(path.read_text(encoding="utf-8")))
    }
    assert readers == {"experiments/profiles.py:resolve_profile"}
