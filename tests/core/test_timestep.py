"""The time step and the control period (mat_hopper.core.timestep)."""

import pytest

from mat_hopper.core.timestep import AUTO, FINE_SUBSTEPS, FINE_TIMESTEP_S, auto_timestep, is_auto, resolve_timestep


def test_the_finer_step_keeps_the_control_period():
    # 2e-5 s x 5 substeps = the authors' 1e-4 s control period, written by hand
    assert (FINE_TIMESTEP_S, FINE_SUBSTEPS) == (2e-5, 5)


def test_auto_is_a_word_in_any_case():
    assert AUTO == "auto" and is_auto(" AUTO ") and not is_auto(1e-4) and not is_auto("autos")


def test_resolve_timestep_passes_numbers_and_needs_a_design_for_auto():
    assert resolve_timestep(5e-5) == (5e-5, 1)
    with pytest.raises(ValueError, match="pass the design"):
        resolve_timestep("auto")
    with pytest.raises(ValueError, match="a number"):
        resolve_timestep("fast", "SS")
    # SS under axial: 8 substeps of the 1e-4 s control period (k = E A / L = 3.8e9 N/m)
    dt, k = resolve_timestep("auto", "SS", "axial")
    assert (k, auto_timestep("SS", "axial")) == (8, (8, dt)) and dt * k == pytest.approx(1e-4)
    with pytest.raises(ValueError, match="LegDesign or a design name"):
        resolve_timestep("auto", 3.0)
