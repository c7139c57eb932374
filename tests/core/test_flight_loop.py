"""The hips' sampled flight loop on a leg that bends: the check that
``timestep_s="auto"`` uses to keep a bending mode out of resonance with
the control rate, against MuJoCo's own runs."""

import numpy as np
import pytest

from mat_hopper.core.flight_loop import flight_loop_radius, flight_loop_stable, joint_damping
from mat_hopper.core.lumped import LumpedHopper
from mat_hopper.core.materials import LegDesign
from mat_hopper.core.model import build_model
from mat_hopper.core.sim import simulate
from mat_hopper.core.stable_step import auto_control_period

STIFF = LegDesign.from_properties([1.39] * 3, [400.0] * 3)  # PVC's density, 100 x its modulus


def test_damping_is_the_compiled_models():
    """The loop's joint damping equals MuJoCo's dof_damping of the built model."""
    for conv in ("bending", "axial+bending"):
        hopper = LumpedHopper(STIFF, conv)
        model = build_model(STIFF, convention=conv).model
        assert np.array_equal(joint_damping(hopper), model.dof_damping)


def test_a_stiff_leg_resonates_at_the_authors_period_and_not_at_auto():
    hopper = LumpedHopper(STIFF, "bending")
    assert flight_loop_radius(hopper, 1e-4) > 1.01  # grows ~5 % a period
    period = auto_control_period(STIFF, "bending")
    assert period < 1e-4 and flight_loop_stable(hopper, period, margin=0.1)
    assert flight_loop_radius(hopper, period) <= 1 + 1e-9


def test_hips_alone_are_stable_at_the_authors_period():
    """No hinges (the paper's springs): only the hips' PD, far inside its limit."""
    hopper = LumpedHopper(LegDesign.mono("SS"), "paper")
    assert flight_loop_radius(hopper, 1e-4) == pytest.approx(1.0, abs=1e-9)  # the free base's rigid modes


def test_mujoco_agrees_the_resonant_period_diverges_and_auto_does_not():
    """MuJoCo itself: at the authors' 1e-4 s control period (physics substeps
    as fine as auto's) the stiff leg diverges within 0.05 s; at auto's
    control period it does not."""
    sub = 8  # 1.25e-5 s physics steps
    r = simulate(
        STIFF,
        "forward",
        duration_s=0.05,
        transient_s=0.0,
        timestep_s=1e-4 / sub,
        substeps=sub,
        convention="bending",
        contact="stiff",
        warn=False,
    )
    assert r.diverged and "mat_bend" in r.divergence_reason
    ok = simulate(
        STIFF,
        "forward",
        duration_s=0.05,
        transient_s=0.0,
        timestep_s="auto",
        convention="bending",
        contact="stiff",
        warn=False,
    )
    assert ok.stable
