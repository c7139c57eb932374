"""Run-size limits: every command's total work, estimated before it starts.

One rule for every command and every count option: a command adds up the
physics steps it would take (runs x steps per run; bisection tries at their
worst case) and refuses, in one line naming the size and the option, work
above :data:`MAX_TOTAL_STEPS`; every count option (``--workers``,
``--replicates``, ``--trials``, ...) is an integer in its documented range.

The limit, 2e10 physics steps, is about 28 core-hours at
:data:`SECONDS_PER_STEP` a step (one core, a 3-segment leg): six times the
paper profile's full reproduction under both conventions (about 3e9 steps). Set
``$MAT_HOPPER_MAX_STEPS`` to raise it, e.g. on a Dask cluster. A single run
has its own limits (:data:`mat_hopper.core.sim.MAX_STEPS`, 2e9 steps, and
:data:`mat_hopper.core.sim.MAX_SAMPLES`, 5e6 recorded samples), because one run
holds its records in memory.
"""

from __future__ import annotations

import math

MAX_TOTAL_STEPS = 20_000_000_000
LIMIT_ENV = "MAT_HOPPER_MAX_STEPS"
SECONDS_PER_STEP = 5e-6  # one core, a 3-segment leg (benchmarks/rollout.py): for the core-hours in messages
MAX_WORKERS = 256  # processes of one command on one machine
MAX_WORLDS = 65_536  # worlds in one MuJoCo Warp batch (--max-batch, --batch-size)
# Rows of a table path (mat_hopper.core.behaviours.Behaviour.from_function,
# from_samples): 80 MB of float64 (x, y), and as many Python calls of the
# user's function. At the default 1 ms a path of 5e6 rows lasts 5000 s, 80 times
# the paper's 60 s run (the path holds its last point after its end: a longer
# run can sample coarser). Same size as one run's recorded samples
# (mat_hopper.core.sim.MAX_SAMPLES).
MAX_PATH_SAMPLES = 5_000_000


def max_total_steps() -> float:
    """The limit in physics steps: ``$MAT_HOPPER_MAX_STEPS`` if set, else
    MAX_TOTAL_STEPS. Raises ValueError for a value that is not a finite
    number >= 1 (a limit below one step would refuse every command).

    Returns:
        The limit (float, physics steps): ``$MAT_HOPPER_MAX_STEPS`` read as
        an ASCII decimal, or ``MAX_TOTAL_STEPS`` (2e10) when it is not set.

    Raises:
        ValueError: ``$MAT_HOPPER_MAX_STEPS`` set but empty, not a finite
            ASCII decimal, or below 1 (:func:`mat_hopper.util.parsing.parse_number`
            with ``low=1``).
    """
    from .parsing import env_value, parse_number

    text = env_value(LIMIT_ENV, "a number of physics steps")
    if text is None:
        return float(MAX_TOTAL_STEPS)

    return parse_number(text, f"${LIMIT_ENV}", low=1.0)


def check_total_steps(steps: float, what: str, advice: str = "") -> float:
    """Refuse work above the limit, before any of it starts.

    Args:
        steps: physics steps the command would take in all.
        what: the options that set the size, as the user typed them
            (e.g. ``"--replicates 100000"``).
        advice: what to lower, appended to the message.

    Returns:
        steps, when within the limit.

    Raises:
        ValueError: one line naming `what`, the size and the limit.
    """
    limit = max_total_steps()
    if not math.isfinite(steps) or steps > limit:
        hours = steps * SECONDS_PER_STEP / 3600
        raise ValueError(
            f"{what}: about {steps:.2g} physics steps in all (~{hours:.3g} core-hours), above the limit of "
            f"{limit:.2g} (${LIMIT_ENV}){f'; {advice}' if advice else ''}"
        )
    return steps


def check_count(value, flag: str, low: int = 1, high: int | None = None, what: str = "") -> int | None:
    """A count option: an integer in [low, high] (None passes: the option's
    default). Raises ValueError naming `flag` and the accepted range.

    Args:
        value: the count: an int, or a float with a whole value; None passes.
        flag: the option named in the error (``--replicates``).
        low: the least value accepted (default 1).
        high: the greatest value accepted; None (the default) for no bound.
        what: what is counted, in parentheses in the error; default empty.

    Returns:
        `value` as an int, or None when `value` is None.

    Raises:
        ValueError: a bool, a value that is not an int or whole float, or
            one outside [low, high].
    """
    if value is None:
        return None
    ok = not isinstance(value, bool) and isinstance(value, int | float) and float(value).is_integer()
    rng = f">= {low}" if high is None else f"in [{low}, {high}]"
    if not ok or value < low or (high is not None and value > high):
        raise ValueError(f"{flag} must be an integer {rng}{f' ({what})' if what else ''}, got {value!r}")
    return int(value)


def check_workers(value, flag: str = "--workers") -> int | None:
    """Worker processes: an integer in [1, MAX_WORKERS] (None: the default).

    Args:
        value: the number of worker processes, or None (the command's
            default).
        flag: the option named in the error (default ``--workers``).

    Returns:
        `value` as an int, or None when `value` is None.

    Raises:
        ValueError: not an integer in [1, MAX_WORKERS] (256)
            (:func:`check_count`).
    """
    return check_count(value, flag, 1, MAX_WORKERS, "processes")


def task_steps(task) -> float:
    """Physics steps of one runner task, estimated before it runs.

    Args:
        task: a runner task: one with ``settings`` (a run) counts its
            ``settings.n_steps``; any other task counts what its own
            ``estimated_steps()`` says (a stable-time-step measurement:
            :meth:`mat_hopper.physics.stability.StabilitySpec.estimated_steps`).

    Returns:
        The estimated physics steps (float); 0.0 for a task that has
        neither.
    """
    settings = getattr(task, "settings", None)
    if settings is not None:
        return float(settings.n_steps)
    estimate = getattr(task, "estimated_steps", None)
    return float(estimate()) if callable(estimate) else 0.0
