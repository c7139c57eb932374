"""The contact setting: names read in any case and refused otherwise at
every door, the compiled model's solref, ``authors`` as the model built
without any solver parameter (MuJoCo's defaults), ``--timestep auto``
under the contact's own limit, and the contact channels the loop records
at the physics rate."""

from dataclasses import replace

import mujoco
import numpy as np
import pytest

from mat_hopper.core import mjcf
from mat_hopper.core.contact import CONTACTS, DEFAULT_CONTACT, check_contact, contact_max_timestep, contact_solref
from mat_hopper.core.materials import parse_design
from mat_hopper.core.model import FOOT_GEOM, GROUND_GEOM, RAMP_GEOM, build_model, reset_to_start
from mat_hopper.core.sim import SimSettings, sim_settings, simulate
from mat_hopper.core.stable_step import auto_substeps

SHORT = dict(duration_s=1.5, transient_s=0.5)


# --- names ---------------------------------------------------------------


@pytest.mark.parametrize("text, name", [("authors", "authors"), ("STIFF", "stiff"), (" Stiff ", "stiff")])
def test_contact_names_any_case(text, name):
    assert check_contact(text) == name
    assert SimSettings(contact=text).contact == name
    assert build_model(parse_design("MD"), contact=text).contact == name


def test_default_is_authors_mujocos_own_solref():
    assert DEFAULT_CONTACT == "authors" and SimSettings().contact == "authors"
    assert contact_solref("authors") == tuple(mujoco.MjSpec().default.geom.solref)
    assert contact_solref("stiff") == (0.001, 1.0)


@pytest.mark.parametrize("bad", ["rigid", "", "  ", None, "soft", 1])
def test_unknown_contact_refused_at_every_door(bad):
    for door in (
        lambda: check_contact(bad),
        lambda: SimSettings(contact=bad),
        lambda: sim_settings("SS", contact=bad),
        lambda: simulate("SS", "forward", contact="" if bad is None else bad, **SHORT),  # None: not given
        lambda: build_model(parse_design("SS"), contact=bad),
        lambda: mjcf.build_spec(parse_design("SS"), contact=bad),
        lambda: auto_substeps(parse_design("SS"), contact=bad),
    ):
        with pytest.raises(ValueError, match="contact"):
            door()


# --- the compiled model ----------------------------------------------------


@pytest.mark.parametrize("contact", list(CONTACTS))
def test_geom_solref_carries_the_time_constant(contact):
    m = build_model(parse_design("SS"), ramp_grade_deg=2.0, contact=contact).model
    for name in (FOOT_GEOM, GROUND_GEOM, RAMP_GEOM):
        assert tuple(m.geom_solref[m.geom(name).id]) == CONTACTS[contact], name
    others = [i for i in range(m.ngeom) if not (m.geom_contype[i] or m.geom_conaffinity[i])]
    assert others and all(tuple(m.geom_solref[i]) == CONTACTS["authors"] for i in others)
    # the contact MuJoCo makes, mixed from the two geoms, carries it exactly
    d = mujoco.MjData(m)
    reset_to_start(m, d)
    d.qpos[m.joint("base_z").qposadr[0]] -= 0.64  # the foot 8 cm deep in the ground
    mujoco.mj_forward(m, d)
    assert d.ncon > 0
    for c in d.contact:
        assert tuple(c.solref) == CONTACTS[contact]


def test_authors_is_the_model_without_solver_parameters(monkeypatch):
    """``authors`` compiles to the model a builder that sets no solref
    gives (MuJoCo's defaults, the authors' file): every numeric array
    equal, and the run bit-identical."""
    design = parse_design("PVC-Ti-SS")
    a = build_model(design, ramp_grade_deg=2.0).model
    ra = simulate(design, "ramp", **SHORT)
    monkeypatch.setattr(mjcf, "_set_contact", lambda spec, solref: None)
    b = build_model(design, ramp_grade_deg=2.0).model
    rb = simulate(design, "ramp", **SHORT)
    compared = 0
    for name in dir(a):
        va = getattr(a, name)
        if not name.startswith("_") and isinstance(va, np.ndarray) and va.dtype.kind in "fiu":
            np.testing.assert_array_equal(va, getattr(b, name), err_msg=name)
            compared += 1
    assert compared > 100
    np.testing.assert_array_equal(ra.data, rb.data)
    np.testing.assert_array_equal(ra.events, rb.events)


def test_stiff_contact_sinks_less():
    soft = simulate("MD", "forward", contact="authors", **SHORT)
    stiff = simulate("MD", "forward", contact="stiff", **SHORT)
    assert not np.array_equal(soft.data, stiff.data)
    assert stiff.settings.contact == "stiff" and soft.settings.contact == "authors"
    assert 5e-3 < -soft.foot_clearance_min_m.min() < 5e-2  # MuJoCo's default: a centimetre or two
    assert 0 < -stiff.foot_clearance_min_m.min() < 3e-3


# --- --timestep auto -------------------------------------------------------


def test_contact_max_timestep_is_half_the_time_constant():
    assert contact_max_timestep("authors") == pytest.approx(0.01)
    assert contact_max_timestep("STIFF") == pytest.approx(5e-4)


@pytest.mark.parametrize("period", [2e-3, 1e-3, 7e-4])
def test_auto_step_honours_the_contact_time_constant(period):
    """MuJoCo uses max(timeconst, 2 dt): the auto step is at most half the
    contact's time constant. MD's springs (only the foot's) allow these
    periods in one step, so the contact is the binding limit."""
    md = parse_design("MD")
    k_soft, dt_soft, _ = auto_substeps(md, "paper", control_period_s=period, contact="authors")
    k_stiff, dt_stiff, _ = auto_substeps(md, "paper", control_period_s=period, contact="stiff")
    assert k_soft == 1 and dt_soft == period
    assert dt_stiff <= contact_max_timestep("stiff") * (1 + 1e-9)
    assert k_stiff == int(np.ceil(period / 5e-4 - 1e-9)) > 1


def test_auto_step_under_stiff_at_todays_control_period():
    """At the 1e-4 s control period the contact never binds: the same
    auto step as under authors, and at most 0.5 ms."""
    for design, conv in (("SS", "bending"), ("MD", "paper"), ("Ti", "axial+bending")):
        a = sim_settings(design, timestep_s="auto", convention=conv, **SHORT)
        s = sim_settings(design, timestep_s="auto", convention=conv, contact="stiff", **SHORT)
        assert (s.timestep_s, s.substeps) == (a.timestep_s, a.substeps)
        assert s.timestep_s <= contact_max_timestep("stiff")


# --- the loop's contact channels -------------------------------------------


@pytest.mark.parametrize("contact", list(CONTACTS))
def test_contact_channels_at_the_physics_rate(contact):
    """Recorded at the physics rate, each record's toggle count is the
    change of the touch state the controller reads (the authors' timing:
    the sensor one physics step old), and the foot is in the ground
    (clearance < 0) wherever the touch sensor reads a force."""
    st = sim_settings("SS", duration_s=2.5, transient_s=0.5, timestep_s=1e-4, contact=contact)
    r = simulate("SS", "forward", settings=replace(st, record_rate_hz=1e4))
    on = r.touch > 0  # the sensor on s_i, record i
    assert on.any() and r.touch_toggles.sum() > 0
    np.testing.assert_array_equal(r.touch_toggles[2:], (on[1:-1] != on[:-2]).astype(float))
    assert r.touch_toggles[:2].tolist() == [0.0, 0.0]  # the start: in the air, no touch
    assert (r.foot_clearance_min_m[on] < 0).all()
    # the first record: MuJoCo's foot-ground distance of the start state
    st0 = sim_settings("SS", duration_s=2.5, transient_s=0.5, timestep_s=1e-4)
    m = build_model(parse_design("SS"), timestep_s=st0.timestep_s).model
    d = mujoco.MjData(m)
    reset_to_start(m, d)
    gap = mujoco.mj_geomDistance(m, d, m.geom(GROUND_GEOM).id, m.geom(FOOT_GEOM).id, 10.0, None)
    assert r.foot_clearance_min_m[0] == pytest.approx(gap, abs=1e-12)


def test_contact_channels_sum_over_any_record_rate():
    """Counted at the physics rate: the toggles of a 1 kHz record add up to
    those of a physics-rate record, and its clearance minima to their minima."""
    st = sim_settings("Ti", duration_s=2.0, transient_s=0.5, timestep_s=1e-4, contact="stiff")
    fine = simulate("Ti", "ramp", settings=replace(st, record_rate_hz=1e4))
    coarse = simulate("Ti", "ramp", settings=st)
    assert coarse.touch_toggles.sum() == fine.touch_toggles.sum() > 0
    assert coarse.foot_clearance_min_m.min() == fine.foot_clearance_min_m.min() < 0


def test_stiff_elliptic_is_stiff_with_mujocos_elliptic_cone():
    """``stiff-elliptic``: the stiff contact's solref with elliptic friction
    cones in the compiled model; every other contact keeps the pyramid."""
    ss = parse_design("SS")
    cones = {c: mjcf.build_spec(ss, contact=c).compile().opt.cone for c in CONTACTS}
    assert cones["stiff-elliptic"] == mujoco.mjtCone.mjCONE_ELLIPTIC
    assert {c: v for c, v in cones.items() if c != "stiff-elliptic"} == {
        "authors": mujoco.mjtCone.mjCONE_PYRAMIDAL,
        "stiff": mujoco.mjtCone.mjCONE_PYRAMIDAL,
    }
    assert contact_solref("stiff-elliptic") == contact_solref("stiff")
    assert contact_max_timestep("stiff-elliptic") == contact_max_timestep("stiff")
    assert check_contact(" Stiff-Elliptic ") == "stiff-elliptic"
    # a setting of the physics: its own cache key
    assert SimSettings(contact="stiff-elliptic") != SimSettings(contact="stiff")
