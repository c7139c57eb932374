"""Tiles after a fall are marked "(fell)" and the title says when it fell,
as a divergence is marked: a hopper tumbling on the ground is no gait."""

from __future__ import annotations

import pytest

from mat_hopper.core.rollout import Rollout
from mat_hopper.core.sim import simulate
from mat_hopper.viz.render import gait_tiles


@pytest.fixture(scope="module")
def rollout():
    return simulate("rho-inc", "ramp", duration_s=1.0, transient_s=0.0, record_qpos=True)


def test_tiles_after_a_fall_are_marked_and_the_title_says_it(rollout, monkeypatch):
    monkeypatch.setattr(Rollout, "fell_at_s", property(lambda self: 0.3))  # a fall at 0.3 s, without 10 s of run
    fig = gait_tiles("rho-inc", "ramp", rollout=rollout, start_s=0.0, seconds=0.6, n_frames=4, size=(40, 60))
    labels = [t.get_text() for t in fig.axes[0].texts]
    assert [lab.endswith("(fell)") for lab in labels] == [False, False, True, True], labels
    assert "fell at t = 0.300 s" in fig.axes[0].get_title()


def test_tiles_before_any_fall_are_not_marked(rollout):
    assert rollout.fell_at_s is None
    fig = gait_tiles("rho-inc", "ramp", rollout=rollout, start_s=0.0, seconds=0.6, n_frames=3, size=(40, 60))
    assert not any("(fell)" in t.get_text() for t in fig.axes[0].texts)
    assert "fell" not in fig.axes[0].get_title()
