"""Chapter 9's optimizer study and chapter 9c's codesign in the plan of the
book's runs (``mat-hopper plan``).

:mod:`mat_hopper.experiments.plan` counts every run the experiments build;
these two run in this layer, above it, so their part is here and
:func:`chapters` assembles the whole registry.

- Chapter 9 (the racing study of gradients, then its validation): the
  sampler picks every trial's design, so its runs are an *estimate*, an
  upper bound: per bracket the screen's trials on the screen rung and the
  promoted third (:meth:`Racing.kept`) at full fidelity, each with the
  objective's replicates and behaviours (trials outside the leg-mass band
  are not run; a rung whose trials fall promotes fewer). The validation
  of the study's front (:mod:`mat_hopper.optimize.validate`): the paper's
  gradients' and designs' runs as tasks, the front's new designs as an
  estimate (:func:`validation_requests`). The study's settings (behaviour, replicates,
  leg-mass target, trials screened) are :func:`~mat_hopper.optimize.book_study`'s,
  which the notebook runs.
- Chapter 9c's codesign (:func:`mat_hopper.optimize.codesign.codesign`): the runs
  known before it runs are tasks (each design's first tuning trial at the
  authors' gains, and the comparison at the authors' gains:
  :func:`~mat_hopper.optimize.codesign.tuning_task`,
  :func:`~mat_hopper.optimize.codesign.comparison_tasks`, what codesign
  itself runs); the other tuning trials and the comparison at the tuned
  gains are counted exactly in number and length (the gains change neither)
  as estimates, their keys unknown.
"""

from __future__ import annotations

from dataclasses import replace

from ..core.behaviours import behaviour as get_behaviour
from ..core.materials import MONO_NAMES, LegDesign, paper_designs, parse_design
from ..experiments.groups import unit_steps
from ..experiments.plan import CHAPTERS, Chapter, Estimate
from . import codesign as cd
from ._book_study import BOOK_GRADIENTS, BOOK_LEG_MASS, book_study
from ._scoring import perturbations
from ._validate_checks import validation_tasks


def racing_estimate(profile) -> list[Estimate]:
    """Chapter 9's racing study, counted before it runs (module doc).

    Args:
        profile: the book's Profile.

    Returns:
        One :class:`~mat_hopper.experiments.plan.Estimate` per rung: its
        trials' runs at most (trials x replicates x behaviours) at the rung's
        run length.
    """
    book = book_study(profile)
    objective, racing, brackets = book.objective, book.racing, book.brackets
    leg = paper_designs()[BOOK_LEG_MASS]
    out, trials = [], racing.screen
    for r in range(len(racing.rungs)):
        ob = racing.objective_at(objective, r)
        runs = brackets * trials * len(perturbations(ob.replicates, ob.profile.scored_window_s)) * len(ob.behaviours)
        note = (
            f"estimate (upper bound): {brackets} brackets x {trials} trials on rung {r}, "
            f"{ob.replicates} replicates; designs picked by the sampler"
        )
        out.append(Estimate("trial-run", runs, ob.sim_settings(design=leg), note))
        trials = racing.kept(trials)
    return out


# The front's new designs that the plan counts for chapter 9's validation:
# the front is the sampler's, known only once the study has run; the paper
# book's recorded build validated 8 (book/records/optimizer-paper.csv).
EXPECTED_FRONT = 8


def validation_requests(profile) -> list:
    """Chapter 9's validation of the study's front (:func:`~mat_hopper.optimize.validate.validate_front`
    of :func:`~mat_hopper.optimize.validated_legs`), counted before the study runs.

    The paper's four gradients and the paper designs they are compared
    with are validated whatever the front: their runs are tasks
    (:func:`~mat_hopper.optimize.validate.validation_tasks`, what the
    validation itself runs, so shared runs and the cache count). The front's
    new designs are the sampler's: :data:`EXPECTED_FRONT` stand-ins (ρ-inc's
    leg with its densities scaled by 1.01, 1.02, ...: graded, so each has the
    controls a new gradient gets) give estimates, one per physics step.

    Args:
        profile: the book's Profile.

    Returns:
        list of RunSpec (the gradients' and paper designs' validation runs)
        and :class:`~mat_hopper.experiments.plan.Estimate` (the front's).
    """
    book = book_study(profile)
    designs = paper_designs()
    known = validation_tasks({n: designs[n] for n in BOOK_GRADIENTS}, book.objective, profile.replicates)
    base = designs[BOOK_LEG_MASS]
    stand_ins = {
        f"#front-{i}": LegDesign.from_properties(
            [d * (1 + 0.01 * i) for d in base.densities_g_cm3], base.moduli_gpa, name=f"#front-{i}"
        )
        for i in range(1, EXPECTED_FRONT + 1)
    }
    front = validation_tasks(stand_ins, book.objective, profile.replicates, paper={})
    by_step: dict[tuple, list] = {}
    for t in front:
        by_step.setdefault((t.settings.timestep_s, t.settings.duration_s), []).append(t)
    note = (
        f"estimate: the validation of {EXPECTED_FRONT} new front designs (the front is the sampler's; "
        "the recorded paper build's had 8), their checks and controls"
    )
    notes = [note] + ["the same validation's runs at another physics step"] * (len(by_step) - 1)
    # the stand-ins' replicates share prefixes as the front's will (a branching protocol): counted as the runner runs them
    return known + [
        Estimate("run", len(ts), ts[0].settings, n, physics_steps=unit_steps(ts))
        for ts, n in zip(by_step.values(), notes)
    ]


def codesign_requests(profile) -> list:
    """Chapter 9c's codesign runs: tasks where known, estimates where the sampler picks (module doc).

    Args:
        profile: the book's Profile.

    Returns:
        list of RunSpec (the first tuning trial per design, the comparison at
        the authors' gains) and :class:`~mat_hopper.experiments.plan.Estimate`
        (the other tuning trials, the comparison at the tuned gains).
    """
    legs = {n: parse_design(n) for n in MONO_NAMES}
    beh = get_behaviour(cd.BEHAVIOUR)
    n = profile.replicates
    out = [cd.tuning_task(leg, beh, profile, cd.authors_gains(), 0) for leg in legs.values()]
    out += cd.comparison_tasks(legs, profile, beh, n)
    screen = cd.screen_profile(profile).sim_settings(design=legs[cd.BASELINE])
    note = f"tuning trials 1-{cd.TRIALS - 1} per design (gains sampled; screening runs)"
    out.append(Estimate("run", len(legs) * (cd.TRIALS - 1), screen, note))
    settings = profile.sim_settings(design=legs[cd.BASELINE])
    out.append(Estimate("run", len(legs) * n, settings, "comparison at the tuned gains (known after tuning)"))
    return out


def chapters() -> tuple[Chapter, ...]:
    """The whole registry of the book's chapters: :data:`mat_hopper.experiments.plan.CHAPTERS`
    with chapter 9's study and chapter 9c's codesign counted here.

    Returns:
        tuple of :class:`~mat_hopper.experiments.plan.Chapter`, in ``_toc.yml`` order.
    """
    own = {
        "09-optimizing-gradients": (racing_estimate, validation_requests),
        "09c-material-or-mass": (codesign_requests,),
    }
    return tuple(
        replace(ch, requests=ch.requests + own[ch.name], in_optimize="") if ch.name in own else ch for ch in CHAPTERS
    )
