"""Local process pools: how many workers, and how to stop one cleanly.

Leaf helpers shared by the grid runner (:mod:`mat_hopper.experiments.runner`)
and the CPU batch backend (:mod:`mat_hopper.batch`).
"""

from __future__ import annotations

import os
from concurrent.futures import ProcessPoolExecutor

__all__ = ["default_workers", "stop_pool"]


def stop_pool(pool: ProcessPoolExecutor, *, terminate: bool = False) -> None:
    """Stop a process pool after an interrupt (Ctrl-C, SIGTERM) or an error:
    the runs not started are cancelled, the workers stopped (at once with
    `terminate`, else when their run under way ends) and the pool joined.

    The pool cancels its queued futures itself (``shutdown(cancel_futures=True)``):
    never ``Future.cancel()`` from here. When a worker dies (killed by the
    same SIGTERM sent to the process group, or by `terminate`), the pool's
    manager thread sets BrokenProcessPool on every future it still holds;
    on CPython before 3.12 a future cancelled from outside makes that
    ``set_exception`` raise InvalidStateError in the thread, a traceback on
    stderr (python/cpython#107219, fixed in 3.12 by ignoring it). Cancelled
    by the manager thread, a future leaves its table first, so whichever of
    the shutdown and the broken pool it sees first, every future it then
    finishes is still pending or running, never already cancelled or done.

    Args:
        pool: the ProcessPoolExecutor (its futures may be pending, running or done).
        terminate: stop the workers now (SIGTERM) rather than let each finish its run.
    """
    processes = list((getattr(pool, "_processes", None) or {}).values()) if terminate else []
    for proc in processes:
        proc.terminate()
    pool.shutdown(wait=True, cancel_futures=True)


def default_workers() -> int:
    """All cores this process may use.

    Returns:
        The size of this process's CPU affinity set (``os.cpu_count()`` where
        affinity is not available), at least 1.
    """
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # pragma: no cover (not Linux)
        return max(1, os.cpu_count() or 1)
