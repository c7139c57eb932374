"""Warm start for the runner's worker processes (private).

The runner's forkserver imports this module once before it forks any
worker (nothing else imports it): the heavy imports (MuJoCo, numba's
compiled rollout loop from its on-disk cache, scipy, pyarrow) and one tiny
rollout happen here, and every worker forked afterwards starts with them
loaded. Nothing here may raise: a failed warm-up only means colder workers.

It also ties the processes' lives to the command's (Linux, prctl
PR_SET_PDEATHSIG): the fork server is killed when the command that started
it ends, and each worker when the fork server ends. So a command killed
outright (SIGKILL, out of memory) leaves no process behind; without this
they would wait forever, since every worker holds both ends of its task
queue and the fork server's keep-alive pipe. (The server dies with the
thread that started it, the one that first submitted work: the runner's
caller's. Should that thread end first, the next grid starts a new server
and pool.)
"""

import os
import signal
import sys


def _die_with_parent() -> None:
    """SIGKILL this process when its parent ends (Linux; elsewhere nothing)."""
    if not sys.platform.startswith("linux"):
        return
    try:
        import ctypes

        ctypes.CDLL(None, use_errno=True).prctl(1, signal.SIGKILL, 0, 0, 0)  # PR_SET_PDEATHSIG
    except (OSError, AttributeError):  # pragma: no cover
        pass


def _worker_dies_with_server(server: int) -> None:
    _die_with_parent()
    if os.getppid() != server:  # the server ended before the line above: end now
        os._exit(1)


try:
    _die_with_parent()
    os.register_at_fork(after_in_child=lambda server=os.getpid(): _worker_dies_with_server(server))
except Exception:  # pragma: no cover
    pass

try:
    import pyarrow.parquet  # noqa: F401

    from ..core.sim import SimSettings, simulate
    from ..physics import (
        stability,  # noqa: F401
    )

    simulate("MD", "static", settings=SimSettings(duration_s=0.002, timestep_s=1e-3, transient_s=0.0), warn=False)
except Exception:  # pragma: no cover
    pass
