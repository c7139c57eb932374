"""mat_hopper.core.damping: loss factors per material class (Ashby 2011, Lakes 2009)."""

import pytest


def test_loss_factors_by_class():
    from mat_hopper.core.damping import LOSS_FACTORS, loss_factor
    from mat_hopper.core.materials import LegDesign, material

    assert loss_factor(material("SS")) == LOSS_FACTORS["metal"] == 1e-3
    assert loss_factor(material("PVC")) == LOSS_FACTORS["polymer"]
    assert loss_factor(material("CorticalBone")) == 1e-2
    assert loss_factor(LegDesign.from_properties([1.0], [0.5]).segments[0]) == LOSS_FACTORS["polymer"]


def test_spring_damping_is_eta_times_sqrt_k_m():
    from mat_hopper.core.damping import spring_damping

    # eta 0.01 on k = 100 N/m, m = 4 kg: 0.01 * sqrt(400) = 0.2 N s/m (damping ratio eta / 2 = 0.005)
    assert spring_damping(0.01, 100.0, 4.0) == pytest.approx(0.2)


def test_damping_name_any_case_is_stored_canonical():
    from mat_hopper.core.damping import check_damping
    from mat_hopper.core.sim import SimSettings

    assert check_damping(" Loss-Factor ") == "loss-factor"
    assert check_damping("AUTHORS") == "authors"
    assert SimSettings(damping="LOSS-FACTOR").damping == "loss-factor"
    with pytest.raises(ValueError, match="unknown damping 'viscous'; accepted: authors, loss-factor"):
        check_damping("viscous")
    with pytest.raises(ValueError, match="damping is empty"):
        SimSettings(damping=" ")
