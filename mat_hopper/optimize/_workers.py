"""Which of the runs on one study a run is: its worker index, claimed in the storage.

Several commands may run one study at once (shared storage, or two
commands on one SQLite file). Each seeds its sampler from ``--seed``, the
study's size when it started and its worker index
(:func:`mat_hopper.optimize._samplers.sampler_seed`): two runs that
started on the same study at the same moment see the same size, and with
the same index they would propose the same points (TPE's first trials are
random draws from its seed), evaluating the same designs twice.

A run claims the smallest index no live run holds: it writes its claim
(study user attr ``mat_hopper_run:<token>``, its own key: writes never
collide), reads every claim back, and moves to another index whenever it
sees a live claim on its own; it keeps the index once it reads its claim
with no other on that index. Two runs cannot both keep one index: each
read follows its own write, so of two runs the later reader sees the
other's claim (every storage commits a study attr write atomically and a
read that starts after the commit sees it). A run gives its index back at
its end (the claim marked ended), so one run at a time on a study always
has index 0: the seeds of a single command are those it had without any
claim. A claim of a process that died on this machine is not live (its
pid is gone); one of another machine whose run died stays taken, which
only makes later runs there take higher indices.
"""

from __future__ import annotations

import random
import time
import uuid

from ._recovery import _alive, worker_identity

RUN_ATTR = "mat_hopper_run:"  # study user attr prefix: one run's claim {"index", "host", "boot", "pid", "live"}
CLAIM_ATTEMPTS = 50


def _live(claim, me: dict) -> bool:
    if not isinstance(claim, dict) or not claim.get("live"):
        return False
    if claim.get("host") == me["host"] and claim.get("boot") == me["boot"]:
        pid = int(claim.get("pid", -1))
        return pid == me["pid"] or _alive(pid)
    return True  # another machine's: live until it ends


def _held(attrs: dict, token: str, me: dict) -> set[int]:
    """The indices that live claims other than `token` hold."""
    return {int(v["index"]) for k, v in attrs.items() if k.startswith(RUN_ATTR) and k != token and _live(v, me)}


def _smallest_free(taken: set[int]) -> int:
    i = 0
    while i in taken:
        i += 1
    return i


def claim_worker(storage, study_id: int) -> tuple[str, int]:
    """Claim this run's worker index on a study (module doc).

    Args:
        storage: the study's Optuna storage.
        study_id: the study's id in it.

    Returns:
        (the claim's key, the index: 0 for the only run on the study).
    """
    me = worker_identity()
    token = f"{RUN_ATTR}{uuid.uuid4().hex}"
    rng = random.Random(token)
    index = _smallest_free(_held(storage.get_study_user_attrs(study_id), token, me))
    for _ in range(CLAIM_ATTEMPTS):
        storage.set_study_user_attr(study_id, token, {"index": index, **me, "live": True})
        taken = _held(storage.get_study_user_attrs(study_id), token, me)
        if index not in taken:
            return token, index
        index = _smallest_free(taken)
        time.sleep(rng.uniform(0.0, 0.05))  # two runs that keep colliding part
    index = 1000 + rng.randrange(1 << 30)  # never seen in practice: an index no claim is likely to hold
    storage.set_study_user_attr(study_id, token, {"index": index, **me, "live": True})
    return token, index


def release_worker(storage, study_id: int, token: str, index: int) -> None:
    """Give a claimed index back (the claim marked ended); a storage error is ignored."""
    try:
        storage.set_study_user_attr(study_id, token, {"index": index, **worker_identity(), "live": False})
    except Exception:  # the run is over either way; a dead claim of this machine is ignored anyway
        pass
