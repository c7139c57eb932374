"""Design optimizer: Optuna multi-objective search over per-segment materials.

Searches leg designs (per-segment density and modulus, or catalogue
materials: :mod:`mat_hopper.optimize._space`) for low tracking error and
low hip power (or two or three other metrics: ``--objectives``,
:mod:`mat_hopper.physics.run_metrics`) under a hop-height and a stability
constraint (:mod:`mat_hopper.optimize._objective`). Every study starts from the
paper's designs its space can express (enqueued first; in a study held to
a leg mass, those inside its band: :mod:`mat_hopper.optimize._mass`). This module
holds what a study is (:class:`StudyConfig`, stored in the study), how to
run it (:class:`RunOptions`) and its creation (:func:`create_or_load`);
:mod:`mat_hopper.optimize._driver` runs it: one ask-and-tell loop, with
the trials of each round simulated together by an evaluator
(:mod:`mat_hopper.optimize._evaluators`: the CPU process pool, or the
MuJoCo Warp batch).

Command line::

    mat-hopper optimize --study NAME --trials 200 [--behaviour ramp] [--segments 3]
        [--space continuous|catalogue|KIND,KIND,...] [--workers 2] [--batch-size 8] [--storage URL]
        [--sampler tpe|nsga2|gp] [--seed 0] [--profile paper|quick] [--cache DIR]
        [--objectives tracking_error_m,power_w]
    mat-hopper optimize --report NAME      # Pareto front, hypervolume, importances, CSV
    mat-hopper optimize --study NAME --replay TRIAL [--render]

``--trials N`` is the study's size: the run stops once the study holds N
finished trials (complete, or failed with an error in the evaluation);
re-running the same command resumes an interrupted study and does
nothing for a finished one. Trials whose process died are failed and
re-enqueued; their retries count, they do not.

Storage (:mod:`mat_hopper.optimize._storage`): by default one SQLite file
per study, ``studies/<name>.db``; ``--storage postgresql://...`` for many
machines (run the same command on each; give each machine its own
``--seed``); ``--storage journal:///shared/path/x.log`` for a shared file
system. ``--workers N`` is the number of processes that simulate on this
machine (default 2, one per core); ``--batch-size K`` the trials asked,
simulated together and told per round (default 8).

Samplers: multi-objective TPE (default; multivariate, constant liar so
that the trials of a round, and of other machines, are kept apart),
NSGA-II (``nsga2``, population 50) or Optuna's GP sampler (``gp``, needs
PyTorch). All see the constraints, which each trial sets with
``Trial.set_constraint`` (Optuna 5's replacement of ``constraints_func``).
A run's sampler seed is derived from ``--seed`` and the study's size when
the run started: a fresh study is exactly reproducible for a seed and a
batch size, on any machine and with any number of ``--workers``.

Watch a study live with optuna-dashboard (pinned in environment.txt)::

    optuna-dashboard sqlite:///studies/NAME.db          # default storage
    optuna-dashboard postgresql://USER@HOST:5432/DB     # shared storage

then open http://127.0.0.1:8080/. See docs/optimizer.md.
"""

from __future__ import annotations

import os
import time
import warnings
from dataclasses import InitVar, dataclass, field, replace

import optuna
from optuna.trial import TrialState

from ..core.materials import DENSITY_RANGE_G_CM3, MODULUS_RANGE_GPA
from ..physics.run_metrics import METRICS
from ._mass import check_mass_band, mass_hold, queued_seeds
from ._objective import Objective
from ._samplers import sampler_name
from ._space import SearchSpace
from ._storage import ERROR_ATTR, PAPER_ATTR, check_study_name, default_url, open_storage

DEFAULT_WORKERS = 2
CONFIG_ATTR = "mat_hopper_config"
RACING_ATTR = "mat_hopper_racing"  # study user attr: the racing settings of a racing study (_racing)
BACKEND_ATTR = "mat_hopper_backend"  # study user attr: the simulator of its trials ("warp"; absent: the CPU path)
TRIAL_BACKEND_ATTR = "backend"  # trial user attr of a warp study's trials: the backend that evaluated it
CONFIG_VERSION = 1
CREATE_WAIT_S = 30.0  # how long a second first start waits for the creator's config


# --- settings ---------------------------------------------------------------


# Behaviours whose objectives vary between designs. Hopping in place
# ("static") alone has none: its desired path is the start point and the
# hopper is symmetric, so tracking error and hip power are zero up to
# round-off (2e-15 m, 7e-26 W) for every design; a front, hypervolume or
# importances computed from them would be noise.
DEGENERATE_BEHAVIOURS = ("static",)


def check_physical_bounds(space: SearchSpace) -> None:
    """The search box inside the physical ranges every design must keep
    (:data:`mat_hopper.core.materials.DENSITY_RANGE_G_CM3`,
    :data:`~mat_hopper.core.materials.MODULUS_RANGE_GPA`): the same ranges
    the simulator checks, named in one line, before any trial."""
    for field_name, bounds, (lo, hi), unit in (
        ("density_g_cm3", space.density_g_cm3, DENSITY_RANGE_G_CM3, "g/cm^3"),
        ("modulus_gpa", space.modulus_gpa, MODULUS_RANGE_GPA, "GPa"),
    ):
        if bounds is None:
            continue
        if not (lo <= bounds[0] and bounds[1] <= hi):
            raise ValueError(
                f"{field_name} bounds must lie in the physical range [{lo:g}, {hi:g}] {unit}, "
                f"got {bounds[0]:g} to {bounds[1]:g}"
            )


def check_objectives_vary(objective: Objective) -> None:
    """Refuse a study whose objectives cannot vary.

    Args:
        objective: the study's objective.

    Raises:
        ValueError: static hopping alone with an objective that is zero by
            symmetry for every design there (tracking error, hip power:
            round-off only; total power, energy, stress and mass vary).
    """
    zero = [o for o in objective.objectives if METRICS[o].static_zero]
    if zero and all(b in DEGENERATE_BEHAVIOURS for b in objective.behaviours):
        what = " and ".join(METRICS[o].label for o in zero)
        raise ValueError(
            f"--behaviour {','.join(objective.behaviours)} alone cannot be optimized for {', '.join(zero)}: "
            f"hopping in place, {what} {'are' if len(zero) > 1 else 'is'} zero by symmetry for every design "
            "(round-off only); add a moving behaviour, e.g. --behaviour static,ramp"
        )


@dataclass(frozen=True)
class StudyConfig:
    """What a study is. Stored in the study (user attr ``mat_hopper_config``);
    resuming checks it.

    Args:
        name: the study's name (:func:`check_study_name`).
        space: where the optimizer looks (:class:`SearchSpace`).
        objective: what it minimizes (:class:`Objective`).
        check_band: refuse a void or unmeetable leg-mass band (False: a
            stored study read back, whose report, replay and export must
            work whatever an older version accepted).

    Raises:
        ValueError: a bad name, space or objective; a leg-mass band that is
            void (it holds every leg of the space) or that no leg of the
            space meets (:func:`~mat_hopper.optimize._mass.check_mass_band`).
    """

    name: str
    space: SearchSpace = field(default_factory=SearchSpace)
    objective: Objective = field(default_factory=Objective)
    check_band: InitVar[bool] = True

    def __post_init__(self, check_band: bool = True):
        check_study_name(self.name)
        if not isinstance(self.space, SearchSpace):
            raise ValueError("space must be a SearchSpace")
        if not isinstance(self.objective, Objective):
            raise ValueError("objective must be an Objective")
        check_physical_bounds(self.space)
        if check_band:  # a void or unmeetable leg-mass band (mat_hopper.optimize._mass)
            check_mass_band(self.space, self.objective)
        hold = mass_hold(self.space, self.objective)
        if hold is not None:  # sample inside the band (not part of the key: derived from the objective)
            object.__setattr__(self, "space", replace(self.space, mass_hold=hold))

    def key(self) -> dict:
        return {"version": CONFIG_VERSION, "space": self.space.key(), "objective": self.objective.key()}

    @classmethod
    def from_key(cls, name: str, key: dict) -> StudyConfig:
        return cls(name, SearchSpace.from_key(key["space"]), Objective.from_key(key["objective"]), check_band=False)


@dataclass(frozen=True)
class RunOptions:
    """How to run a study.

    Args:
        trials: target number of finished trials.
        workers: local processes that simulate (None: all cores; 1: in the
            run's own process). They never change the trials: see batch_size.
        sampler: an Optuna sampler's name (:data:`SAMPLERS`).
        seed: the sampler's seed (the run's is derived from it and the study's size).
        storage: a storage URL (None: ``studies_dir/<name>.db``).
        studies_dir: the folder of the default SQLite files.
        heartbeat_s, grace_s: heartbeat interval and grace period of RDB storages, s.
        max_retry: retries per trial whose process died.
        progress: show a progress bar.
        batch_size: trials asked, simulated together and told per round (None:
            the backend's default, 8 on the CPU, 64 on warp). With the seed, it
            fixes a fresh study's trials on any machine.
        cache_dir: the CPU path's cache of runs (None: $MAT_HOPPER_CACHE, else
            results/cache).

    Raises:
        ValueError: any value out of range (naming it).
    """

    trials: int = 200
    workers: int | None = DEFAULT_WORKERS
    sampler: str = "tpe"
    seed: int = 0
    storage: str | None = None
    studies_dir: str = "studies"
    heartbeat_s: int = 10
    grace_s: int = 60
    max_retry: int = 3
    progress: bool = True
    batch_size: int | None = None
    cache_dir: str | None = None

    def __post_init__(self):
        for name, lo, optional in (("trials", 1, False), ("workers", 1, True), ("max_retry", 0, False)):
            v = getattr(self, name)
            if v is None and optional:
                continue
            if isinstance(v, bool) or not isinstance(v, int) or v < lo:
                raise ValueError(f"{name} must be an integer >= {lo}, got {v!r}")
        if self.workers is not None and self.workers > 256:
            raise ValueError(f"workers must be in [1, 256], got {self.workers}")
        b = self.batch_size
        if b is not None and (isinstance(b, bool) or not isinstance(b, int) or b < 1):
            raise ValueError(f"batch_size must be an integer >= 1 (trials asked per round), got {b!r}")
        object.__setattr__(self, "sampler", sampler_name(self.sampler))
        if isinstance(self.seed, bool) or not isinstance(self.seed, int) or self.seed < 0:
            raise ValueError(f"seed must be an integer >= 0, got {self.seed!r}")

    def storage_url(self, study_name: str) -> str:
        """The study's storage URL.

        Args:
            study_name: the study's name.

        Returns:
            ``storage`` (its scheme in lower case), or the default SQLite
            file's URL in ``studies_dir`` (made if missing).
        """
        if self.storage:
            from ..util.parsing import normalize_url

            return normalize_url(self.storage)  # RFC 3986: schemes are case-insensitive
        os.makedirs(self.studies_dir, exist_ok=True)
        return default_url(study_name, self.studies_dir)

    def open(self, study_name: str):
        """The study's storage, opened (:func:`~mat_hopper.optimize.open_storage`).

        Args:
            study_name: the study's name.

        Returns:
            An Optuna storage with these heartbeat and retry settings.

        Raises:
            ValueError: an unreachable or bad storage (one line).
        """
        return open_storage(
            self.storage_url(study_name), heartbeat_s=self.heartbeat_s, grace_s=self.grace_s, max_retry=self.max_retry
        )


# --- studies ----------------------------------------------------------------


def _quiet() -> None:
    optuna.logging.set_verbosity(optuna.logging.WARNING)


def study_exists(name: str, storage) -> bool:
    """Whether `storage` (an Optuna storage) holds a study named `name`.

    Args:
        name: the study's name.
        storage: an Optuna storage object (``get_study_id_from_name`` is
            called on it; a URL string is not accepted).

    Returns:
        True when it does; False when the storage answers KeyError (no
        such study).
    """
    try:
        storage.get_study_id_from_name(name)
        return True
    except KeyError:
        return False


def load_existing(name: str, storage, **kwargs) -> optuna.Study:
    """An existing study, loaded: ``optuna.load_study`` with a ValueError,
    not Optuna's KeyError, for a name the storage does not hold.

    Args:
        name: the study's name.
        storage: an Optuna storage or a storage URL (as ``optuna.load_study``
            takes it).
        **kwargs: passed on to ``optuna.load_study`` (e.g. ``sampler``).

    Returns:
        The ``optuna.Study``.

    Raises:
        ValueError: no study named `name` in `storage` (the message names it
            and lists the studies the storage holds), or a SQLite URL whose
            file does not exist (checked first: opening it would create it).
    """
    if isinstance(storage, str) and storage.lower().startswith("sqlite:///"):
        path = storage[len("sqlite:///") :]
        if path != ":memory:" and not os.path.isfile(path):  # opening it would create an empty database
            raise ValueError(f"no study {name!r}: no SQLite file {path}")
    try:
        return optuna.load_study(study_name=name, storage=storage, **kwargs)
    except KeyError:
        present = sorted(optuna.study.get_all_study_names(storage))
        held = ", ".join(repr(n) for n in present) if present else "none"
        raise ValueError(f"no study {name!r} in the storage; studies present: {held}") from None


def stored_config(name: str, storage) -> StudyConfig | None:
    """The config a study was created with.

    Args:
        name: the study's name.
        storage: an Optuna storage.

    Returns:
        The :class:`StudyConfig`, or None (no such study, or not ours).
    """
    if not study_exists(name, storage):
        return None
    attrs = storage.get_study_user_attrs(storage.get_study_id_from_name(name))
    key = attrs.get(CONFIG_ATTR)
    return StudyConfig.from_key(name, key) if key else None


class StudyMismatch(ValueError):
    """A study that exists cannot run as asked. `kind` says why:
    ``"settings"`` (its stored settings differ; `differences` holds
    (field path, stored value, asked value), a profile that differs by name
    as one ``objective.profile`` entry), ``"racing"`` (a racing study
    resumed by the plain loop) or ``"not racing"`` (a plain study resumed by
    racing)."""

    def __init__(self, message: str, name: str, kind: str, differences: tuple = ()):
        super().__init__(message)
        self.name, self.kind, self.differences = name, kind, tuple(differences)


def differences(a: dict, b: dict, prefix: str = "") -> list[tuple[str, object, object]]:
    """(dotted field path, value in `a`, value in `b`) of each field of two
    nested settings dicts that differs; two profiles of other names are
    one entry, by name (their fields follow from the names)."""
    out = []
    for k in sorted(set(a) | set(b)):
        va, vb = a.get(k), b.get(k)
        if isinstance(va, dict) and isinstance(vb, dict):
            if "name" in va and "name" in vb and va["name"] != vb["name"]:
                out.append((f"{prefix}{k}", va["name"], vb["name"]))
            else:
                out += differences(va, vb, f"{prefix}{k}.")
        elif va != vb:
            out.append((f"{prefix}{k}", va, vb))
    return out


def create_or_load(
    config: StudyConfig, storage, sampler=None, backend: str = "mujoco", *, wait_s: float = CREATE_WAIT_S
) -> optuna.Study:
    """The study `config.name` in `storage`: created with the paper's designs
    enqueued first, or loaded and checked against `config`.

    Safe when several processes start the same new study at once: the
    study's creation is atomic in the storage (a unique name), and only
    its creator enqueues the paper's designs, then stores the config last,
    as the mark that the study is ready. The others wait for that mark (up
    to `wait_s`; a creator that died before setting it is replaced).

    Args:
        config: the study.
        storage: an Optuna storage (:func:`open_storage`).
        sampler: an Optuna sampler (None: Optuna's default).
        backend: the backend its trials run on (``"mujoco"`` or ``"warp"``).
        wait_s: how long to wait for another process's new study, s.

    Returns:
        The ``optuna.Study``.

    Raises:
        ValueError: a stored config other than `config`, or trials of another backend.
    """
    _quiet()
    check_objectives_vary(config.objective)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", optuna.exceptions.ExperimentalWarning)
        try:
            study = optuna.create_study(
                study_name=config.name,
                storage=storage,
                sampler=sampler,
                directions=["minimize"] * len(config.objective.objectives),
            )
            created = True
        except optuna.exceptions.DuplicatedStudyError:
            study = optuna.load_study(study_name=config.name, storage=storage, sampler=sampler)
            created = False
    attrs = study.user_attrs
    if CONFIG_ATTR not in attrs and not created:
        deadline = time.monotonic() + wait_s
        while CONFIG_ATTR not in attrs and time.monotonic() < deadline:
            time.sleep(0.1)
            attrs = study.user_attrs
    stored = attrs.get(CONFIG_ATTR)
    has = attrs.get(BACKEND_ATTR, "mujoco" if stored is not None else backend)
    if has != backend:  # one study, one simulator (mat_hopper.optimize._batch)
        raise ValueError(
            f"study {config.name!r} holds trials of the {has} backend: use a new --study name for {backend}"
        )
    if backend != "mujoco" and BACKEND_ATTR not in attrs:
        study.set_user_attr(BACKEND_ATTR, backend)
    if stored is None:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", optuna.exceptions.ExperimentalWarning)
            study.set_metric_names(list(config.objective.objectives))
        for name, params in queued_seeds(config.space, config.objective)[0]:  # outside a mass band: not queued
            study.enqueue_trial(params, user_attrs={PAPER_ATTR: name}, skip_if_exists=True)
        study.set_user_attr(CONFIG_ATTR, config.key())  # last: the study is ready
    elif stored != config.key():
        diff = differences(stored, config.key())
        text = "; ".join(f"{k}: study has {va!r}, asked {vb!r}" for k, va, vb in diff)
        raise StudyMismatch(
            f"study {config.name!r} exists with other settings ({text}); use a new study name or the study's own settings",
            config.name,
            "settings",
            diff,
        )
    return study


def counts(study) -> tuple[int, int]:
    """(finished, running): finished = complete, or failed by an error in
    the evaluation (a trial whose process died is retried, not counted)."""
    done = running = 0
    for t in study.get_trials(deepcopy=False, states=(TrialState.COMPLETE, TrialState.FAIL, TrialState.RUNNING)):
        if t.state == TrialState.RUNNING:
            running += 1
        elif t.state == TrialState.COMPLETE or ERROR_ATTR in t.user_attrs:
            done += 1
    return done, running
