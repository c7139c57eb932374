"""A trial caught while it simulates, for the tests that stop or kill the
process that runs it (the optimize command: ``stop_a_running_trial``) or
that simulates it (one of its evaluation processes:
``stop_an_evaluation_process``)."""

from __future__ import annotations

import os
import signal
import time

import optuna
from optuna.trial import TrialState

from mat_hopper.optimize import open_storage
from mat_hopper.optimize._storage import WORKER_ATTR

# How long a test waits for a trial or an evaluation process to appear: a
# bound against a hang, not a speed check. Under CI's load (4 test workers
# and the book's kernels on 2 cores) a first evaluation process took over
# 90 s to start (a run fork-serves the pool, then compiles the loop).
WAIT_S = 600.0


def _state(storage, name: str, number: int) -> TrialState:
    study = optuna.load_study(study_name=name, storage=storage)
    return next(t.state for t in study.get_trials(deepcopy=False) if t.number == number)


def stop_a_running_trial(url: str, name: str, timeout_s: float = WAIT_S) -> tuple[int, int]:
    """(number, pid) of a trial of study ``name`` that is being simulated
    (its process named, all six parameters drawn), with the process that
    asked it (user attr ``worker``: the optimize command) stopped (SIGSTOP)
    and the trial read RUNNING again after the stop.

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


def _parents() -> dict[int, int]:
    """{pid: parent pid} of every process, from /proc."""
    parent = {}
    for entry in os.listdir("/proc"):
        if entry.isdigit():
            try:
                with open(f"/proc/{entry}/stat") as f:
                    parent[int(entry)] = int(f.read().rsplit(")", 1)[1].split()[1])
            except (OSError, IndexError, ValueError):
                continue
    return parent


def descendants(root: int, min_depth: int = 1) -> list[int]:
    """Process ids below `root`: children (depth 1), grandchildren (2), ...,
    from depth `min_depth` down."""
    parent = _parents()
    out, level, depth = [], [root], 0
    while level:
        depth += 1
        level = [c for c, pp in parent.items() if pp in level]
        if depth >= min_depth:
            out += level
    return out


def _exited(pid: int) -> bool:
    """Whether process `pid` is gone or a zombie (exited, not yet reaped)."""
    try:
        with open(f"/proc/{pid}/stat") as f:
            return f.read().rsplit(")", 1)[1].split()[0] == "Z"
    except (OSError, IndexError):
        return True


def evaluation_processes(root: int) -> list[int]:
    """The pool processes of the optimize command `root`: the children of its
    fork server (forks of it, so with its command line)."""
    out = []
    for pid in descendants(root, min_depth=2):
        try:
            with open(f"/proc/{pid}/cmdline", "rb") as f:
                if b"multiprocessing.forkserver" in f.read():
                    out.append(pid)
        except OSError:
            continue
    return out


def wait_for_evaluation_processes(root: int, timeout_s: float = WAIT_S) -> list[int]:
    """The pool processes of `root` once there are any (AssertionError after `timeout_s`)."""
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        found = evaluation_processes(root)
        if found:
            return found
        if _exited(root):
            raise AssertionError(f"the command {root} exited before any evaluation process started")
        time.sleep(0.05)
    raise AssertionError(f"no evaluation process under {root} within {timeout_s:g} s")


def _cpu_ticks(pid: int) -> int:
    try:
        with open(f"/proc/{pid}/stat") as f:
            fields = f.read().rsplit(")", 1)[1].split()
        return int(fields[11]) + int(fields[12])  # utime + stime
    except (OSError, IndexError, ValueError):
        return -1


def stop_an_evaluation_process(url: str, name: str, root: int, timeout_s: float = WAIT_S) -> tuple[set[int], int]:
    """(numbers of the trials of study ``name`` running at the stop, pid) of
    a process below ``root`` (the optimize command) that is simulating while
    the study has a running trial, with that process stopped (SIGSTOP): its
    round cannot be told while it is stopped.

    The evaluation processes are the pool's: the children of the command's
    fork server (its own children are the fork server and the resource
    tracker). One simulates when its CPU time grows by 50 ms or more over a
    fifth of a second (idle ones wait on a pipe). The caller owns the
    stopped process: SIGKILL it, or SIGCONT it.

    Raises AssertionError when none simulates within ``timeout_s`` seconds."""
    storage = open_storage(url)
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        try:
            study = optuna.load_study(study_name=name, storage=storage)
        except KeyError:  # not created yet
            time.sleep(0.05)
            continue
        if any(len(t.params) == 6 for t in study.get_trials(deepcopy=False, states=(TrialState.RUNNING,))):
            pids = evaluation_processes(root)
            before = {p: _cpu_ticks(p) for p in pids}
            time.sleep(0.2)
            busy = [p for p in pids if before[p] >= 0 and _cpu_ticks(p) >= before[p] + 5]  # 5 ticks: 50 ms
            for pid in busy:
                os.kill(pid, signal.SIGSTOP)
                running = {t.number for t in study.get_trials(deepcopy=False, states=(TrialState.RUNNING,))}
                if running:
                    return running, pid
                os.kill(pid, signal.SIGCONT)
        time.sleep(0.05)
    raise AssertionError(f"no process under {root} simulated a trial of {name!r} within {timeout_s:g} s")
