"""A running rollout forked part-way: the fork and its parent each end
bit-identical to a run that was never forked, and neither disturbs the other."""

import numpy as np
import pandas as pd
import pytest

from mat_hopper.core.perturbations import Perturbation
from mat_hopper.core.sim import C, RolloutRunner, SimSettings, simulate
from mat_hopper.physics.metrics import hop_table

FLIGHT, STANCE = 0.0, 1.0
PLAIN = SimSettings(duration_s=3.0, transient_s=0.5)
# The replicate's push (drawn in the scored window) and its sensor noise; record_qpos as rendering asks.
PERTURBED = SimSettings(duration_s=3.0, transient_s=0.5, perturbation=Perturbation.replicate(7, (0.5, 3.0)))
# A longer reading history (2 steps) and a control held over 2 physics steps (the same 1e-4 s period).
LAGGED = SimSettings(duration_s=2.0, transient_s=0.5, timestep_s=5e-5, sensor_timing=2, substeps=2)
OFF_RECORD = 7  # physics steps past a record: the filters' and probes' sums are part-way


@pytest.fixture(scope="module")
def straight():
    """The never-forked runs, by settings name (each hops to its end)."""
    runs = {
        "plain": simulate("SS", "forward", settings=PLAIN),
        "perturbed": simulate("SS", "forward", settings=PERTURBED, record_qpos=True),
        "lagged": simulate("SS", "forward", settings=LAGGED),
    }
    assert all(r.stable for r in runs.values())
    return runs


def branch_step(rollout, phase: float) -> int:
    """A physics step in the middle of the rollout's first stretch of the
    given recorded phase after its first touchdown, OFF_RECORD steps past
    a record whose neighbours hold the same phase."""
    ph = rollout.data[:, C["phase"]]
    first_touchdown = int(np.argmax(ph == STANCE))
    same = (ph[1:-1] == phase) & (ph[:-2] == phase) & (ph[2:] == phase)
    idx = np.flatnonzero(same) + 1
    idx = idx[idx > first_touchdown]
    gaps = np.flatnonzero(np.diff(idx) > 1)
    stretch = idx[: gaps[0] + 1 if len(gaps) else len(idx)]  # the first run of consecutive records
    return int(stretch[len(stretch) // 2]) * rollout.settings.record_every + OFF_RECORD


def assert_same_run(a, b):
    """Bit for bit: records, events, stress, joint positions, divergence and the hop table."""
    assert np.array_equal(a.data, b.data)
    assert np.array_equal(a.events, b.events, equal_nan=True)
    assert np.array_equal(a.stress, b.stress)
    assert (a.qpos is None) == (b.qpos is None)
    if a.qpos is not None:
        assert np.array_equal(a.qpos, b.qpos)
    assert a.diverged_step == b.diverged_step
    pd.testing.assert_frame_equal(hop_table(a, warn=False), hop_table(b, warn=False), check_exact=True)


def fork_at(settings, step, *, record_qpos=False):
    parent = RolloutRunner("SS", "forward", settings, record_qpos=record_qpos).advance(step)
    return parent, parent.fork()


@pytest.mark.parametrize("phase", [FLIGHT, STANCE], ids=["flight", "stance"])
@pytest.mark.parametrize("name", ["plain", "lagged"])
def test_a_fork_and_its_parent_end_as_the_straight_run(straight, name, phase):
    one = straight[name]
    step = branch_step(one, phase)
    parent, twin = fork_at(one.settings, step)
    assert twin.step == parent.step == step
    assert parent.result().data[-1, C["phase"]] == phase  # the branch really lies in that phase
    assert_same_run(twin.advance().result(), one)
    assert_same_run(parent.advance().result(), one)


def test_a_fork_at_the_start_ends_as_the_straight_run(straight):
    assert_same_run(RolloutRunner("SS", "forward", PLAIN).fork().advance().result(), straight["plain"])


@pytest.mark.parametrize("phase", [FLIGHT, STANCE], ids=["flight", "stance"])
def test_a_perturbed_fork_with_joint_positions_ends_as_the_straight_run(straight, phase):
    one = straight["perturbed"]
    push_end_s = PERTURBED.perturbation.draw(PERTURBED.duration_s, PERTURBED.timestep_s)[2][1]
    step = branch_step(one, phase)
    assert step * PERTURBED.timestep_s < push_end_s  # the push is still to come or under way at the branch
    parent, twin = fork_at(PERTURBED, step, record_qpos=True)
    assert parent.result().data[-1, C["phase"]] == phase
    assert_same_run(twin.advance().result(), one)
    assert_same_run(parent.advance().result(), one)


def test_advancing_a_fork_leaves_its_parent_as_it_was(straight):
    one = straight["perturbed"]
    parent, twin = fork_at(PERTURBED, branch_step(one, STANCE), record_qpos=True)
    before = parent.result()
    state = {name: getattr(parent.data, name).copy() for name in ("qpos", "qvel", "qacc", "sensordata", "ctrl")}
    time_s, n_contacts = parent.data.time, parent.data.ncon
    twin.advance()
    assert twin.done and not parent.done
    assert_same_run(parent.result(), before)
    for name, value in state.items():
        assert np.array_equal(getattr(parent.data, name), value), name
    assert (parent.data.time, parent.data.ncon) == (time_s, n_contacts)
    assert_same_run(parent.advance().result(), one)


# What a fork may share with its parent: what no physics step writes.
READ_ONLY = {"_disturbance", "_scored", "_path", "_gains", "_apex"}
READ_ONLY_FIELDS = {"coef", "adr", "gain", "terrain"}  # of the jerk filter, stress and contact probes


def arrays_of(runner):
    """(name, array) of every numpy array the runner holds, directly or in a tuple of arrays."""
    for name, value in vars(runner).items():
        if name in READ_ONLY:
            continue
        if isinstance(value, np.ndarray):
            yield name, value
        elif isinstance(value, tuple):
            fields = getattr(value, "_fields", range(len(value)))
            for field, item in zip(fields, value, strict=True):
                if isinstance(item, np.ndarray) and field not in READ_ONLY_FIELDS:
                    yield f"{name}.{field}", item


def test_a_fork_shares_no_array_a_step_writes():
    parent, twin = fork_at(PLAIN, 1234)
    assert twin.hopper is parent.hopper and twin.data is not parent.data
    theirs = dict(arrays_of(parent))
    mine = dict(arrays_of(twin))
    assert mine.keys() == theirs.keys() and "_buffers.qpos" in mine
    for name, array in mine.items():
        assert not np.shares_memory(array, theirs[name]), name
        assert array.tobytes() == theirs[name].tobytes(), name  # bit for bit, NaN included
    assert np.shares_memory(twin._buffers.qpos, twin.data.qpos)  # the loop's views are of the fork's own data
