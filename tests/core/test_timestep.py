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


# auto's (substeps k, control period 1e-4 s / p) for each catalogue material, 3 segments, under
# paper, axial, bending and axial+bending (segment mass leg, the authors' sensor timing), as they
# were when the spring bounds were read from the compiled model: the analytic bodies
# (mat_hopper.core.lumped) must not move them.
CATALOGUE_AUTO = {
    "MD": ((1, 1), (1, 1), (1, 1), (1, 1)),
    "PVC": ((1, 1), (3, 1), (1, 1), (3, 1)),
    "Al": ((2, 1), (8, 1), (3, 1), (8, 1)),
    "Ti": ((2, 1), (8, 1), (3, 1), (8, 1)),
    "SS": ((2, 1), (8, 1), (3, 1), (8, 1)),
    "CorticalBone": ((1, 1), (5, 1), (2, 1), (5, 1)),
    "TrabecularBone": ((1, 1), (2, 1), (1, 4), (1, 4)),
    "Tendon": ((1, 1), (2, 1), (1, 3), (1, 3)),
    "Alumina": ((4, 1), (15, 1), (4, 1), (15, 1)),
    "CFRP": ((3, 1), (12, 1), (4, 1), (12, 1)),
    "Nylon": ((1, 1), (3, 1), (1, 3), (1, 3)),
    "Mg": ((2, 1), (8, 1), (2, 1), (8, 1)),
    "WC": ((3, 1), (10, 1), (3, 1), (10, 1)),
}
# a few more: (design, segments, convention, segment mass, sensor timing) -> (k, p)
OTHER_AUTO = {
    ("TrabecularBone", 5, "bending", "capsule", "authors"): (1, 6),
    ("TrabecularBone", 1, "bending", "leg", "fresh"): (1, 1),
    ("SS", 1, "axial", "capsule", 3): (1, 3),
    ("WC", 5, "axial+bending", "capsule", "fresh"): (15, 1),
    ("rho-inc", 3, "bending", "leg", "authors"): (1, 2),  # its flight loop resonates within 10 % above 1e-4 s
    ("PVC-Ti-SS", 3, "axial", "capsule", 3): (3, 3),
    ("Tendon", 5, "axial+bending", "leg", 3): (1, 4),
}


def test_auto_keeps_the_substeps_of_the_catalogue():
    from mat_hopper.core.conventions import CONVENTIONS
    from mat_hopper.core.materials import parse_design

    assert CONVENTIONS == ("paper", "axial", "bending", "axial+bending") and len(CATALOGUE_AUTO) == 13
    got = {m: tuple(auto_timestep(m, c) for c in CONVENTIONS) for m in CATALOGUE_AUTO}
    for m, want in CATALOGUE_AUTO.items():
        assert [k for k, _ in got[m]] == [k for k, _ in want], m
        assert [dt for _, dt in got[m]] == pytest.approx([1e-4 / p / k for k, p in want], rel=1e-12), m
    for (name, n, conv, mass, timing), (k, p) in OTHER_AUTO.items():
        d = parse_design(name, n)
        assert auto_timestep(d, conv, mass, timing) == (k, pytest.approx(1e-4 / p / k, rel=1e-12)), name


def test_building_settings_compiles_no_model(monkeypatch):
    """sim_settings(timestep_s="auto"), a profile's settings and resolve_timestep
    read the leg's masses and stiffnesses from the design, not from a model."""
    import mujoco

    from mat_hopper.core.materials import parse_design
    from mat_hopper.core.model import build_model
    from mat_hopper.core.sim import sim_settings
    from mat_hopper.experiments.profiles import PROFILES

    def compiled(*args, **kwargs):
        raise AssertionError("a MuJoCo model was compiled")

    monkeypatch.setattr(mujoco.MjSpec, "compile", compiled)
    for conv in ("Paper", "axial", "BENDING", "axial+bending"):
        s = sim_settings("TrabecularBone", duration_s=2.0, transient_s=1.0, timestep_s="auto", convention=conv)
        assert s.substeps >= 1 and s.convention == conv.lower()
        assert resolve_timestep("auto", "SS", conv, "capsule", "fresh")[1] >= 1
    bending = PROFILES["quick"].for_convention("bending")
    assert bending.sim_settings(design="SS").substeps == 3
    with pytest.raises(AssertionError, match="compiled"):  # the patch bites
        build_model(parse_design("SS"))
