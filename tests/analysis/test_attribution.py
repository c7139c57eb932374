"""What leg mass and hip inertia explain (mat_hopper.analysis.attribution),
on synthetic factorials with known elasticities."""

import numpy as np
import pandas as pd
import pytest

from mat_hopper.analysis.attribution import attribution, modulus_at_equal_mass


def test_attribution_separates_mass_from_springs_and_the_time_step():
    rng = np.random.default_rng(2)
    rows = []
    # the axial step itself lowers the metric by 10 %; axial springs a further 20 % at that step
    cells = (("rigid", 1.0), ("paper", 0.8), ("axial", 0.9 * 0.8), ("rigid, axial step", 0.9))
    for mass in (2.0, 3.0, 5.0, 8.0, 6.0):
        inertia = 0.05 * mass * np.exp(rng.normal(0, 0.3))
        for springs, f in cells:
            for rep in range(3):
                y = 0.1 * mass**0.5 * f * (1 + 0.1 * rep) * np.exp(rng.normal(0, 0.01))
                rows.append(
                    {
                        "design": f"m{mass}" if "rigid" not in springs else f"m{mass}~rigid",
                        "mass_of": f"m{mass}",
                        "springs": springs,
                        "behaviour": "forward",
                        "replicate": rep,
                        "leg_mass_kg": mass,
                        "hip_inertia_kg_m2": inertia,
                        "tracking_error_m": y,
                    }
                )
    att = attribution(pd.DataFrame(rows), metrics=("tracking_error_m",)).set_index("term")
    for term, want in (("springs_paper", np.log(0.8)), ("springs_axial", np.log(0.8)), ("axial_step", np.log(0.9))):
        assert att.loc[term, "estimate"] == pytest.approx(want, abs=0.02)
        assert att.loc[term, "ci_low"] < want < att.loc[term, "ci_high"]
    assert att["n_clusters"].iloc[0] == 5 and att["vif"].iloc[0] >= 1
    assert att["r2_with_springs"].iloc[0] > att["r2_mass_inertia"].iloc[0]
    with pytest.raises(ValueError, match="springs"):
        attribution(pd.DataFrame({"x": [1]}))


def test_modulus_at_equal_mass_sees_through_a_density_confound():
    rng = np.random.default_rng(4)
    rows = []
    # light legs at low moduli, mostly heavy ones at high moduli; tracking depends on density only
    points = [("PVC", rho, 4.0, "density") for rho in (1.1, 1.4, 1.9, 2.5)]
    points += [("PVC", 1.39, e, "modulus") for e in (0.1, 0.45, 2.0, 9.0)]
    points += [("Ti", rho, 120.0, "density") for rho in (2.0, 2.7, 4.4, 8.0, 19.0)]
    points += [("Ti", 4.43, e, "modulus") for e in (18.0, 64.0, 226.0, 800.0)]
    for base, rho, e, prop in points:
        for rep in range(3):
            rows.append(
                {
                    "sweep_base": base,
                    "sweep_property": prop,
                    "density_g_cm3": rho,
                    "modulus_gpa": e,
                    "replicate": rep,
                    "tracking_error_m": 0.08 * rho**-0.5 * np.exp(rng.normal(0, 0.02)),
                }
            )
    out = modulus_at_equal_mass(pd.DataFrame(rows)).set_index(["scope", "term"])
    low = out.loc[("pooled, density-adjusted", "low")]
    assert low["ci_low"] < 0 < low["ci_high"] and abs(low["estimate"]) < 0.05
    assert out.loc[("pooled, density-adjusted", "log_density"), "estimate"] == pytest.approx(-0.5, abs=0.05)
    assert (
        out.loc[("Ti (equal mass)", "log_modulus"), "ci_low"]
        < 0
        < out.loc[("Ti (equal mass)", "log_modulus"), "ci_high"]
    )
    assert "extrapolation" in low["density_overlap_g_cm3"] and low["density_overlap_g_cm3"].startswith("2-2.5")
    with pytest.raises(ValueError, match="columns"):
        modulus_at_equal_mass(pd.DataFrame({"x": [1]}))
