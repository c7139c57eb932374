"""Stress, strength and fatigue (mat_hopper.physics.fatigue): rainflow on a
hand-counted history, Basquin-Miner by hand, the hop table's columns."""

import math

import numpy as np
import pytest

from mat_hopper.core.materials import LegDesign, material
from mat_hopper.physics.fatigue import (
    CLASS_STRENGTH,
    DESIGN_LIFE_CYCLES,
    STRENGTH,
    Strength,
    _fibres,
    equivalent_amplitude,
    miner_damage,
    rainflow_cycles,
    strength,
)


def test_rainflow_counts_a_hand_counted_history():
    # Reversals 0, 40, 10, 30, 0 MPa, counted by hand per ASTM E1049-85 5.4.4:
    # read 0, 40, 10, 30: X = 20 < Y = 30, go on; read 0: X = 30 >= Y = 20 and
    # Y (10 -> 30) does not hold the start: one cycle of range 20, mean 20;
    # left 0, 40, 0: X = 40 >= Y = 40 and Y holds the start: a half cycle of
    # range 40; at the end the last range 40 -> 0 is a half cycle. So: range 20 x 1,
    # range 40 x 1/2 + 1/2, all of mean 20 MPa.
    c = rainflow_cycles(np.array([0.0, 40.0, 10.0, 30.0, 0.0]) * 1e6)
    by_range = c.groupby("range")["count"].sum()
    assert by_range.to_dict() == {20e6: 1.0, 40e6: 1.0}
    assert sorted(c["count"]) == [0.5, 0.5, 1.0]
    assert set(c["mean"]) == {20e6}


def test_miner_damage_by_hand():
    # sigma_f' = 100 MPa, b = -0.1; Morrow: sigma_ar = sigma_a / (1 - sigma_m / sigma_f').
    # range 20 (a = 10), mean 20: ar = 12.5, N_f = 0.5 x 8^10 = 536,870,912;
    # range 40 (a = 20), mean 20: ar = 25, N_f = 0.5 x 4^10 = 524,288;
    # D = 1 / 536870912 + 1 / 524288 = 1.909211e-6.
    st = Strength(50.0, 100.0, -0.1, "test")
    assert st.cycles_to_failure(10e6, 20e6) == pytest.approx(536870912.0)
    assert st.cycles_to_failure(20e6, 20e6) == pytest.approx(524288.0)
    d = miner_damage(np.array([0.0, 40.0, 10.0, 30.0, 0.0]) * 1e6, st)
    assert d == pytest.approx(1.909211e-6, rel=1e-6)


def test_equivalent_amplitude_by_hand():
    # The hand-counted history above: its largest cycle is the range-40 half
    # cycle, amplitude 20 MPa at mean 20 MPa. Morrow with sigma_f' = 100 MPa:
    # 20 / (1 - 20 / 100) = 25 MPa.
    st = Strength(50.0, 100.0, -0.1, "test")
    assert equivalent_amplitude(np.array([0.0, 40.0, 10.0, 30.0, 0.0]) * 1e6, st) == pytest.approx(25e6)
    assert equivalent_amplitude(np.array([5e6]), st) == 0.0


def test_amplitude_at_the_design_life_by_hand():
    # Dowling's 2024-T4: 900 MPa x (2e7)^-0.102; log10(2e7) = 7.30103, x -0.102 =
    # -0.744705, 10^-0.744705 = 10^0.255295 / 10 = 1.80009 / 10: 162.01 MPa at 1e7 cycles.
    assert DESIGN_LIFE_CYCLES == 1e7
    assert STRENGTH["al"].amplitude_at(1e7) == pytest.approx(162.01e6, rel=1e-4)
    # and it is the amplitude that lasts exactly that long
    assert STRENGTH["al"].cycles_to_failure(STRENGTH["al"].amplitude_at(1e7)) == pytest.approx(1e7)


def test_eight_fibres_catch_an_oblique_moment():
    # bending stress s about an axis at 45 degrees: (bx, by) = s (1/sqrt2, 1/sqrt2).
    # The four fibres at 0/90/180/270 degrees see s / sqrt2 = 0.707 s; the
    # eight fibres include 45 degrees, which sees the whole s.
    s = 100e6
    block = np.zeros((3, 4))
    block[:, 1] = block[:, 2] = s / math.sqrt(2.0)
    assert max(f.max() for f in _fibres(block)) == pytest.approx(s)
    assert len(_fibres(block)) == 8


def test_strength_of_a_catalogue_name_with_other_properties_is_its_class():
    # a porous stainless steel point of the density sweep (4 g/cm^3, 193 GPa) is
    # not the catalogue's AISI 304: it takes the metals' class curve, not SS's
    from mat_hopper.core.materials import Material

    porous = Material("SS", 4.0, 193.0, "metal", "sweep")
    assert strength(porous) is CLASS_STRENGTH["metal"]
    assert strength(material("SS")) is STRENGTH["ss"]


def test_strength_catalogue():
    # Dowling 2013, table 9.1: 2024-T4 Al sigma_f' = 900 MPa, b = -0.102, yield 303 MPa
    al = strength(material("Al"))
    assert (al.yield_mpa, al.sigma_f_mpa, al.b) == (303.0, 900.0, -0.102)
    # two-point curve: AISI 304 through (1 reversal, 505 MPa) and (1e7 cycles, 240 MPa)
    ss = strength(material("SS"))
    assert ss.sigma_f_mpa * (2e7) ** ss.b == pytest.approx(240.0)
    for m in material("SS"), material("CFRP"), material("Tendon"):
        assert strength(m).yield_mpa > 0 and strength(m).b < 0
    assert len(STRENGTH) == 12  # every elastic catalogue material
    # a material from properties takes its class's curve by modulus (70 GPa: metal -> Al's)
    custom = LegDesign.from_properties([1.39], [70.0]).segments[0]
    assert strength(custom) is al
    with pytest.raises(ValueError, match="rigid"):
        strength(material("MD"))


def test_hop_table_has_stress_columns():
    from mat_hopper.core.sim import simulate
    from mat_hopper.physics.metrics import hop_table

    r = simulate("SS", "forward", duration_s=4.0, transient_s=1.0, convention="bending", timestep_s="auto")
    hops = hop_table(r)
    for col in ("peak_stress_pa", "peak_stress_segment", "damage", "yield_exceeded", "damping"):
        assert col in hops.columns
    assert len(hops) > 0 and (hops["peak_stress_pa"] > 0).all()
    assert not hops["yield_exceeded"].any()  # tens of MPa against 215 MPa
    # the section stress the loop records is the springs' force over area and moment c / I
    k = r.spring_stiffness_n_m
    assert k == (0.0, 0.0, 0.0)
    assert r.stress.shape == (len(r.time), 3, 4)
    assert np.all(r.stress[:, :, 0] == 0.0)  # bending: axially rigid
    assert math.isfinite(hops["damage"].iloc[0])
    # the run's summary: its extreme is the largest hop peak; the typical hop is their median
    from mat_hopper.core.rollout import hop_cycles
    from mat_hopper.physics.fatigue import fatigue_summary

    life = fatigue_summary(r, hop_cycles(r, 1.0))
    assert life["peak_stress_pa"] == hops["peak_stress_pa"].max()
    assert life["hop_peak_stress_median_pa"] == float(np.median(hops["peak_stress_pa"]))


def test_loop_stress_is_the_springs_force_over_section():
    # sigma = E epsilon by hand: a hinge's K = E I / l gives M c / I = E r theta / l
    # (SS, N = 3: 193e9 x 0.025 / 0.1 = 4.825e10 Pa/rad); an axial slide's E A / l gives
    # F / A = E q / l (1.93e12 Pa/m)
    from mat_hopper.core.model import build_model, stress_gains
    from mat_hopper.core.sim import RolloutRunner, SimSettings

    adr, gain = stress_gains(build_model(LegDesign.mono("SS", 3), convention="axial+bending"))
    assert gain[0].tolist() == pytest.approx([1.93e12, 4.825e10, 4.825e10])
    assert (adr >= 0).all()
    # the loop, every physics step recorded: stress of s_i against qpos of s_i (recorded after step i - 1)
    s = SimSettings(duration_s=0.6, transient_s=0.0, convention="bending", record_rate_hz=1e4)
    runner = RolloutRunner(LegDesign.mono("PVC", 3), "forward", s, record_qpos=True)
    r = runner.advance().result()
    adr, gain = stress_gains(runner.hopper)
    for seg in range(3):
        for col in (1, 2):
            want = gain[seg, col] * r.qpos[:-1, adr[seg, col]]
            np.testing.assert_allclose(r.stress[1:, seg, col], want, rtol=1e-12, atol=0)
        section = np.abs(r.stress[:, seg, 0]) + np.hypot(r.stress[:, seg, 1], r.stress[:, seg, 2])
        np.testing.assert_allclose(r.stress[:, seg, 3], section, rtol=1e-12)  # one step per record: peak = value
    assert np.abs(r.stress[:, :, 1:3]).max() > 0  # the leg did bend (the first touchdown is at about 0.4 s)


def test_class_strength_covers_every_loss_factor_class():
    # every class a material can be read into has a curve (no KeyError)
    from mat_hopper.core.damping import LOSS_FACTORS

    assert set(CLASS_STRENGTH) == set(LOSS_FACTORS)


def test_strength_of_a_custom_ceramic_and_natural_material():
    # Ashby-class materials outside the catalogue: ceramic takes alumina's
    # curve (tensile strength 300 MPa as "yield"), natural compact bone's
    # (yield 110 MPa, Wegst & Ashby 2004)
    from mat_hopper.core.materials import Material

    ceramic = Material("my-ceramic", 3.5, 250.0, "ceramic", "test")
    assert strength(ceramic).yield_mpa == 300.0
    natural = Material("my-bone", 1.8, 15.0, "natural", "test")
    assert strength(natural).yield_mpa == 110.0


def test_the_s_n_curve_a_leg_is_judged_by_is_named():
    """A catalogue entry keeps its own curve; the same density and modulus
    given as properties (not a catalogue entry by name) take the class's."""
    from mat_hopper.core.materials import Material, parse_design
    from mat_hopper.physics.fatigue import strength_basis

    assert strength_basis(parse_design("SS").segments[0]) == "SS's own"
    assert strength_basis(Material("custom", 8.0, 193.0)) == "the metal class's"
