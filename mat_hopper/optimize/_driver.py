"""The optimizer's one loop: ask a round of trials, simulate them together,
tell them in order.

:func:`run_study` (the CPU process pool,
:class:`~mat_hopper.optimize._evaluators.PoolEvaluator`) and
:func:`run_batch_study` (the MuJoCo Warp batch,
:class:`~mat_hopper.optimize._evaluators.WarpEvaluator`) open the study and
hand it to :func:`run_loop`, which drives any
:class:`~mat_hopper.optimize._evaluators.Evaluator`. Each round

1. fails and re-queues the running trials of dead runs (on this machine
   by process, anywhere by stale heartbeat), counts the study's finished
   and running trials (other commands' included) and stops at the target;
2. asks k = min(batch size, trials left) trials in a row with Optuna's
   ask-and-tell interface (enqueued trials first: the paper's designs,
   then re-queued ones; TPE's constant liar keeps the round's trials
   apart). Each trial names its process (user attr ``worker``: host, boot
   id, pid) before anything else can happen to it: Ctrl-C, SIGTERM and
   SIGHUP are held from ``study.ask()`` until the name is stored
   (:class:`~mat_hopper.optimize._processes.HeldSignals`), so no RUNNING
   trial is ever anonymous. Then it gets its first heartbeat and its design;
3. simulates the round's designs together (the evaluator), while a thread
   keeps the running trials' heartbeats (RDB storages: Optuna sends them
   only inside ``Study.optimize``);
4. tells the trials in trial order: values and constraints (COMPLETE); the
   error of a run that raised (FAIL, counted as finished); a design whose
   evaluation process died (FAIL with a ``fail_reason``, its parameters
   re-queued).

What the sampler sees at each ask depends only on the seed, the batch size,
the trials before it and the run's worker index (0 for a run alone on its
study; runs started together on one study claim different ones in the
storage, :mod:`mat_hopper.optimize._workers`, so their samplers do not
propose the same points), never on the number of processes or on timing:
a fresh study run by one command is bit-identical on any machine, with
any number of ``workers``.

A design outside the study's leg-mass band is known before any run: its
trial fails at once, saying why (:mod:`mat_hopper.optimize._mass`), and the
run ends with the study's trials counted by feasibility
(:mod:`mat_hopper.optimize._feasibility`).

Guarantees:

- Ctrl-C, SIGTERM, SIGHUP: the round's running trials are failed
  (``fail_reason`` "interrupted (SIGTERM) (pid N)") and re-queued, the
  finished ones kept; then the interrupt propagates (the command exits
  with 128 + the signal number);
- an evaluation process killed (SIGKILL, out of memory): the round's
  unfinished trials are failed and re-queued, and the run goes on (a fresh
  pool);
- the whole run killed (SIGKILL, a machine lost): its trials stay RUNNING
  under its name (its evaluation processes end with it); the next round of
  any run on the same machine fails and re-queues them at once
  (:func:`~mat_hopper.optimize._storage.recover_dead`), of a run on any
  machine once their heartbeat is older than the grace period
  (``optuna.storages.fail_stale_trials``, RDB storages);
- shared storage: any number of commands may run one study, each this
  loop; each stops when the study holds its target (finished plus running);
- a finished study: nothing is asked and no process started.

Public Optuna API only: trials are told through ``Study.tell``, and the
storage the run opened gives a trial's id
(``get_trial_id_from_study_id_trial_number``) for its heartbeat and its
re-queueing.
"""

from __future__ import annotations

import signal
import sys
import threading
import warnings
from dataclasses import dataclass, field

import optuna
from optuna.trial import TrialState

from ..util.progress import progress_bar
from ._batch import check_unperturbed
from ._evaluators import Evaluator, Lost, PoolEvaluator, WarpEvaluator
from ._feasibility import feasibility
from ._mass import SKIPPED_ATTR, outside_band, queued_seeds
from ._objective import RESULT_ATTR, Evaluation, record_evaluation, result_attr
from ._processes import HeldSignals, _signals_ignored, stop_signals
from ._recovery import fail_and_retry, recover_dead, worker_identity
from ._samplers import check_sampler, make_sampler, sampler_seed
from ._storage import ERROR_ATTR, WORKER_ATTR, redact, storage_errors
from ._study import (
    RACING_ATTR,
    TRIAL_BACKEND_ATTR,
    RunOptions,
    StudyConfig,
    StudyMismatch,
    check_objectives_vary,
    counts,
    create_or_load,
)
from ._workers import claim_worker, release_worker

HELD = (signal.SIGINT, signal.SIGTERM, signal.SIGHUP)  # held from ask until the trial names its process


@dataclass
class RunResult:
    """What a run did.

    Args:
        study: the study's name.
        url: its storage URL, password hidden.
        target: the trials the study was to hold.
        done, running: finished and running trials at the end (other commands' included).
        told: (trial number, state name) of each trial this run told, in order.
        lost: trials of this run whose evaluation process died (failed and re-queued).
        recovered: trials of dead runs on this machine (earlier ones, or
            other commands), failed and re-queued by this run.
        evaluator: what simulated (``"pool:2"``, ``"warp:cuda"``; empty when
            the study needed nothing).
        worker: this run's worker index on the study (0 when it ran alone;
            :mod:`mat_hopper.optimize._workers`), None when it asked nothing.
        feasibility: the study's finished trials by feasibility at the end
            (:class:`~mat_hopper.optimize._feasibility.Feasibility`; its
            ``text()`` is the line a study ends with).
        left_out: the paper designs not queued, (name, leg mass kg): their
            leg mass outside the study's band (:mod:`mat_hopper.optimize._mass`).
    """

    study: str
    url: str
    target: int
    done: int
    running: int
    told: list = field(default_factory=list)
    lost: list = field(default_factory=list)
    recovered: list = field(default_factory=list)
    evaluator: str = ""
    worker: int | None = None
    feasibility: object = None
    left_out: list = field(default_factory=list)

    @property
    def finished(self) -> bool:
        """Whether the study holds its target of finished trials."""
        return self.done >= self.target


def run_study(config: StudyConfig, options: RunOptions = RunOptions()) -> RunResult:
    """Run `config`'s study until it holds options.trials finished trials,
    each round's trials simulated together in options.workers processes
    (:class:`~mat_hopper.optimize._evaluators.PoolEvaluator`; module doc).

    Args:
        config: the study (name, search space, objective).
        options: trials, processes, batch size, sampler and seed, storage, cache.

    Returns:
        A :class:`RunResult`.

    Raises:
        ValueError: bad settings or an unreachable storage, before any work; a
            database error later, as one line naming the storage and its cause
            (e.g. "database is locked"); a racing study.
        KeyboardInterrupt: Ctrl-C (:class:`~mat_hopper.optimize._processes.Interrupted`
            for SIGTERM and SIGHUP), after the running trials are failed and re-queued.
    """
    check_sampler(options.sampler)
    check_objectives_vary(config.objective)
    url = options.storage_url(config.name)
    with stop_signals(), storage_errors(url):
        return _run(config, options, url, PoolEvaluator(options.cache_dir, workers=options.workers), None)


def run_batch_study(
    config: StudyConfig,
    options: RunOptions = RunOptions(),
    *,
    device: str | None = None,
    batch_size: int | None = None,
) -> RunResult:
    """Run `config`'s study on the warp backend until it holds options.trials
    finished trials, each round's trials simulated as one batch
    (:class:`~mat_hopper.optimize._evaluators.WarpEvaluator`; module doc).

    Args:
        config: the study.
        options: as :func:`run_study` (options.workers and cache_dir are not
            used: one process drives the device).
        device: a Warp device (``"cpu"``, ``"cuda"``; default cuda where Warp sees a GPU).
        batch_size: trials per round (None: options.batch_size, else 64).

    Returns:
        A :class:`RunResult`.

    Raises:
        mat_hopper.batch.WarpUnavailable: (an ImportError) without mujoco-warp.
        ValueError: bad settings, before any study is made.
        KeyboardInterrupt: as :func:`run_study`.
    """
    if batch_size is not None and (isinstance(batch_size, bool) or not isinstance(batch_size, int) or batch_size < 1):
        raise ValueError(f"batch_size must be an integer >= 1, got {batch_size!r}")
    check_unperturbed(config.objective)
    evaluator = WarpEvaluator(device)
    check_sampler(options.sampler)
    url = options.storage_url(config.name)
    with stop_signals(), storage_errors(url):
        return _run(config, options, url, evaluator, batch_size)


def _run(config: StudyConfig, options: RunOptions, url: str, evaluator: Evaluator, batch_size) -> RunResult:
    """Open the study, recover what dead runs left, and run the loop if trials remain."""
    storage = options.open(config.name)
    study = create_or_load(config, storage, backend=evaluator.backend)
    if RACING_ATTR in study.user_attrs:  # its open bracket's trials stay RUNNING
        raise StudyMismatch(
            f"study {config.name!r} is a racing study (mat_hopper.optimize.run_racing): resume it there",
            config.name,
            "racing",
        )
    recovered = _recover(study, storage, options.max_retry)
    done, running = counts(study)
    result = RunResult(config.name, redact(url), options.trials, done, running, recovered=recovered)
    result.left_out = queued_seeds(config.space, config.objective)[1]
    if options.trials - done - running <= 0:
        result.feasibility = feasibility(study, config)
        return result
    study_id = storage.get_study_id_from_name(config.name)
    token, result.worker = claim_worker(storage, study_id)  # runs started together get different seeds
    try:
        seed = sampler_seed(options.seed, len(study.get_trials(deepcopy=False)), result.worker)
        study = optuna.load_study(study_name=config.name, storage=storage, sampler=make_sampler(options.sampler, seed))
        with evaluator:
            run_loop(study, storage, config, evaluator, options, batch_size=batch_size, result=result)
    finally:
        release_worker(storage, study_id, token, result.worker)
    result.feasibility = feasibility(study, config)
    return result


def _recover(study, storage, max_retry: int) -> list[int]:
    """Fail and re-queue the running trials of dead runs: on this machine at
    once (by process), anywhere once their heartbeat is stale (RDB storages;
    Optuna's callback re-queues those). Returns the numbers failed here by process."""
    recovered = recover_dead(study, storage, max_retry=max_retry, reason="process of an earlier run died")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", optuna.exceptions.ExperimentalWarning)
        optuna.storages.fail_stale_trials(study)
    return recovered


def run_loop(
    study: optuna.Study,
    storage,
    config: StudyConfig,
    evaluator: Evaluator,
    options: RunOptions,
    *,
    batch_size: int | None = None,
    result: RunResult | None = None,
) -> RunResult:
    """Ask, evaluate and tell rounds of trials until `study` holds
    options.trials finished trials (module doc).

    Args:
        study: the study, loaded with the run's sampler.
        storage: the storage it was opened on (any Optuna storage; heartbeats on RDB ones).
        config: the study's settings (its space and objective).
        evaluator: what simulates; the caller closes it.
        options: the target (``trials``), ``max_retry``, ``progress`` and ``batch_size``.
        batch_size: trials per round (None: options.batch_size, else the evaluator's default).
        result: the :class:`RunResult` to fill (None: a new one).

    Returns:
        The :class:`RunResult`, its done and running counted at the end.

    Raises:
        KeyboardInterrupt: Ctrl-C, SIGTERM or SIGHUP
            (:class:`~mat_hopper.optimize._processes.Interrupted`), after the
            round's running trials are failed and re-queued.
        ValueError: evaluation processes that died round after round
            (``max_retry`` + 1 rounds lost whole).
        Exception: what the evaluator raised for a round as a whole (its trials
            failed with the error first).
    """
    if result is None:
        done, running = counts(study)
        result = RunResult(study.study_name, "", options.trials, done, running)
    result.evaluator = evaluator.name
    k = batch_size or options.batch_size or evaluator.default_batch
    _Loop(study, storage, config, evaluator, options, result).run(k)
    result.done, result.running = counts(study)
    return result


class _Loop:
    """One run's rounds (:func:`run_loop`)."""

    def __init__(self, study, storage, config: StudyConfig, evaluator: Evaluator, options: RunOptions, result):
        self.study, self.storage, self.config, self.evaluator = study, storage, config, evaluator
        self.options, self.result = options, result
        self.identity = worker_identity()
        self.study_id = storage.get_study_id_from_name(study.study_name)
        self.beat = _Heartbeat(storage)

    def run(self, batch_size: int) -> None:
        """Rounds until the target; at most max_retry + 1 rounds in a row lost whole."""
        o, backend = self.options, self.evaluator.backend
        desc = self.study.study_name + ("" if backend == "mujoco" else f" ({backend})")
        bar = progress_bar(
            total=o.trials,
            initial=min(self.result.done, o.trials),
            unit="trial",
            desc=desc,
            enabled=o.progress,
            dynamic_ncols=True,
            file=sys.stderr,
        )
        lost_rounds = 0
        try:
            with self.beat:
                while True:
                    self.result.recovered += _recover(self.study, self.storage, o.max_retry)  # other runs' too
                    done, running = counts(self.study)
                    bar.n = min(done, o.trials)
                    bar.set_postfix(running=running, refresh=False)
                    bar.refresh()
                    k = min(batch_size, o.trials - done - running)
                    if k <= 0:
                        return
                    lost_rounds = lost_rounds + 1 if self._round(k) else 0
                    if lost_rounds > o.max_retry:
                        raise ValueError(
                            f"the evaluation processes died in {lost_rounds} rounds in a row "
                            f"(trials failed and re-queued: {self.result.lost}); see the system log (out of memory?)"
                        )
        finally:
            bar.close()

    def _round(self, k: int) -> bool:
        """Ask k trials, evaluate, tell; True when every evaluated trial was lost."""
        asked: list[list] = []  # [trial, design] in trial order
        try:
            self._ask(k, asked)
            outcomes = self._evaluate(asked)
            return self._tell(asked, outcomes)
        except BaseException as e:
            interrupt = not isinstance(e, Exception)  # Ctrl-C, SIGTERM, SIGHUP
            reason = f"interrupted ({getattr(e, 'signal_name', 'SIGINT')})" if interrupt else "stopped by an error"
            with _signals_ignored():  # a second signal does not cut the clean-up short
                try:
                    self._requeue([t for t, _ in asked], reason)
                except Exception:
                    if interrupt:
                        raise
                    # after an error, that error (a database's, say) is the one to report
            raise

    def _ask(self, k: int, asked: list) -> None:
        """Ask k trials into `asked`, each named, beating and designed; a bad
        point of the space (an enqueued design) fails its trial at once."""
        backend = self.evaluator.backend
        for _ in range(k):
            with HeldSignals(*HELD):
                with warnings.catch_warnings():  # "heartbeat ... with Study.optimize": _Heartbeat sends them
                    warnings.simplefilter("ignore", UserWarning)
                    trial = self.study.ask()
                asked.append([trial, None])
                trial.set_user_attr(WORKER_ATTR, self.identity)
            self.beat.add(self._id(trial.number))
            if backend != "mujoco":
                trial.set_user_attr(TRIAL_BACKEND_ATTR, backend)
            try:
                asked[-1][1] = self.config.space.suggest(trial)
            except Exception as e:
                self._fail(trial, f"{type(e).__name__}: {e}")
                self.beat.discard(self._id(trial.number))
                asked.pop()
                continue
            why = outside_band(asked[-1][1], self.config.objective)
            if why is not None:  # outside the leg-mass band: known before any run (mat_hopper.optimize._mass)
                trial.set_user_attr(SKIPPED_ATTR, "leg_mass")
                self._fail(trial, why)
                self.beat.discard(self._id(trial.number))
                asked.pop()

    def _evaluate(self, asked: list) -> list:
        """The evaluator's outcomes; if it raises, the round's trials fail with its error."""
        try:
            return self.evaluator.evaluate([d for _, d in asked], self.config.objective, desc="study round")
        except Exception as e:
            for trial, _ in asked:
                self._fail(trial, f"{type(e).__name__}: {e}")
            raise

    def _tell(self, asked: list, outcomes: list) -> bool:
        """Tell the round in trial order; True when every outcome was Lost."""
        backend, lost = self.evaluator.backend, 0
        for (trial, design), out in zip(asked, outcomes):
            if isinstance(out, Lost):
                lost += 1
                self._requeue([trial], out.reason, self.result.lost)
            elif isinstance(out, Evaluation):
                record_evaluation(trial, design, out)
                if backend != "mujoco":
                    trial.set_user_attr(RESULT_ATTR, {**result_attr(design, out), "backend": backend})
                self.study.tell(trial, list(out.values))
                self.result.told.append((trial.number, TrialState.COMPLETE.name))
            else:  # the error of a run that raised
                self._fail(trial, str(out))
            self.beat.discard(self._id(trial.number))
        return bool(asked) and lost == len(asked)

    def _id(self, number: int) -> int:
        return self.storage.get_trial_id_from_study_id_trial_number(self.study_id, number)

    def _fail(self, trial, error: str) -> None:
        trial.set_user_attr(ERROR_ATTR, error[:500])
        self.study.tell(trial, state=TrialState.FAIL)
        self.result.told.append((trial.number, TrialState.FAIL.name))

    def _requeue(self, trials, reason: str, into: list | None = None) -> None:
        """Fail running trials and enqueue their parameters again (finished ones are left alone)."""
        for trial in trials:
            why = f"{reason} (pid {self.identity['pid']})"
            if fail_and_retry(self.study, self.storage, trial.number, why, self.options.max_retry) and into is not None:
                into.append(trial.number)


class _Heartbeat:
    """Heartbeats of the loop's running trials on a storage that keeps them
    (RDB: ``record_heartbeat`` and ``get_heartbeat_interval``, public
    methods): one when a trial is added, then one every interval from a
    thread until the trial is discarded."""

    def __init__(self, storage):
        interval = getattr(storage, "get_heartbeat_interval", lambda: None)()
        self.storage, self.interval_s = storage, interval
        self.ids: set[int] = set()
        self._lock = threading.Lock()
        self._stop = threading.Event()
        self._thread: threading.Thread | None = None

    def add(self, trial_id: int) -> None:
        if self.interval_s is None:
            return
        with self._lock:
            self.ids.add(trial_id)
        self.storage.record_heartbeat(trial_id)

    def discard(self, trial_id: int) -> None:
        with self._lock:
            self.ids.discard(trial_id)

    def _run(self) -> None:
        while not self._stop.wait(self.interval_s):
            with self._lock:
                ids = sorted(self.ids)
            for i in ids:
                try:
                    self.storage.record_heartbeat(i)
                except Exception:  # a busy database: the next beat retries
                    pass

    def __enter__(self) -> _Heartbeat:
        if self.interval_s is not None:
            self._stop.clear()
            self._thread = threading.Thread(target=self._run, daemon=True, name="mat-hopper-heartbeat")
            self._thread.start()
        return self

    def __exit__(self, *exc) -> None:
        self._stop.set()
        if self._thread is not None:
            self._thread.join()
            self._thread = None
        with self._lock:
            self.ids.clear()
