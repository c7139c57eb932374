"""Body jerk: zero phase, no ringing, independent of the record rate."""

import numpy as np
import pytest

from mat_hopper.core.materials import parse_design
from mat_hopper.core.rollout import hop_cycles
from mat_hopper.core.sim import SimSettings, simulate
from mat_hopper.physics import jerk


class _Fake:
    def __init__(self, t, az):
        self.time, self._az = t, az

    def __getitem__(self, name):
        assert name == "az_mean"
        return self._az


def test_zero_phase_and_the_jerk_of_a_known_signal():
    t = np.arange(0, 10, 1e-3)
    a, f = 5.0, 2.0  # body: 5 m/s^2 at 2 Hz; ringing: 50 m/s^2 at 300 Hz
    az = a * np.sin(2 * np.pi * f * t) + 50.0 * np.sin(2 * np.pi * 300 * t)
    ro = _Fake(t, az)
    body = jerk.body_acceleration(ro)
    mid = slice(1000, 9000)
    assert np.max(np.abs(body[mid] - a * np.sin(2 * np.pi * f * t[mid]))) < 0.01 * a  # no lag, no ringing
    # mean |d/dt (A sin wt)| = A w 2/pi = 4 A f
    assert jerk.body_jerk(ro)[mid].mean() == pytest.approx(4 * a * f, rel=0.01)
    with pytest.raises(ValueError, match="cutoff_hz"):
        jerk.body_acceleration(ro, cutoff_hz=600.0)
    with pytest.raises(ValueError, match="order"):
        jerk.body_acceleration(ro, order=0)


def test_body_jerk_does_not_depend_on_the_record_rate():
    d = parse_design("rho-dec")
    out = []
    for rate in (1000.0, 10000.0):
        ro = simulate(d, "forward", settings=SimSettings(duration_s=6.0, transient_s=2.0, record_rate_hz=rate))
        cyc = hop_cycles(ro)
        i0, i1 = np.searchsorted(ro.time, cyc[:, 0]), np.searchsorted(ro.time, cyc[:, 1])
        out.append(jerk.hop_body_jerk(ro, i0, i1).mean())
        if rate == 1000.0:
            sens = jerk.jerk_sensitivity(ro, cutoffs_hz=(20.0, 50.0), orders=(4,))
    assert out[0] == pytest.approx(out[1], rel=0.02)
    assert list(sens["cutoff_hz"]) == [20.0, 50.0] and (sens["jerk_body_m_s3"] > 0).all()
    assert sens["jerk_body_m_s3"].iloc[0] < sens["jerk_body_m_s3"].iloc[1]  # a higher cut-off lets more through


@pytest.mark.parametrize("order", [float("inf"), float("nan"), 2.5, True, "4"])
def test_a_bad_filter_order_is_a_value_error(order):
    # order=inf raised OverflowError (int(inf)) before the fix
    ro = _Fake(np.arange(0, 2, 1e-3), np.zeros(2000))
    with pytest.raises(ValueError, match="order must be an integer >= 1"):
        jerk.body_acceleration(ro, order=order)


def test_sensitivity_checks_every_filter_even_without_scored_hops():
    ro = simulate(parse_design("SS"), "static", duration_s=1.0, transient_s=0.5)
    assert len(hop_cycles(ro, 0.9)) == 0
    for kw, what in ((dict(cutoffs_hz=(20.0, float("nan"))), "cutoff_hz"), (dict(orders=(2, 0)), "order")):
        with pytest.raises(ValueError, match=what):
            jerk.jerk_sensitivity(ro, transient_s=0.9, **kw)
