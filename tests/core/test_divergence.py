"""A time step above a leg's analytic stable step is warned of before the
run (mat_hopper.core.timestep.check_stable_step), and a run that diverges
says when, why and what to try (Rollout.divergence_message): in the Rollout,
as a DivergenceWarning from simulate() and from hop_table, never a silent
empty table."""

import warnings

import numpy as np
import pytest

import mat_hopper
from mat_hopper.core.materials import LegDesign
from mat_hopper.core.sim import SimSettings, sim_settings, simulate
from mat_hopper.core.timestep import CLI_AUTO_HINT, check_stable_step
from mat_hopper.physics.metrics import hop_table, run_summary

# A five-segment leg whose springs' bound (9.29e-05 s) lies just under the authors' 1e-4 s step:
# at that step it diverges 4.3 ms in; at --timestep auto (3 substeps) it hops.
FIVE = LegDesign.from_properties([2.0, 3.0, 4.5, 6.0, 7.8], [50, 80, 110, 150, 200])


def _run(*args, **kwargs):
    """simulate(), and every warning it gave."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        r = simulate(*args, **kwargs)
    return r, caught


def test_the_check_names_the_bound_and_auto_and_passes_the_paper_designs():
    note = check_stable_step(FIVE, SimSettings())
    assert "the physics step 0.0001 s is above this leg's analytic stable step 9.29e-05 s" in note
    assert 'try timestep_s="auto" (3 physics substeps of 3.33e-05 s' in note and "\n" not in note
    assert "--timestep auto (3 physics substeps" in check_stable_step(FIVE, SimSettings(), auto_hint=CLI_AUTO_HINT)
    # the control period above the controller's own limit is named too
    assert "the control period 0.001 s is above the controller's explicit limit" in check_stable_step(
        "SS", SimSettings(timestep_s=1e-3)
    )
    # the authors' designs at their 1e-4 s step, and any design at auto: nothing to say
    for name in ("MD", "PVC", "Al", "Ti", "SS", "PVC-Ti-SS", "SS-Ti-PVC", "rho-inc", "rho-dec"):
        assert check_stable_step(name, SimSettings()) is None, name
    assert check_stable_step(FIVE, sim_settings(FIVE, timestep_s="auto")) is None
    assert check_stable_step("SS", sim_settings("SS", timestep_s="auto", convention="axial")) is None


def test_simulate_warns_before_and_after_a_run_that_diverges():
    r, caught = _run(FIVE, "forward", duration_s=2.0, transient_s=1.0)
    kinds = [w.category for w in caught]
    assert kinds == [mat_hopper.StableStepWarning, mat_hopper.DivergenceWarning]
    assert issubclass(mat_hopper.DivergenceWarning, RuntimeWarning)
    assert issubclass(mat_hopper.StableStepWarning, RuntimeWarning)
    assert all(w.filename == __file__ for w in caught)  # pointed at the caller's line
    assert 'timestep_s="auto"' in str(caught[0].message)
    assert str(caught[1].message).startswith(f"{FIVE.name}: diverged at t = 0.0043 s")


def test_a_diverged_rollout_says_when_why_and_what_to_try():
    r, _ = _run(FIVE, "forward", duration_s=2.0, transient_s=1.0)
    assert r.diverged and not r.stable and r.diverged_at_s == pytest.approx(0.0043)
    why = r.divergence_reason
    assert why.startswith("numerical divergence: |qacc| ") and "> 1e+06 at joint mat_spring_" in why
    assert "the physics step 0.0001 s is above this leg's analytic stable step 9.29e-05 s" in why
    message = r.divergence_message(CLI_AUTO_HINT)
    assert message.startswith("diverged at t = 0.0043 s (numerical divergence: ")
    assert message.endswith("try --timestep auto (3 physics substeps of 3.33e-05 s per 0.0001 s control period)")
    # the stable run: nothing of the kind
    ok, caught = _run(FIVE, "forward", duration_s=2.0, transient_s=1.0, timestep_s="auto")
    assert ok.stable and not ok.diverged and ok.divergence_reason is None and ok.divergence_message() is None
    assert caught == [] and len(hop_table(ok)) >= 1


def test_a_nan_is_told_apart_from_a_large_acceleration():
    """The reason reads the state the check stopped at: a NaN names itself."""
    from mat_hopper.core.rollout import divergence_reason

    r, _ = _run(FIVE, "forward", duration_s=2.0, transient_s=1.0, warn=False)

    class Model:
        dof_jntid = np.arange(12)
        jnt_qposadr = np.arange(12)

        def joint(self, i):
            return type("J", (), {"name": f"j{i}"})

    class Data:
        qacc = np.array([0.0, np.nan] + [0.0] * 10)
        qpos = np.zeros(12)

    assert divergence_reason(r, Model(), Data()).startswith("numerical divergence: NaN or inf in qacc at joint j1")


def test_hop_table_of_a_diverged_run_warns_and_warn_false_is_silent():
    r, caught = _run(FIVE, "forward", duration_s=2.0, transient_s=1.0, warn=False)
    assert caught == [] and r.diverged
    with pytest.warns(mat_hopper.DivergenceWarning, match="hop_table holds the 0 hop cycles scored before it"):
        table = hop_table(r)
    assert len(table) == 0  # its empty table, with its columns
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert len(hop_table(r, warn=False)) == 0
        s = run_summary(r)  # the summary says it itself
    assert not s["stable"]
    assert s["diverged_at_s"] == pytest.approx(0.0043)


def test_no_hop_cycle_is_scored_through_a_fall():
    """A heavy leg falls (9.4 s) before it diverges (11.1 s): the cycles
    the fall cuts through were scored, with 'hip power' of 1e5-1e6 W; now
    every scored cycle ends before the fall."""
    from mat_hopper.core.materials import LegDesign
    from mat_hopper.core.rollout import hop_cycles
    from mat_hopper.core.sim import simulate
    from mat_hopper.physics.metrics import hop_table

    r = simulate(LegDesign.from_properties([19] * 3, [120] * 3), "forward", duration_s=12, transient_s=4, warn=False)
    assert r.fell_at_s is not None and r.fell_at_s < 10.5
    cycles = hop_cycles(r)
    assert len(cycles) > 0 and (cycles[:, 1] <= r.fell_at_s).all()
    hops = hop_table(r, warn=False)
    assert len(hops) == len(cycles) and hops["power_w"].max() < 1e3
