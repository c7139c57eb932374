"""Studies held to a leg mass (mat_hopper.optimize._mass): a void or
unmeetable band refused before any work, the paper designs outside the
band never queued nor run, the sampler's designs inside it, and any other
design outside it skipped before its runs. Runs use a 2 s profile (tiny)."""

from __future__ import annotations

import math

import numpy as np
import optuna
import pytest
from optuna.trial import TrialState

from mat_hopper.cli import main
from mat_hopper.core.materials import LegDesign, Material, paper_designs, segment_masses
from mat_hopper.core.model import build_model
from mat_hopper.experiments.profiles import Profile, get_profile
from mat_hopper.optimize import (
    MASS_PARAM,
    Objective,
    PoolEvaluator,
    RunOptions,
    SearchSpace,
    StudyConfig,
    create_or_load,
    feasibility,
    leg_mass_kg,
    leg_mass_model,
    leg_mass_range_kg,
    queued_seeds,
    run_loop,
    run_study,
)
from mat_hopper.optimize._space import scaled_to_sum

optuna.logging.set_verbosity(optuna.logging.WARNING)
TINY = Profile("tiny", duration_s=2.0, transient_s=0.5)


def _held(leg_mass=6.5, space=None, **kw):
    return StudyConfig("held", space or SearchSpace(), Objective(profile=TINY, replicates=0, leg_mass=leg_mass, **kw))


def test_the_leg_mass_is_linear_in_the_densities():
    """fixed + per x sum(rho) is MuJoCo's leg mass (the mass model the hold
    derives densities from), for any N and both segment-mass conventions."""
    rng = np.random.default_rng(0)
    for n in (1, 3, 7):
        for convention in ("leg", "capsule"):
            fixed, per = leg_mass_model(n, convention)
            for _ in range(3):
                rho = rng.uniform(0.9, 20.0, n)
                d = LegDesign(tuple(Material(f"s{i}", float(r), 50.0) for i, r in enumerate(rho)))
                assert leg_mass_kg(d, convention) == pytest.approx(fixed + per * rho.sum(), rel=1e-13)
                assert segment_masses(d, convention)[0] == pytest.approx(per * rho[0], rel=1e-13)


def test_scaled_to_sum_is_exact_and_keeps_the_bounds():
    v = [1.0, 4.0, 16.0]
    for total in (3.0, 10.0, 21.0, 30.0, 40.0):
        out = scaled_to_sum(v, total, (0.9, 20.0))
        assert all(0.9 <= x <= 20.0 for x in out)
        assert sum(out) == pytest.approx(min(max(total, 2.7), 60.0), rel=1e-14)
    assert scaled_to_sum(v, 1.0, (0.9, 20.0)) == [0.9] * 3 and scaled_to_sum(v, 99.0, (0.9, 20.0)) == [20.0] * 3
    out = scaled_to_sum(v, 21.0, (0.9, 20.0))  # no bound reached: the shape kept
    assert out[1] / out[0] == pytest.approx(4.0) and out[2] / out[0] == pytest.approx(16.0)


def test_a_void_tolerance_is_refused_naming_the_threshold():
    """At 3 segments and the default density bounds the legs weigh 1.80 to
    20.55 kg: around 6.5 kg, a tolerance of 14.05 kg or more holds every
    one of them (max(6.5 - 1.80, 20.55 - 6.5)), so the constraint is void."""
    lo, hi = leg_mass_range_kg(SearchSpace(), "leg")
    assert (round(lo, 3), round(hi, 2)) == (1.802, 20.55)
    void = max(6.5 - lo, hi - 6.5)
    _held(leg_mass_tolerance_kg=void * 0.999)  # constrains: accepted
    for tol in (void, 50.0):
        with pytest.raises(ValueError, match=rf"leg_mass_tolerance_kg .* void.*below {void:.4g} kg"):
            _held(leg_mass_tolerance_kg=tol)
    with pytest.raises(ValueError, match=r"leg_mass 30 \+- 1.5 kg: no leg of the search space"):
        _held(leg_mass=30.0)
    # a study an older version stored with a void band is still read (report, replay, export)
    key = _held(leg_mass_tolerance_kg=void * 0.999).key()
    key["objective"]["leg_mass_tolerance_kg"] = 50.0
    assert StudyConfig.from_key("held", key).objective.leg_mass_tolerance_kg == 50.0
    # a space of one material has one leg mass: any band around it is void
    with pytest.raises(ValueError, match="void"):
        _held(leg_mass="SS", space=SearchSpace(kinds="catalogue", materials=("SS",)))


@pytest.mark.parametrize(
    "extra, text",
    [
        (["--leg-mass-tolerance", "50"], "--leg-mass-tolerance 50 kg makes the leg-mass constraint void"),
        (["--leg-mass", "30"], "--leg-mass 30 +- 1.5 kg: no leg of the search space"),
    ],
)
def test_cli_refuses_a_void_or_unmeetable_band(extra, text, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    argv = ["optimize", "--study", "v", "--trials", "12", "--behaviour", "ramp", "--profile", "quick"]
    argv += ["--leg-mass", "6.5", *extra] if extra[0] != "--leg-mass" else extra
    assert main(argv) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and err.startswith("mat-hopper optimize: error: ") and text in err, err
    assert list(tmp_path.iterdir()) == []  # before any work


def test_the_leg_mass_is_the_legs_not_the_hoppers(tmp_path, monkeypatch, capsys):
    """--leg-mass is the leg's mass, kg, without the base: the whole SS
    hopper (MuJoCo's model: 23.77 kg) is heavier than any leg of the space,
    and its refusal, like the help, says what the leg's mass leaves out
    (the base's mass as MuJoCo's model has it)."""
    model = build_model(paper_designs()["SS"]).model
    base_kg, whole_kg = float(model.body("base").mass[0]), float(model.body_mass.sum())
    monkeypatch.chdir(tmp_path)
    argv = ["optimize", "--study", "v", "--trials", "12", "--profile", "quick", "--leg-mass", f"{whole_kg:.2f}"]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert "no leg of the search space" in err and f"without the base's {base_kg:g} kg" in err, err
    with pytest.raises(SystemExit):
        main(["optimize", "--help"])
    help_text = " ".join(capsys.readouterr().out.split())
    assert (
        f"--leg-mass LEG_MASS constrain the leg's mass (the leg from hip stub to foot, without the base's {base_kg:g} kg"
        in help_text
    )


def test_paper_designs_outside_the_band_are_not_queued():
    """6.5 kg: every paper design of the default space is outside 6.5 +- 5 %
    (SS 8.77 kg, the gradients 5.44 kg, ...): none queued, each named with
    its mass. SS's own mass: SS alone queued, exactly itself."""
    kept, left = queued_seeds(_held().space, _held().objective)
    assert kept == [] and [n for n, _ in left] == [n for n, _ in SearchSpace().seeds()]
    assert dict(left)["SS"] == pytest.approx(8.772, abs=1e-3)
    study = create_or_load(_held(), optuna.storages.InMemoryStorage())
    assert study.get_trials() == []  # nothing queued: nothing to simulate
    ss = _held(leg_mass="SS", leg_mass_tolerance_kg=0.5)
    kept, left = queued_seeds(ss.space, ss.objective)
    assert [n for n, _ in kept] == ["SS"] and "SS" not in dict(left)
    design = ss.space.design(kept[0][1])
    assert [m.density_g_cm3 for m in design.segments] == [m.density_g_cm3 for m in paper_designs()["SS"].segments]


def test_the_sampler_proposes_designs_inside_the_band():
    """The hold: every sampled design (TPE, and random) weighs inside the
    band, its densities within the bounds; the band is no parameter of the
    space's key, so the study's stored settings are those of before."""
    config = _held()
    assert config.key() == StudyConfig("held", SearchSpace(), config.objective).key()
    lo, hi = 6.5 * 0.95, 6.5 * 1.05
    for sampler in (optuna.samplers.TPESampler(seed=1), optuna.samplers.RandomSampler(seed=2)):
        study = optuna.create_study(directions=["minimize"] * 2, sampler=sampler)
        for _ in range(20):
            t = study.ask()
            d = config.space.suggest(t)
            assert lo < leg_mass_kg(d, "leg") < hi and MASS_PARAM in t.params
            assert all(0.9 <= m.density_g_cm3 <= 20.0 for m in d.segments)
            assert config.space.design(t.params).segments == d.segments  # replay and export see the same leg
            study.tell(t, [float(np.sum([m.density_g_cm3 for m in d.segments])), 1.0])


class Counting(PoolEvaluator):
    """The CPU evaluator, counting the designs it was given."""

    designs: list = []

    def evaluate(self, designs, objective, desc=""):
        Counting.designs += list(designs)
        return super().evaluate(designs, objective, desc=desc)


def test_a_design_outside_the_band_is_skipped_before_any_run(tmp_path):
    """A catalogue space the hold cannot steer: PVC, Al, Ti and SS legs,
    the band around Ti's leg (5.27 kg +- 0.1). Its queued designs outside the
    band are not queued; sampled designs outside it fail before any run
    (never given to the evaluator), as finished trials that say why."""
    space = SearchSpace(kinds="catalogue", materials=("PVC", "Al", "Ti", "SS"))
    config = StudyConfig("cat", space, Objective(profile=TINY, replicates=0, leg_mass="Ti", leg_mass_tolerance_kg=0.1))
    assert [n for n, _ in queued_seeds(config.space, config.objective)[0]] == ["Ti"]
    storage = optuna.storages.InMemoryStorage()
    study = create_or_load(config, storage, sampler=optuna.samplers.RandomSampler(seed=0))
    Counting.designs = []
    with Counting(str(tmp_path / "cache"), workers=1) as evaluator:
        run_loop(study, storage, config, evaluator, RunOptions(trials=8, progress=False))
    trials = study.get_trials(states=(TrialState.COMPLETE, TrialState.FAIL))
    skipped = [t for t in trials if t.user_attrs.get("skipped") == "leg_mass"]
    assert skipped and all(t.state == TrialState.FAIL and "outside the leg-mass band" in t.user_attrs["error"]
                           for t in skipped)  # fmt: skip
    run = [t for t in trials if t not in skipped]
    assert len(Counting.designs) == len(run)  # the skipped ones never reached the evaluator
    for d in Counting.designs:
        assert abs(leg_mass_kg(d, "leg") - leg_mass_kg(paper_designs()["Ti"], "leg")) <= 0.1
    f = feasibility(study, config)
    assert f.finished == 8 and f.reasons.get("leg mass") == len(skipped)
    assert f"{len(skipped)} leg mass outside" in f.text()


@pytest.mark.slow
def test_a_mass_held_study_finds_feasible_designs(tmp_path):
    """The newcomer's study, optimize --trials 12 --behaviour ramp
    --leg-mass 6.5 --profile quick: 0 of 12 feasible before (8 paper
    designs outside the band run first, the 4 sampled ones outside it too);
    now none is queued, every trial is sampled inside the band, and at
    least 8 of 12 are feasible (about 2 min on 2 cores)."""
    config = StudyConfig("held", SearchSpace(), Objective(profile=get_profile("quick"), leg_mass=6.5))
    options = RunOptions(trials=12, storage=f"sqlite:///{tmp_path}/held.db", progress=False,
                         cache_dir=str(tmp_path / "cache"))  # fmt: skip
    res = run_study(config, options)
    assert res.done == 12 and len(res.left_out) == 8
    f = res.feasibility
    assert f.finished == 12 and f.feasible >= 8, f.text()
    assert not f.reasons.get("leg mass")
    assert math.isclose(sum(f.reasons.values()) + f.feasible, 12)


def test_the_command_names_the_designs_it_does_not_queue(tmp_path, monkeypatch, capsys):
    """One quick trial of a 6.5 kg study: the first line names the eight
    paper designs left out of the queue with their masses, before any run."""
    monkeypatch.chdir(tmp_path)
    argv = ["optimize", "--study", "m", "--trials", "1", "--leg-mass", "6.5", "--replicates", "0"]
    assert main([*argv, "--profile", "quick", "--workers", "1", "--no-progress", "--cache", "cache"]) == 0
    out = capsys.readouterr().out.splitlines()
    assert out[0].startswith(
        "paper designs not queued, their leg mass outside the band 6.175 to 6.825 kg: SS (8.772 kg)"
    )
    assert out[0].count(" kg)") == 8
    assert out[2].startswith("feasible: ") and "of 1 finished trials" in out[2]
