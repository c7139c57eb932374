"""Chapter 9's racing study as the book runs it, and its validated record.

:func:`book_study` is the one place the chapter's study is configured: the
search space, the objective (the ramp, the objective's replicates on
common random numbers, the mean, a leg of rho-inc's mass), the racing, the
screened trials per profile in brackets, the sampler and its seed, and the
:class:`~mat_hopper.optimize.StudyConfig` whose name carries a digest of
all of them (a study of other settings gets another name, so a build never
resumes a study it did not make). The notebook, the plan of the book's
runs (:mod:`mat_hopper.optimize.book_plan`) and :func:`book_record_tables`
read it.

:func:`validated_legs` is what the chapter validates: the front's new
designs and the paper's four gradients. :func:`book_record_tables`
rebuilds the chapter's record tables (``book/records/optimizer-paper.csv``
and ``optimizer-paired-paper.csv``) from a finished build: its study,
loaded read-only, and its result cache, running nothing.
"""

from __future__ import annotations

import hashlib
import json
import os
from dataclasses import dataclass

from optuna.trial import TrialState

from ..core.materials import paper_designs
from ..experiments.cache import Cache
from . import validate
from ._objective import Objective
from ._racing import Racing, closed_brackets, default_racing
from ._report_tables import front_designs, pareto_frame, trials_frame
from ._scoring import DEFAULT_REPLICATES
from ._space import SearchSpace
from ._storage import default_url, dispose, open_storage
from ._study import CONFIG_ATTR, StudyConfig, load_existing

BOOK_BEHAVIOURS = ("ramp",)  # the paper's headline behaviour
BOOK_LEG_MASS = "rho-inc"  # every leg of the study weighs what the paper's gradients weigh (+- 5 %)
BOOK_SCREENED = {"paper": 180, "quick": 27}  # trials screened per profile (any other: 27), in brackets of 9
BOOK_SAMPLER = "tpe"  # multi-objective TPE, the best of benchmarks/sampler.py's side-by-side runs
BOOK_SEED = 0
BOOK_GRADIENTS = ("rho-inc", "rho-dec", "PVC-Ti-SS", "SS-Ti-PVC")  # validated beside the front: the question's


@dataclass(frozen=True)
class BookStudy:
    """Chapter 9's study for one profile (:func:`book_study`).

    Attributes:
        space: the search space (per segment: density 0.9-20 g/cm^3, modulus 0.1-1000 GPa, log scales).
        objective: the objective and its constraints.
        racing: the rungs (:func:`~mat_hopper.optimize.default_racing`).
        screened: trials screened in all (a multiple of ``racing.screen``).
        brackets: finished brackets the study runs to (``screened // racing.screen``).
        sampler: the sampler's name (:data:`~mat_hopper.optimize.SAMPLERS`).
        seed: the sampler's seed.
        config: the :class:`~mat_hopper.optimize.StudyConfig`, named
            ``book-racing-ramp-<profile>-<digest>``.
    """

    space: SearchSpace
    objective: Objective
    racing: Racing
    screened: int
    brackets: int
    sampler: str
    seed: int
    config: StudyConfig


def book_study(profile) -> BookStudy:
    """Chapter 9's study under `profile` (module doc).

    Args:
        profile: the book's :class:`~mat_hopper.experiments.profiles.Profile`.

    Returns:
        A :class:`BookStudy`. Its study name is ``book-racing-ramp-<profile
        name>-<digest>``, the digest the first 8 hex digits of the SHA-256 of
        the JSON (keys sorted) of the space's, objective's and racing's keys,
        the sampler and the seed: other settings, another study.
    """
    space = SearchSpace()
    objective = Objective(
        behaviours=BOOK_BEHAVIOURS,
        profile=profile,
        replicates=DEFAULT_REPLICATES,
        risk="mean",
        leg_mass=BOOK_LEG_MASS,
    )
    racing = default_racing(objective)
    screened = BOOK_SCREENED.get(profile.name, 27)
    key = {"space": space.key(), "objective": objective.key(), "racing": racing.key(),
           "sampler": BOOK_SAMPLER, "seed": BOOK_SEED}  # fmt: skip
    digest = hashlib.sha256(json.dumps(key, sort_keys=True, default=str).encode()).hexdigest()[:8]
    config = StudyConfig(f"book-racing-ramp-{profile.name}-{digest}", space, objective)
    return BookStudy(space, objective, racing, screened, screened // racing.screen, BOOK_SAMPLER, BOOK_SEED, config)


def validated_legs(front) -> tuple[dict, dict]:
    """What chapter 9 validates: the front's new designs, then the paper's four gradients.

    Args:
        front: the study's Pareto table (:func:`~mat_hopper.optimize.pareto_frame`).

    Returns:
        ({name: LegDesign} of the front's new designs, ``#<trial>``, the
        paper's own left out: they are comparators; {name: LegDesign} of
        those and then the paper's gradients of :data:`BOOK_GRADIENTS`).
    """
    searched = front_designs(front)
    paper = paper_designs()
    return searched, {**searched, **{n: paper[n] for n in BOOK_GRADIENTS}}


def _finished_front(book: BookStudy, studies_dir) -> dict:
    """The front's new designs of the book's finished study in `studies_dir`, read-only (ValueError if not finished)."""
    name = book.config.name
    path = os.path.join(os.fspath(studies_dir), f"{name}.db")
    if not os.path.isfile(path):
        raise ValueError(f"no study {name!r}: {path} does not exist (build chapter 9 under this profile first)")
    storage = open_storage(default_url(name, os.fspath(studies_dir)), read_only=True)
    try:
        study = load_existing(name, storage)
        if study.user_attrs.get(CONFIG_ATTR) != book.config.key():
            raise ValueError(f"study {name!r} in {path} holds other settings than chapter 9's: not its study")
        done = closed_brackets(study)
        complete = len(study.get_trials(deepcopy=False, states=(TrialState.COMPLETE,)))
        if done < book.brackets or not complete:
            raise ValueError(
                f"study {name!r} is not finished: {done} of {book.brackets} brackets "
                f"({book.screened} trials screened), {complete} complete trials; finish chapter 9's build first "
                "(no trial is run here)"
            )
        front = pareto_frame(trials_frame(study, book.config), best=[t.number for t in study.best_trials])
    finally:
        dispose(storage)
    return front


def book_record_tables(studies_dir, cache_dir, profile, *, workers: int | None = None, allow_runs: bool = False):
    """Chapter 9's record tables from a finished build, by the chapter's own calls.

    Loads the book's study (:func:`book_study`) from `studies_dir`
    read-only, takes its front (:func:`~mat_hopper.optimize.trials_frame`,
    :func:`~mat_hopper.optimize.pareto_frame`, :func:`validated_legs`),
    validates it from the result cache
    (:func:`~mat_hopper.optimize.validate.validate_front`) and judges it
    under every domination rule (:func:`~mat_hopper.optimize.validate.record_tables`).

    Args:
        studies_dir: the build's study folder (``<root>/studies``).
        cache_dir: the build's result cache.
        profile: the build's :class:`~mat_hopper.experiments.profiles.Profile`.
        workers: the runner's processes, for runs not cached (only with `allow_runs`).
        allow_runs: run the validation runs the cache lacks (False: refuse,
            since a record is rebuilt from a build's own runs).

    Returns:
        (verdicts, paired): the ``optimizer-paper.csv`` and
        ``optimizer-paired-paper.csv`` tables
        (:data:`~mat_hopper.optimize.validate.RECORD_COLUMNS`,
        :data:`~mat_hopper.optimize.validate.PAIRED_RECORD_COLUMNS`; write
        them with ``float_format=validate.RECORD_FLOAT_FORMAT``, as the
        records are written).

    Raises:
        ValueError: no such study, a study of other settings or unfinished
            (fewer finished brackets than the profile's, or no complete
            trial), or, without `allow_runs`, validation runs missing from
            the cache (a cache of other code or settings).
    """
    book = book_study(profile)
    front = _finished_front(book, studies_dir)
    searched, legs = validated_legs(front)
    n = profile.replicates
    if not allow_runs:
        cache = Cache(cache_dir)
        tasks = validate.validation_tasks(legs, book.objective, n)
        missing = sum(t.key() not in cache for t in tasks)
        if missing:
            raise ValueError(
                f"{missing} of {len(tasks)} validation runs are not in the cache {cache.root} "
                "(another version of the code or settings?); pass allow_runs=True to run them"
            )
    checked = validate.validate_front(legs, book.objective, cache_dir=cache_dir, workers=workers)
    return validate.record_tables(checked, legs, book.objective, searched)
