"""Runs that share a prefix, computed once: the runner's unit of work.

Under a branching replicate protocol (``branch``, ``branch-settled``:
:mod:`mat_hopper.core.replicates`) every replicate of one design, behaviour
and settings runs unperturbed up to its branch time (``transient_s``, or
half of it), exactly as the unperturbed run does. A grid's runs
(``kind == "run"``, :class:`mat_hopper.experiments.runner.RunSpec`) that
differ only in their perturbation therefore form one *group*: one worker
process simulates the prefix once and forks it for each run
(:meth:`mat_hopper.core.sim.RolloutRunner.fork_as`), and each run's result is
its own, under its own key, bit-identical to the run computed alone
(tests/experiments/test_prefix_groups.py). The paper profile's 60 s runs
with a 20 s transient save 20 s of every replicate but one under ``branch``:
with the unperturbed run and 10 replicates, 11 x 60 s become 20 + 11 x 40 s,
30 % fewer physics steps (10 replicates alone, 27 %); under
``branch-settled`` 10 s of each, 15 %.

A unit is one task or one group (halved where a grid has too few units to
keep its processes busy, :func:`prefix_units`); :func:`execute_unit` is the
worker's entry and never raises (a failed task, or a failed prefix for every run of its
group, is an error text: a ``failed`` row).
"""

from __future__ import annotations

import traceback
from dataclasses import replace

from ..core.replicates import branch_step, branch_time_s, is_branching
from ..core.sim import RolloutRunner, route_mujoco_warnings
from ..util.keys import design_key, hash_key, settings_key
from ..util.limits import task_steps

__all__ = [
    "UNITS_PER_WORKER",
    "execute_unit",
    "iter_unit",
    "prefix_key",
    "prefix_units",
    "shared_prefix_steps",
    "unit_steps",
]

# Units of work per process at least, where groups can be halved to give them
# (prefix_units): the pool's makespan against the prefixes simulated again.
UNITS_PER_WORKER = 2


def prefix_key(task) -> str | None:
    """What a task's unperturbed prefix depends on, or None for a task that
    shares none.

    Args:
        task: a runner task.

    Returns:
        For a run (``kind == "run"``) under a branching ``replicate_protocol``
        (``branch``, ``branch-settled``):
        a hash of its design (the physics and its repr), behaviour and
        settings without the perturbation; None for any other task.
    """
    settings = getattr(task, "settings", None)
    if getattr(task, "kind", None) != "run" or not is_branching(getattr(settings, "replicate_protocol", None)):
        return None
    return hash_key(
        {
            "design": design_key(task.design),
            "design_repr": repr(task.design),
            "behaviour": task.behaviour.key(),
            "behaviour_repr": repr(task.behaviour),
            "settings": settings_key(replace(settings, perturbation=None)),
        }
    )


def prefix_units(keys, tasks: dict, workers: int | None = None) -> list[tuple[str, ...]]:
    """The units of work of `keys`: each group of runs sharing a prefix, and
    every other task alone, the largest units first.

    Args:
        keys: task keys (distinct), in the order to keep among equals.
        tasks: key -> task.
        workers: the processes that will run the units (None or 1: no
            split). Fewer than :data:`UNITS_PER_WORKER` units per process
            would leave processes idle while one computes a whole group: the
            largest groups are then halved (each half simulating the prefix
            again) until there are that many units or none can be halved.

    Returns:
        list of tuples of keys: a group's keys in the order given; sorted by
        the unit's physics steps (:func:`unit_steps`), largest first (a long
        unit started last would finish alone).
    """
    units: dict = {}
    for k in keys:
        group = prefix_key(tasks[k])
        units.setdefault(k if group is None else ("group", group), []).append(k)
    out = [tuple(u) for u in units.values()]
    if workers is not None and workers > 1:
        out = _split(out, tasks, UNITS_PER_WORKER * workers)
    return sorted(out, key=lambda u: -unit_steps([tasks[k] for k in u]))


def _split(units: list, tasks: dict, target: int) -> list:
    """Halve the largest group (by physics steps) until there are `target` units or none has 2 runs."""
    units = list(units)
    while len(units) < target:
        groups = [u for u in units if len(u) > 1]
        if not groups:
            break
        big = max(groups, key=lambda u: unit_steps([tasks[k] for k in u]))
        i, half = units.index(big), (len(big) + 1) // 2
        units[i : i + 1] = [big[:half], big[half:]]
    return units


def shared_prefix_steps(tasks) -> float:
    """Physics steps that computing each group's prefix once saves.

    Args:
        tasks: runner tasks (distinct keys).

    Returns:
        Over every group of n > 1 runs sharing a prefix: (n - 1) x the
        prefix's steps (:func:`mat_hopper.core.replicates.branch_step`); 0.0
        without groups.
    """
    counts: dict = {}
    for t in tasks:
        group = prefix_key(t)
        if group is not None:
            n, steps = counts.get(group, (0, 0))
            counts[group] = (n + 1, branch_step(branch_time_s(t.settings), t.settings.timestep_s))
    return float(sum((n - 1) * steps for n, steps in counts.values()))


def unit_steps(tasks) -> float:
    """Physics steps of runner tasks computed as the runner does, each
    shared prefix once.

    Args:
        tasks: runner tasks (distinct keys): a unit, a grid, a plan row's.

    Returns:
        Their physics steps (:func:`mat_hopper.util.limits.task_steps`) less
        the prefixes they share (:func:`shared_prefix_steps`).
    """
    return sum(map(task_steps, tasks)) - shared_prefix_steps(tasks)


def _error(e: Exception) -> str:
    return traceback.format_exception_only(type(e), e)[-1].strip()


def execute_unit(tasks) -> list[tuple]:
    """Worker entry: compute a unit (one task, or a group of runs sharing a
    prefix). Never raises. MuJoCo's warnings go to logging (a diverging run
    is a result, not a message on stderr nor a MUJOCO_LOG.TXT in the
    working folder).

    Args:
        tasks: the unit's tasks: one task, or runs of one :func:`prefix_key`.

    Returns:
        ``list(iter_unit(tasks))``: one (key, table, summary, error text) per task, in order.
    """
    return list(iter_unit(tasks))


def iter_unit(tasks):
    """Compute a unit's tasks one by one (:func:`execute_unit`), so that a
    caller in this process stores each result as it comes (a run killed
    part-way through a group keeps the replicates it finished).

    Args:
        tasks: one task, or runs of one :func:`prefix_key`.

    Yields:
        (key, table, summary, None) of each task's ``compute()`` (a group's
        runs: of its ``summarize(rollout)`` on its fork), or (key, None,
        None, error text), in order; a failed prefix fails every run of
        its group.
    """
    route_mujoco_warnings()
    tasks = list(tasks)
    keys = [t.key() for t in tasks]
    if len(tasks) == 1:
        try:
            yield (keys[0], *tasks[0].compute(), None)
        except Exception as e:  # a failed row, not a crashed grid
            yield (keys[0], None, None, _error(e))
        return
    if len({prefix_key(t) for t in tasks} - {None}) != 1 or prefix_key(tasks[0]) is None:
        yield from ((k, None, None, "a group's runs must share one branch prefix") for k in keys)
        return
    first = tasks[0]
    try:
        base = RolloutRunner(first.design, first.behaviour, replace(first.settings, perturbation=None))
        base.advance(branch_step(branch_time_s(first.settings), first.settings.timestep_s))
    except Exception as e:
        yield from ((k, None, None, f"the shared prefix failed: {_error(e)}") for k in keys)
        return
    for k, t in zip(keys, tasks):
        try:
            got = (k, *t.summarize(base.fork_as(t.settings).advance().result()), None)
        except Exception as e:
            got = (k, None, None, _error(e))
        yield got
