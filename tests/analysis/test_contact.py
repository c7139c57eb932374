"""contact_toggles: touch on/off switches per touchdown, on a hand-made
rollout whose answer is counted by hand."""

from __future__ import annotations

import numpy as np
import pytest

from mat_hopper.analysis.contact import contact_table, contact_toggles
from mat_hopper.core.behaviours import behaviour
from mat_hopper.core.controller import LIFTOFF, TOUCHDOWN
from mat_hopper.core.materials import parse_design
from mat_hopper.core.rollout import Rollout
from mat_hopper.core.sim import CHANNELS, C, SimSettings


def _rollout(touch, events, transient_s=0.0):
    dt = 1e-3
    data = np.zeros((len(touch), len(CHANNELS)))
    data[:, C["t"]] = np.arange(len(touch)) * dt
    data[:, C["touch"]] = touch
    settings = SimSettings(duration_s=1.0, transient_s=transient_s, timestep_s=dt, record_rate_hz=1000.0)
    return Rollout(parse_design("MD"), behaviour("ramp"), settings, data, np.array(events, float), -1, 16.9, ())


# touch (N) at t = 0, 1, ..., 11 ms: contact 0 0 1 1 0 0 1 0 1 1 0 0;
# it changes at 2, 4, 6, 7, 8 and 10 ms: 6 toggles.
TOUCH = [0.0, 0.0, 5.0, 5.0, 0.0, 0.0, 3.0, 0.0, 2.0, 2.0, 0.0, 0.0]
EVENTS = [(0.002, TOUCHDOWN, np.nan), (0.004, LIFTOFF, np.nan), (0.006, TOUCHDOWN, 1.0), (0.010, LIFTOFF, np.nan)]


def test_counts_toggles_per_touchdown_by_hand():
    # 6 toggles over 2 touchdowns: the second stance chatters (on, off, on, off)
    assert contact_toggles(_rollout(TOUCH, EVENTS)) == pytest.approx(3.0)


def test_a_clean_hop_is_two():
    touch = [0.0, 4.0, 4.0, 0.0, 0.0]
    events = [(0.001, TOUCHDOWN, np.nan), (0.003, LIFTOFF, np.nan)]
    assert contact_toggles(_rollout(touch, events)) == 2.0


def test_window_starts_at_the_transient():
    # from 5 ms on: samples 5..11 -> contact 0 1 0 1 1 0 0: 4 toggles, one touchdown (6 ms)
    assert contact_toggles(_rollout(TOUCH, EVENTS, transient_s=0.005)) == pytest.approx(4.0)
    assert contact_toggles(_rollout(TOUCH, EVENTS), transient_s=0.005) == pytest.approx(4.0)


def test_no_touchdown_is_an_error():
    with pytest.raises(ValueError, match="no touchdown"):
        contact_toggles(_rollout(TOUCH, EVENTS), transient_s=0.008)


def test_table_one_row_per_rollout():
    t = contact_table([_rollout(TOUCH, EVENTS)])
    assert t.loc[0, "design"] == "MD" and t.loc[0, "behaviour"] == "ramp"
    assert t.loc[0, "toggles_per_touchdown"] == pytest.approx(3.0)
