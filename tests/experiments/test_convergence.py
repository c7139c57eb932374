import pandas as pd
import pytest

from mat_hopper.core.model import build_model
from mat_hopper.experiments import convergence


def test_tasks_are_the_same_leg_cut_finer():
    tasks = convergence.tasks("quick", designs=("SS", "rho-inc"), behaviours=("forward",))
    assert len(tasks) == 2 * len(convergence.PLANS["quick"].segments)
    for t in tasks:
        s = t.settings
        assert s.convention == "axial" and s.segment_mass == "leg"
        assert s.substeps * s.timestep_s == pytest.approx(1e-4)  # the controller keeps its period
        assert t.labels["n_segments"] == t.design.n_segments
    masses = {t.design.n_segments: build_model(t.design).total_mass_kg for t in tasks if t.labels["design"] == "SS"}
    assert max(masses.values()) - min(masses.values()) < 1e-9 * max(masses.values())
    assert masses[3] == pytest.approx(23.77, abs=0.005)  # the spec's stainless hopper
    rho = [t for t in tasks if t.labels["design"] == "rho-inc" and t.labels["n_segments"] == 3][0]
    assert rho.design.densities_g_cm3 == (1.39, 4.43, 8.0)


def test_metrics_table_against_the_finest_leg():
    runs = pd.DataFrame(
        {
            "design": ["SS"] * 3,
            "behaviour": ["forward"] * 3,
            "n_segments": [24, 1, 3],
            "status": ["ok"] * 3,
            "mean_tracking_error_m": [0.02, 0.03, 0.021],
            "mean_power_w": [2.0, 1.0, 2.2],
            "mean_hop_height_m": [1.0, 1.0, 1.0],
        }
    )
    t = convergence.metrics_table(runs).set_index("n_segments")
    assert t.loc[1, "tracking_error_m_vs_finest_pct"] == pytest.approx(50.0)
    assert t.loc[3, "power_w_vs_finest_pct"] == pytest.approx(10.0)
    assert t.loc[24, "hop_height_m_vs_finest_pct"] == 0.0


def test_chain_mode_one_converges_to_the_rod():
    t = convergence.modes_table(designs=("SS",), segments=(4, 8, 16))
    err = t.set_index("n_segments")["error_pct"].abs()
    assert err[16] < 1.0 and 3 < err[8] / err[16] < 5
