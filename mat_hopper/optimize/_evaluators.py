"""How the optimizer's one loop (:mod:`mat_hopper.optimize._driver`) and
multi-fidelity racing (:mod:`mat_hopper.optimize._racing`) simulate trials:
its evaluators.

An evaluator scores a batch of designs under an objective, all together,
and gives back one outcome per design, in order:

- an :class:`~mat_hopper.optimize._objective.Evaluation`: the trial is told
  COMPLETE with it;
- a string, the error of a run that raised: the trial fails with it (it
  counts as finished: the same design would raise again);
- :class:`Lost`: a process simulating the design died (killed, out of
  memory); the loop fails the trial and enqueues its parameters again.

Two evaluators:

- :class:`PoolEvaluator`, the CPU path and the reference (MuJoCo, float64):
  each design's runs (behaviours x replicates) become :class:`TrialRun`
  tasks, and the batch's tasks one grid through
  :class:`mat_hopper.experiments.runner.Runner`: its process pool
  (``workers``, default all cores; 1 runs in this process), its cache
  (every run keyed by its settings, so a repeated design, a re-queued trial,
  a resumed rung or a rerun costs nothing) and its handling of a pool
  process that died (its grid's unfinished runs come back failed, and the
  next grid gets a fresh pool). The runner reads every result back from
  its stored form, so the outcomes do not depend on the number of
  processes, on the cache or on timing.
- :class:`WarpEvaluator`, the MuJoCo Warp batch on a device
  (:func:`mat_hopper.optimize._batch.evaluate_batch`): unperturbed runs
  only; no evaluation process to lose.
"""

from __future__ import annotations

import hashlib
import math
import os
from concurrent.futures.process import BrokenProcessPool
from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from ..core.behaviours import behaviour as get_behaviour
from ..core.materials import LegDesign
from ..core.perturbations import Perturbation
from ..experiments.runner import FAILED, Runner, check_workers, default_workers
from ..util.keys import design_key, hash_key, settings_key, versions
from ._batch import DEFAULT_BATCH_SIZE, default_device, evaluate_batch
from ._objective import Objective, aggregate, mujoco_warnings_to, run_behaviour
from ._scoring import perturbations

DEFAULT_BATCH = 8  # trials asked per round on the CPU path
# The runner's error text for a task whose pool process died (runner.Runner._compute_pool).
DEAD_PROCESS = "worker process died"


@dataclass(frozen=True)
class Lost:
    """The outcome of a design whose evaluation process died.

    Args:
        reason: what happened, for the trial's ``fail_reason``.
    """

    reason: str


# the modules that score a run (run_behaviour, run_values), relative to the mat_hopper package
SCORE_SOURCES = ("optimize/_objective.py", "physics/run_metrics.py")


def _objective_source() -> str:
    """Digest of the score's source (:data:`SCORE_SOURCES`): an edited score never reuses old trial runs."""
    h = hashlib.sha256()
    package = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    for name in SCORE_SOURCES:
        with open(os.path.join(package, *name.split("/")), "rb") as f:
            h.update(f.read())
    return h.hexdigest()[:16]


@dataclass(frozen=True, eq=False)
class TrialRun:
    """A runner task: one design on one behaviour of an objective, scored as
    :func:`mat_hopper.optimize._objective.run_behaviour` scores it (the
    row it returns is the task's one-row table and its summary)."""

    design: LegDesign
    behaviour: str
    objective: Objective
    labels: dict = field(default_factory=dict)
    perturbation: Perturbation | None = None  # a replicate's (mat_hopper.optimize._scoring)

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


class Evaluator:
    """What the loop needs of a simulator: :meth:`evaluate` a batch, and
    :meth:`close` (or use it as a context manager).

    Attributes:
        backend: the simulator's name, stored with a study
            (:func:`mat_hopper.optimize._study.create_or_load`): ``"mujoco"`` or ``"warp"``.
        default_batch: trials per round when the run does not say.
        name: a short description for :class:`~mat_hopper.optimize.RunResult`.
    """

    backend = "mujoco"
    default_batch = DEFAULT_BATCH
    name = ""

    def evaluate(self, designs, objective: Objective, desc: str = "trials") -> list:
        """Score designs together.

        Args:
            designs: the legs (LegDesign).
            objective: what to run and score.
            desc: a label for progress and logs.

        Returns:
            One outcome per design, in order (the module doc).
        """
        raise NotImplementedError

    def close(self) -> None:
        """Release what the evaluator holds (processes)."""

    def __enter__(self):
        return self

    def __exit__(self, *exc) -> None:
        self.close()


class PoolEvaluator(Evaluator):
    """The CPU path: runs through :class:`~mat_hopper.experiments.runner.Runner`
    (module doc). The runner and its pool start at the first batch.

    Args:
        cache_dir: the runner's cache (None: $MAT_HOPPER_CACHE, else results/cache).
        workers: local processes (None: all cores; 1: in this process).

    Raises:
        ValueError: workers not an integer >= 1.
    """

    def __init__(self, cache_dir=None, *, workers: int | None = None):
        self.cache_dir, self.workers = cache_dir, check_workers(workers)
        self.name = f"pool:{self.workers or default_workers()}"
        self._runner: Runner | None = None

    def evaluate(self, designs, objective: Objective, desc: str = "trials") -> list:
        """Every design's runs as one grid (see :meth:`Evaluator.evaluate`)."""
        designs = list(designs)
        tasks = [
            TrialRun(d, b, objective, labels={"item": i}, perturbation=p)
            for i, d in enumerate(designs)
            for p in perturbations(objective.replicates, objective.profile.scored_window_s)
            for b in objective.behaviours
        ]
        if not tasks:
            return []
        summary = self._grid(tasks, desc).summary
        return [_outcome(summary[summary["item"] == i].to_dict("records"), objective, d) for i, d in enumerate(designs)]

    def _grid(self, tasks, desc):
        if self._runner is None:
            self._runner = Runner(self.cache_dir, workers=self.workers, progress=False)
        try:
            return self._runner.run(tasks, desc=desc)
        except (BrokenProcessPool, EOFError):
            # The pool broke before this grid's first result: a process died after
            # the last grid's results were in, or the fork server while the pool
            # grew. Once more, with a fresh pool (and fork server).
            self._runner.close()
            return self._runner.run(tasks, desc=desc)

    def close(self) -> None:
        """Shut the pool down (it finishes the runs under way)."""
        if self._runner is not None:
            self._runner.close()
            self._runner = None


def _outcome(rows: list[dict], objective: Objective, design: LegDesign):
    """One design's outcome from its grid rows."""
    bad = [r for r in rows if r.get("status") == FAILED]
    if bad:
        errors = [str(r.get("error") or "run failed") for r in bad]
        died = [e for e in errors if e.startswith(DEAD_PROCESS)]
        return Lost(f"evaluation process died ({died[0].split(';')[0]})") if died else errors[0]
    fixed = []
    for r in rows:
        r = dict(r)
        r["diverged_at_s"] = None if not np.isfinite(r.get("diverged_at_s", np.nan)) else r["diverged_at_s"]
        r["n_hops"], r["replicate"] = int(r["n_hops"]), int(r.get("replicate", -1))
        r["stable"], r["upright"] = bool(r["stable"]), bool(r["upright"])
        fixed.append({k: r[k] for k in r if k not in ("item", "design", "error", "key", "status")})
    return aggregate(fixed, objective, design)


class WarpEvaluator(Evaluator):
    """The MuJoCo Warp batch (:func:`mat_hopper.optimize._batch.evaluate_batch`).

    Args:
        device: a Warp device (``"cpu"``, ``"cuda"``; None: cuda where Warp sees a GPU).
        max_batch: most worlds in one batch (None: the batch's default).

    Raises:
        mat_hopper.batch.WarpUnavailable: (an ImportError) without mujoco-warp.
    """

    backend = "warp"

    def __init__(self, device: str | None = None, *, max_batch: int | None = None):
        from ..batch import require_warp

        require_warp()
        self.device, self.max_batch = device or default_device(), max_batch
        self.default_batch = DEFAULT_BATCH_SIZE
        self.name = f"warp:{self.device}"

    def evaluate(self, designs, objective: Objective, desc: str = "trials") -> list:
        """The designs as one batch per behaviour (see :meth:`Evaluator.evaluate`).

        Raises:
            ValueError: a design the batch cannot run (physics substeps), or a perturbed objective.
        """
        return evaluate_batch(designs, objective, device=self.device, max_batch=self.max_batch)
