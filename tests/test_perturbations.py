"""Replicate pushes fall inside the scored window of every profile."""

import pytest

from mat_hopper.experiments.profiles import PROFILES
from mat_hopper.perturbations import REPLICATE_PUSH_FORCE_N, Perturbation, push_window_s


@pytest.mark.parametrize("name", sorted(PROFILES))
def test_replicate_push_inside_the_scored_window(name):
    prof = PROFILES[name]
    for seed in range(20):
        p = Perturbation.replicate(seed, (prof.transient_s, prof.duration_s))
        _, _, push, _, _ = p.draw(prof.duration_s, prof.timestep_s)
        assert prof.transient_s < push[0] and push[1] < prof.duration_s


def test_push_scale_and_window_errors():
    assert Perturbation.replicate(0, push_scale=2.0).push_force_n == 2 * REPLICATE_PUSH_FORCE_N
    assert Perturbation.replicate(0, push_scale=0.0).push_force_n == 0.0
    assert push_window_s(4.0, 12.0) == pytest.approx((4.8, 8.0))
    with pytest.raises(ValueError, match="push_scale"):
        Perturbation.replicate(0, push_scale=-1.0)
    with pytest.raises(ValueError, match="scored window"):
        push_window_s(12.0, 4.0)
