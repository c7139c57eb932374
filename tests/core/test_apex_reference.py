"""The apex reference: what the controller's hop height is measured from.
Names read in any case and refused otherwise at every door; ``world`` is
the authors' controller, bit for bit; ``ground`` measures the apex above
the terrain under the foot at each lift-off (the compiled terrain height
agrees with the metrics' own), and changes nothing on flat ground."""

import numpy as np
import pytest

from mat_hopper.core import controller as c
from mat_hopper.core.controller import (
    APEX_REFERENCES,
    DEFAULT_APEX_REFERENCE,
    ControllerSettings,
    check_apex_reference,
    initial_state,
    update_phase,
)
from mat_hopper.core.sim import SimSettings, sim_settings, simulate
from mat_hopper.core.terrain import terrain_height_at, terrain_height_m, terrain_params
from mat_hopper.physics.metrics import hop_table, run_summary
from mat_hopper.util.keys import settings_key

SHORT = dict(duration_s=3.0, transient_s=1.0)
G = ControllerSettings().gains()


# --- names ---------------------------------------------------------------


@pytest.mark.parametrize("text, name", [("world", "world"), ("GROUND", "ground"), (" Ground ", "ground")])
def test_apex_reference_names_any_case(text, name):
    assert check_apex_reference(text) == name
    assert SimSettings(apex_reference=text).apex_reference == name


def test_default_is_world():
    assert DEFAULT_APEX_REFERENCE == "world" and SimSettings().apex_reference == "world"
    assert set(APEX_REFERENCES) == {"world", "ground"}


@pytest.mark.parametrize("bad", ["terrain", "", "  ", None, 1])
def test_unknown_apex_reference_refused_at_every_door(bad):
    for door in (
        lambda: check_apex_reference(bad),
        lambda: SimSettings(apex_reference=bad),
        lambda: sim_settings("SS", apex_reference=bad),
        lambda: simulate("SS", "ramp", apex_reference="" if bad is None else bad, **SHORT),  # None: not given
    ):
        with pytest.raises(ValueError, match="apex_reference"):
            door()


def test_recorded_in_the_key_and_the_tables():
    assert settings_key(SimSettings())["apex_reference"] == "world"
    assert settings_key(SimSettings(apex_reference="Ground"))["apex_reference"] == "ground"
    r = simulate("SS", "ramp", apex_reference="ground", **SHORT)
    hops = hop_table(r)
    assert len(hops) and (hops["apex_reference"] == "ground").all()
    assert run_summary(r, hops=hops)["apex_reference"] == "ground"


# --- the controller --------------------------------------------------------


def test_hop_height_measured_from_the_reference():
    """With a reference of 0.1 m the hop height is the apex less 0.1 m, and
    the thrust adapts from it: F += gain (target - height)."""
    heights = {}
    for ground in (0.0, 0.1):
        s = initial_state(ControllerSettings())
        s[c.S_GROUND_Z] = ground
        assert update_phase(0.2, 5.0, 0.9, -1.0, G, s) == c.TOUCHDOWN  # the first adapts nothing
        assert update_phase(0.4, 0.0, 0.9, 1.0, G, s) == c.LIFTOFF
        update_phase(0.6, 0.0, 1.05, 0.0, G, s)  # apex at 1.05 m world z
        assert update_phase(0.8, 5.0, 0.9, -1.0, G, s) == c.TOUCHDOWN
        heights[ground] = (s[c.S_LAST_HEIGHT], s[c.S_THRUST])
    assert heights[0.0][0] == 1.05  # exactly the apex: world z
    assert heights[0.1][0] == pytest.approx(0.95)
    assert heights[0.1][1] == pytest.approx(200.0 + 100.0 * (1.0 - 0.95))
    assert initial_state(ControllerSettings())[c.S_GROUND_Z] == 0.0


# --- the terrain the loop reads ----------------------------------------------


@pytest.mark.parametrize("grade", [None, 2.0, -5.0, 20.0])
def test_compiled_terrain_height_agrees_with_the_metrics(grade):
    rng = np.random.default_rng(0)
    x = np.concatenate([rng.uniform(-2.0, 12.0, 300), [0.0, 2.0, 5.0, -10.0, 100.0]])
    y = np.concatenate([rng.uniform(-6.0, 6.0, 300), [0.0, 0.0, 4.9, 0.0, 0.0]])
    p = terrain_params(grade)
    want = terrain_height_m(x, y, grade)
    got = np.array([terrain_height_at(a, b, p) for a, b in zip(x, y)])
    np.testing.assert_allclose(got, want, rtol=0, atol=1e-12)
    py = np.array([terrain_height_at.py_func(a, b, p) for a, b in zip(x, y)])
    np.testing.assert_allclose(py, want, rtol=0, atol=1e-12)
    if grade == 2.0:
        assert want.max() > 0.05  # the ramp is under some of the points


def test_terrain_params_refuse_a_wall():
    with pytest.raises(ValueError, match="ramp_grade_deg"):
        terrain_params(90.0)


# --- runs ------------------------------------------------------------------


def test_world_is_the_default_run_bit_for_bit():
    a = simulate("rho-inc", "ramp", **SHORT)
    b = simulate("rho-inc", "ramp", apex_reference="world", **SHORT)
    np.testing.assert_array_equal(a.data, b.data)
    np.testing.assert_array_equal(a.events, b.events)


def test_ground_changes_nothing_on_flat_ground():
    """The terrain under the foot is z = 0 on flat ground: the same run, bit for bit."""
    a = simulate("SS", "forward", **SHORT)
    b = simulate("SS", "forward", apex_reference="ground", **SHORT)
    np.testing.assert_array_equal(a.data, b.data)
    np.testing.assert_array_equal(a.events, b.events)


def _controller_heights(rollout, hops) -> np.ndarray:
    """The controller's hop height of each hop cycle: the one recorded at
    the touchdown inside it (the apex since the touchdown before)."""
    ev = rollout.events[rollout.events[:, 1] == c.TOUCHDOWN]
    out = []
    for t0, t1 in zip(hops["t_start_s"], hops["t_end_s"]):
        (k,) = np.flatnonzero((ev[:, 0] > t0) & (ev[:, 0] < t1))
        out.append(ev[k, 2])
    return np.array(out)


def test_ground_regulates_the_apex_above_the_ramp():
    """On the ramp the controller's own hop heights are the hop table's
    height above the ground under ``ground`` and the world-z apex under
    ``world`` (within the mm the ground moves under the base between
    lift-off and apex), and the two runs differ."""
    runs = {
        ref: simulate("rho-inc", "ramp", apex_reference=ref, duration_s=8.0, transient_s=1.0) for ref in APEX_REFERENCES
    }
    assert not np.array_equal(runs["world"].data, runs["ground"].data)
    for ref, column in (("world", "hop_height_m"), ("ground", "hop_height_ground_m")):
        r = runs[ref]
        hops = hop_table(r)
        assert len(hops) >= 6
        ctl = _controller_heights(r, hops)
        assert ctl == pytest.approx(hops[column].to_numpy(), abs=2e-3), ref
