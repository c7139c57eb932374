"""Multi-fidelity racing: screen trials cheaply, promote the best by
successive halving, and let only full-fidelity trials form the front.

Scoring every trial on K replicates of the full profile costs K times a
single draw. Racing spends most of that only on trials worth it. A study
runs in *brackets*; each bracket

1. asks ``screen`` trials (the enqueued paper designs first; Optuna's
   ask-and-tell interface, since Optuna has no multi-objective pruner);
2. runs them on rung 0, the cheapest fidelity (default: the quick
   profile's short runs, one replicate);
3. keeps the best ``ceil(n / eta)`` of the n trials of a rung (:func:`promote`)
   and runs them on the next rung, up to the last, the study's own
   objective (its profile, its K replicates);
4. tells the last rung's trials COMPLETE with their full-fidelity values,
   and the others PRUNED: only full-fidelity trials form the front
   (``study.best_trials`` holds complete trials only).

Every rung's record of a trial is a trial user attr, ``rung<r>``
(objective values, constraints, feasibility, simulated seconds), written
as soon as its runs finish, and the open bracket is a study user attr
(``mat_hopper_bracket``: its index and trial numbers), so a study killed
mid-rung resumes there: the trials keep their parameters (they stay
RUNNING in the storage), the rungs already recorded are not run again, and
promotions are recomputed from the records: the same as an uninterrupted
run. A trial left RUNNING outside the open bracket (a kill between its ask
and the bracket's record) is failed. Each rung's designs are evaluated
together by the optimizer's evaluator interface
(:mod:`mat_hopper.optimize._evaluators`; by default
:class:`~mat_hopper.optimize._evaluators.PoolEvaluator`, the runner's cache
and pool): a run that a later rung repeats (the same design, behaviour and
settings) costs nothing, a resumed rung re-reads what was cached, and a
design whose evaluation process died is evaluated again (up to
``MAX_LOST`` times, then failed).

One process runs a racing study at a time (its trials stay RUNNING while
their bracket races, without a heartbeat; a new bracket fails RUNNING
trials outside it); the processes it uses are the evaluator's. Public
Optuna API only: trials are told by number (``Study.tell``), and a
resumed trial is reached through the storage's public
``get_trial_id_from_study_id_trial_number``.
"""

from __future__ import annotations

import contextlib
import math
import warnings
from dataclasses import asdict, dataclass, replace

import numpy as np
import optuna
from optuna.trial import TrialState

from ..core.materials import LegDesign
from ..experiments.profiles import get_profile
from ._driver import RunResult
from ._evaluators import Evaluator, Lost, PoolEvaluator
from ._feasibility import LEFT_OUT_ATTR, PRUNED_WHY_ATTR, fall_reason, feasibility
from ._mass import SKIPPED_ATTR, outside_band, queued_seeds
from ._objective import OBJECTIVES, Evaluation, Objective, record_evaluation
from ._samplers import make_sampler, sampler_seed
from ._storage import ERROR_ATTR, WORKER_ATTR
from ._study import RACING_ATTR, StudyConfig, StudyMismatch, _quiet, create_or_load, differences

BRACKET_ATTR = "mat_hopper_bracket"  # study user attr: the open (or last) bracket
RUNG_ATTR = "rung"  # trial user attrs rung0, rung1, ...: a rung's record
REACHED_ATTR = "racing_rung"  # trial user attr: the last rung it ran
# LEFT_OUT_ATTR (trial user attr: why a trial that fell was not promoted) and
# PRUNED_WHY_ATTR ("diverged" or "fell") are _feasibility's, which counts them.
DEFAULT_ETA = 3
DEFAULT_SCREEN = 9
MAX_LOST = 3  # evaluations of a design whose evaluation process died, before its trial fails


@dataclass(frozen=True)
class Rung:
    """One fidelity: run length and transient (s; None: the study profile's)
    and replicates (None: the study objective's)."""

    duration_s: float | None = None
    transient_s: float | None = None
    replicates: int | None = None

    def __post_init__(self):
        for name in ("duration_s", "transient_s"):
            v = getattr(self, name)
            if v is not None and (isinstance(v, bool) or not isinstance(v, (int, float)) or not v > 0):
                raise ValueError(f"rung {name} must be a number > 0 s or None, got {v!r}")
        r = self.replicates
        if r is not None and (isinstance(r, bool) or not isinstance(r, int) or r < 0):
            raise ValueError(f"rung replicates must be an integer >= 0 or None, got {r!r}")


@dataclass(frozen=True)
class Racing:
    """Successive halving: the rungs, cheapest first (the last must be the
    study's own fidelity: Rung()), the reduction factor eta (keep 1 in
    eta per rung) and the trials screened per bracket."""

    rungs: tuple[Rung, ...] = (Rung(), Rung())
    eta: int = DEFAULT_ETA
    screen: int = DEFAULT_SCREEN

    def __post_init__(self):
        rungs = tuple(self.rungs)
        if len(rungs) < 2 or not all(isinstance(r, Rung) for r in rungs):
            raise ValueError("rungs: give two or more Rung (cheapest first, Rung() last)")
        if rungs[-1] != Rung():
            raise ValueError("rungs: the last rung must be the study's own fidelity, Rung()")
        object.__setattr__(self, "rungs", rungs)
        for name, lo in (("eta", 2), ("screen", 1)):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, int) or v < lo:
                raise ValueError(f"{name} must be an integer >= {lo}, got {v!r}")

    def objective_at(self, objective: Objective, r: int) -> Objective:
        """The objective of rung `r`: the study's, with the rung's run length and replicates."""
        rung = self.rungs[r]
        prof = objective.profile
        prof = replace(
            prof,
            duration_s=prof.duration_s if rung.duration_s is None else rung.duration_s,
            transient_s=prof.transient_s if rung.transient_s is None else rung.transient_s,
        )
        reps = objective.replicates if rung.replicates is None else rung.replicates
        risk = objective.risk if reps >= 2 else "mean"
        return replace(objective, profile=prof, replicates=reps, risk=risk)

    def kept(self, n: int) -> int:
        """Trials promoted from a rung of n: ceil(n / eta), at least one."""
        return max(1, math.ceil(n / self.eta))

    def key(self) -> dict:
        return {"rungs": [asdict(r) for r in self.rungs], "eta": self.eta, "screen": self.screen}


def default_racing(objective: Objective) -> Racing:
    """Screen on the quick profile's run length (or the study's, if shorter)
    with one replicate, then the study's own fidelity; eta 3, 9 per bracket.

    Args:
        objective: the study's :class:`~mat_hopper.optimize.Objective`.

    Returns:
        A :class:`Racing` of two rungs: the screen, Rung(duration_s, transient_s
        (s): the smaller of the quick profile's and the objective profile's;
        replicates: 1, or 0 for an objective of 0 replicates, one unperturbed
        run), then Rung() (the study's fidelity); eta DEFAULT_ETA (3),
        screen DEFAULT_SCREEN (9).
    """
    quick = get_profile("quick")
    prof = objective.profile
    screen = Rung(
        duration_s=min(quick.duration_s, prof.duration_s),
        transient_s=min(quick.transient_s, prof.transient_s),
        replicates=min(1, objective.replicates),
    )
    return Racing(rungs=(screen, Rung()))


def promote(records: dict[int, Evaluation], k: int) -> list[int]:
    """The `k` best trial numbers of a rung's {number: Evaluation}: feasible
    before infeasible (then by total constraint violation), then by
    non-dominated layer of the objectives, then by the sum of the
    per-objective ranks, then by trial number (deterministic). A trial
    whose runs fell or diverged (its ``unstable`` constraint above 0) is
    never promoted, and its values, those of a run that did not hop to
    its end, are no comparator for the others: the layers and ranks are
    those of the trials that stood.

    Ours: Optuna's non-dominated sorting is private
    (``optuna.study._multi_objective``).

    Args:
        records: {trial number: Evaluation} of one rung; only each
            Evaluation's ``values`` (minimized) and ``constraints`` (<= 0
            feasible; the violation is the sum of the positive ones) are
            read.
        k: how many to keep.

    Returns:
        Up to `k` trial numbers, best first (all that stood when `k` is at
        least their number).
    """
    nums = sorted(n for n in records if not fell(records[n]))
    if not nums:
        return []
    vals = np.array([records[n].values for n in nums], float).reshape(len(nums), -1)
    violation = np.array([sum(max(c, 0.0) for c in records[n].constraints) for n in nums])
    layer = np.full(len(nums), -1)
    left, depth = set(range(len(nums))), 0
    while left:  # peel non-dominated layers
        front = {
            i for i in left if not any(np.all(vals[j] <= vals[i]) and np.any(vals[j] < vals[i]) for j in left if j != i)
        }
        for i in front:
            layer[i] = depth
        left -= front
        depth += 1
    ranks = np.argsort(np.argsort(vals, axis=0, kind="stable"), axis=0, kind="stable").sum(axis=1)
    order = sorted(range(len(nums)), key=lambda i: (violation[i] > 0, violation[i], layer[i], ranks[i], nums[i]))
    return [nums[i] for i in order[:k]]


def fell(ev: Evaluation) -> bool:
    """Whether an Evaluation's runs fell or diverged: its ``unstable``
    constraint (:data:`~mat_hopper.optimize._objective.CONSTRAINTS`) above 0."""
    names = tuple(ev.constraint_names)
    i = names.index("unstable") if "unstable" in names and len(names) == len(ev.constraints) else 1
    return len(ev.constraints) > i and ev.constraints[i] > 0


# --- records in the storage ------------------------------------------------------


def _record(ev: Evaluation) -> dict:
    fin = lambda v: None if not math.isfinite(v) else float(v)  # noqa: E731
    return {
        "values": [float(v) for v in ev.values],
        "constraints": [float(c) for c in ev.constraints],
        "feasible": ev.feasible,
        "standard_errors": [fin(v) for v in ev.standard_errors],
        "simulated_s": float(ev.simulated_s),
        "why": _fall_kind(ev),
    }


def _fall_kind(ev: Evaluation) -> str | None:
    """``"diverged"`` or ``"fell"`` for an Evaluation whose runs went wrong
    (:func:`~mat_hopper.optimize._feasibility.fall_reason`), else None."""
    why = fall_reason(ev.per_behaviour)
    return None if why is None else ("diverged" if why.startswith("diverged") else "fell")


def _as_evaluation(rec: dict, constraint_names=None) -> Evaluation:
    return Evaluation(
        values=tuple(rec["values"]),
        constraints=tuple(rec["constraints"]),
        hop_height_m=math.nan,
        simulated_s=rec["simulated_s"],
        **({"constraint_names": tuple(constraint_names)} if constraint_names is not None else {}),
    )


class _Trials:
    """Live Trial objects of a study's trials by number, through the
    storage's public API (the trials a resumed run did not ask itself)."""

    def __init__(self, study: optuna.Study, storage):
        self.study, self.storage = study, storage
        self.study_id = storage.get_study_id_from_name(study.study_name)
        self.live: dict[int, optuna.trial.Trial] = {}

    def __getitem__(self, number: int) -> optuna.trial.Trial:
        if number not in self.live:
            tid = self.storage.get_trial_id_from_study_id_trial_number(self.study_id, number)
            self.live[number] = optuna.trial.Trial(self.study, tid)
        return self.live[number]

    def frozen(self, number: int) -> optuna.trial.FrozenTrial:
        return self.storage.get_trial(self.storage.get_trial_id_from_study_id_trial_number(self.study_id, number))


# --- the loop ----------------------------------------------------------------------


def _storage_of(storage):
    """An Optuna storage object for a URL or a storage (ours, with its checks)."""
    if isinstance(storage, str):
        from ._storage import open_storage

        return open_storage(storage)
    return storage


def _check_racing(study: optuna.Study, racing: Racing) -> None:
    stored = study.user_attrs.get(RACING_ATTR)
    if stored is None:
        if any(t.state == TrialState.COMPLETE for t in study.get_trials(deepcopy=False)):
            raise StudyMismatch(
                f"study {study.study_name!r} was not run by racing: use a new study name",
                study.study_name,
                "not racing",
            )
        study.set_user_attr(RACING_ATTR, racing.key())
    elif stored != racing.key():
        diff = differences({"racing": stored}, {"racing": racing.key()})
        text = "; ".join(f"{k}: study has {va!r}, asked {vb!r}" for k, va, vb in diff)
        raise StudyMismatch(
            f"study {study.study_name!r} races with other settings ({text}); use its own or a new name",
            study.study_name,
            "settings",
            diff,
        )


def closed_brackets(study: optuna.Study) -> int:
    """How many brackets of the study are finished."""
    b = study.user_attrs.get(BRACKET_ATTR)
    if b is None:
        return 0
    return b["index"] + 1 if b["closed"] else b["index"]


def run_racing(
    config: StudyConfig,
    storage,
    *,
    brackets: int,
    racing: Racing | None = None,
    sampler="tpe",
    seed: int = 0,
    cache_dir=None,
    workers: int | None = None,
    evaluator: Evaluator | None = None,
    on_rung=None,
) -> optuna.Study:
    """Run (or resume) a racing study until it holds `brackets` finished brackets (module doc).

    Args:
        config: the study.
        storage: a URL or an Optuna storage.
        brackets: finished brackets to reach.
        racing: the rungs (None: :func:`default_racing`).
        sampler: a sampler's name (seeded from `seed` and the study's size,
            as :func:`mat_hopper.optimize.run_study` seeds it) or an Optuna sampler as it is.
        seed: the sampler's seed.
        cache_dir, workers: the default evaluator's cache and processes
            (:class:`~mat_hopper.optimize._evaluators.PoolEvaluator`).
        evaluator: what simulates instead (the caller closes it).
        on_rung: called as on_rung(bracket, rung) after each rung's records are
            stored (tests kill the process there).

    Returns:
        The study.

    Raises:
        ValueError: bad settings, or a study raced with other settings.
    """
    if isinstance(brackets, bool) or not isinstance(brackets, int) or brackets < 1:
        raise ValueError(f"brackets must be an integer >= 1, got {brackets!r}")
    racing = racing or default_racing(config.objective)
    if not isinstance(racing, Racing):
        raise ValueError("racing must be a Racing")
    _quiet()
    storage = _storage_of(storage)
    n_existing = len(create_or_load(config, storage).get_trials(deepcopy=False))
    if isinstance(sampler, str):
        sampler = make_sampler(sampler, sampler_seed(seed, n_existing))
    study = create_or_load(config, storage, sampler=sampler)
    _check_racing(study, racing)
    trials = _Trials(study, storage)
    with contextlib.nullcontext(evaluator) if evaluator else PoolEvaluator(cache_dir, workers=workers) as ev:
        while True:
            b = study.user_attrs.get(BRACKET_ATTR)
            if b is None or b["closed"]:
                if closed_brackets(study) >= brackets:
                    break
                b = _open_bracket(study, trials, config, racing, 0 if b is None else b["index"] + 1)
            else:
                _fail_strays(study, trials, set(b["trials"]))
            _run_bracket(study, trials, b, config, racing, ev, on_rung)
            study.set_user_attr(BRACKET_ATTR, {**b, "closed": True})
    return study


def _evaluate(evaluator: Evaluator, designs: list, objective: Objective, desc: str) -> list:
    """The evaluator's outcomes, a design whose evaluation process died
    evaluated again (MAX_LOST times in all, then its error)."""
    if not designs:  # every trial of the rung before fell: nothing promoted
        return []
    out = evaluator.evaluate(designs, objective, desc=desc)
    for _ in range(MAX_LOST - 1):
        again = [i for i, o in enumerate(out) if isinstance(o, Lost)]
        if not again:
            break
        for i, o in zip(again, evaluator.evaluate([designs[i] for i in again], objective, desc=desc)):
            out[i] = o
    return [o.reason if isinstance(o, Lost) else o for o in out]


def _fail_strays(study, trials: _Trials, keep: set) -> None:
    """Fail RUNNING trials outside the open bracket (asked, never recorded)."""
    for t in study.get_trials(deepcopy=False, states=(TrialState.RUNNING,)):
        if t.number not in keep:
            trials[t.number].set_user_attr(ERROR_ATTR, "racing: asked but not recorded in a bracket (interrupted)")
            study.tell(t.number, state=TrialState.FAIL)


def _open_bracket(study, trials: _Trials, config: StudyConfig, racing: Racing, index: int) -> dict:
    """Ask the bracket's trials, each recorded in the bracket as soon as its
    parameters are (a kill in between leaves a stray, failed on resume)."""
    _fail_strays(study, trials, set())
    b = {"index": index, "trials": [], "closed": False}
    study.set_user_attr(BRACKET_ATTR, b)
    for _ in range(racing.screen):
        with warnings.catch_warnings():  # racing trials run outside Study.optimize (no heartbeat)
            warnings.filterwarnings("ignore", message="Heartbeat of storage", category=UserWarning)
            t = study.ask()
        trials.live[t.number] = t
        t.set_user_attr(WORKER_ATTR, {"host": "racing", "pid": 0})
        try:
            config.space.suggest(t)
        except ValueError as e:
            t.set_user_attr(ERROR_ATTR, f"{type(e).__name__}: {e}"[:500])
        b = {**b, "trials": [*b["trials"], t.number]}
        study.set_user_attr(BRACKET_ATTR, b)
    return b


def _designs(trials: _Trials, numbers, space, objective) -> dict[int, LegDesign]:
    """The bracket's designs by number; a trial without one, or whose
    design lies outside the objective's leg-mass band, is failed."""
    out = {}
    for n in numbers:
        ft = trials.frozen(n)
        if ft.state != TrialState.RUNNING:
            continue
        try:
            if ERROR_ATTR in ft.user_attrs:
                raise ValueError(ft.user_attrs[ERROR_ATTR])
            design = space.design(ft.params)
        except ValueError as e:
            if ERROR_ATTR not in ft.user_attrs:
                trials[n].set_user_attr(ERROR_ATTR, f"{type(e).__name__}: {e}"[:500])
            trials.study.tell(n, state=TrialState.FAIL)
            continue
        why = outside_band(design, objective)
        if why is not None:  # outside the leg-mass band: not run (mat_hopper.optimize._mass)
            trials[n].set_user_attr(SKIPPED_ATTR, "leg_mass")
            trials[n].set_user_attr(ERROR_ATTR, why)
            trials.study.tell(n, state=TrialState.FAIL)
            continue
        out[n] = design
    return out


def _run_bracket(study, trials: _Trials, b: dict, config: StudyConfig, racing: Racing, evaluator, on_rung) -> None:
    """Rungs of one bracket, from the first whose records are missing."""
    designs = _designs(trials, b["trials"], config.space, config.objective)
    alive = sorted(designs)
    last = len(racing.rungs) - 1
    for r in range(last + 1):
        objective = racing.objective_at(config.objective, r)
        key = f"{RUNG_ATTR}{r}"
        stored = {n: trials.frozen(n).user_attrs.get(key) for n in alive}
        todo = [n for n in alive if stored[n] is None]
        evs = _evaluate(evaluator, [designs[n] for n in todo], objective, f"bracket {b['index']} rung {r}")
        full: dict[int, Evaluation] = {}
        for n, ev in zip(todo, evs):
            if isinstance(ev, str):  # the runs raised: a failed trial
                trials[n].set_user_attr(ERROR_ATTR, ev[:500])
                study.tell(n, state=TrialState.FAIL)
                continue
            trials[n].set_user_attr(key, _record(ev))
            trials[n].set_user_attr(REACHED_ATTR, r)
            stored[n] = _record(ev)
            full[n] = ev
        alive = [n for n in alive if stored.get(n) is not None and trials.frozen(n).state == TrialState.RUNNING]
        if on_rung is not None:
            on_rung(b["index"], r)
        if r == last:
            _tell_complete(study, trials, alive, designs, objective, full, evaluator)
            return
        records = {n: _as_evaluation(stored[n], objective.constraint_names) for n in alive}
        keep = set(promote(records, racing.kept(len(alive))))
        for n in alive:
            if n not in keep:  # its constraints as screened: the sampler sees why it lost
                for name, c in zip(objective.constraint_names, stored[n]["constraints"]):
                    trials[n].set_constraint(name, c)
                if fell(records[n]):  # never promoted, nor a comparator (promote)
                    why = stored[n].get("why") or "fell or diverged"
                    trials[n].set_user_attr(LEFT_OUT_ATTR, f"{why} on rung {r}: not promoted")
                    if stored[n].get("why"):
                        trials[n].set_user_attr(PRUNED_WHY_ATTR, stored[n]["why"])
                study.tell(n, state=TrialState.PRUNED)
        alive = sorted(keep)


def _tell_complete(study, trials: _Trials, numbers, designs, objective, evaluated, evaluator) -> None:
    """Tell the last rung's trials with their full-fidelity records (an
    Evaluation evaluated now, or, resumed, re-read from the runner's cache)."""
    missing = [n for n in numbers if n not in evaluated]
    if missing:
        for n, ev in zip(missing, _evaluate(evaluator, [designs[n] for n in missing], objective, "told")):
            evaluated[n] = ev
    for n in numbers:
        ev = evaluated[n]
        if isinstance(ev, str):  # a resumed rung whose runs raised this time
            trials[n].set_user_attr(ERROR_ATTR, ev[:500])
            study.tell(n, state=TrialState.FAIL)
            continue
        record_evaluation(trials[n], designs[n], ev)
        study.tell(n, list(ev.values))


def simulated_seconds(study: optuna.Study, racing: Racing) -> dict:
    """Simulated seconds the study spent, from its rung records: total,
    per full-fidelity (complete) trial, and what scoring every screened
    trial at full fidelity would have cost (each at the mean full-fidelity
    cost of the complete trials), and the study's objectives (their names).

    Args:
        study: the racing ``optuna.Study``; trials without a ``rung<r>``
            user attr are not counted.
        racing: its :class:`Racing` (its number of rungs names the last,
            full-fidelity rung).

    Returns:
        A dict: ``screened`` (int, trials with a rung record),
        ``complete`` (int, COMPLETE trials with a last-rung record),
        ``simulated_s`` (float, s, every rung record of every trial),
        ``simulated_s_per_complete`` (``simulated_s`` / ``complete``, s;
        nan without a complete trial), ``all_full_fidelity_s`` (``screened``
        x the mean last-rung cost of the complete trials, s; nan without
        one) and ``objectives`` (list of the study's metric names, else the
        default objectives).
    """
    last = f"{RUNG_ATTR}{len(racing.rungs) - 1}"
    total, full, screened = 0.0, [], 0
    for t in study.get_trials(deepcopy=False):
        recs = [v for k, v in t.user_attrs.items() if k.startswith(RUNG_ATTR) and k[len(RUNG_ATTR) :].isdigit()]
        if not recs:
            continue
        screened += 1
        total += sum(r["simulated_s"] for r in recs)
        if t.state == TrialState.COMPLETE and last in t.user_attrs:
            full.append(t.user_attrs[last]["simulated_s"])
    per_full = float(np.mean(full)) if full else math.nan
    return {
        "screened": screened,
        "complete": len(full),
        "simulated_s": total,
        "simulated_s_per_complete": total / len(full) if full else math.nan,
        "all_full_fidelity_s": screened * per_full,
        "objectives": list(study.metric_names or OBJECTIVES),
    }


def race_study(config: StudyConfig, options, racing: Racing | None = None):
    """:func:`run_racing` for the command line.

    Args:
        config: the study.
        options: a :class:`~mat_hopper.optimize._study.RunOptions`: the
            storage, the sampler and seed, the processes (``workers``), the
            cache (``cache_dir``) and the size: ``trials`` screened trials,
            rounded up to whole brackets.
        racing: the rungs (None: :func:`default_racing`).

    Returns:
        A :class:`~mat_hopper.optimize.RunResult` (done and target in
        screened trials).

    Raises:
        ValueError: as :func:`run_racing`; a database error as one line.
    """
    from ._storage import redact, storage_errors

    racing = racing or default_racing(config.objective)
    brackets = math.ceil(options.trials / racing.screen)
    url = options.storage_url(config.name)
    with storage_errors(url):
        study = run_racing(
            config,
            options.open(config.name),
            brackets=brackets,
            racing=racing,
            sampler=options.sampler,
            seed=options.seed,
            cache_dir=options.cache_dir,
            workers=options.workers,
        )
        done = closed_brackets(study) * racing.screen
        result = RunResult(config.name, redact(url), brackets * racing.screen, done, 0, evaluator="racing")
        result.feasibility = feasibility(study, config)
        result.left_out = queued_seeds(config.space, config.objective)[1]
    return result
