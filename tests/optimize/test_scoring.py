"""Noise- and mass-aware scores (mat_hopper.optimize._scoring): replicates on
common random numbers, mean and CVaR with standard errors, the leg-mass
constraint. Runs use a 2 s profile (tiny)."""

from __future__ import annotations

import math

import numpy as np
import optuna
import pytest

from mat_hopper.core.behaviours import behaviour
from mat_hopper.core.materials import LegDesign, paper_designs
from mat_hopper.core.sim import C, RolloutRunner
from mat_hopper.experiments.profiles import Profile
from mat_hopper.optimize import (
    OBJECTIVES,
    Objective,
    PoolEvaluator,
    RunOptions,
    SearchSpace,
    StudyConfig,
    _scoring,
    create_or_load,
    evaluate,
    run_loop,
)
from mat_hopper.optimize._objective import aggregate

optuna.logging.set_verbosity(optuna.logging.WARNING)
TINY = Profile("tiny", duration_s=2.0, transient_s=0.5)


# --- risk measures ----------------------------------------------------------


def test_cvar_by_hand():
    v = [2.0, 4.0, 1.0, 3.0]
    assert _scoring.cvar(v, 0.0) == 2.5  # the mean
    assert _scoring.cvar(v, 0.75) == 4.0  # the worst quarter: one sample
    assert _scoring.cvar(v, 0.5) == 3.5  # (4 + 3) / 2
    assert _scoring.cvar(v, 0.6) == pytest.approx((4 + 0.6 * 3) / 1.6)  # 1.6 samples: 4, and 0.6 of 3
    for bad in (1.0, -0.1, True):
        with pytest.raises(ValueError, match="alpha"):
            _scoring.cvar(v, bad)


def test_score_mean_and_cvar_standard_errors():
    v = [1.0, 2.0, 3.0, 4.0]
    value, se = _scoring.score(v, "mean")
    assert value == 2.5
    assert se == pytest.approx(math.sqrt(5 / 3) / 2)  # sd (ddof 1) 1.2910 / sqrt(4)
    value, se = _scoring.score(v, "cvar", 0.5)
    assert value == 3.5 and 0 < se < 2
    assert math.isnan(_scoring.score([1.0], "mean")[1])
    with pytest.raises(ValueError, match="risk"):
        _scoring.score(v, "median")


def test_objective_fields_checked_and_keyed():
    for kw, match in (
        ({"replicates": -1}, "replicates"),
        ({"replicates": 1.5}, "replicates"),
        ({"risk": "worst"}, "risk"),
        ({"risk": "cvar", "replicates": 1}, "replicates >= 2"),
        ({"cvar_alpha": 1.0}, "cvar_alpha"),
        ({"leg_mass": "steel"}, "leg_mass"),
        ({"leg_mass": -2.0}, "leg_mass"),
        ({"leg_mass_tolerance_kg": 0.1}, "needs leg_mass"),
        ({"leg_mass": "SS", "leg_mass_tolerance_kg": 0}, "leg_mass_tolerance_kg"),
    ):
        with pytest.raises(ValueError, match=match):
            Objective(profile=TINY, **kw)
    plain = Objective(profile=TINY, replicates=0)
    assert not {"replicates", "risk", "leg_mass"} & set(plain.key())  # older studies keep their keys
    ob = Objective(profile=TINY, replicates=3, risk="cvar", cvar_alpha=0.5, leg_mass="ss", leg_mass_tolerance_kg=0.2)
    assert ob.leg_mass == "SS"
    assert Objective.from_key(ob.key()) == ob
    assert Objective.from_key(plain.key()) == plain
    assert ob.constraint_names == ("hop_height", "unstable", "leg_mass")


# --- common random numbers ------------------------------------------------------


def _optimize(config, n: int, cache, sampler=None):
    """A study in memory with n trials, asked, evaluated and told by the optimizer's loop."""
    storage = optuna.storages.InMemoryStorage()
    study = create_or_load(config, storage, sampler=sampler)
    with PoolEvaluator(str(cache), workers=1) as evaluator:
        run_loop(study, storage, config, evaluator, RunOptions(trials=n, progress=False))
    return study


def test_common_random_numbers_across_trials(tmp_path):
    """Every trial draws the same perturbations: the same seeds, and from
    them the same start of the base (the first recorded sample) whatever
    the leg; a study's trials record those seeds."""
    seeds = _scoring.replicate_seeds(3)
    assert seeds == (1000, 1001, 1002) and len(set(seeds)) == 3
    ob = Objective(profile=TINY, replicates=3)
    window = ob.profile.scored_window_s
    assert _scoring.perturbations(3, window) == _scoring.perturbations(3, window)
    assert _scoring.perturbations(0, window) == [None]
    for pert in _scoring.perturbations(3, window):  # the push falls among the scored hops
        assert window[0] < pert.push_window_s[0] and pert.push_window_s[1] < window[1]
    starts = {}
    for name in ("SS", "PVC"):
        for pert in _scoring.perturbations(3, window):
            runner = RolloutRunner(paper_designs()[name], behaviour("ramp"), ob.sim_settings(pert))
            runner.advance(1)
            starts[name, pert.seed] = runner.result().data[0, [C["x"], C["y"]]]
    for s in seeds:
        assert np.array_equal(starts["SS", s], starts["PVC", s])  # paired: same draw for both legs
        assert np.linalg.norm(starts["SS", s]) > 1e-4  # a real offset (5 mm std)
    assert not np.array_equal(starts["SS", seeds[0]], starts["SS", seeds[1]])

    config = StudyConfig("crn", SearchSpace(), ob)
    study = _optimize(config, 2, tmp_path / "cache")
    done = study.get_trials(states=(optuna.trial.TrialState.COMPLETE,))
    assert len(done) == 2
    for t in done:
        rows = t.user_attrs["result"]["per_behaviour"]
        assert [r["replicate"] for r in rows] == list(seeds)
        se = t.user_attrs[_scoring.SE_ATTR]
        reps = np.array(t.user_attrs["result"]["replicate_values"])
        assert reps.shape == (3, 2)
        assert tuple(t.values) == pytest.approx(tuple(reps.mean(axis=0)), rel=1e-15)
        assert se["tracking_error_m"] == pytest.approx(reps[:, 0].std(ddof=1) / math.sqrt(3))


def test_aggregate_replicates_and_behaviours():
    """Each replicate: the mean over behaviours; the objective: the risk
    measure over replicates; the hop height: each behaviour's mean over
    replicates."""

    def row(b, rep, te, pw, h):
        return dict(
            behaviour=b, replicate=rep, tracking_error_m=te, power_w=pw, hop_height_m=h, n_hops=5, upright=True,
            simulated_s=2.0, total_mass_kg=9.0,
        )  # fmt: skip

    rows = [row("ramp", 1, 1.0, 10.0, 1.0), row("forward", 1, 3.0, 30.0, 1.2)]
    rows += [row("ramp", 2, 2.0, 20.0, 1.0), row("forward", 2, 6.0, 40.0, 1.0)]
    ob = Objective(behaviours=("ramp", "forward"), profile=TINY, replicates=2)
    ev = aggregate(rows, ob)
    assert ev.replicate_values == [[2.0, 20.0], [4.0, 30.0]]
    assert ev.values == (3.0, 25.0)
    assert ev.standard_errors == pytest.approx((1.0, 5.0))  # sd / sqrt(2)
    assert ev.constraints[0] == pytest.approx(abs(1.1 - 1.0) - 0.05)  # forward's mean height, the worst
    cv = aggregate(rows, Objective(behaviours=("ramp", "forward"), profile=TINY, replicates=2, risk="cvar"))
    assert cv.values == (4.0, 30.0)  # alpha 0.75 of two: the worst replicate


# --- the leg-mass constraint --------------------------------------------------------


def test_leg_mass_by_hand():
    # SS, docs/reference-hopper.md's parts: the stub, a capsule r 0.03 m, L 0.05 m at 1000 kg/m^3
    # (pi r^2 L + 4/3 pi r^3 = 2.5447e-4 m^3); 3 segments of two half capsules r 0.025 m, L 0.05 m
    # (1.63625e-4 m^3 each) at 8000 kg/m^3; the foot's upper capsule (the same shape) at 1000 kg/m^3;
    # the foot's lower body, 0.5 kg: 0.25447 + 7.854 + 0.16363 + 0.5 = 8.7721 kg (the
    # leg mass simulate, batch and the controls report; the optimizer counted 7.854 until round 3)
    by_hand = 2.5447e-4 * 1000 + 3 * 2 * 1.63625e-4 * 8000 + 1.63625e-4 * 1000 + 0.5
    assert _scoring.leg_mass_kg(paper_designs()["SS"], "leg") == pytest.approx(by_hand, rel=1e-4)
    assert _scoring.leg_mass_target_kg("SS", 6, "leg") == pytest.approx(_scoring.leg_mass_target_kg("SS", 3, "leg"))
    assert _scoring.leg_mass_target_kg(4.5, 3, "leg") == 4.5


def test_mass_constraint_honoured(tmp_path):
    """Trials record their leg mass and the ``leg_mass`` constraint; every
    trial run, feasible or not, and every trial of Optuna's constrained
    front, has a leg mass within the tolerance of SS's: the sampler
    proposes designs inside the band (mat_hopper.optimize._mass), and a
    design outside it is scored infeasible."""
    ob = Objective(profile=TINY, replicates=0, leg_mass="SS", leg_mass_tolerance_kg=0.5)
    target = _scoring.leg_mass_kg(paper_designs()["SS"], ob.segment_mass)
    config = StudyConfig("mass", SearchSpace(density_g_cm3=(4.0, 12.0)), ob)
    study = _optimize(config, 14, tmp_path / "cache", sampler=optuna.samplers.RandomSampler(seed=3))
    feasible, infeasible = [], []
    for t in study.get_trials(states=(optuna.trial.TrialState.COMPLETE,)):
        res = t.user_attrs["result"]
        mass = res["leg_mass_kg"]
        design = config.space.design(t.params)
        assert mass == pytest.approx(_scoring.leg_mass_kg(design, ob.segment_mass), rel=1e-12)
        assert t.constraints["leg_mass"] == pytest.approx(abs(mass - target) - 0.5)
        (feasible if res["feasible"] else infeasible).append(mass)
    assert feasible and all(abs(m - target) <= 0.5 for m in feasible + infeasible)
    light = LegDesign.mono("Ti")  # 5.27 kg: outside SS's band, the constraint binds
    assert evaluate(light, ob).constraints[2] == pytest.approx(target - _scoring.leg_mass_kg(light, "leg") - 0.5)
    for t in study.best_trials:
        assert abs(t.user_attrs["result"]["leg_mass_kg"] - target) <= 0.5


def test_evaluate_without_replicates_is_one_unperturbed_run():
    ob = Objective(profile=TINY, replicates=0)
    ev = evaluate(LegDesign.mono("SS"), ob)
    assert [r["replicate"] for r in ev.per_behaviour] == [-1]
    assert math.isnan(ev.standard_errors[0]) and len(ev.standard_errors) == len(OBJECTIVES)


# --- the command line -----------------------------------------------------------


def test_cli_options_and_their_errors(tmp_path, monkeypatch, capsys):
    import argparse

    from mat_hopper.cli import main
    from mat_hopper.cli.optimize import config_from_args, register_cli

    parser = argparse.ArgumentParser()
    register_cli(parser.add_subparsers())
    args = parser.parse_args(["optimize", "--study", "s", "--replicates", "3", "--risk", "CVaR", "--leg-mass", "ss"])
    ob = config_from_args(args, None).objective
    assert (ob.replicates, ob.risk, ob.leg_mass, ob.leg_mass_tolerance_kg) == (3, "cvar", "SS", None)
    resumed = config_from_args(parser.parse_args(["optimize", "--study", "s"]), config_from_args(args, None))
    assert resumed.objective == ob  # left out: the stored study's
    lifted = config_from_args(parser.parse_args(["optimize", "--study", "s", "--leg-mass", "none"]), None)
    assert lifted.objective.leg_mass is None
    assert config_from_args(parser.parse_args(["optimize", "--study", "s"]), None).objective.replicates == 4
    monkeypatch.chdir(tmp_path)
    for argv, text in (
        (["--replicates", "-1"], "--replicates must be"),
        (["--risk", "cvar", "--replicates", "1"], "--risk cvar needs --replicates >= 2"),
        (["--leg-mass", "steel"], "--leg-mass:"),
        (["--leg-mass-tolerance", "0.1"], "--leg-mass-tolerance needs --leg-mass"),
    ):
        assert main(["optimize", "--study", "bad", "--trials", "1", *argv]) == 2
        err = capsys.readouterr().err.strip()
        assert text in err and len(err.splitlines()) == 1, err
        assert not (tmp_path / "studies").exists()


def test_warp_backend_needs_unperturbed_runs():
    from mat_hopper.optimize import run_batch_study
    from mat_hopper.optimize._batch import batch_settings, check_unperturbed

    check_unperturbed(Objective(profile=TINY, replicates=0))
    with pytest.raises(ValueError, match="--replicates 0"):
        batch_settings(Objective(profile=TINY, replicates=4), LegDesign.mono("SS"))
    with pytest.raises(ValueError, match="--replicates 0"):  # before any storage or Warp
        run_batch_study(StudyConfig("w", SearchSpace(), Objective(profile=TINY)), RunOptions(storage="bad://"))


def test_cli_stress_constraints(tmp_path, monkeypatch, capsys):
    """--max-yield-fraction and --min-hops-to-failure set
    the objective's stress constraints, are kept on resume, and are refused
    where they cannot act: out of range, or on the warp backend (no stress)."""
    import argparse
    import os

    from mat_hopper.cli import main
    from mat_hopper.cli.optimize import config_from_args, register_cli

    parser = argparse.ArgumentParser()
    register_cli(parser.add_subparsers())
    argv = ["optimize", "--study", "s", "--convention", "bending"]
    args = parser.parse_args([*argv, "--max-yield-fraction", "0.5", "--min-hops-to-failure", "1e7"])
    ob = config_from_args(args, None).objective
    assert (ob.max_yield_fraction, ob.min_hops_to_failure) == (0.5, 1e7)
    assert ob.constraint_names[-2:] == ("peak_stress", "fatigue_life")
    resumed = config_from_args(parser.parse_args(["optimize", "--study", "s"]), config_from_args(args, None))
    assert (resumed.objective.max_yield_fraction, resumed.objective.min_hops_to_failure) == (0.5, 1e7)
    plain = config_from_args(parser.parse_args(argv), None).objective
    assert "peak_stress" not in plain.constraint_names and "fatigue_life" not in plain.constraint_names
    monkeypatch.chdir(tmp_path)
    for extra, text in (
        (["--max-yield-fraction", "-0.5"], "--max-yield-fraction must be"),
        (["--min-hops-to-failure", "0"], "--min-hops-to-failure must be"),
        (["--max-yield-fraction", "0.5", "--backend", "warp", "--replicates", "0"], "--max-yield-fraction: the warp"),
    ):
        assert main(["optimize", "--study", "bad", "--trials", "1", *extra]) == 2
        err = capsys.readouterr().err.strip()
        assert text in err and "\n" not in err, err
    assert os.listdir(tmp_path) == []


def test_risk_name_any_case_is_stored_canonical():
    from mat_hopper.optimize import Objective

    v = [1.0, 2.0, 4.0, 8.0]
    assert _scoring.score(v, "CVaR", 0.5) == _scoring.score(v, "cvar", 0.5)
    assert _scoring.score(v, " Mean ")[0] == 3.75
    assert Objective(profile=TINY, replicates=3, risk="CVAR", cvar_alpha=0.5).risk == "cvar"
    with pytest.raises(ValueError, match="unknown risk 'max'"):
        _scoring.score(v, "max")


# --- ranges of the mass and stress settings (a newcomer's attack) ------------------


def test_no_accepted_design_is_heavier_than_the_leg_mass_cap():
    from mat_hopper.core.materials import DENSITY_RANGE_G_CM3, MAX_SEGMENTS

    heaviest = LegDesign.from_properties([DENSITY_RANGE_G_CM3[1]] * MAX_SEGMENTS, [100.0] * MAX_SEGMENTS)
    assert _scoring.leg_mass_kg(heaviest, "capsule") < _scoring.MAX_LEG_MASS_KG
    assert _scoring.leg_mass_kg(heaviest, "leg") < _scoring.MAX_LEG_MASS_KG


@pytest.mark.parametrize("mass", [1e9, 300.5, "1e9", 1e300])
def test_a_leg_mass_no_design_can_reach_is_refused(mass):
    # leg_mass 1e9 kg was accepted before the fix
    with pytest.raises(ValueError, match=r"leg_mass must be a paper design's name or a mass in \(0, 300\] kg"):
        _scoring.check_leg_mass(mass)
    assert _scoring.check_leg_mass(300) == 300.0 and _scoring.check_leg_mass(" 7.5 ") == 7.5
    with pytest.raises(ValueError, match=r"leg_mass_tolerance_kg must be in \(0, 300\] kg"):
        Objective(profile=TINY, leg_mass="SS", leg_mass_tolerance_kg=1e9)


@pytest.mark.parametrize(
    "field, value",
    [
        ("max_yield_fraction", 1e9),
        ("max_yield_fraction", 10.5),
        ("min_hops_to_failure", 0.5),
        ("min_hops_to_failure", 1e300),
        ("min_hops_to_failure", True),
    ],
)
def test_stress_constraints_out_of_their_physical_range_are_refused(field, value):
    with pytest.raises(ValueError, match=f"{field} must be a finite number in"):
        Objective(profile=TINY, **{field: value})
    ob = Objective(profile=TINY, max_yield_fraction=10, min_hops_to_failure=1)
    assert (ob.max_yield_fraction, ob.min_hops_to_failure) == (10, 1)


@pytest.mark.parametrize(
    "argv, text",
    [
        (["--leg-mass", "1e9"], "--leg-mass must be a paper design's name or a mass in (0, 300] kg"),
        (["--leg-mass", "SS", "--leg-mass-tolerance", "1e9"], "--leg-mass-tolerance must be in (0, 300] kg"),
        (["--max-yield-fraction", "1e9"], "--max-yield-fraction must be in (0, 10]"),
        (["--min-hops-to-failure", "1e300"], "--min-hops-to-failure must be in [1, 1e+20] hops"),
        (["--min-hops-to-failure", "0.5"], "--min-hops-to-failure must be in [1, 1e+20] hops"),
        # lists naming one item twice: refused, not dropped in silence
        (["--space", "catalogue", "--materials", "SS,Ti,ss"], "--materials: 'SS,Ti,ss' names an item twice"),
        (["--ashby-classes", "metal, Metal"], "--ashby-classes: 'metal, Metal' names an item twice"),
        (["--behaviour", "ramp,RAMP"], "--behaviour"),
    ],
)
def test_cli_refuses_settings_out_of_range_before_any_file(tmp_path, monkeypatch, capsys, argv, text):
    import os

    from mat_hopper.cli import main

    monkeypatch.chdir(tmp_path)
    assert main(["optimize", "--study", "bad", "--trials", "1", *argv]) == 2
    err = capsys.readouterr().err.strip()
    assert text in err and len(err.splitlines()) == 1, err
    assert os.listdir(tmp_path) == []


@pytest.mark.parametrize("flag", ["--replay", "--export"])
def test_cli_refuses_a_negative_trial_number_before_opening_the_study(tmp_path, monkeypatch, capsys, flag):
    import os

    from mat_hopper.cli import main

    monkeypatch.chdir(tmp_path)
    assert main(["optimize", "--study", "nosuch", flag, "-1"]) == 2
    err = capsys.readouterr().err.strip()
    assert f"{flag} must be an integer >= 0" in err and len(err.splitlines()) == 1, err
    assert os.listdir(tmp_path) == []
