"""The optimizer's processes (private): how worker processes start, die
with their coordinator, and how SIGTERM and SIGHUP stop a run the way
Ctrl-C does. :mod:`mat_hopper.optimize._study` uses them.
"""

from __future__ import annotations

import multiprocessing as mp
import os
import signal
import sys
import threading
from contextlib import contextmanager


def _orphaned(parent: int) -> bool:
    return os.getppid() != parent


def _die_with_parent() -> None:
    """Linux: SIGTERM this worker when its coordinator dies, even by
    SIGKILL (prctl PR_SET_PDEATHSIG), so that no worker runs on orphaned;
    its trial is failed and re-queued by the next run (or the heartbeat)."""
    if not sys.platform.startswith("linux"):
        return
    try:
        import ctypes

        libc = ctypes.CDLL(None, use_errno=True)
        libc.prctl(1, signal.SIGTERM, 0, 0, 0)  # PR_SET_PDEATHSIG
    except (OSError, AttributeError):
        pass


def _start_method() -> str:
    """fork when this process has no other thread (workers start at once,
    with everything imported; they never touch the parent's connections and
    open their own storage); else spawn, which re-imports MuJoCo, numba and
    Optuna in every worker (seconds) but is safe beside threads."""
    if "fork" in mp.get_all_start_methods() and threading.active_count() == 1:
        return "fork"
    return "spawn"


def _warm_up() -> None:
    """Load the compiled rollout (numba's on-disk cache, about 0.6 s) once
    here, so that forked workers start with it."""
    from ..sim import SimSettings, simulate

    simulate("SS", "static", settings=SimSettings(duration_s=0.002, timestep_s=1e-3, transient_s=0.0))


class HeldSignals:
    """Hold signals back over a short critical section: one that arrives
    inside it is recorded, and delivered again (``signal.raise_signal``,
    with the handlers from before) at :meth:`release` or at the block's end,
    whichever comes first. Used where a trial exists in the storage but
    does not yet name its worker: a process stopped there would leave a
    RUNNING trial that no one can tell is dead.

    Python-level handlers, not a thread's signal mask: Python runs handlers
    in the main thread whatever thread the kernel chose, so this holds in a
    process with threads too. Outside the main thread it does nothing.

    >>> import signal
    >>> got = []
    >>> before = signal.signal(signal.SIGUSR1, lambda signum, frame: got.append("delivered"))
    >>> with HeldSignals(signal.SIGUSR1) as held:
    ...     signal.raise_signal(signal.SIGUSR1)  # recorded, not delivered
    ...     got, held.pending
    ([], [<Signals.SIGUSR1: 10>])
    >>> got  # delivered at the block's end, to the handler from before
    ['delivered']
    >>> _ = signal.signal(signal.SIGUSR1, before)
    """

    def __init__(self, *signals: int):
        self.signals = tuple(signals)
        self.pending: list[signal.Signals] = []
        self._old: dict = {}

    def _hold(self, signum, frame):
        self.pending.append(signal.Signals(signum))

    def __enter__(self) -> HeldSignals:
        if threading.current_thread() is threading.main_thread():
            self._old = {sig: signal.signal(sig, self._hold) for sig in self.signals}
        return self

    def release(self) -> None:
        """Restore the handlers, then deliver what came meanwhile (which may
        raise, or end the process at a default action)."""
        old, self._old = self._old, {}
        for sig, handler in old.items():
            signal.signal(sig, handler)
        pending, self.pending = self.pending, []
        for sig in dict.fromkeys(pending):
            signal.raise_signal(sig)

    def __exit__(self, *exc) -> None:
        self.release()


class Interrupted(KeyboardInterrupt):
    """SIGTERM or SIGHUP, handled like Ctrl-C (KeyboardInterrupt): the
    coordinator stops its workers, fails and re-queues their trials."""

    def __init__(self, signum: int):
        super().__init__(signal.Signals(signum).name)
        self.signal_number = int(signum)
        self.signal_name = signal.Signals(signum).name


@contextmanager
def stop_signals():
    """A context in which SIGTERM and SIGHUP stop the program as Ctrl-C does.

    In the main thread the previous handlers are restored when the block
    ends; elsewhere it does nothing (Python delivers signals to the main
    thread only).

    Raises:
        Interrupted: (a KeyboardInterrupt) on SIGTERM or SIGHUP inside the block.
    """
    if threading.current_thread() is not threading.main_thread():
        yield
        return

    def handler(signum, frame):
        raise Interrupted(signum)

    old = {sig: signal.signal(sig, handler) for sig in (signal.SIGTERM, signal.SIGHUP)}
    try:
        yield
    finally:
        for sig, h in old.items():
            signal.signal(sig, h)


@contextmanager
def _signals_ignored():
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    sigs = (signal.SIGINT, signal.SIGTERM, signal.SIGHUP)
    old = {sig: signal.signal(sig, signal.SIG_IGN) for sig in sigs}
    try:
        yield
    finally:
        for sig, h in old.items():
            signal.signal(sig, h)
