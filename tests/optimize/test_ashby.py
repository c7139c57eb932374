"""Ashby classes as regions (mat_hopper.optimize._ashby) and the search
space restricted to them; the study's record of the leg's length and mass
convention. Expected values: hand-made hulls and hand-worked nearest
points, a brute-force search of the boundary, the catalogue's own numbers."""

from __future__ import annotations

import math

import numpy as np
import optuna
import pytest

from mat_hopper.core.materials import LegDesign, Material, paper_designs
from mat_hopper.experiments.profiles import Profile
from mat_hopper.optimize import Objective, SearchSpace, StudyConfig, create_or_load
from mat_hopper.optimize._ashby import (
    ASHBY_CLASSES,
    class_hulls,
    classes_bounds,
    hull_of,
    in_classes,
    project,
    segment_class,
)

optuna.logging.set_verbosity(optuna.logging.WARNING)


def test_hand_made_hulls():
    square = hull_of([(0, 0), (1, 0), (1, 1), (0, 1), (0.5, 0.5)])  # the centre is not a vertex
    assert square.kind == "polygon" and len(square.vertices) == 4
    assert square.contains(0.5, 0.5) and square.contains(1.0, 0.3)  # inside, on an edge
    assert not square.contains(1.01, 0.5)
    assert square.nearest(2.0, 0.5) == (1.0, 0.5)  # straight across the right edge
    assert square.nearest(2.0, 3.0) == (1.0, 1.0)  # the corner
    assert square.nearest(0.25, 0.75) == (0.25, 0.75)  # inside: itself
    seg = hull_of([(0, 0), (1, 1), (0.5, 0.5)])  # collinear: Qhull refuses, a segment
    assert seg.kind == "segment" and seg.contains(0.25, 0.25) and not seg.contains(0.25, 0.3)
    assert seg.nearest(1.0, 0.0) == pytest.approx((0.5, 0.5))  # foot of the perpendicular
    assert seg.nearest(3.0, 2.0) == pytest.approx((1.0, 1.0))  # beyond the end
    pt = hull_of([(0.2, 0.3)])
    assert pt.kind == "point" and pt.nearest(5, 5) == (0.2, 0.3) and pt.contains(0.2, 0.3)


def test_catalogue_hulls():
    hulls = class_hulls()
    assert set(ASHBY_CLASSES) == {"metal", "polymer", "natural", "ceramic", "composite"}  # MD (rigid) in none
    assert set(hulls["metal"].members) == {"Mg", "Al", "Ti", "SS"}
    assert hulls["polymer"].kind == "segment" and hulls["composite"].kind == "point"
    assert hulls["natural"].kind == "polygon"
    # the catalogue's numbers: metals from Mg (1.8, 45) to SS (8, 193)
    assert classes_bounds("metal") == ((1.8, 8.0), (45.0, 193.0))
    assert classes_bounds(["metal", "polymer"]) == ((1.13, 8.0), (2.9, 193.0))
    for name in ("SS", "Al", "Ti", "PVC"):
        assert in_classes(paper_designs()[name])
    assert segment_class(paper_designs()["SS"].segments[0]) == "metal"
    # the old book's trial 20 lies in the design box but in no class
    assert segment_class(Material("t20", 11.9, 0.96)) is None
    # rho-inc's 1.39 g/cm^3 at 70 GPa is no catalogue class either
    assert not in_classes(paper_designs()["rho-inc"])
    assert not in_classes(paper_designs()["MD"])  # rigid


def test_projection_is_the_nearest_hull_point_by_brute_force():
    hulls = class_hulls()
    boundary = []
    for c in ("metal", "polymer"):
        v = hulls[c].vertices
        n = len(v) if len(v) >= 3 else 1
        for i in range(n):
            a, b = v[i], v[(i + 1) % len(v)]
            boundary.append(a + np.linspace(0, 1, 20001)[:, None] * (b - a))
    boundary = np.vstack(boundary)
    for rho, e in ((11.9, 0.96), (1.0, 1000.0), (3.0, 10.0), (20.0, 300.0)):
        d, m, cls = project(rho, e, ("metal", "polymer"))
        p = np.array([math.log10(rho), math.log10(e)])
        brute = np.hypot(*(boundary - p).T).min()
        assert math.hypot(math.log10(d) - p[0], math.log10(m) - p[1]) == pytest.approx(brute, abs=1e-5)
        assert segment_class(Material("x", d, m), ("metal", "polymer")) == cls
    assert project(4.43, 120.0, ["polymer", "metal"]) == (4.43, 120.0, "metal")  # inside: unchanged


def test_space_restricted_to_classes():
    space = SearchSpace(ashby_classes="metal,polymer")
    assert space.ashby_classes == ("metal", "polymer")
    assert space.density_g_cm3 == (1.13, 8.0) and space.modulus_gpa == (2.9, 193.0)
    assert [n for n, _ in space.seeds()] == ["SS", "PVC-Ti-SS", "SS-Ti-PVC", "PVC", "Al", "Ti"]
    study = optuna.create_study(sampler=optuna.samplers.RandomSampler(seed=3), directions=["minimize"] * 2)
    for _ in range(60):
        t = study.ask()
        d = space.suggest(t)
        assert in_classes(d, ("metal", "polymer")), d
        study.tell(t, [0.0, 0.0])
    assert SearchSpace.from_key(space.key()) == space
    assert "ashby_classes" not in SearchSpace().key()  # older studies keep their key
    with pytest.raises(ValueError, match="give either bounds or ashby_classes"):
        SearchSpace(ashby_classes="metal", density_g_cm3=(1.0, 20.0))
    with pytest.raises(ValueError, match="unknown Ashby class 'metals'"):
        SearchSpace(ashby_classes="metals")
    cat = SearchSpace(kinds="catalogue", ashby_classes="polymer")
    assert cat.materials == ("PVC", "Nylon")
    with pytest.raises(ValueError, match="of the classes composite"):
        SearchSpace(kinds="catalogue", ashby_classes="composite", materials=("SS",))
    assert in_classes(LegDesign.mono("CFRP"), ("composite",))


def test_study_refuses_to_mix_leg_conventions(tmp_path):
    tiny = Profile("tiny", duration_s=2.0, transient_s=0.5)
    leg = StudyConfig("mix", SearchSpace(), Objective(replicates=0, profile=tiny))
    assert leg.key()["objective"]["segment_mass"] == "leg"
    assert leg.key()["objective"]["leg_material_length_m"] == 0.3  # 0.3 m of material at any N
    assert Objective(replicates=0, profile=tiny, segment_mass="capsule").sim_settings().segment_mass == "capsule"
    url = f"sqlite:///{tmp_path}/mix.db"
    create_or_load(leg, url)
    capsule = StudyConfig("mix", SearchSpace(), Objective(replicates=0, profile=tiny, segment_mass="capsule"))
    with pytest.raises(ValueError, match=r"objective.segment_mass: study has 'leg', asked 'capsule'"):
        create_or_load(capsule, url)
    # a study stored before the convention was recorded is refused too
    old = leg.key()
    del old["objective"]["segment_mass"], old["objective"]["leg_material_length_m"]
    study = optuna.create_study(study_name="old", storage=url, directions=["minimize"] * 2)
    study.set_user_attr("mat_hopper_config", old)
    with pytest.raises(ValueError, match="segment_mass: study has None, asked 'leg'"):
        create_or_load(StudyConfig("old", SearchSpace(), Objective(replicates=0, profile=tiny)), url)
    with pytest.raises(ValueError, match="unknown segment mass convention"):
        Objective(replicates=0, profile=tiny, segment_mass="per-capsule")


def test_cli_config_carries_classes_and_mass_convention():
    import argparse

    from mat_hopper.cli.optimize import config_from_args, register_cli

    parser = argparse.ArgumentParser()
    register_cli(parser.add_subparsers())
    args = parser.parse_args(
        ["optimize", "--study", "s", "--ashby-classes", "metal,polymer", "--segment-mass", "capsule"]
    )
    config = config_from_args(args, None)
    assert config.space.ashby_classes == ("metal", "polymer") and config.space.modulus_gpa == (2.9, 193.0)
    assert config.objective.segment_mass == "capsule"
    resumed = config_from_args(parser.parse_args(["optimize", "--study", "s"]), config)  # stored settings kept
    assert resumed.key() == config.key()
