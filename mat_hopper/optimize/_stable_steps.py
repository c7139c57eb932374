"""A study's time step against its designs' stable steps: the warning
before any run, and the advice a study that met divergences ends with.

A study's runs take its profile's step under its convention
(:meth:`mat_hopper.experiments.profiles.Profile.for_convention`): under
``paper`` the profile's step (the authors' 1e-4 s unless ``optimize
--timestep`` set it, ``auto`` included), under ``axial``, ``bending`` and
``axial+bending`` the automatic one (``timestep_s="auto"``). So the
advice for a leg above its bound names what the study offers: a new
study at ``--timestep auto`` (each trial's design its own substeps),
fewer ``--segments`` (a shorter segment is a stiffer spring on a lighter
mass, whose stable step is smaller), or a convention whose step is
automatic. A search is expected to meet designs that diverge: they are
infeasible trials, counted at the end, and the study still exits 0 when
it reaches its target.
"""

from __future__ import annotations

import re

from ..core.timestep import is_auto, stable_step_excess

# What a study offers instead of a step it cannot change (module doc).
FIXED_STEP_ADVICE = (
    "the study runs a fixed {dt:g} s step; try a new study with --timestep auto (each design its own physics "
    "substeps), fewer --segments, or --convention axial (or bending), whose runs take the automatic step"
)
AUTO_WORDS = "the automatic step"  # how a study names --timestep auto
AUTO_STEP_ADVICE = "the automatic step of --convention {convention} does not hold it; try fewer --segments"


def _advice(objective) -> str:
    profile = objective.profile.for_convention(objective.convention)
    if is_auto(profile.timestep_s):
        return AUTO_STEP_ADVICE.format(convention=objective.convention)
    return FIXED_STEP_ADVICE.format(dt=float(profile.timestep_s))


def queued_step_warnings(config, queued, trials: int | None = None) -> list[str]:
    """One line per queued design whose run lies above its analytic stable
    step (:func:`mat_hopper.core.timestep.stable_step_excess`), before any
    run: what lies above which bound, that its runs may diverge, and what
    the study offers instead (module doc).

    Args:
        config: the study's :class:`~mat_hopper.optimize._study.StudyConfig`.
        queued: the designs the study enqueues, as (name, params)
            (:func:`~mat_hopper.optimize._mass.queued_seeds`' first list).
        trials: the study's size; only the first `trials` queued designs run
            (None: all).

    Returns:
        The lines (empty when every queued design is within its bounds).
    """
    ob, space = config.objective, config.space
    lines = []
    for name, params in list(queued)[: None if trials is None else int(trials)]:
        design = space.design(params, name=name)
        excess = stable_step_excess(design, ob.sim_settings(design=design))
        if excess:
            lines.append(f"queued design {name}: {excess}: its runs may diverge; {_advice(ob)}")
    return lines


def divergence_advice(feasibility, config) -> str | None:
    """The line a study ends with when some of its trials diverged: how
    many (finished, and stopped by racing on a screening rung) and what to
    try (module doc).

    Args:
        feasibility: the study's :class:`~mat_hopper.optimize._feasibility.Feasibility`.
        config: its :class:`~mat_hopper.optimize._study.StudyConfig`.

    Returns:
        The line, or None when no trial diverged.
    """
    if feasibility is None:
        return None
    done = int(feasibility.reasons.get("diverged", 0))
    pruned = int(getattr(feasibility, "pruned_reasons", {}).get("diverged", 0))
    if not done + pruned:
        return None
    where = f"{done} of {feasibility.finished} finished trials" if done else ""
    if pruned:
        where += f"{' and ' if done else ''}{pruned} on a screening rung (stopped there by racing)"
    return (
        f"diverged: {where} (infeasible, kept in the study: a search meets such designs, and the study "
        f"exits 0 when it reaches its target); {_advice(config.objective)}"
    )


def diverged_run_message(design, objective, row: dict) -> str | None:
    """Why one of a replayed trial's runs diverged, in one line: when, which
    check, the step above the leg's analytic bound where it is
    (:meth:`mat_hopper.core.rollout.Rollout.divergence_message`), and what a
    study offers to try (module doc). The run is made again to the
    divergence (it stops there: a short run).

    Args:
        design: the trial's LegDesign.
        objective: the study's :class:`~mat_hopper.optimize._objective.Objective`.
        row: the run's row of the replay's Evaluation (``behaviour``,
            ``replicate``: the perturbation's seed, -1 for none).

    Returns:
        The line, or None when the run did not diverge.
    """
    from ..core.perturbations import Perturbation
    from ..core.sim import simulate

    seed = int(row.get("replicate", -1) if row.get("replicate") is not None else -1)
    pert = Perturbation.replicate(seed, objective.profile.scored_window_s) if seed >= 0 else None
    rollout = simulate(design, row["behaviour"], settings=objective.sim_settings(pert, design=design), warn=False)
    message = rollout.divergence_message(AUTO_WORDS)
    if message is None:
        return None
    message = re.sub(rf"try {AUTO_WORDS} \((.*)\)$", rf"{AUTO_WORDS} would take \1", message)
    return f"{message}; {_advice(objective)}"
