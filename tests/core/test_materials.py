import math

import numpy as np
import pytest

from mat_hopper.core import reference as ref
from mat_hopper.core.materials import (
    CATALOGUE,
    LegDesign,
    Material,
    bulk_density,
    material,
    order_designs,
    paper_designs,
    parse_design,
    porosity,
    spring_stiffness,
)


def test_paper_convention_pinned():
    assert spring_stiffness(4.0, "paper") == pytest.approx(3.77e6, rel=1e-3)
    assert spring_stiffness(193.0, "paper") == pytest.approx(1.819e8, rel=1e-3)
    assert ref.PAPER_STIFFNESS_PER_GPA == pytest.approx(9.4248e5, rel=1e-4)


def test_axial_convention_is_EA_over_L():
    area = math.pi * 0.025**2
    assert spring_stiffness(193.0, "axial", 3) == pytest.approx(193e9 * area / 0.1)
    assert spring_stiffness(193.0, "axial", 3) == pytest.approx(3.79e9, rel=1e-2)
    # Shorter segments are stiffer.
    assert spring_stiffness(70.0, "axial", 6) == pytest.approx(2 * spring_stiffness(70.0, "axial", 3))


def test_porosity_roundtrip():
    assert porosity(1.0, 2.0) == pytest.approx(0.5)
    assert porosity(8.0, 8.0) == 0.0
    assert bulk_density(porosity(1.39, 1.9), 1.9) == pytest.approx(1.39)
    with pytest.raises(ValueError, match="porosity"):
        bulk_density(1.0, 2.0)
    with pytest.raises(ValueError, match="exceeds"):
        porosity(3.0, 2.0)


def test_catalogue_has_paper_materials_and_sources():
    # the paper's materials table (docs/reference-hopper.md): density g/cm^3, modulus GPa
    paper = {"MD": (1.0, None), "PVC": (1.39, 4.0), "Al": (2.7, 70.0), "Ti": (4.43, 120.0), "SS": (8.0, 193.0)}
    for name, (rho, e) in paper.items():
        m = material(name.lower())
        assert (m.density_g_cm3, m.modulus_gpa) == (rho, e)
    assert material("MD").rigid
    assert len(CATALOGUE) >= 9
    assert all(m.source for m in CATALOGUE.values())


@pytest.mark.parametrize("density", [0, -1, float("nan"), float("inf"), "x"])
def test_bad_density(density):
    with pytest.raises(ValueError, match="density.*g/cm\\^3"):
        Material("bad", density, 10.0)


@pytest.mark.parametrize("modulus", [-1, float("nan"), 0])
def test_bad_modulus(modulus):
    with pytest.raises(ValueError, match="modulus.*GPa"):
        Material("bad", 1.0, modulus)


def test_bad_names():
    with pytest.raises(ValueError, match="unknown material 'unobtainium'.*accepted"):
        parse_design("unobtainium")
    with pytest.raises(ValueError, match="convention"):
        spring_stiffness(10, "beam")
    with pytest.raises(ValueError, match="1 to 64 segments"):
        LegDesign(())
    with pytest.raises(ValueError, match="n_segments"):
        LegDesign.mono("SS", 0)
    with pytest.raises(ValueError, match="one value per segment"):
        LegDesign.from_properties([1, 2, 3], [1, 2])


def test_design_forms():
    assert parse_design("ss").densities_g_cm3 == (8.0, 8.0, 8.0)
    g = parse_design("PVC-Ti-SS")
    assert g.name == "PVC-Ti-SS" and g.moduli_gpa == (4.0, 120.0, 193.0)
    assert parse_design("rho-inc").densities_g_cm3 == (1.39, 4.43, 8.0)
    assert parse_design("RHO-DEC").densities_g_cm3 == (8.0, 4.43, 1.39)
    assert parse_design("rho-inc").moduli_gpa == (70.0, 70.0, 70.0)
    assert LegDesign.from_properties([1.39, 4.43, 8], [70]).moduli_gpa == (70.0,) * 3
    assert LegDesign.mono("Al", 5).n_segments == 5
    assert set(paper_designs()) == {"MD", "PVC", "Al", "Ti", "SS", "rho-inc", "rho-dec", "PVC-Ti-SS", "SS-Ti-PVC"}


def test_capsule_volume_by_hand():
    """0.1 m of material at 1 g/cm^3 in two half-capsules of r = 2.5 cm weighs
    0.327 kg, end caps included (the spec's figure)."""
    from mat_hopper.core.materials import capsule_volume_m3

    v = capsule_volume_m3(0.025, 0.05)
    assert v == pytest.approx(math.pi * 0.025**2 * 0.05 + 4 / 3 * math.pi * 0.025**3)
    assert 2 * v * 1000.0 == pytest.approx(0.327, abs=5e-4)


def test_segment_masses_leg_and_capsule():
    from mat_hopper.core.materials import capsule_density_scale, segment_masses

    assert capsule_density_scale(3) == 1.0  # exactly: the authors' leg
    assert capsule_density_scale(6, "capsule") == 1.0
    ss3 = sum(segment_masses(LegDesign.mono("SS", 3)))
    for n in (1, 2, 6, 12, 24):
        assert sum(segment_masses(LegDesign.mono("SS", n))) == pytest.approx(ss3, rel=1e-12)
    # capsule: each of 2N half-capsules has its own two hemispherical caps (8000 kg/m^3)
    caps = 4 / 3 * math.pi * 0.025**3 * 8000.0
    assert sum(segment_masses(LegDesign.mono("SS", 6), "capsule")) - ss3 == pytest.approx(6 * caps)


@pytest.mark.parametrize(
    "density, modulus, field",
    [
        (1e30, 70, "density"),
        (1e-5, 70, "density"),
        (-1, 70, "density"),
        (8, 1e-30, "modulus"),
        (8, 1e5, "modulus"),
        (8, float("inf"), "modulus"),
        (True, 70, "density"),
    ],
)
def test_physical_ranges_are_enforced(density, modulus, field):
    with pytest.raises(ValueError, match=field) as e:
        LegDesign.from_properties([density], [modulus])
    assert "g/cm^3" in str(e.value) or "GPa" in str(e.value)


def test_numeric_strings_parse_one_way():
    leg = LegDesign.from_properties(["8"], ["70"])
    assert leg.densities_g_cm3 == (8.0,) and leg.moduli_gpa == (70.0,)
    assert leg.name == "custom(8/70)"
    with pytest.raises(ValueError, match="density"):
        LegDesign.from_properties(["eight"], ["70"])


@pytest.mark.parametrize("n", [2.5, 0, -1, True, "x", 10000, float("nan")])
def test_bad_segment_counts(n):
    with pytest.raises(ValueError, match="n_segments|segments"):
        LegDesign.mono("SS", n)


def test_resample_conserves_mass_and_compliance():
    leg = parse_design("PVC-Ti-SS")  # 1.39/4, 4.43/120, 8/193
    assert leg.resample(3) is leg
    six = leg.resample(6)
    assert six.densities_g_cm3 == (1.39, 1.39, 4.43, 4.43, 8.0, 8.0)
    one = leg.resample(1)
    assert one.densities_g_cm3[0] == pytest.approx((1.39 + 4.43 + 8.0) / 3)
    # springs in series, by hand: 1 / E = (1/4 + 1/120 + 1/193) / 3
    assert one.moduli_gpa[0] == pytest.approx(3 / (1 / 4 + 1 / 120 + 1 / 193))
    two = leg.resample(2)  # cells [0, 1/2], [1/2, 1]
    assert two.densities_g_cm3 == pytest.approx(((1.39 * 2 + 4.43) / 3, (4.43 + 8.0 * 2) / 3))
    for n in (1, 2, 4, 5, 12, 24):
        r = leg.resample(n)
        assert sum(r.densities_g_cm3) / n == pytest.approx(sum(leg.densities_g_cm3) / 3)
        assert sum(1 / e for e in r.moduli_gpa) / n == pytest.approx(sum(1 / e for e in leg.moduli_gpa) / 3)
    md = parse_design("MD").resample(5)
    assert all(s.rigid for s in md.segments)


def test_segment_masses_by_hand():
    from mat_hopper.core.materials import capsule_volume_m3, parse_design, segment_masses

    # one capsule r = 0.025 m, L = 0.05 m: pi r^2 L + 4/3 pi r^3 = 9.8175e-5 + 6.5450e-5 m^3
    assert capsule_volume_m3(0.025, 0.05) == pytest.approx(1.63625e-4, rel=1e-5)
    # an SS segment (8 g/cm^3 = 8000 kg/m^3) of the 3-segment leg: two such half capsules
    ss = segment_masses(parse_design("SS"))
    assert ss == pytest.approx((2.618,) * 3, rel=1e-3)
    # rho-inc: 1.39, 4.43, 8 g/cm^3 from base to foot, same volumes
    assert segment_masses(parse_design("rho-inc")) == pytest.approx((0.4549, 1.4497, 2.618), rel=1e-3)


def test_designs_in_the_papers_order():
    """The order of the paper's tables (Table I's five materials, then the
    gradients as the paper introduces them), typed from the paper."""
    paper = ["MD", "PVC", "Al", "Ti", "SS", "rho-inc", "rho-dec", "PVC-Ti-SS", "SS-Ti-PVC"]
    assert order_designs(["mine", *reversed(paper), "SS"]) == [*paper, "mine"]
    assert list(paper_designs()) == paper


def test_numeric_strings_are_ascii_decimals_only():
    # float() reads "٨" as 8, "1_0" as 10 and "inf" as infinity: none is a density a user means
    from mat_hopper.core.materials import Material

    assert Material("x", "8", "193").density_g_cm3 == 8.0
    for bad in ("٨", "1_0", "inf", "nan", "0x10"):
        with pytest.raises(ValueError, match="density"):
            Material("x", bad, 193.0)


def test_segment_length_checks_the_count():
    from mat_hopper.core.materials import segment_length

    assert segment_length(3) == pytest.approx(0.1)  # 0.3 m of material in three
    for bad in (0, -1, 2.5, None, True):
        with pytest.raises(ValueError, match=r"n_segments must be an integer in \[1, 64\]"):
            segment_length(bad)
    with pytest.raises(ValueError, match="n_segments"):
        spring_stiffness(70.0, "axial", 0)  # used to be ZeroDivisionError


def test_bulk_density_refuses_a_porosity_that_is_not_a_number():
    assert bulk_density(0.25, 2.0) == pytest.approx(1.5)
    assert bulk_density("0.25", 2.0) == pytest.approx(1.5)  # a decimal string is read, as before
    for bad in (None, [0.1], "lots", float("nan"), -0.1, 1.0):
        with pytest.raises(ValueError, match=r"porosity must be .*in \[0, 1\)"):
            bulk_density(bad, 2.0)


def test_section_geometry_refuses_bad_radii():
    from mat_hopper.core.materials import capsule_volume_m3, second_moment_m4

    assert second_moment_m4(0.025) == pytest.approx(math.pi * 0.025**4 / 4)
    assert capsule_volume_m3(1.0, 0.0) == pytest.approx(4.0 / 3.0 * math.pi)  # a sphere
    for bad in (0.0, -0.025, None, float("inf")):
        with pytest.raises(ValueError, match="section radius"):
            second_moment_m4(bad)
        with pytest.raises(ValueError, match="capsule radius"):
            capsule_volume_m3(bad, 0.1)
    with pytest.raises(ValueError, match="capsule length"):
        capsule_volume_m3(0.025, -0.1)


def test_material_class_any_case_and_unknown_refused():
    from mat_hopper.core.materials import Material

    assert Material("x", 3.9, 380.0, " Ceramic ").material_class == "ceramic"
    for bad in ("nonsense", 5, ""):
        with pytest.raises(ValueError, match="material class"):
            Material("x", 3.9, 380.0, bad)


def test_from_properties_refuses_a_string_or_a_bare_number_for_a_sequence():
    # "8" was read a character at a time: a 1-segment density against moduli 1, 9, 3 GPa;
    # a bare number raised Python's "'float' object is not iterable", naming no argument
    from mat_hopper.core.materials import LegDesign

    for dens, mods in (
        ("8", "193"),
        ([8.0], "193"),
        (None, None),
        (1.0, 70),
        ([1.0], 70.0),
        (np.float64(2.7), [70]),
        ({1.0, 2.0}, [70]),
    ):
        with pytest.raises(ValueError, match="must be a sequence of numbers"):
            LegDesign.from_properties(dens, mods)


def test_n_segments_refuses_non_ascii_digits():
    from mat_hopper.core.materials import check_n_segments

    assert check_n_segments("3") == 3
    with pytest.raises(ValueError, match="n_segments"):
        check_n_segments("\u0663")  # ARABIC-INDIC DIGIT THREE: float() reads it as 3


@pytest.mark.parametrize("text", ["SS--Ti", "-SS", "SS-", "SS- -Ti", "PVC/_SS", "Ti__SS", "-", "SS-Ti-", " -PVC-Ti"])
def test_a_design_name_with_an_empty_component_is_refused(text):
    # "SS--Ti" was read as SS-Ti (the empty name dropped) before the fix
    with pytest.raises(ValueError, match="empty name between separators"):
        parse_design(text)
    assert parse_design(" PVC - Ti - SS ").name == "PVC-Ti-SS"  # blanks around a name are no empty name
