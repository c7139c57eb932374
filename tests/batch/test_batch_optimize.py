"""The optimizer on the warp backend (Warp's CPU device): one batch of four
trials asked from Optuna, simulated together, told back.

Two sources: the table mat_hopper.batch.evaluate returned to the study (the
told values must be its per-design summaries, exactly; recorded as the
study ran, not run again: Warp's CPU device costs about 10 ms a step, and a
second batch cost 4-5 min of CI; tests/batch/test_batch_warp.py checks that
a short batch run twice is bit-identical), and the CPU path's objective,
mat_hopper.optimize.evaluate, independent of the batch (within the batch
agreement tests' tolerance: tracking error and power 10 %, hop height
0.01 m).
2.5 s of forward hopping (transient 0.2 s) at 2e-4 s (the step MD and PVC hold under the
authors' timing), PVC-like bounds so that every design is stable. A design
that scores no hop cycle in so short a run is scored by its whole-run means,
as on the CPU path: both branches of the objective are compared.
"""

from __future__ import annotations

import signal
import time

import optuna
import pytest

pytest.importorskip("mujoco_warp")

from _authors_loop import rel  # noqa: E402

import mat_hopper.batch  # noqa: E402
from mat_hopper.batch import BatchSettings  # noqa: E402
from mat_hopper.batch import evaluate as batch_evaluate
from mat_hopper.experiments.profiles import Profile  # noqa: E402
from mat_hopper.optimize import (  # noqa: E402
    CONSTRAINTS,
    Objective,
    RunOptions,
    SearchSpace,
    StudyConfig,
    evaluate,
    open_storage,
    run_batch_study,  # noqa: E402
)
from mat_hopper.optimize._objective import RESULT_ATTR  # noqa: E402
from mat_hopper.optimize._study import BACKEND_ATTR  # noqa: E402

optuna.logging.set_verbosity(optuna.logging.WARNING)
PROFILE = Profile("tiny-warp", duration_s=2.5, transient_s=0.2, timestep_s=2e-4)
OBJ = Objective(replicates=0, behaviours=("forward",), profile=PROFILE)
SPACE = SearchSpace(n_segments=3, density_g_cm3=(1.5, 2.5), modulus_gpa=(0.45, 9.0))  # PVC (1.39) outside
SETTINGS = BatchSettings(duration_s=2.5, timestep_s=2e-4, transient_s=0.2)


def _constraints(trial) -> tuple:
    """The constraints as Trial.set_constraint stored them (system attrs "constraints:NAME")."""
    return tuple(trial.system_attrs[f"constraints:{name}"] for name in CONSTRAINTS)


@pytest.fixture(scope="module")
def study(tmp_path_factory):
    folder = tmp_path_factory.mktemp("studies")
    assert SPACE.seeds() == []  # no paper design in these bounds: four sampled designs
    tables = []

    def recording(designs, behaviour, settings, **kw):  # the batch's own tables, as the study got them
        table = batch_evaluate(designs, behaviour, settings, **kw)
        tables.append((designs, behaviour, settings, kw, table))
        return table

    t0 = time.perf_counter()
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(mat_hopper.batch, "evaluate", recording)
        res = run_batch_study(
            StudyConfig("warp-tiny", SPACE, OBJ),
            RunOptions(trials=4, studies_dir=str(folder), progress=False),
            device="cpu",
            batch_size=4,
        )
    print(f"4 trials, one batch: {time.perf_counter() - t0:.1f} s")
    assert res.done == 4 and res.finished and res.evaluator == "warp:cpu"
    url = f"sqlite:///{folder / 'warp-tiny.db'}"
    return optuna.load_study(study_name="warp-tiny", storage=open_storage(url)), tables


@pytest.mark.slow
def test_warp_study_tells_the_batch_summaries(study):
    study, tables = study
    trials = study.get_trials()
    assert study.user_attrs[BACKEND_ATTR] == "warp"
    assert [t.state.name for t in trials] == ["COMPLETE"] * 4
    assert all(t.user_attrs["backend"] == "warp" for t in trials)
    assert len(tables) == 1  # four trials, one behaviour: one batch
    designs, behaviour, settings, kw, table = tables[0]
    assert [d.name for d in designs] == [SPACE.design(t.params).name for t in trials]
    assert (behaviour, settings, kw["backend"], kw["device"]) == ("forward", SETTINGS, "warp", "cpu")
    assert list(table["design"]) == [d.name for d in designs]
    scored = 0
    for t, (_, row) in zip(trials, table.iterrows()):
        assert row["stable"] and row["upright"], row.to_dict()
        if row["n_hops"] >= 1:  # the per-hop means; the height constraint |h - 1 m| - 0.05 m
            scored += 1
            assert tuple(t.values) == (row["tracking_error_m"], row["power_w"])
            assert t.user_attrs[RESULT_ATTR]["hop_height_m"] == row["hop_height_m"]
            assert _constraints(t) == (abs(row["hop_height_m"] - 1.0) - 0.05, 0.0)
        else:  # no hop scored: the whole-run means; the height constraint 1 m - 0.05 m
            assert tuple(t.values) == (row["run_tracking_error_m"], row["run_power_w"])
            assert _constraints(t) == (0.95, 0.0)
    assert scored >= 2


@pytest.mark.slow
def test_warp_study_agrees_with_the_cpu_objective(study):
    study, _ = study
    for t in study.get_trials():
        cpu = evaluate(SPACE.design(t.params), OBJ)
        label = f"trial {t.number}: warp {t.values} vs cpu {cpu.values}"
        assert rel(t.values[0], cpu.values[0]) <= 0.10, label
        assert rel(t.values[1], cpu.values[1]) <= 0.10, label
        warp_row, cpu_row = t.user_attrs[RESULT_ATTR]["per_behaviour"][0], cpu.per_behaviour[0]
        assert abs(warp_row["n_hops"] - cpu_row["n_hops"]) <= 1, label
        if warp_row["n_hops"] and cpu_row["n_hops"]:
            assert abs(warp_row["hop_height_m"] - cpu_row["hop_height_m"]) <= 0.01, label
            assert abs(_constraints(t)[0] - cpu.constraints[0]) <= 0.01, label
        assert _constraints(t)[1] == cpu.constraints[1] == 0.0


def test_ctrl_c_right_after_a_trial_is_asked_requeues_it(tmp_path, monkeypatch):
    """Ctrl-C just after Study.ask made the second trial of a batch: both
    trials asked so far are failed and re-queued (none is left RUNNING), and
    KeyboardInterrupt reaches the caller. Nothing is simulated."""
    real_ask, calls = optuna.Study.ask, []

    def ask(self, *a, **kw):
        trial = real_ask(self, *a, **kw)
        calls.append(trial.number)
        if len(calls) == 2:
            signal.raise_signal(signal.SIGINT)
        return trial

    monkeypatch.setattr(optuna.Study, "ask", ask)
    with pytest.raises(KeyboardInterrupt):
        run_batch_study(
            StudyConfig("warp-int", SPACE, OBJ),
            RunOptions(trials=4, studies_dir=str(tmp_path), progress=False),
            device="cpu",
            batch_size=4,
        )
    ts = optuna.load_study(study_name="warp-int", storage=open_storage(f"sqlite:///{tmp_path / 'warp-int.db'}")).trials
    assert calls == [0, 1]
    assert [t.state for t in ts] == [optuna.trial.TrialState.FAIL] * 2 + [optuna.trial.TrialState.WAITING] * 2
    assert [t.system_attrs["failed_trial"] for t in ts[2:]] == [0, 1]
    assert [t.params for t in ts[2:]] == [ts[0].params, ts[1].params]
