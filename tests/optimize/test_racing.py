"""Multi-fidelity racing (mat_hopper.optimize._racing): promotion, the rungs
recorded in the storage, only full-fidelity trials on the front, and a
study killed mid-rung (SIGKILL) that resumes there. Runs use a 2 s profile
(tiny) screened on 1 s runs."""

from __future__ import annotations

import os
import signal
import subprocess
import sys

import optuna
import pytest
from optuna.trial import TrialState

from mat_hopper.experiments.profiles import Profile
from mat_hopper.optimize import (
    Evaluation,
    Lost,
    Objective,
    PoolEvaluator,
    Racing,
    Rung,
    RunOptions,
    SearchSpace,
    StudyConfig,
    default_racing,
    evaluate,
    promote,
    run_racing,
    run_study,
    simulated_seconds,
)
from mat_hopper.optimize._racing import BRACKET_ATTR

optuna.logging.set_verbosity(optuna.logging.WARNING)
REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
TINY = Profile("tiny", duration_s=2.0, transient_s=0.5)
OB = Objective(profile=TINY, replicates=2)
RACING = Racing(rungs=(Rung(duration_s=1.0, transient_s=0.3, replicates=1), Rung()), eta=3, screen=6)


def _ev(values, constraints=(0.0, 0.0)):
    return Evaluation(values=tuple(values), constraints=tuple(constraints), hop_height_m=1.0)


def test_promote_by_hand():
    recs = {
        0: _ev((3.0, 3.0)),  # dominated by 1
        1: _ev((1.0, 2.0)),  # front
        2: _ev((2.0, 1.0)),  # front
        3: _ev((0.1, 0.1), (0.5, 0.0)),  # best values, infeasible: last
        4: _ev((4.0, 0.5)),  # front
        5: _ev((0.2, 0.2), (0.1, 0.0)),  # infeasible, less so than 3
    }
    # front {1, 2, 4}: rank sums 1+2=3, 2+1=3 (tie: by number), 3+0=3 -> 1, 2, 4; then 0; then 5, 3
    assert promote(recs, 6) == [1, 2, 4, 0, 5, 3]
    assert promote(recs, 2) == [1, 2]
    assert RACING.kept(6) == 2 and RACING.kept(1) == 1 and Racing(eta=2).kept(5) == 3


def test_racing_settings_checked():
    for kw, match in (
        ({"rungs": (Rung(),)}, "two or more"),
        ({"rungs": (Rung(duration_s=1.0), Rung(replicates=1))}, "last rung"),
        ({"eta": 1}, "eta"),
        ({"screen": 0}, "screen"),
    ):
        with pytest.raises(ValueError, match=match):
            Racing(**kw)
    with pytest.raises(ValueError, match="duration_s"):
        Rung(duration_s=-1.0)
    r = default_racing(Objective(replicates=4))  # the paper profile: screened on the quick profile's 12 s
    assert r.rungs[0] == Rung(duration_s=12.0, transient_s=4.0, replicates=1)
    ob = RACING.objective_at(OB, 0)
    assert (ob.profile.duration_s, ob.replicates, RACING.objective_at(OB, 1)) == (1.0, 1, OB)


def test_racing_study_fronts_full_fidelity_trials_only(tmp_path):
    config = StudyConfig("race", SearchSpace(), OB)
    url = f"sqlite:///{tmp_path}/race.db"
    study = run_racing(config, url, brackets=1, racing=RACING, cache_dir=str(tmp_path / "cache"), workers=1)
    states = [t.state for t in study.get_trials(states=(TrialState.COMPLETE, TrialState.PRUNED))]
    assert states.count(TrialState.COMPLETE) == 2 and states.count(TrialState.PRUNED) == 4
    assert study.user_attrs[BRACKET_ATTR] == {"index": 0, "trials": list(range(6)), "closed": True}
    for t in study.get_trials(states=(TrialState.COMPLETE,)):
        assert {"rung0", "rung1"} <= set(t.user_attrs) and t.user_attrs["racing_rung"] == 1
        again = evaluate(config.space.design(t.params), OB)  # the study's own fidelity, K = 2
        assert tuple(again.values) == tuple(t.values)
        assert t.user_attrs["rung1"]["values"] == list(t.values)
    for t in study.get_trials(states=(TrialState.PRUNED,)):
        assert "rung1" not in t.user_attrs and set(t.constraints) == {"hop_height", "unstable"}
    assert {t.number for t in study.best_trials} <= {t.number for t in study.get_trials(states=(TrialState.COMPLETE,))}
    sim = simulated_seconds(study, RACING)
    # rung 0: 6 trials x 1 s x 1 replicate; rung 1: 2 trials x 2 s x 2 replicates
    assert sim["simulated_s"] == pytest.approx(6 * 1.0 + 2 * 4.0)
    assert sim["simulated_s_per_complete"] == pytest.approx(7.0) and sim["all_full_fidelity_s"] == pytest.approx(24.0)
    again = run_racing(config, url, brackets=1, racing=RACING, cache_dir=str(tmp_path / "cache"), workers=1)
    assert len(again.trials) == len(study.trials)  # finished: nothing new
    with pytest.raises(ValueError, match="other settings"):
        run_racing(config, url, brackets=2, racing=Racing(rungs=RACING.rungs, eta=2, screen=6), workers=1)
    with pytest.raises(ValueError, match="racing study"):
        run_study(config, RunOptions(trials=8, workers=1, storage=url, progress=False))


_KILLED = """
import os, signal
from mat_hopper.experiments.profiles import Profile
from mat_hopper.optimize import Objective, Racing, Rung, SearchSpace, StudyConfig, run_racing

ob = Objective(profile=Profile("tiny", duration_s=2.0, transient_s=0.5), replicates=2)
racing = Racing(rungs=(Rung(duration_s=1.0, transient_s=0.3, replicates=1), Rung()), eta=3, screen={screen})
kill = lambda bracket, rung: os.kill(os.getpid(), signal.SIGKILL) if rung == 0 else None
run_racing(StudyConfig("race", SearchSpace(), ob), {url!r}, brackets=1, racing=racing, cache_dir={cache!r},
           workers=1, on_rung=kill)
"""


class Counting(PoolEvaluator):
    """The CPU evaluator, counting the designs of each call."""

    def __init__(self, *a, **kw):
        super().__init__(*a, **kw)
        self.evaluated = []

    def evaluate(self, designs, objective, desc="trials"):
        self.evaluated.append(len(designs))
        return super().evaluate(designs, objective, desc)


class Dying(PoolEvaluator):
    """The CPU evaluator whose first evaluation of each design loses it (as
    if its evaluation process died)."""

    def __init__(self, *a, **kw):
        super().__init__(*a, **kw)
        self.seen = set()

    def evaluate(self, designs, objective, desc="trials"):
        out = super().evaluate(designs, objective, desc)
        lost = [Lost("evaluation process died") if d.name not in self.seen else o for d, o in zip(designs, out)]
        self.seen |= {d.name for d in designs}
        return lost


def test_racing_evaluates_a_lost_design_again(tmp_path):
    """A design whose evaluation process died is evaluated again (racing keeps
    its bracket: its trials are not re-queued), and the study is the one an
    evaluator that never loses a design makes."""
    config = StudyConfig("lost", SearchSpace(), OB)
    racing = Racing(rungs=RACING.rungs, eta=3, screen=3)
    with Dying(str(tmp_path / "cache"), workers=1) as dying:
        lossy = run_racing(config, f"sqlite:///{tmp_path}/lost.db", brackets=1, racing=racing, evaluator=dying)
    plain = run_racing(config, f"sqlite:///{tmp_path}/plain.db", brackets=1, racing=racing, workers=1,
                       cache_dir=str(tmp_path / "cache"))  # fmt: skip
    summary = lambda s: [(t.number, t.state, t.params, t.values) for t in s.get_trials()]  # noqa: E731
    assert summary(lossy) == summary(plain)
    assert [t.state for t in plain.get_trials()].count(TrialState.COMPLETE) == 1


@pytest.mark.slow  # a fresh interpreter (numba's first import) and two studies: 16-95 s here
def test_sigkill_mid_rung_resumes_there(tmp_path):
    """SIGKILL right after rung 0 of the first bracket is stored: the
    resumed run does not ask new trials nor run rung 0 again, and ends with
    the study an uninterrupted run makes."""
    racing = Racing(rungs=RACING.rungs, eta=3, screen=11)  # past the 9 paper seeds: sampled trials too
    url = f"sqlite:///{tmp_path}/killed.db"
    code = _KILLED.format(screen=11, url=url, cache=str(tmp_path / "cache-killed"))
    env = {**os.environ, "PYTHONPATH": REPO + os.pathsep + os.environ.get("PYTHONPATH", "")}
    p = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=300)
    assert p.returncode == -signal.SIGKILL, p.stderr
    killed = optuna.load_study(study_name="race", storage=url)
    assert killed.user_attrs[BRACKET_ATTR]["closed"] is False
    running = killed.get_trials(states=(TrialState.RUNNING,))
    assert len(running) == 11 and all("rung0" in t.user_attrs for t in running)

    config = StudyConfig("race", SearchSpace(), OB)
    with Counting(str(tmp_path / "cache-resumed"), workers=1) as counting:
        resumed = run_racing(config, url, brackets=1, racing=racing, evaluator=counting)
    assert counting.evaluated == [4]  # rung 0: nothing run again (no call); rung 1: the 4 promoted
    fresh = run_racing(
        config, f"sqlite:///{tmp_path}/fresh.db", brackets=1, racing=racing, cache_dir=str(tmp_path / "c"), workers=1
    )

    def summary(study):
        return [
            (t.number, t.state, t.params, t.values)
            for t in study.get_trials(states=(TrialState.COMPLETE, TrialState.PRUNED))
        ]

    assert summary(resumed) == summary(fresh) and len(summary(fresh)) == 11


def test_cli_race(tmp_path, monkeypatch, capsys):
    from mat_hopper.cli import main
    from mat_hopper.optimize import create_or_load, default_url, open_storage

    monkeypatch.chdir(tmp_path)  # the runner's cache: results/cache here
    (tmp_path / "studies").mkdir()
    create_or_load(StudyConfig("r", SearchSpace(), OB), open_storage(default_url("r", "studies")))
    argv = ["optimize", "--study", "r", "--trials", "9", "--race", "--workers", "1", "--no-progress"]
    assert main(argv) == 0
    out = capsys.readouterr().out
    assert "9/9 trials screened by racing: 3 finished at full fidelity, 6 stopped on a screening rung" in out
    assert "of 3 trials finished at full fidelity (6 more stopped on a screening rung" in out
    study = optuna.load_study(study_name="r", storage=default_url("r", "studies"))
    states = [t.state for t in study.trials]
    assert states.count(TrialState.COMPLETE) == 3 and states.count(TrialState.PRUNED) == 6
    assert main(["optimize", "--study", "r", "--trials", "9", "--workers", "1", "--no-progress"]) == 2
    assert "racing study" in capsys.readouterr().err
    assert main([*argv, "--backend", "warp"]) == 2
