"""mat_hopper.core.perturbations: seeded disturbances, the same seed the same
replicate, each disturbance of the size its settings give, and replicate
pushes inside the scored window of every profile."""

import math

import numpy as np
import pytest

from mat_hopper.core.perturbations import NO_PUSH, REPLICATE_PUSH_FORCE_N, Perturbation, push_window_s
from mat_hopper.experiments.profiles import PROFILES


def test_the_same_seed_draws_the_same_replicate_bit_for_bit():
    a = Perturbation.replicate(3).draw(12.0, 1e-4)
    b = Perturbation.replicate(3).draw(12.0, 1e-4)
    c = Perturbation.replicate(4).draw(12.0, 1e-4)
    for x, y in zip(a[:4], b[:4]):
        assert np.array_equal(x, y)
    assert a[4] == b[4]
    assert not np.array_equal(a[0], c[0]) and not np.array_equal(a[3], c[3])


def test_replicate_is_the_books_documented_disturbance():
    p = Perturbation.replicate(0)
    # 5 mm start offset, 0.5 deg tilt, 5 N for 0.1 s between 5 and 15 s, 1 mm and 5 mm/s noise
    assert (p.start_offset_m, p.push_force_n, p.push_duration_s, p.push_window_s) == (0.005, 5.0, 0.1, (5.0, 15.0))
    assert p.start_tilt_rad == pytest.approx(0.5 * math.pi / 180)
    assert (p.noise_pos_m, p.noise_vel_m_s, p.noise_period_s) == (0.001, 0.005, 1e-3) and p.has_noise


def test_push_lies_in_its_window_with_its_force():
    p = Perturbation(seed=1, push_force_n=5.0, push_duration_s=0.2, push_window_s=(2.0, 3.0))
    for seed in range(20):
        _, _, push, _, _ = Perturbation(**{**p.__dict__, "seed": seed}).draw(10.0, 1e-4)
        t0, t1, fx, fy = push
        assert 2.0 <= t0 <= 3.0 and t1 == pytest.approx(t0 + 0.2)
        assert math.hypot(fx, fy) == pytest.approx(5.0)  # a horizontal force of 5 N in some direction


def test_noise_table_covers_the_run_at_its_period():
    p = Perturbation(seed=0, noise_pos_m=0.002, noise_vel_m_s=0.0)
    _, _, _, noise, every = p.draw(1.0, 1e-4)
    assert every == 10  # 1e-3 s period / 1e-4 s step
    assert noise.shape == (1001, 6)  # ceil(1 s / 1e-3 s) + 1 rows: position (3), velocity (3)
    assert np.all(noise[:, 3:] == 0.0)
    assert np.std(noise[:, :3]) == pytest.approx(0.002, rel=0.1)  # 3003 normal draws of std 2 mm


def test_no_disturbance_when_all_zero():
    offset, tilt, push, noise, every = Perturbation(seed=9).draw(60.0, 1e-4)
    assert np.all(offset == 0) and np.all(tilt == 0)
    assert push[2] == 0 and push[3] == 0  # a push of 0 N
    assert noise.shape == (1, 6) and np.all(noise == 0) and every > 60.0 / 1e-4  # never redrawn
    assert np.isinf(NO_PUSH[:2]).all() and np.all(NO_PUSH[2:] == 0)


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"seed": -1}, "seed"),
        ({"seed": 1.5}, "seed"),
        ({"push_force_n": -1.0}, "push_force_n"),
        ({"noise_pos_m": math.nan}, "noise_pos_m"),
        ({"push_duration_s": 0.0}, "push_duration_s"),
        ({"push_window_s": (5.0, 1.0)}, "push_window_s"),
    ],
)
def test_bad_settings_are_refused(kwargs, message):
    with pytest.raises(ValueError, match=message):
        Perturbation(**kwargs)


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


@pytest.mark.parametrize("scale", [1e9, 100.5, -1.0, math.nan, math.inf, True, "2"])
def test_a_push_scale_out_of_range_is_refused(scale):
    # push_scale 1e9 (5e9 N) was accepted before the fix
    from dataclasses import replace

    from mat_hopper.core.perturbations import MAX_PUSH_SCALE, check_push_scale

    with pytest.raises(ValueError, match=r"push_scale must be a finite number in \[0, 100\]"):
        Perturbation.replicate(0, push_scale=scale)
    with pytest.raises(ValueError, match=r"push_scale must be a finite number in \[0, 100\]"):
        replace(PROFILES["quick"], push_scale=scale)
    assert check_push_scale(MAX_PUSH_SCALE) == 100.0 and check_push_scale(0) == 0.0
