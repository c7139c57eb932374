"""The optimizer's signals (private): SIGTERM and SIGHUP stop a run the way
Ctrl-C does, and a short critical section can hold them back.
:mod:`mat_hopper.optimize._driver` uses them.
"""

from __future__ import annotations

import signal
import threading
from contextlib import contextmanager


class HeldSignals:
    """Hold signals back over a short critical section: one that arrives
    inside it is recorded, and delivered again (``signal.raise_signal``,
    with the handlers from before) at :meth:`release` or at the block's end,
    whichever comes first. Used where a trial exists in the storage but
    does not yet name its process: a process stopped there would leave a
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
    optimizer's loop fails and re-queues its running trials."""

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

    Yields:
        None; the block runs with the handlers in place.

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
