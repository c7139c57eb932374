"""A run that did not diverge but whose numbers the integrator corrupted (a
physics step just below the leg's stable step) is told apart, warned of and
left out like a diverged run; a fall without divergence is warned of too."""

import warnings

import numpy as np
import pandas as pd
import pytest

from mat_hopper import FallWarning, LegDesign, SuspectWarning, simulate
from mat_hopper.analysis.stats import unusable_runs
from mat_hopper.core.behaviours import behaviour
from mat_hopper.core.rollout import SUSPECT_APEX_MARGIN_M, hop_cycles
from mat_hopper.core.sim import sim_settings
from mat_hopper.experiments.runner import SUSPECT, RunSpec
from mat_hopper.physics.metrics import hop_table, run_summary

TI_4 = LegDesign.mono("Ti", 4)  # analytic stable step 1.02e-4 s: the default 1e-4 s sits just below it


def test_a_step_just_below_the_bound_is_numerically_suspect():
    """Ti in 4 segments at 1e-4 s hops to 1.9 m by t = 2.35 s against the 1 m target
    (3.8 m later); at --timestep auto it holds about 1 m."""
    with pytest.warns(SuspectWarning, match=r'numerically suspect: a hop apex of 1\.90 m .*timestep_s="auto"'):
        r = simulate(TI_4, "forward", duration_s=3.0, transient_s=1.0)
    assert r.stable and r.suspect
    t, apex = r.suspect_apex
    assert apex > 1.0 + SUSPECT_APEX_MARGIN_M and 2.0 < t < 3.0
    s = run_summary(r)
    assert s["suspect_at_s"] == t and s["suspect_apex_m"] == apex
    bad = unusable_runs(pd.DataFrame([{**s, "status": "ok", "upright": True, "timestep_s": 1e-4}]))
    assert bad["why"].tolist() == ["numerically suspect at dt=1e-4 s, hop apex 1.9 m at t=2.35 s"]


def test_the_runner_gives_a_suspect_run_its_own_status():
    spec = RunSpec(TI_4, behaviour("forward"), sim_settings(TI_4, duration_s=3.0, transient_s=1.0))
    _, summary = spec.compute()
    assert summary["stable"] and summary["status"] == SUSPECT


@pytest.mark.parametrize("name", ["SS", "PVC", "rho-dec"])
def test_the_papers_designs_at_the_default_step_are_not_suspect(name):
    """The paper's own SS (near its bound at 1e-4 s) and the designs with the
    highest apexes of the paper's nine (PVC, rho-dec: 1.21 and 1.17 m on the ramp)."""
    with warnings.catch_warnings():
        warnings.simplefilter("error", SuspectWarning)
        r = simulate(name, "ramp", duration_s=4.0, transient_s=1.0)
    assert r.stable and not r.suspect and r.suspect_apex is None
    assert run_summary(r)["suspect_at_s"] is None


def test_a_fall_without_divergence_is_warned_and_no_cycle_after_it_scored():
    """8 g/cm^3, 260 GPa on the ramp at 1e-4 s: a 2.9 m apex, then a fall at t = 4.339 s."""
    leg = LegDesign.from_properties([8.0] * 3, [260.0] * 3)
    with (
        pytest.warns(SuspectWarning, match=r"hop apex of 2\.91 m"),
        pytest.warns(FallWarning, match=r"the hopper fell \(base tilted past 60 deg at t = 4\.339 s\)"),
    ):
        r = simulate(leg, "ramp", duration_s=6.0, transient_s=1.0)
    assert r.stable and r.suspect and r.fell_at_s == pytest.approx(4.339)
    with pytest.warns(SuspectWarning), pytest.warns(FallWarning):
        table = hop_table(r)
    assert (table["t_end_s"] <= r.fell_at_s).all()
    assert np.all(hop_cycles(r)[:, 1] <= r.fell_at_s)
