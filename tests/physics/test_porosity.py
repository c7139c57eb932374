"""mat_hopper.physics.porosity: Gibson-Ashby softening, checked against the cited power law by hand."""

import pytest


def test_gibson_ashby_half_density_quarter_modulus():
    from mat_hopper.core.materials import material
    from mat_hopper.physics.porosity import gibson_ashby_modulus, porous_modulus

    # Gibson & Ashby 1997, open-cell foams: E / E_s = (rho / rho_s)^2; 0.5^2 = 1/4
    assert gibson_ashby_modulus(200.0, 0.5) == 50.0
    ss = material("SS")
    assert porous_modulus(ss, 4.0, "gibson-ashby") == pytest.approx(193.0 / 4)
    assert porous_modulus(ss, 4.0, "independent") == 193.0
    assert porous_modulus(ss, 9.0, "gibson-ashby") == 193.0  # denser than solid: not porous
    with pytest.raises(ValueError, match="porosity_model"):
        porous_modulus(ss, 4.0, "closed-cell")
    with pytest.raises(ValueError, match="relative density"):
        gibson_ashby_modulus(200.0, 1.5)


def test_porosity_model_any_case_is_canonical():
    from mat_hopper.core.materials import material
    from mat_hopper.physics.porosity import check_porosity_model, porous_modulus

    assert check_porosity_model(" Gibson-Ashby ") == "gibson-ashby"
    assert check_porosity_model("INDEPENDENT") == "independent"
    # E_s (rho / rho_s)^2 = 193 / 4 for SS at half its 8 g/cm^3, whatever the spelling
    assert porous_modulus(material("SS"), 4.0, "GIBSON-ASHBY") == pytest.approx(193.0 / 4)
    with pytest.raises(ValueError, match="unknown porosity_model 'closed-cell'; accepted: independent, gibson-ashby"):
        check_porosity_model("closed-cell")
