"""The optimizer's backends: one study holds trials of one backend, the
batch rows are scored by the CPU path's definitions, and ``--backend warp``
without mujoco-warp is a one-line error. No simulation here (the study on
the warp backend itself: tests/batch/test_batch_optimize.py)."""

from __future__ import annotations

import math
import os
import subprocess
import sys

import optuna
import pytest

from mat_hopper.experiments.profiles import Profile
from mat_hopper.optimize import Objective, SearchSpace, StudyConfig, create_or_load, open_storage
from mat_hopper.optimize._batch import behaviour_row, default_device  # noqa: F401  (imports without warp)
from mat_hopper.optimize._objective import NO_DATA_VALUE, aggregate
from mat_hopper.optimize._study import BACKEND_ATTR

optuna.logging.set_verbosity(optuna.logging.WARNING)
OBJ = Objective(replicates=0, profile=Profile("tiny", duration_s=2.0, transient_s=0.5))


def _storage(tmp_path):
    return open_storage(f"sqlite:///{tmp_path / 'studies.db'}")


def test_a_study_holds_one_backend(tmp_path):
    storage = _storage(tmp_path)
    cpu = StudyConfig("cpu-study", SearchSpace(), OBJ)
    create_or_load(cpu, storage)
    with pytest.raises(ValueError, match="holds trials of the mujoco backend"):
        create_or_load(cpu, storage, backend="warp")
    warp = StudyConfig("warp-study", SearchSpace(), OBJ)
    study = create_or_load(warp, storage, backend="warp")
    assert study.user_attrs[BACKEND_ATTR] == "warp"
    assert len(study.get_trials()) == 8  # the paper's eight expressible designs enqueued, as on the CPU path
    create_or_load(warp, storage, backend="warp")  # resuming on the same backend is fine
    with pytest.raises(ValueError, match="holds trials of the warp backend"):
        create_or_load(warp, storage)  # the CPU path (run_study) refuses it


def _summary(**kw):
    row = dict(
        n_hops=4,
        upright=True,
        stable=True,
        tracking_error_m=0.02,
        power_w=1.5,
        hop_height_m=1.08,
        run_tracking_error_m=0.5,
        run_power_w=7.0,
        diverged_at_s=None,
        total_mass_kg=3.2,
    )
    return {**row, **kw}


def test_batch_rows_are_scored_as_on_the_cpu_path():
    # scored hops, upright: the per-hop means
    r = behaviour_row(_summary(), "ramp", 2.0)
    assert (r["tracking_error_m"], r["power_w"], r["simulated_s"], r["backend"]) == (0.02, 1.5, 2.0, "warp")
    # no hop scored, or not upright: the whole-run means; none recorded: NO_DATA_VALUE
    assert behaviour_row(_summary(n_hops=0), "ramp", 2.0)["power_w"] == 7.0
    fell = behaviour_row(_summary(upright=False, stable=False, diverged_at_s=0.7), "ramp", 2.0)
    assert (fell["tracking_error_m"], fell["simulated_s"]) == (0.5, 0.7)
    empty = behaviour_row(_summary(upright=False, run_tracking_error_m=math.nan, run_power_w=3e9), "ramp", 2.0)
    assert (empty["tracking_error_m"], empty["power_w"]) == (NO_DATA_VALUE, NO_DATA_VALUE)
    # the Evaluation: mean over behaviours; worst height violation |1.08 - 1| - 0.05 = 0.03; unstable 1
    ev = aggregate([r, behaviour_row(_summary(hop_height_m=0.99, tracking_error_m=0.04), "forward", 2.0)], OBJ)
    assert ev.values == pytest.approx((0.03, 1.5)) and ev.constraints == pytest.approx((0.03, 0.0))
    ev = aggregate([r, fell], OBJ)
    assert ev.constraints[1] == 1.0 and not ev.feasible


def _cli(*args, env_code: str = ""):
    code = f"import sys\n{env_code}\nfrom mat_hopper.cli import main\nsys.exit(main({list(args)!r}))"
    return subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)


def test_warp_backend_without_mujoco_warp_is_a_one_line_error(tmp_path):
    studies = tmp_path / "studies"
    p = _cli(
        "optimize",
        "--study",
        "s",
        "--trials",
        "2",
        "--backend",
        "warp",
        "--studies-dir",
        str(studies),
        env_code="sys.modules['mujoco_warp'] = None   # as if not installed",
    )
    assert p.returncode == 2, p.stderr
    lines = p.stderr.strip().splitlines()
    assert len(lines) == 1 and "mujoco-warp" in lines[0] and "Traceback" not in p.stderr, p.stderr
    assert not os.path.exists(studies)  # no study made


@pytest.mark.parametrize(
    "extra, message", [(["--device", "cpu"], "for --backend warp"), (["--backend", "gpu"], "invalid choice")]
)
def test_backend_options(tmp_path, extra, message):
    p = _cli("optimize", "--study", "s", "--trials", "2", "--studies-dir", str(tmp_path / "s"), *extra)
    assert p.returncode == 2 and message in p.stderr, p.stderr
    assert not os.path.exists(tmp_path / "s")
