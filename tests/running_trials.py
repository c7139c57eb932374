"""A trial caught while it simulates, for the tests that stop or kill its
worker (import it: ``from running_trials import stop_a_running_trial``)."""

from __future__ import annotations

import os
import signal
import time

import optuna
from optuna.trial import TrialState

from mat_hopper.optimize._storage import WORKER_ATTR, open_storage


def _state(storage, name: str, number: int) -> TrialState:
    study = optuna.load_study(study_name=name, storage=storage)
    return next(t.state for t in study.get_trials(deepcopy=False) if t.number == number)


def stop_a_running_trial(url: str, name: str, timeout_s: float = 90.0) -> tuple[int, int]:
    """(number, worker pid) of a trial of study ``name`` that is simulating
    (its worker named, all six parameters drawn), with that worker stopped
    (SIGSTOP) and the trial read RUNNING again after the stop.

    Polling and then signalling leaves a window in which a loaded machine
    (pytest-xdist, CI) lets the trial finish, so a test meaning to kill a
    running trial killed a finished one. The stop closes it. The caller owns
    the stopped process: SIGKILL it, or SIGCONT it after its own signal.

    Raises AssertionError when no trial runs within ``timeout_s`` seconds."""
    storage = open_storage(url)
    deadline = time.monotonic() + timeout_s
    missed: set[int] = set()
    while time.monotonic() < deadline:
        try:
            study = optuna.load_study(study_name=name, storage=storage)
        except KeyError:  # not created yet
            time.sleep(0.05)
            continue
        for t in study.get_trials(deepcopy=False, states=(TrialState.RUNNING,)):
            worker = t.user_attrs.get(WORKER_ATTR)
            if not worker or len(t.params) != 6 or t.number in missed:
                continue
            pid = worker["pid"]
            try:
                os.kill(pid, signal.SIGSTOP)
            except ProcessLookupError:
                missed.add(t.number)
                continue
            if _state(storage, name, t.number) == TrialState.RUNNING:
                return t.number, pid
            os.kill(pid, signal.SIGCONT)  # it finished in between: let it go on
            missed.add(t.number)
        time.sleep(0.05)
    raise AssertionError(f"no trial of {name!r} started within {timeout_s:g} s")
