"""A plan of the book's runs before any run (``mat-hopper plan``).

For a profile, every cached run each chapter of the book requests, in the
order of ``_toc.yml``: per chapter and task kind, its runs, how many of them
an earlier chapter already requested (the same cache key: computed once),
how many are in the result cache now, and their simulated seconds,
physics steps and time steps. Nothing is simulated: a task's key and its
physics steps (:func:`mat_hopper.util.limits.task_steps`) are known before
it runs. The replicates of one design, behaviour and settings under a
branching protocol (``branch``, ``branch-settled``) share the unperturbed
prefix up to their branch time, which the runner computes
once: the physics steps count it once per group and chapter
(:func:`mat_hopper.experiments.groups.unit_steps`; a pool with fewer than
two units of work per process halves groups, simulating a prefix again);
the simulated seconds are every run's whole duration.

The chapters (:data:`CHAPTERS`) build their runs with the very task builders
the notebooks' calls run: :func:`~mat_hopper.experiments.reproduce.experiment_tasks`
(``run_experiments``), :func:`~mat_hopper.experiments.controls.control_tasks`
(``run_controls``), :func:`~mat_hopper.experiments.convergence.tasks`
(``convergence.run``), :func:`~mat_hopper.experiments.crossed_legs.tasks`
(chapter 9c's crossed legs), the book checks' ``*_tasks`` of
:mod:`mat_hopper.experiments.paper`, and
:func:`~mat_hopper.experiments.runner.rollout_specs` (the tasks
:func:`~mat_hopper.experiments.runner.rollouts` runs). What a chapter passes them (its designs, behaviours, replicates) is
copied from its notebook, one entry per call.

Not counted here: cells that simulate outside the cache (``simulate``,
``RolloutRunner``, rendering, the batch backends) and grids a cell builds
itself; each chapter's ``uncounted`` names them. Chapter 9's optimizer
study and chapter 9c's codesign run in :mod:`mat_hopper.optimize`, a layer
above this one: :data:`CHAPTERS` names them (``in_optimize``), and
:func:`mat_hopper.optimize.book_plan.chapters` (what the command uses) gives
their runs: codesign's known runs as tasks, the runs whose designs or gains
a sampler picks as stated estimates (:class:`Estimate`).
"""

from __future__ import annotations

import math
import os
from collections.abc import Callable
from dataclasses import dataclass, replace

import pandas as pd

from ..util.limits import task_steps
from ..util.parsing import is_real
from . import controls, convergence, crossed_legs
from .groups import unit_steps
from .paper import axial_check_tasks, clock_tasks, convention_tasks, in_place_tasks, parse_experiments
from .profiles import get_profile
from .reproduce import experiment_tasks
from .runner import rollout_specs
from .stress_pairs import stress_pair_tasks

# Wall time of one physics step on one core, microseconds: measured 5.0-5.6
# us on one idle core for the 3-segment leg (benchmarks/rollout.py;
# mat_hopper.util.limits.SECONDS_PER_STEP rounds it to 5e-6 s for messages).
US_PER_STEP = 5.3
# The hop table, run summary and parquet write of a run: about 1.0 s of one
# core per 60 s simulated, on top of the physics steps.
POSTPROCESS_S_PER_SIMULATED_S = 1.0 / 60.0

COLUMNS = (
    "chapter",
    "kind",
    "counted",
    "runs",
    "shared_with_earlier",
    "cached",
    "simulated_s",
    "physics_steps",
    "timesteps",
    "new_simulated_s",
    "new_physics_steps",
    "to_compute",
    "to_compute_simulated_s",
    "to_compute_steps",
    "note",
)


@dataclass(frozen=True)
class Estimate:
    """Runs whose designs or settings are chosen while the chapter runs (a
    sampler's trials): counted, not keyed. Each run takes `settings` (its
    length and step); none is known to be shared or cached.

    Attributes:
        kind: the task kind the runs will be (``"trial-run"``, ``"run"``).
        runs: how many runs, at most.
        settings: the SimSettings of each run.
        note: how the count is made, for the plan's notes.
        physics_steps: the runs' physics steps where the runner shares
            their prefixes (stand-in tasks counted by
            :func:`~mat_hopper.experiments.groups.unit_steps`); None: every
            run whole, ``runs x settings.n_steps``.
    """

    kind: str
    runs: int
    settings: object
    note: str
    physics_steps: float | None = None

    def steps(self) -> float:
        """The runs' physics steps (see ``physics_steps``)."""
        return float(self.runs * self.settings.n_steps if self.physics_steps is None else self.physics_steps)


@dataclass(frozen=True)
class Chapter:
    """One notebook of the book: its name (as in ``_toc.yml``, without
    ``notebooks/``), its requests (functions of the Profile, each giving the
    tasks of one call, or :class:`Estimate`), what it runs that is not
    counted, and what it runs in :mod:`mat_hopper.optimize` (counted by
    :func:`mat_hopper.optimize.book_plan.chapters`, which clears it)."""

    name: str
    requests: tuple[Callable, ...] = ()
    uncounted: str = ""
    in_optimize: str = ""


def experiments(spec: str) -> Callable:
    """A chapter's ``reproduce.run_experiments(profile, spec)`` call.

    Args:
        spec: the experiments as the notebook names them (``"1,3,robustness"``).

    Returns:
        A function of the Profile giving the call's tasks (paper convention,
        the profile's replicates), every experiment's in order.
    """
    names = parse_experiments(spec)
    return lambda profile: [t for ts in experiment_tasks(profile, names).values() for t in ts]


def _contact_rollouts(p) -> list:
    """Chapter 8's contact diagnostics: 8 s at the physics rate."""
    diag = replace(p.sim_settings(), duration_s=8.0, transient_s=4.0)
    return rollout_specs(["MD", "SS", "rho-inc"], ["ramp"], diag, record_rate_hz=1.0 / diag.timestep_s)


_SERIES = ["MD", "SS", "rho-inc", "rho-dec", "PVC-Ti-SS", "SS-Ti-PVC"]
_OPTIMIZE = "runs in mat_hopper.optimize, counted by mat-hopper plan (mat_hopper.optimize.book_plan)"

CHAPTERS: tuple[Chapter, ...] = (
    Chapter("00-findings", (), "none: reads the records"),
    Chapter("01-introduction", (), "none"),
    Chapter("03-modelling-material", (), "none"),
    Chapter("04-hopper-controller", (), "uncached cells not counted: 2 simulate() runs, 1 rendered still"),
    Chapter("05-numerical-stability", (lambda p: convention_tasks(profile=p), experiments("stability"))),
    Chapter(
        "06-mono-materials",
        (experiments("1"), lambda p: rollout_specs(["MD", "SS"], ["forward"], p.sim_settings()), in_place_tasks),
        "not counted: the jerk filter study's RolloutRunner cells (uncached)",
    ),
    Chapter("07-one-property", (experiments("2"), experiments("1"), experiments("2-gibson-ashby"))),
    Chapter(
        "08-gradients",
        (
            experiments("3"),
            _contact_rollouts,
            lambda p: rollout_specs(_SERIES, ["forward", "ramp"], p.sim_settings(), record_rate_hz=250),
        ),
        "uncached cells not counted: gait tiles and a video (rendered rollouts)",
    ),
    Chapter(
        "08b-gradients-stress",
        (
            lambda p: stress_pair_tasks(p, ("paper",)),
            lambda p: stress_pair_tasks(p, ("bending",), one_step=False, replicates=p.figure_replicates),
        ),
        "not counted: RolloutRunner cells (uncached)",
    ),
    Chapter("09-optimizing-gradients", (), "", "the racing study and its validation"),
    Chapter(
        "09c-material-or-mass",
        (
            lambda p: controls.control_tasks(p),
            crossed_legs.tasks,
            lambda p: controls.push_scale_tasks(p),
            lambda p: controls.attribution_tasks(
                p, behaviours=("forward", "ramp") if p.name == "paper" else ("forward",)
            ),
            experiments("2"),
        ),
        "",
        "codesign (gains tuned per material)",
    ),
    Chapter(
        "10-reproduction-report",
        (
            experiments("1,2,3,stability,robustness,controls"),
            clock_tasks,
            axial_check_tasks,
        ),
    ),
    Chapter("11-robustness", (experiments("1,3,robustness"),)),
    Chapter("12-convergence", (convergence.tasks,), "uncached cells not counted: step_cost's timing runs"),
    Chapter("13-batch-backend", (), "uncached cells not counted: batch backends (their size depends on a GPU)"),
)


def cached_keys(cache_dir=None) -> set[str]:
    """Keys of the results in the cache folder, read without creating it.

    Args:
        cache_dir: the result cache folder (None: $MAT_HOPPER_CACHE, else
            ``results/cache``, as :class:`~mat_hopper.experiments.cache.Cache`).

    Returns:
        The keys of the complete results there (``<key>.parquet``, temp
        files left out); empty for a folder that does not exist.

    Raises:
        ValueError: $MAT_HOPPER_CACHE set but empty.
    """
    from ..util.atomic import TEMP_PREFIX
    from ..util.parsing import env_value
    from .cache import CACHE_ENV, DEFAULT_CACHE_DIR

    root = cache_dir or env_value(CACHE_ENV, "the result cache folder") or DEFAULT_CACHE_DIR
    if not os.path.isdir(root):
        return set()
    return {f[:-8] for f in os.listdir(root) if f.endswith(".parquet") and not f.startswith(TEMP_PREFIX)}


def _seconds(task) -> float:
    """Simulated seconds of a task: a run's duration; a stable-step search's
    tries at most (bisection tries and the reference scan's rungs)."""
    settings = getattr(task, "settings", None)
    if settings is not None:
        return float(settings.duration_s)
    from ..physics.stability import spec_ladder

    tries = task.max_iter + (len(spec_ladder()) if task.scan else 0)
    return float(tries * task.duration_s)


def _steps_text(task) -> str:
    settings = getattr(task, "settings", None)
    if settings is not None:
        return f"{settings.timestep_s:.3g}"
    return f"search {task.dt_min:.3g} to {task.dt_max:.3g}"


def _timesteps(tokens) -> str:
    """Distinct time steps (s), e.g. ``"0.0001"`` or ``"3 from 1.9e-06 to 0.0001"``."""
    tokens = sorted(set(tokens), key=lambda t: (t.startswith("search"), float(t) if t[0].isdigit() else 0.0))
    numbers = [t for t in tokens if not t.startswith("search")]
    searches = [t for t in tokens if t.startswith("search")]
    if len(numbers) > 2:
        numbers = [f"{len(numbers)} from {numbers[0]} to {numbers[-1]}"]
    return ", ".join(numbers + searches)


def _task_row(chapter: str, kind: str, tasks: list, seen: set, cached: set) -> dict:
    """One plan row: a chapter's distinct tasks of one kind."""
    new = [t for t in tasks if t.key() not in seen]
    todo = [t for t in new if t.key() not in cached]
    bound = any(getattr(t, "settings", None) is None for t in tasks)
    return {
        "chapter": chapter,
        "kind": kind,
        "counted": "upper bound" if bound else "exact",
        "runs": len(tasks),
        "shared_with_earlier": len(tasks) - len(new),
        "cached": sum(t.key() in cached for t in tasks),
        "simulated_s": sum(map(_seconds, tasks)),
        "physics_steps": unit_steps(tasks),
        "timesteps": _timesteps(_steps_text(t) for t in tasks),
        "new_simulated_s": sum(map(_seconds, new)),
        "new_physics_steps": unit_steps(new),
        "to_compute": len(todo),
        "to_compute_simulated_s": sum(map(_seconds, todo)),
        "to_compute_steps": unit_steps(todo),
        "note": "stable-step searches: their tries at most" if bound else "",
    }


def _estimate_row(chapter: str, e: Estimate) -> dict:
    """One plan row of an :class:`Estimate`: every run new and to compute."""
    seconds = e.runs * float(e.settings.duration_s)
    steps = e.steps()
    return {
        "chapter": chapter,
        "kind": e.kind,
        "counted": "estimate",
        "runs": e.runs,
        "shared_with_earlier": 0,
        "cached": 0,
        "simulated_s": seconds,
        "physics_steps": steps,
        "timesteps": f"{e.settings.timestep_s:.3g}",
        "new_simulated_s": seconds,
        "new_physics_steps": steps,
        "to_compute": e.runs,
        "to_compute_simulated_s": seconds,
        "to_compute_steps": steps,
        "note": e.note,
    }


def _chapter_rows(chapter: Chapter, profile, seen: set, cached: set) -> list[dict]:
    """A chapter's rows (one per task kind, then its estimates); `seen` gains its keys."""
    distinct: dict[str, dict] = {}  # kind -> {key: task}, in request order
    estimates = []
    for request in chapter.requests:
        for t in request(profile):
            if isinstance(t, Estimate):
                estimates.append(t)
            else:
                distinct.setdefault(t.kind, {}).setdefault(t.key(), t)
    rows = [_task_row(chapter.name, kind, list(ts.values()), seen, cached) for kind, ts in distinct.items()]
    rows += [_estimate_row(chapter.name, e) for e in estimates]
    for ts in distinct.values():
        seen.update(ts)
    if not rows:
        rows = [{**dict.fromkeys(COLUMNS, 0), "chapter": chapter.name, "kind": "-", "counted": "none", "timesteps": ""}]
        rows[0]["note"] = ""
    upper = f"{chapter.in_optimize} {_OPTIMIZE}" if chapter.in_optimize else ""
    rows[-1]["note"] = "; ".join(n for n in (rows[-1]["note"], chapter.uncounted, upper) if n)
    return rows


def plan(profile, cache_dir=None, chapters=None) -> pd.DataFrame:
    """Every cached run each chapter requests, counted and looked up in the
    cache, nothing run.

    Args:
        profile: a Profile or its name (``paper``, ``quick``).
        cache_dir: the result cache folder (None: $MAT_HOPPER_CACHE, else
            ``results/cache``); read only, never created.
        chapters: the registry (None: :data:`CHAPTERS`, the runs of
            :mod:`mat_hopper.optimize` in chapters 9 and 9c named, not counted;
            :func:`mat_hopper.optimize.book_plan.chapters` counts them).

    Returns:
        DataFrame, one row per chapter and task kind, in the registry's order
        (a chapter without counted runs: one row of kind ``-``), columns
        :data:`COLUMNS`: runs (distinct keys), shared_with_earlier (of them,
        requested by an earlier chapter), cached (of them, in the cache),
        simulated_s (s), physics_steps, timesteps (the distinct physics steps,
        s), the ``new_*`` sums over the runs no earlier chapter requested, the
        ``to_compute*`` ones over those also not cached, counted (``exact``,
        ``upper bound`` or ``estimate``) and note.

    Raises:
        ValueError: an unknown profile, or $MAT_HOPPER_CACHE set but empty.
    """
    prof = get_profile(profile)
    cached = cached_keys(cache_dir)
    seen: set[str] = set()
    rows = [r for ch in (CHAPTERS if chapters is None else chapters) for r in _chapter_rows(ch, prof, seen, cached)]
    return pd.DataFrame(rows, columns=list(COLUMNS))


def book_tasks(profile, chapters=None) -> list:
    """Every cached run the book's chapters request that is known before
    any run, each once, longest first: what ``mat-hopper plan --run``
    computes into the cache before the notebooks execute, in one pool (a
    notebook then reads its runs from the cache). Runs a sampler picks
    (:class:`Estimate`) are left out: they are known only while their
    chapter runs.

    Args:
        profile: a Profile or its name.
        chapters: the registry (None: :data:`CHAPTERS`).

    Returns:
        list of runner tasks, distinct cache keys, sorted by their physics
        steps (:func:`mat_hopper.util.limits.task_steps`), largest first.

    Raises:
        ValueError: an unknown profile.
    """
    prof = get_profile(profile)
    tasks: dict[str, object] = {}
    for chapter in CHAPTERS if chapters is None else chapters:
        for request in chapter.requests:
            for t in request(prof):
                if not isinstance(t, Estimate):
                    tasks.setdefault(t.key(), t)
    return sorted(tasks.values(), key=lambda t: -task_steps(t))


def core_hours(physics_steps: float, simulated_s: float, us_per_step: float = US_PER_STEP) -> float:
    """Core-hours of runs: their physics steps at `us_per_step`, plus the
    post-processing (:data:`POSTPROCESS_S_PER_SIMULATED_S`).

    Args:
        physics_steps: physics steps in all.
        simulated_s: simulated seconds in all (s).
        us_per_step: wall time of one physics step on one core, microseconds.

    Returns:
        The estimate, hours of one core.
    """
    return (physics_steps * us_per_step * 1e-6 + simulated_s * POSTPROCESS_S_PER_SIMULATED_S) / 3600.0


def format_plan(table: pd.DataFrame, us_per_step: float = US_PER_STEP) -> str:
    """The plan as text: the table, the notes, what is left to compute, and
    the total (a run shared by chapters counted once).

    Args:
        table: :func:`plan`'s table.
        us_per_step: wall time of one physics step on one core, microseconds
            (> 0; default :data:`US_PER_STEP`).

    Returns:
        Lines of text; the last ``total: <runs> runs, <steps> physics steps,
        <hours> core-hours (estimated)`` (steps as %.3g).

    Raises:
        ValueError: `us_per_step` not a finite number > 0.
    """
    if not (is_real(us_per_step) and math.isfinite(us_per_step) and us_per_step > 0):
        raise ValueError(f"us_per_step must be a finite number > 0 (microseconds), got {us_per_step!r}")
    shown = table[["chapter", "kind", "counted", "runs", "shared_with_earlier", "cached"]].copy()
    shown["simulated_s"] = table["simulated_s"].map(lambda v: f"{v:.4g}")
    shown["physics_steps"] = table["physics_steps"].map(lambda v: f"{v:.3g}")
    shown["timesteps"] = table["timesteps"]
    lines = [shown.rename(columns={"shared_with_earlier": "shared"}).to_string(index=False)]
    notes = [f"  {r.chapter} ({r.kind}): {r.note}" for r in table.itertuples() if r.note]
    if notes:
        lines += ["notes:", *notes]
    total = table["runs"].sum() - table["shared_with_earlier"].sum()
    steps, seconds = table["new_physics_steps"].sum(), table["new_simulated_s"].sum()
    todo, todo_steps = table["to_compute"].sum(), table["to_compute_steps"].sum()
    todo_h = core_hours(todo_steps, table["to_compute_simulated_s"].sum(), us_per_step)
    lines.append(
        f"estimate: {us_per_step:g} us per physics step on one core (measured on the project's 2-core VM, "
        f"benchmarks/rollout.py), plus {POSTPROCESS_S_PER_SIMULATED_S * 60:.1f} s per 60 s simulated"
    )
    lines.append(f"not in the cache: {todo} runs, {todo_steps:.3g} physics steps, {todo_h:.3g} core-hours (estimated)")
    hours = core_hours(steps, seconds, us_per_step)
    lines.append(
        "the totals: each cache key once (runs less shared); exact counts, upper bounds and estimates added as "
        "the counted column says, so a total is itself an estimate, neither exact nor a bound; core-hours divided "
        "by the cores give the wall time at best, before the notebooks' own cells"
    )
    lines.append(f"total: {total} runs, {steps:.3g} physics steps, {hours:.3g} core-hours (estimated)")
    return "\n".join(lines)
