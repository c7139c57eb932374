"""Studies in deterministic batches through the result runner.

:func:`mat_hopper.optimize.run_study` runs trials in worker
processes that each ask and tell on their own: fast, and right for many
machines, but with more than one worker the trials depend on which worker
finishes first. The book needs a study that is the same on every machine
*and* uses every core. This module runs one with Optuna's ask-and-tell
interface:

1. ask ``batch`` trials in a row (the enqueued paper designs come first;
   the TPE sampler's constant liar sees the batch's trials as running);
2. simulate every trial's runs as one grid of :class:`TrialRun` tasks
   through :mod:`mat_hopper.experiments.runner` (the one cache and pool:
   all cores, and every run cached by its settings, so a trial that
   repeats a design, a rerun or a replay costs nothing);
3. tell the results in trial order.

What the sampler sees at each ask depends only on the seed, the batch size
and the earlier trials, never on the number of processes or on timing:
a fresh study is bit-identical on any machine. An interrupted study
resumes: trials left running are evaluated from their parameters (cached
runs cost nothing) and told, then new batches follow. The sampler's seed
derives from the seed and the study's size when the run starts
(:func:`mat_hopper.optimize._samplers.worker_seed`), as for ``run_study``.

Trials carry the same records as ``run_study``'s (constraints, the
``result`` user attr, errors), so reports read both alike.
"""

from __future__ import annotations

import hashlib
import math
import os
from dataclasses import dataclass, field

import numpy as np
import optuna
import pandas as pd
from optuna.trial import TrialState

from ..behaviours import behaviour as get_behaviour
from ..experiments.runner import FAILED, Runner
from ..keys import design_key, hash_key, settings_key, versions
from ..materials import LegDesign
from ..perturbations import Perturbation
from ._objective import Evaluation, Objective, aggregate, mujoco_warnings_to, record_evaluation, run_behaviour
from ._robust import perturbations
from ._samplers import make_sampler, worker_seed
from ._storage import ERROR_ATTR, WORKER_ATTR
from ._study import StudyConfig, _quiet, create_or_load

DEFAULT_BATCH = 8


def _objective_source() -> str:
    """Digest of the objective's source: an edited score never reuses old trial runs."""
    path = os.path.join(os.path.dirname(os.path.abspath(__file__)), "_objective.py")
    with open(path, "rb") as f:
        return hashlib.sha256(f.read()).hexdigest()[:16]


@dataclass(frozen=True, eq=False)
class TrialRun:
    """A runner task: one design on one behaviour of an objective, scored as
    :func:`mat_hopper.optimize._objective.run_behaviour` scores it (the
    row it returns is the task's one-row table and its summary)."""

    design: LegDesign
    behaviour: str
    objective: Objective
    labels: dict = field(default_factory=dict)
    perturbation: Perturbation | None = None  # a replicate's (mat_hopper.optimize._robust)

    kind = "trial-run"

    def key_dict(self) -> dict:
        ob = self.objective
        return {
            "kind": self.kind,
            "design": design_key(self.design),
            "behaviour": get_behaviour(self.behaviour).key(),
            "settings": settings_key(ob.sim_settings(self.perturbation, design=self.design)),
            "score": {"objective_source": _objective_source()},
            "versions": versions(),
        }

    def key(self) -> str:
        return f"{self.kind}-{hash_key(self.key_dict())}"

    def default_labels(self) -> dict:
        return {"design": self.design.name, "behaviour": self.behaviour}

    def compute(self) -> tuple[pd.DataFrame, dict]:
        with mujoco_warnings_to([]) as sink:
            row = run_behaviour(self.design, self.behaviour, self.objective, perturbation=self.perturbation)
        row["mujoco_warnings"] = len(sink)
        row = {k: (math.nan if v is None else v) for k, v in row.items()}
        row.pop("behaviour")
        return pd.DataFrame([row]), dict(row)


def evaluate_many(designs, objective: Objective, runner: Runner, desc: str = "trials") -> list:
    """Evaluation (or an error text) of each design, in order: every
    design's behaviours as one grid through `runner`."""
    tasks = [
        TrialRun(d, b, objective, labels={"item": i}, perturbation=p)
        for i, d in enumerate(designs)
        for p in perturbations(objective.replicates, objective.profile.scored_window_s)
        for b in objective.behaviours
    ]
    if not tasks:
        return []
    res = runner.run(tasks, desc=desc)
    out = []
    for i in range(len(designs)):
        rows = res.summary[res.summary["item"] == i].to_dict("records")
        bad = [r for r in rows if r.get("status") == FAILED]
        if bad:
            out.append(str(bad[0].get("error") or "run failed"))
            continue
        fixed = []
        for r in rows:
            r = dict(r)
            r["diverged_at_s"] = None if not np.isfinite(r.get("diverged_at_s", np.nan)) else r["diverged_at_s"]
            r["n_hops"], r["replicate"] = int(r["n_hops"]), int(r.get("replicate", -1))
            r["stable"], r["upright"] = bool(r["stable"]), bool(r["upright"])
            fixed.append({k: r[k] for k in r if k not in ("item", "design", "error", "key", "status")})
        out.append(aggregate(fixed, objective, designs[i]))
    return out


def _finite(x):
    return None if x is None or (isinstance(x, float) and not math.isfinite(x)) else x


def _tell(study, trial, design: LegDesign, ev) -> None:
    if isinstance(ev, str):  # an exception in the run: a failed trial, with its error
        trial.set_user_attr(ERROR_ATTR, ev[:500])
        study.tell(trial, state=TrialState.FAIL)
        return
    assert isinstance(ev, Evaluation)
    record_evaluation(trial, design, ev)
    study.tell(trial, list(ev.values))


def _finished(study) -> int:
    return sum(
        1
        for t in study.get_trials(deepcopy=False, states=(TrialState.COMPLETE, TrialState.FAIL))
        if t.state == TrialState.COMPLETE or ERROR_ATTR in t.user_attrs
    )


def run_batched(
    config: StudyConfig,
    storage,
    *,
    trials: int,
    batch: int = DEFAULT_BATCH,
    sampler="tpe",
    seed: int = 0,
    cache_dir=None,
    workers: int | None = None,
    progress: bool = False,
) -> optuna.Study:
    """Run (or resume) study `config` in `storage` (a URL or an Optuna
    storage) up to `trials` finished trials with `sampler` (a name of
    :data:`~mat_hopper.optimize._samplers.SAMPLERS`, seeded from `seed`, or an
    Optuna sampler as it is), `batch` trials at a time (module
    doc); runs through the runner's cache (`cache_dir`, default
    results/cache) and pool (`workers`, default all cores). Returns the
    study."""
    if isinstance(batch, bool) or not isinstance(batch, int) or batch < 1:
        raise ValueError(f"batch must be an integer >= 1 (trials asked before the first is told), got {batch!r}")
    if isinstance(trials, bool) or not isinstance(trials, int) or trials < 1:
        raise ValueError(f"trials must be an integer >= 1, got {trials!r}")
    _quiet()
    n_existing = len(create_or_load(config, storage).trials)
    if isinstance(sampler, str):
        sampler = make_sampler(sampler, worker_seed(seed, n_existing, 0))
    study = create_or_load(config, storage, sampler=sampler)
    space, objective = config.space, config.objective
    with Runner(cache_dir, workers=workers, progress=progress) as runner:
        stale = study.get_trials(deepcopy=False, states=(TrialState.RUNNING,))
        if stale:  # an interrupted batch: finish it from the trials' parameters
            frozen = [optuna.trial.Trial(study, t._trial_id) for t in stale]
            _run(study, frozen, [_design(space, t.params) for t in stale], objective, runner)
        while (done := _finished(study)) < trials:
            asked = [study.ask() for _ in range(min(batch, trials - done))]
            designs = []
            for t in asked:
                t.set_user_attr(WORKER_ATTR, {"host": "batch", "pid": 0})
                try:
                    designs.append(space.suggest(t))
                except ValueError as e:
                    designs.append(f"{type(e).__name__}: {e}")
            _run(study, asked, designs, objective, runner)
    return study


def _design(space, params):
    try:
        return space.design(params)
    except ValueError as e:
        return f"{type(e).__name__}: {e}"


def _run(study, trials, designs, objective, runner) -> None:
    ok = [d for d in designs if isinstance(d, LegDesign)]
    evs = iter(evaluate_many(ok, objective, runner, desc="study batch"))
    for t, d in zip(trials, designs):
        _tell(study, t, d, next(evs) if isinstance(d, LegDesign) else d)
