"""Dead runs: who runs a trial, and what happens to the trials of a
process that died (the module doc of :mod:`mat_hopper.optimize._storage`
describes the whole). A trial records its process (user attr ``worker``:
host, boot id, pid); :func:`recover_dead` fails the RUNNING trials of dead
processes on this machine and enqueues their parameters again
(:func:`retry_trial`, as Optuna's heartbeat callback does), through the
storage's public API."""

from __future__ import annotations

import os
import socket

import optuna
from optuna.trial import TrialState

from ._storage import FAIL_REASON_ATTR, WORKER_ATTR, retry_trial


def _boot_id() -> str:
    try:
        with open("/proc/sys/kernel/random/boot_id") as f:
            return f.read().strip()
    except OSError:
        return ""


def worker_identity(pid: int | None = None) -> dict:
    """Who runs a trial: host name, boot id (tells reboots and containers
    apart) and process id."""
    return {"host": socket.gethostname(), "boot": _boot_id(), "pid": int(pid or os.getpid())}


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    try:  # a zombie is dead too
        with open(f"/proc/{pid}/stat") as f:
            return f.read().rsplit(")", 1)[1].split()[0] != "Z"
    except (OSError, IndexError):
        return True


def fail_and_retry(study, storage, number: int, reason: str, max_retry: int = 3) -> bool:
    """Fail a RUNNING trial (user attr ``fail_reason``) and enqueue its
    parameters again (:func:`retry_trial`), through the storage's public API.

    Args:
        study: the trial's study.
        storage: the storage the study was opened on.
        number: the trial's number.
        reason: why it failed (stored as ``fail_reason``).
        max_retry: retries per trial.

    Returns:
        True when this call failed it; False when the trial had finished or
        another process failed it first.
    """
    study_id = storage.get_study_id_from_name(study.study_name)
    trial_id = storage.get_trial_id_from_study_id_trial_number(study_id, number)
    try:
        storage.set_trial_user_attr(trial_id, FAIL_REASON_ATTR, reason)
        if not storage.set_trial_state_values(trial_id, state=TrialState.FAIL):
            return False
    except (optuna.exceptions.UpdateFinishedTrialError, RuntimeError):
        return False
    retry_trial(study, storage.get_trial(trial_id), max_retry)
    return True


def recover_dead(study, storage, *, max_retry: int = 3, reason: str = "worker died") -> list[int]:
    """Fail the RUNNING trials of dead processes on this machine and enqueue
    their parameters again (:func:`fail_and_retry`).

    Args:
        study: the study.
        storage: the storage it was opened on.
        max_retry: retries per trial.
        reason: the ``fail_reason``, followed by the dead process's id.

    Returns:
        The numbers of the trials failed here: every RUNNING trial recorded
        by this machine (same host and boot id) whose process is gone (a
        trial another process failed first is left alone).
    """
    me = worker_identity()
    failed = []
    for t in study.get_trials(deepcopy=False, states=(TrialState.RUNNING,)):
        w = t.user_attrs.get(WORKER_ATTR)
        if not isinstance(w, dict) or w.get("host") != me["host"] or w.get("boot") != me["boot"]:
            continue
        pid = int(w.get("pid", -1))
        if pid == me["pid"] or _alive(pid):
            continue
        if fail_and_retry(study, storage, t.number, f"{reason} (pid {pid})", max_retry):
            failed.append(t.number)
    return failed
