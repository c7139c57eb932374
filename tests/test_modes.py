import math

import pytest

from mat_hopper.materials import LegDesign, parse_design
from mat_hopper.modes import _rod_roots, auto_substeps, axial_modes, chain_frequencies, estimate_timestep


def test_chain_two_masses_by_hand():
    # two masses on one spring: w^2 = k (1/m1 + 1/m2)
    w = chain_frequencies([2.0, 3.0], [600.0])
    assert w[0] == pytest.approx(0.0, abs=1e-6)
    assert w[1] == pytest.approx(math.sqrt(600.0 * (1 / 2.0 + 1 / 3.0)), rel=1e-12)


@pytest.mark.parametrize(
    "a1, a2, first",
    [
        (0.0, 0.0, math.pi),  # free-free rod: z = n pi
        (1e9, 0.0, math.pi / 2),  # top fixed (huge mass), bottom free: z = pi / 2
    ],
)
def test_rod_roots_limits_by_hand(a1, a2, first):
    assert _rod_roots(a1, a2, 3)[0] == pytest.approx(first, rel=1e-6)


def test_rod_root_with_a_tip_mass_by_hand():
    """Fixed-free rod with a tip mass equal to its own (a2 = 1): z tan z = 1,
    first root 0.8603 (tabulated, e.g. Rao, Vibration of Continuous Systems)."""
    assert _rod_roots(1e12, 1.0, 1)[0] == pytest.approx(0.8603, abs=1e-4)


def test_chain_converges_to_the_rod_as_one_over_n_squared():
    err = {n: abs(axial_modes(LegDesign.mono("SS", n))["error_pct"].iloc[0]) for n in (4, 8, 16, 32)}
    assert err[16] < 1.0 and err[32] < 1.0  # mode 1 within 1 % at N >= 16
    for n in (4, 8, 16):
        assert 3.0 < err[n] / err[2 * n] < 5.0  # halving the segment: error / 4


def test_modes_need_a_uniform_elastic_leg():
    with pytest.raises(ValueError, match="one elastic material"):
        axial_modes(parse_design("rho-inc"))
    with pytest.raises(ValueError, match="one elastic material"):
        axial_modes(parse_design("MD"))


def test_auto_substeps_below_the_safety_fraction():
    for n in (3, 12):
        k, dt, bound = auto_substeps(LegDesign.mono("SS", n), "axial")
        assert dt == pytest.approx(1e-4 / k)
        assert dt <= 0.5 * bound < 1e-4 / (k - 1)  # the smallest such k
        assert bound == pytest.approx(estimate_timestep(LegDesign.mono("SS", n), "axial")[1])
