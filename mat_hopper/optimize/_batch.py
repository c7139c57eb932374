"""The optimizer on the batch backend: Optuna's ask-and-tell, many trials at once.

:func:`run_batch_study` is :func:`~mat_hopper.optimize.run_study` with the
designs simulated together by :mod:`mat_hopper.batch` (MuJoCo Warp, on a
GPU or, slowly, on Warp's CPU device) instead of one CPU rollout per worker
process. Each round asks the study for up to ``batch_size`` trials
(``study.ask()``, Optuna's ask-and-tell interface: the sampler proposes
them one after the other, TPE's constant liar keeping them apart), runs
their designs as one batch per behaviour (grouped by topology inside
:func:`mat_hopper.batch.evaluate`), and tells each trial its values and
constraints.

The objective is the CPU path's, definition for definition
(:mod:`mat_hopper.optimize._objective`): per behaviour, the per-hop means
of tracking error and hip power when the run scored hop cycles and ended
upright, else the whole-run means over every finite recorded sample; the
objectives are the means over the behaviours, the constraints the worst
hop-height violation and instability (:func:`~._objective.aggregate`, the
same function the CPU path calls). Only the simulator differs: MJWarp in
float32 against MuJoCo's CPU engine in float64 (the batch agreement tests
bound the difference: hop count +-1, height +-0.01 m, tracking error and
power within 10 %).

A study holds trials of one backend only: a warp study is marked (study
user attr ``mat_hopper_backend`` = ``"warp"``) and each of its trials
carries ``backend`` = ``"warp"``; the CPU path refuses a warp study and
this path refuses a study the CPU path created
(:func:`~._study.create_or_load`). Replaying a warp trial
(:func:`~mat_hopper.optimize.replay`) re-simulates it on the CPU, so its
values agree within the batch tolerance, not exactly.

The CPU path (:func:`~mat_hopper.optimize.run_study`) stays the default and
the reference.
"""

from __future__ import annotations

import math
import signal
import sys
import threading
import warnings
from collections import OrderedDict
from collections.abc import Sequence

import optuna
from optuna.storages._heartbeat import is_heartbeat_enabled
from optuna.trial import TrialState

from ..materials import LegDesign
from ..progress import progress_bar
from ._coordinator import RunResult
from ._objective import (
    RESULT_ATTR,
    Evaluation,
    Objective,
    aggregate,
    result_attr,
    scored_by_hops,
    whole_run_value,
)
from ._processes import HeldSignals
from ._samplers import check_sampler, make_sampler, worker_seed
from ._storage import ERROR_ATTR, FAIL_REASON_ATTR, WORKER_ATTR, recover_dead, redact, retry_trial, worker_identity
from ._study import (
    RunOptions,
    StudyConfig,
    counts,
    create_or_load,
)

BACKEND = "warp"
TRIAL_BACKEND_ATTR = "backend"  # trial user attr: the backend that evaluated it
DEFAULT_BATCH_SIZE = 64  # trials asked per round (a GPU takes thousands: raise it there)


def check_unperturbed(objective: Objective) -> None:
    """ValueError unless `objective` runs unperturbed (replicates 0): the
    batch kernels have no perturbations (:mod:`mat_hopper.perturbations`)."""
    if objective.replicates:
        raise ValueError(
            f"the warp backend runs unperturbed rollouts only: give --replicates 0 (this objective asks for "
            f"{objective.replicates} perturbed replicates), or use --backend mujoco"
        )


def batch_settings(objective: Objective, design: LegDesign):
    """The :class:`~mat_hopper.batch.BatchSettings` of one design's runs
    under `objective`: the profile's SimSettings (the CPU path's) as a batch.
    ValueError where the batch cannot run them (physics substeps, i.e. the
    ``axial`` convention's automatic time step)."""
    from ..batch import BatchSettings

    check_unperturbed(objective)
    sim = objective.profile.for_convention(objective.convention).sim_settings(design=design)
    if sim.substeps != 1:
        raise ValueError(
            f"the warp backend runs the controller every physics step; under this profile design "
            f"{design.name!r} needs {sim.substeps} physics substeps (automatic time step): give the "
            "profile a fixed axial_timestep_s, or use --backend mujoco"
        )
    return BatchSettings.of(sim)


def behaviour_row(summary: dict, behaviour: str, duration_s: float) -> dict:
    """One behaviour's row of an Evaluation (the keys of
    ``_objective.run_behaviour``) from a batch result row."""
    n_hops = int(summary["n_hops"])
    upright = bool(summary["upright"])
    if scored_by_hops(n_hops, upright):
        tracking, power = float(summary["tracking_error_m"]), float(summary["power_w"])
    else:
        tracking = whole_run_value(float(summary["run_tracking_error_m"]))
        power = whole_run_value(float(summary["run_power_w"]))
    diverged = summary["diverged_at_s"]
    diverged = None if diverged is None or (isinstance(diverged, float) and math.isnan(diverged)) else float(diverged)
    return {
        "behaviour": behaviour,
        "tracking_error_m": tracking,
        "power_w": power,
        "hop_height_m": float(summary["hop_height_m"]),
        "n_hops": n_hops,
        "stable": bool(summary["stable"]),
        "upright": upright,
        "diverged_at_s": diverged,
        # the batch runs every world to the end; a diverged world stops counting at its divergence
        "simulated_s": float(duration_s if diverged is None else diverged),
        "total_mass_kg": float(summary["total_mass_kg"]),
        "backend": BACKEND,
    }


def evaluate_batch(
    designs: Sequence[LegDesign],
    objective: Objective,
    *,
    device: str | None = None,
    max_batch: int | None = None,
    progress: bool = False,
) -> list[Evaluation]:
    """Each design scored as :func:`~mat_hopper.optimize.evaluate` scores it on
    the CPU, all of them simulated together by the warp backend (one batch per
    behaviour, topology and set of run settings).

    Args:
        designs: the legs.
        objective: what to run and score.
        device: the Warp device (``"cpu"``, ``"cuda"``).
        max_batch: most worlds in one batch.
        progress: show a progress bar.

    Returns:
        One :class:`Evaluation` per design, in order.

    Raises:
        ValueError: a design that needs physics substeps under the profile.
        mat_hopper.batch.WarpUnavailable: without mujoco-warp.
    """
    from ..batch import evaluate as batch_evaluate

    designs = list(designs)
    if not designs:
        return []
    groups: OrderedDict = OrderedDict()
    for i, d in enumerate(designs):
        groups.setdefault(batch_settings(objective, d), []).append(i)
    rows: list[list[dict]] = [[] for _ in designs]
    for settings, idx in groups.items():
        for b in objective.behaviours:
            table = batch_evaluate(
                [designs[i] for i in idx],
                b,
                settings,
                backend=BACKEND,
                device=device,
                max_batch=max_batch,
                progress=progress,
            )
            for i, summary in zip(idx, table.to_dict("records")):
                rows[i].append(behaviour_row(summary, b, settings.duration_s))
    return [aggregate(r, objective, d) for r, d in zip(rows, designs)]


def default_device() -> str:
    """ "cuda" where Warp sees a GPU, else "cpu"."""
    from ..batch import require_warp

    wp, _ = require_warp()
    return "cuda" if wp.get_cuda_device_count() > 0 else "cpu"


def _finite(x):
    return None if x is None or (isinstance(x, float) and not math.isfinite(x)) else x


def _result_attr(design: LegDesign, ev: Evaluation) -> dict:
    """The trial's ``result`` user attr, as the CPU path writes it, plus the backend."""
    return {**result_attr(design, ev), "backend": BACKEND}


def _fail(study, trial, error: str) -> None:
    trial.set_user_attr(ERROR_ATTR, error[:500])
    study.tell(trial, state=TrialState.FAIL)


def _requeue(study, trials, reason: str, max_retry: int) -> None:
    """Fail the batch's unfinished trials and enqueue their parameters again
    (as the CPU path does for a dead worker's trials)."""
    storage = study._storage
    for trial in trials:
        try:
            storage.set_trial_user_attr(trial._trial_id, FAIL_REASON_ATTR, reason)
            if storage.set_trial_state_values(trial._trial_id, state=TrialState.FAIL):
                retry_trial(study, storage.get_trial(trial._trial_id), max_retry)
        except (optuna.exceptions.UpdateFinishedTrialError, RuntimeError):
            continue


class _Heartbeat:
    """Heartbeats of a batch's running trials while it simulates (Optuna
    sends them only inside Study.optimize; without them another process's
    fail_stale_trials would fail a batch longer than the grace period)."""

    def __init__(self, study, interval_s: float):
        self.storage, self.interval_s = study._storage, float(interval_s)
        self.ids: list[int] = []
        self._stop = threading.Event()
        self._thread = None

    def __enter__(self):
        self._stop = threading.Event()
        if is_heartbeat_enabled(self.storage):
            self._thread = threading.Thread(target=self._run, daemon=True, name="mat-hopper-batch-heartbeat")
            self._thread.start()
        return self

    def _run(self):
        while not self._stop.wait(self.interval_s):
            for i in list(self.ids):
                try:
                    self.storage.record_heartbeat(i)
                except Exception:  # a finished trial, a busy database: the next beat retries
                    pass

    def __exit__(self, *exc):
        self._stop.set()
        if self._thread is not None:
            self._thread.join()


def _ask(study, config, k: int, identity: dict, told: list, max_retry: int) -> tuple[list, list]:
    """Ask Optuna for k trials and their designs: (trials, designs). A bad
    point of the space fails its trial, as on the CPU path; Ctrl-C while
    asking puts the trials asked so far back in the queue."""
    asked, designs = [], []
    try:
        for _ in range(k):
            # Ctrl-C, SIGTERM and SIGHUP wait until the new trial is in `asked`
            # (and names this process), so that the handler below re-queues it.
            with HeldSignals(signal.SIGINT, signal.SIGTERM, signal.SIGHUP):
                with warnings.catch_warnings():  # "heartbeat ... with Study.optimize": _Heartbeat sends them
                    warnings.simplefilter("ignore", UserWarning)
                    trial = study.ask()
                asked.append(trial)
                trial.set_user_attr(WORKER_ATTR, identity)
            trial.set_user_attr(TRIAL_BACKEND_ATTR, BACKEND)
            try:
                designs.append(config.space.suggest(trial))
            except Exception as e:  # a bad point of the space: this trial fails, as on the CPU path
                asked.pop()
                _fail(study, trial, f"{type(e).__name__}: {e}")
                told.append((trial.number, "FAIL"))
    except BaseException:
        _requeue(study, asked, "interrupted", max_retry)
        raise
    return asked, designs


def run_batch_study(
    config: StudyConfig,
    options: RunOptions = RunOptions(),
    *,
    device: str | None = None,
    batch_size: int = DEFAULT_BATCH_SIZE,
) -> RunResult:
    """Run `config`'s study on the warp backend until it holds options.trials
    finished trials, asking for up to `batch_size` trials per batch (module doc).

    Args:
        config: the study.
        options: as :func:`run_study` (options.workers is not used: one process
            drives the device).
        device: a Warp device (``"cpu"``, ``"cuda"``; default cuda where Warp sees a GPU).
        batch_size: trials asked per round.

    Returns:
        A :class:`RunResult`.

    Raises:
        mat_hopper.batch.WarpUnavailable: (an ImportError) without mujoco-warp.
        ValueError: bad settings, before any study is made.
    """
    from ..batch import require_warp

    if isinstance(batch_size, bool) or not isinstance(batch_size, int) or batch_size < 1:
        raise ValueError(f"batch_size must be an integer >= 1, got {batch_size!r}")
    check_unperturbed(config.objective)
    require_warp()
    device = device or default_device()
    check_sampler(options.sampler)
    url = options.storage_url(config.name)
    storage = options.open(config.name)
    study = create_or_load(config, storage, backend=BACKEND)
    recovered = recover_dead(study, max_retry=options.max_retry, reason="batch run of an earlier process died")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", optuna.exceptions.ExperimentalWarning)
        optuna.storages.fail_stale_trials(study)
    done, running = counts(study)
    result = RunResult(config.name, redact(url), options.trials, done, running, recovered=recovered)
    result.start_method = f"{BACKEND}:{device}"
    if options.trials - done - running <= 0:
        return result
    seed = worker_seed(options.seed, len(study.get_trials(deepcopy=False)), 0)
    study = optuna.load_study(study_name=config.name, storage=storage, sampler=make_sampler(options.sampler, seed))
    identity = worker_identity()
    bar = progress_bar(
        total=options.trials,
        initial=min(done, options.trials),
        unit="trial",
        desc=f"{config.name} ({BACKEND})",
        enabled=options.progress,
        dynamic_ncols=True,
        file=sys.stderr,
    )
    told: list[tuple[int, str]] = []
    beat = _Heartbeat(study, options.heartbeat_s)
    try:
        while True:
            done, running = counts(study)
            k = min(batch_size, options.trials - done - running)
            if k <= 0:
                break
            asked, designs = _ask(study, config, k, identity, told, options.max_retry)
            beat.ids = [t._trial_id for t in asked]
            try:
                with beat:
                    evaluations = evaluate_batch(designs, config.objective, device=device, progress=options.progress)
            except Exception as e:
                # The batch as a whole failed: every trial in it fails with the error, which is raised.
                for trial in asked:
                    _fail(study, trial, f"{type(e).__name__}: {e}")
                raise
            except BaseException:  # Ctrl-C: nothing evaluated, the trials go back in the queue
                _requeue(study, asked, "interrupted", options.max_retry)
                raise
            for trial, design, ev in zip(asked, designs, evaluations):
                for name, value in zip(ev.constraint_names, ev.constraints):
                    trial.set_constraint(name, value)
                trial.set_user_attr(RESULT_ATTR, _result_attr(design, ev))
                study.tell(trial, ev.values)
                told.append((trial.number, "COMPLETE"))
            bar.update(k)
    finally:
        bar.close()
    result.worker_reports.append({"pid": identity["pid"], "seed": seed, "told": told})
    result.done, result.running = counts(study)
    return result
