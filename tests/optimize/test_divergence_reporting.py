"""A study tells its divergences: a warning before a run above a queued
design's stable step, the diverged trials counted and advised at the end,
racing's pruned trials counted by why, a replayed divergence explained,
and a report that neither scores diverged trials nor compares a
mass-held study with legs of other masses."""

from __future__ import annotations

import dataclasses
import math

import optuna
from optuna.trial import TrialState, create_trial

from mat_hopper.core.materials import parse_design
from mat_hopper.experiments.profiles import resolve_profile
from mat_hopper.optimize import (
    Feasibility,
    SearchSpace,
    StudyConfig,
    diverged_run_message,
    divergence_advice,
    feasibility,
    queued_seeds,
    queued_step_warnings,
    trials_frame,
)
from mat_hopper.optimize._feasibility import LEFT_OUT_ATTR, PRUNED_WHY_ATTR
from mat_hopper.optimize._objective import RESULT_ATTR
from mat_hopper.optimize._scoring import SE_ATTR
from mat_hopper.optimize.report import _outside_band, importances


def _config(n_segments: int = 5, **objective) -> StudyConfig:
    c = StudyConfig("x", SearchSpace(n_segments=n_segments))
    ob = dataclasses.replace(c.objective, profile=resolve_profile("quick"), replicates=0, **objective)
    return StudyConfig("x", c.space, ob)


def test_a_queued_design_above_its_stable_step_is_warned_of_with_what_a_study_offers():
    config = _config(5)
    lines = queued_step_warnings(config, queued_seeds(config.space, config.objective)[0], trials=4)
    assert len(lines) == 4 and lines[0].startswith("queued design SS: the physics step 0.0001 s is above")
    assert "may diverge" in lines[0] and "fewer --segments" in lines[0] and "--convention axial" in lines[0]
    assert "try a new study with --timestep auto" in lines[0]  # a study's step is in its key: a new study
    three = _config(3)  # the paper's legs at 3 segments lie within their bounds
    assert queued_step_warnings(three, queued_seeds(three.space, three.objective)[0]) == []


def test_diverged_trials_end_the_study_with_a_count_and_what_to_try():
    config = _config(5)
    line = divergence_advice(Feasibility(finished=4, reasons={"diverged": 4}), config)
    assert line.startswith("diverged: 4 of 4 finished trials") and "exits 0" in line and "fewer --segments" in line
    raced = divergence_advice(Feasibility(finished=2, feasible=2, pruned=7, pruned_reasons={"diverged": 7}), config)
    assert "7 on a screening rung (stopped there by racing)" in raced and "pruned" not in raced
    assert divergence_advice(Feasibility(finished=3, feasible=3), config) is None


def test_racing_counts_its_pruned_trials_by_why():
    study = optuna.create_study(directions=["minimize", "minimize"])
    for attrs in ({PRUNED_WHY_ATTR: "diverged"},) * 3 + ({LEFT_OUT_ATTR: "fell or diverged on rung 0"}, {}):
        study.add_trial(create_trial(state=TrialState.PRUNED, user_attrs=attrs))
    f = feasibility(study, _config(3))
    assert f.pruned == 5 and f.pruned_reasons == {"diverged": 3, "fell or diverged": 1, "ranked out": 1}
    assert f.text() == (
        "feasible: 0 of 0 trials finished at full fidelity (5 more stopped on a screening rung: 3 diverged, "
        "1 fell or diverged, 1 pruned by racing (ranked out))"
    )
    frame = trials_frame(study, _config(3))  # each row names its trial diverged, not pruned
    assert list(frame["not_feasible_because"]) == [
        *["diverged (screening rung)"] * 3,
        "fell or diverged (screening rung)",
        "pruned by racing (ranked out)",
    ]


def test_a_replayed_divergence_says_when_why_and_what_to_try():
    config = _config(5)
    line = diverged_run_message(parse_design("SS", n_segments=5), config.objective, {"behaviour": "ramp"})
    assert line.startswith("diverged at t = ") and "analytic stable step" in line
    assert "the automatic step would take 3 physics substeps" in line and "fewer --segments" in line


def test_a_diverged_trial_has_no_objective_values_in_the_trials_table():
    config = _config(3)
    study = optuna.create_study(directions=["minimize", "minimize"])
    rows = [{"behaviour": "ramp", "upright": False, "diverged_at_s": 0.004, "replicate": -1}]
    study.add_trial(
        create_trial(
            state=TrialState.COMPLETE,
            values=[0.003, 0.01],  # whole-run means of a run cut short: better than any feasible trial's
            user_attrs={RESULT_ATTR: {"feasible": False, "per_behaviour": rows}},
        )
    )
    frame = trials_frame(study, config)
    assert math.isnan(frame.loc[0, "tracking_error_m"]) and math.isnan(frame.loc[0, "power_w"])
    assert frame.loc[0, "not_feasible_because"] == "diverged"


def test_a_diverged_trials_standard_errors_hop_height_and_constraints_are_empty_too():
    """Every number measured on runs cut short is empty, on a full-fidelity
    trial and on one racing stopped on a screening rung; ``unstable`` (which
    says that they diverged) is kept."""
    config = _config(3)
    study = optuna.create_study(directions=["minimize", "minimize"])
    rows = [{"behaviour": "ramp", "upright": False, "diverged_at_s": 0.004, "replicate": -1}]
    result = {"feasible": False, "per_behaviour": rows, "hop_height_m": 0.8958}
    se = {"tracking_error_m": 0.000866, "power_w": 195044.43}
    study.add_trial(
        create_trial(
            state=TrialState.COMPLETE,
            values=[0.003, 0.01],
            user_attrs={RESULT_ATTR: result, SE_ATTR: se},
            constraints={"hop_height": 0.5, "unstable": 1.0},
        )
    )
    study.add_trial(create_trial(state=TrialState.PRUNED, user_attrs={PRUNED_WHY_ATTR: "diverged", SE_ATTR: se}))
    frame = trials_frame(study, config)
    assert list(frame["not_feasible_because"]) == ["diverged", "diverged (screening rung)"]
    blank = ["tracking_error_m_se", "power_w_se", "hop_height_m", "constraint_hop_height"]
    assert frame[blank].isna().all().all()
    assert frame.loc[0, "constraint_unstable"] == 1.0


def test_importances_leave_out_the_trials_that_diverged():
    """Three trials that stood and one that diverged: fewer than the four
    sampled trials importances need, so none (the diverged one's values
    would count otherwise)."""
    study = optuna.create_study(directions=["minimize", "minimize"])
    dist = {"x": optuna.distributions.FloatDistribution(0.0, 1.0)}
    ok = {RESULT_ATTR: {"feasible": True, "per_behaviour": [{"behaviour": "ramp", "upright": True}]}}
    bad = [{"behaviour": "ramp", "upright": False, "diverged_at_s": 0.004, "replicate": -1}]
    for x, attrs in ((0.1, ok), (0.5, ok), (0.9, ok), (0.3, {RESULT_ATTR: {"feasible": False, "per_behaviour": bad}})):
        study.add_trial(
            create_trial(
                state=TrialState.COMPLETE, values=[x, 1 - x], params={"x": x}, distributions=dist, user_attrs=attrs
            )
        )
    assert importances(study).empty


def test_an_exported_diverged_trial_says_so_in_its_row_and_its_lines(tmp_path, capsys):
    """--export of a trial whose runs diverged: the CSV row names why
    (as trials.csv), its objective columns are empty (means of runs cut
    short), the design still reads back, and the command's lines say when
    it diverged."""
    import pandas as pd

    from mat_hopper.batch import designs_from_csv
    from mat_hopper.cli import main
    from mat_hopper.optimize._study import create_or_load

    config = _config(3)
    study = create_or_load(config, f"sqlite:///{tmp_path / 'x.db'}")
    rows = [{"behaviour": "ramp", "upright": False, "diverged_at_s": 0.0009, "replicate": -1}]
    params = {f"seg{i}_{q}": v for i in (1, 2, 3) for q, v in (("density_g_cm3", 1.2), ("modulus_gpa", 700.0))}
    dists = {k: optuna.distributions.FloatDistribution(0.1, 1000.0) for k in params}
    study.add_trial(
        create_trial(
            state=TrialState.COMPLETE, values=[2e-5, 0.07], params=params, distributions=dists,
            user_attrs={RESULT_ATTR: {"feasible": False, "per_behaviour": rows}},
        )
    )  # fmt: skip
    n = study.trials[-1].number
    assert main(["optimize", "--export", str(n), "--study", "x", "--studies-dir", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert f"trial {n} diverged at t = 0.0009 s (ramp): not feasible" in out
    row = pd.read_csv(tmp_path / f"x-trial{n}.csv").iloc[0]
    assert row["not_feasible_because"] == "diverged" and not row["feasible"]
    assert math.isnan(row["tracking_error_m"]) and math.isnan(row["power_w"])
    assert designs_from_csv(tmp_path / f"x-trial{n}.csv")[0].moduli_gpa == (700.0, 700.0, 700.0)


def test_a_mass_held_study_compares_with_no_baseline_of_another_mass():
    held = _config(3, leg_mass=6.5, leg_mass_tolerance_kg=0.325)
    assert "8.77 kg lies outside the study's band 6.17 to 6.83 kg" in _outside_band("SS", held)
    assert "outside the study's band" in _outside_band("rho-inc", held)
    assert _outside_band("SS", _config(3)) is None  # no mass held: every baseline compares


def test_a_racing_studys_header_counts_what_its_feasibility_line_counts():
    """Under racing the target counts screened trials: the header says so,
    and splits them as the feasibility line below it does (full fidelity,
    stopped on a screening rung), so "9/9" never stands beside "2 of 2"."""
    from mat_hopper.cli._optimize_outputs import done_text
    from mat_hopper.optimize._driver import RunResult

    f = Feasibility(finished=2, feasible=2, pruned=7, pruned_reasons={"diverged": 7})
    res = RunResult("r", "sqlite:///r.db", 9, 9, 0, evaluator="racing")
    res.feasibility = f
    head = done_text(res, trials=4)
    assert head == (
        "9/9 trials screened by racing, --trials 4 rounded up to whole brackets: 2 finished at full fidelity, "
        "7 stopped on a screening rung"
    )
    assert f.text().startswith("feasible: 2 of 2 trials finished at full fidelity (7 more stopped on a screening")
    plain = RunResult("s", "sqlite:///s.db", 4, 4, 0, evaluator="pool:1")
    assert done_text(plain, trials=4) == "4/4 trials finished"
