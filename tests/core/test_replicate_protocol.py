"""The replicate protocol: ``authors`` perturbs from step 0, ``branch`` runs
unperturbed up to transient_s and perturbs from there (a velocity kick, the
sensor noise, the push), so its replicates share the unperturbed prefix."""

import math
from dataclasses import replace

import numpy as np
import pytest

from mat_hopper.core.perturbations import Perturbation
from mat_hopper.core.replicates import (
    BRANCH_KICK_TIME_S,
    BRANCH_SETTLE_FRACTION,
    branch_time_s,
    check_replicate_protocol,
)
from mat_hopper.core.sim import C, RolloutRunner, SimSettings, simulate
from mat_hopper.util.keys import settings_key

TRANSIENT_S, DURATION_S = 0.5, 2.0
SEED = 3
PREFIX_RECORDS = 500  # records at 1 kHz before 0.5 s


def replicate(seed=SEED):
    return Perturbation.replicate(seed, (TRANSIENT_S, DURATION_S))


def settings(protocol, perturbation=None):
    return SimSettings(
        duration_s=DURATION_S, transient_s=TRANSIENT_S, perturbation=perturbation, replicate_protocol=protocol
    )


@pytest.fixture(scope="module")
def runs():
    return {
        "plain": simulate("SS", "ramp", settings=settings("branch")),
        "branch": simulate("SS", "ramp", settings=settings("branch", replicate())),
        "authors": simulate("SS", "ramp", settings=settings("authors", replicate())),
    }


def test_the_protocol_is_a_named_setting_authors_by_default():
    assert SimSettings().replicate_protocol == "authors"
    assert settings(" Branch ").replicate_protocol == "branch"
    with pytest.raises(ValueError, match="replicate_protocol"):
        SimSettings(replicate_protocol="forked")
    assert check_replicate_protocol("AUTHORS") == "authors"


def test_the_protocol_is_in_the_settings_key():
    a, b = settings_key(settings("authors", replicate())), settings_key(settings("branch", replicate()))
    assert a["replicate_protocol"] == "authors" and b["replicate_protocol"] == "branch"
    assert {k for k in a if a[k] != b[k]} == {"replicate_protocol"}


def test_a_branch_replicate_runs_unperturbed_up_to_the_transient(runs):
    plain, branch = runs["plain"], runs["branch"]
    t = branch.data[:, C["t"]]
    assert np.array_equal(branch.data[:PREFIX_RECORDS], plain.data[:PREFIX_RECORDS])  # t < 0.5 s, bit for bit
    assert t[PREFIX_RECORDS - 1] < TRANSIENT_S <= t[PREFIX_RECORDS]
    before = branch.events[:, 0] < TRANSIENT_S
    assert np.array_equal(branch.events[before], plain.events[plain.events[:, 0] < TRANSIENT_S], equal_nan=True)
    assert not np.array_equal(branch.data[PREFIX_RECORDS:], plain.data[PREFIX_RECORDS:])  # perturbed after


def test_an_authors_replicate_is_perturbed_from_the_start(runs):
    plain, authors = runs["plain"], runs["authors"]
    # the drawn start offset, from numpy's generator directly: 5 mm std in x and y
    offset = np.random.default_rng(SEED).normal(0.0, 1.0, 2) * 0.005
    start = authors.data[0, [C["x"], C["y"]]] - plain.data[0, [C["x"], C["y"]]]
    np.testing.assert_allclose(start, offset, rtol=1e-12, atol=1e-15)


def test_the_branch_kick_is_the_start_disturbance_over_half_a_second(runs):
    """At transient_s the base's velocity jumps by the drawn offset / 0.5 s
    (m/s), its roll and pitch rates by the drawn tilt / 0.5 s (rad/s)."""
    plain, branch = runs["plain"], runs["branch"]
    rng = np.random.default_rng(SEED)  # Perturbation.draw's order: offset (x, y), then tilt (roll, pitch)
    offset = rng.normal(0.0, 1.0, 2) * 0.005
    tilt = rng.normal(0.0, 1.0, 2) * math.radians(0.5)
    k = PREFIX_RECORDS  # the record at transient_s holds the state just after the kick
    jump = branch.data[k, [C["vx"], C["vy"]]] - plain.data[k, [C["vx"], C["vy"]]]
    np.testing.assert_allclose(jump, offset / 0.5, rtol=1e-9)
    assert BRANCH_KICK_TIME_S == 0.5
    rates = branch.data[k, [C["roll_rate"], C["pitch_rate"]]] - plain.data[k, [C["roll_rate"], C["pitch_rate"]]]
    np.testing.assert_allclose(rates, tilt / 0.5, rtol=0.05)  # the gyro reads in the (nearly upright) base frame
    assert np.array_equal(branch.data[0], plain.data[0])  # no start offset nor tilt


@pytest.mark.parametrize("protocol", ["authors", "branch", "branch-settled"])
def test_a_push_window_outside_the_run_is_refused(protocol):
    """A push drawn after the run ends never acts: refused under every
    protocol, naming the scored window to draw it from."""
    with pytest.raises(
        ValueError, match=r"ends after the run .*will never act.*Perturbation.replicate\(seed, \(1, 3\)\)"
    ):
        SimSettings(
            duration_s=3.0, transient_s=1.0, perturbation=Perturbation.replicate(0, None), replicate_protocol=protocol
        )
    with pytest.raises(ValueError, match="ends after the run"):
        SimSettings(duration_s=3.0, transient_s=1.0, perturbation=Perturbation.replicate(0, (20.0, 60.0)))
    with pytest.raises(ValueError, match="may fall after the run's end"):  # window 1.9-3.5 s in a 3 s run
        SimSettings(duration_s=3.0, transient_s=1.0, perturbation=Perturbation.replicate(0, (1.5, 5.5)))
    SimSettings(
        duration_s=3.0, transient_s=1.0, perturbation=Perturbation.replicate(0, (1.0, 3.0)), replicate_protocol=protocol
    )
    # no push: nothing to check
    SimSettings(duration_s=3.0, transient_s=1.0, perturbation=Perturbation.replicate(0, None, push_scale=0))


def test_the_branch_push_lies_in_the_scored_window():
    early = Perturbation.replicate(SEED, None)  # the historical 5-15 s window
    with pytest.raises(ValueError, match="push window"):
        SimSettings(duration_s=30.0, transient_s=20.0, perturbation=early, replicate_protocol="branch")
    SimSettings(duration_s=30.0, transient_s=20.0, perturbation=early)  # authors: anywhere
    SimSettings(  # no push: no window to check
        duration_s=30.0,
        transient_s=20.0,
        perturbation=Perturbation.replicate(SEED, None, push_scale=0),
        replicate_protocol="branch",
    )


def test_a_fork_as_each_replicate_ends_as_the_replicate_run_alone(runs):
    base = RolloutRunner("SS", "ramp", settings("branch")).advance(int(round(TRANSIENT_S / 1e-4)))
    for seed in (SEED, 5):
        twin = base.fork_as(settings("branch", replicate(seed))).advance().result()
        alone = runs["branch"] if seed == SEED else simulate("SS", "ramp", settings=settings("branch", replicate(seed)))
        assert np.array_equal(twin.data, alone.data)
        assert np.array_equal(twin.events, alone.events, equal_nan=True)
        assert np.array_equal(twin.stress, alone.stress)
        assert twin.settings == alone.settings
    assert np.array_equal(base.advance().result().data, runs["plain"].data)  # the parent goes on unperturbed


def test_fork_as_refuses_what_would_not_share_the_prefix():
    base = RolloutRunner("SS", "ramp", settings("branch")).advance(100)
    with pytest.raises(ValueError, match="branch"):
        base.fork_as(settings("authors", replicate()))
    with pytest.raises(ValueError, match="only in the perturbation"):
        base.fork_as(replace(settings("branch", replicate()), contact="stiff"))
    late = RolloutRunner("SS", "ramp", settings("branch")).advance(int(round(TRANSIENT_S / 1e-4)) + 1)
    with pytest.raises(ValueError, match="past its unperturbed prefix"):
        late.fork_as(settings("branch", replicate()))


# -- branch-settled: the same kick, noise and push, from half the transient ---------------------------------------

SETTLED_RECORDS = 250  # records at 1 kHz before 0.25 s, half of TRANSIENT_S


def test_branch_settled_perturbs_from_half_the_transient(runs):
    """Unperturbed (bit for bit the plain run) up to 0.25 s, then the same
    kick as ``branch``: the drawn offset / 0.5 s."""
    assert BRANCH_SETTLE_FRACTION == 0.5
    settled = simulate("SS", "ramp", settings=settings("branch-settled", replicate()))
    plain, t = runs["plain"], settled.data[:, C["t"]]
    k = SETTLED_RECORDS
    assert t[k - 1] < TRANSIENT_S / 2 <= t[k]
    assert np.array_equal(settled.data[:k], plain.data[:k])
    offset = np.random.default_rng(SEED).normal(0.0, 1.0, 2) * 0.005
    jump = settled.data[k, [C["vx"], C["vy"]]] - plain.data[k, [C["vx"], C["vy"]]]
    np.testing.assert_allclose(jump, offset / 0.5, rtol=1e-9)
    assert not np.array_equal(settled.data[k:], runs["branch"].data[k:])  # not the branch run: kicked earlier
    assert branch_time_s(settings("branch-settled")) == TRANSIENT_S / 2
    assert branch_time_s(settings("branch")) == TRANSIENT_S
    with pytest.raises(ValueError, match="does not branch"):
        branch_time_s(settings("authors"))


def test_a_settled_fork_ends_as_the_replicate_run_alone():
    base = RolloutRunner("SS", "ramp", settings("branch-settled")).advance(int(round(TRANSIENT_S / 2 / 1e-4)))
    twin = base.fork_as(settings("branch-settled", replicate(5))).advance().result()
    alone = simulate("SS", "ramp", settings=settings("branch-settled", replicate(5)))
    assert np.array_equal(twin.data, alone.data) and np.array_equal(twin.stress, alone.stress)
    assert np.array_equal(twin.events, alone.events, equal_nan=True)
    late = RolloutRunner("SS", "ramp", settings("branch-settled")).advance(int(round(TRANSIENT_S / 2 / 1e-4)) + 1)
    with pytest.raises(ValueError, match="past its unperturbed prefix"):
        late.fork_as(settings("branch-settled", replicate()))
    with pytest.raises(ValueError, match="only in the perturbation"):  # no fork across protocols
        base.fork_as(settings("branch", replicate()))
