"""``mat-hopper simulate --control``: the controls of any design, from the CLI."""

import os

import pandas as pd
import pytest

from mat_hopper.cli import main
from mat_hopper.core.control_legs import CONTROLS, control, mass_properties
from mat_hopper.core.materials import CATALOGUE, LegDesign, paper_designs, parse_design


@pytest.mark.parametrize("kind", CONTROLS)
def test_simulate_control_writes_the_controls_rows(tmp_path, kind, capsys):
    out = tmp_path / "hops.csv"
    rc = main(
        ["simulate", "--design", "rho-inc", "--control", kind, "--duration", "4", "--transient", "2"]
        + ["--csv", str(out), "--no-progress"]
    )
    assert rc == 0
    table = pd.read_csv(out)
    assert (table.design == f"rho-inc~{kind}").all() and len(table) >= 1
    mp = mass_properties(parse_design("rho-inc"))
    assert table["leg_mass_kg"].iloc[0] == pytest.approx(mp.leg_mass_kg)
    text = capsys.readouterr().out
    assert "hip inertia" in text and "by the thrust" in text


def test_every_catalogue_design_and_gradient_has_its_controls():
    designs = [LegDesign.mono(m) for m in CATALOGUE.values()] + list(paper_designs().values())
    for d in designs:
        for kind in CONTROLS:
            c = control(d, kind)
            assert c.name == f"{d.name}~{kind}"
            assert mass_properties(c).leg_mass_kg == pytest.approx(mass_properties(d).leg_mass_kg, rel=1e-12)


def test_unknown_control_is_refused(capsys):
    with pytest.raises(SystemExit) as e:
        main(["simulate", "--control", "springy"])
    assert e.value.code == 2


def test_a_fall_is_told_apart_from_a_numerical_divergence(capsys):
    # SS under bending at the auto step on the default soft contact: the leg
    # chatters and the hopper rolls over near 11.7 s; an
    # axial leg at the authors' 1e-4 s step diverges numerically in 0.9 ms.
    main(["simulate", "--design", "SS", "--convention", "bending", "--timestep", "auto"]
         + ["--behaviour", "forward", "--duration", "13", "--transient", "5"])  # fmt: skip
    out = capsys.readouterr().out
    assert "UNSTABLE: the hopper fell (base tilted past 60 deg" in out and "--contact stiff" in out
    main(["simulate", "--design", "SS", "--convention", "axial", "--duration", "2", "--transient", "1"])
    out = capsys.readouterr().out
    assert "UNSTABLE: diverged at t = 0.0009 s (numerical divergence" in out and "try --timestep auto" in out


@pytest.mark.parametrize(
    "command, design",
    [
        ("simulate", "rho-inc"),
        ("simulate", "PVC-Ti-SS"),
        ("simulate", "custom(1.39/70,8/rigid)"),
        ("render", "rho-dec"),
        ("modes", "SS-Ti-PVC"),
    ],
)
def test_segments_with_a_design_that_sets_its_own_is_refused(tmp_path, monkeypatch, capsys, command, design):
    # `simulate --design rho-inc --segments 4` must not run rho-inc's 3 segments, --segments ignored
    monkeypatch.chdir(tmp_path)
    extra = ["--still", "s.png"] if command == "render" else []
    assert main([command, "--design", design, "--segments", "4", *extra]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "--segments is for a single-material --design" in err, err
    assert f"--design {design} has its own" in err and "Traceback" not in err
    assert os.listdir(tmp_path) == []


def test_segments_still_set_a_single_material_design():
    import argparse

    from mat_hopper.cli.simulate import add_sim_arguments, design_from_args

    p = argparse.ArgumentParser()
    add_sim_arguments(p)
    assert design_from_args(p.parse_args(["--design", "ss", "--segments", "5"])).n_segments == 5
    assert design_from_args(p.parse_args(["--design", "rho=8 E=193", "--segments", "2"])).n_segments == 2
    assert design_from_args(p.parse_args(["--design", "rho-inc"])).n_segments == 3


def test_control_rigid_of_a_rigid_leg_is_refused_naming_the_design(capsys):
    assert main(["simulate", "--design", "MD", "--control", "rigid", "--duration", "1", "--transient", "0"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--control rigid" in err and "MD" in err and "no springs" in err


def test_a_run_cut_short_by_divergence_says_stopped_not_done(capsys):
    # an axial leg at the authors' 1e-4 s step diverges numerically in 0.9 ms
    main(["simulate", "--design", "SS", "--convention", "axial", "--duration", "2", "--transient", "1"])
    err = capsys.readouterr().err
    assert "SS: stopped" in err and "SS: done" not in err, err


FIVE = ["--density", "2.0,3.0,4.5,6.0,7.8", "--modulus", "50,80,110,150,200", "--behaviour", "forward"]


def test_a_step_above_the_bound_is_warned_of_and_a_divergence_says_when_why_and_what_to_try(capsys):
    # the five-segment leg's springs' bound, 9.29e-05 s, lies under the authors' 1e-4 s step
    argv = ["simulate", *FIVE, "--duration", "2", "--transient", "1", "--no-progress"]
    assert main(argv) == 1
    cap = capsys.readouterr()
    warned = [line for line in cap.err.splitlines() if "warning" in line]
    assert len(warned) == 1 and warned[0].startswith("mat-hopper simulate: warning: the physics step 0.0001 s is above")
    assert "analytic stable step 9.29e-05 s" in warned[0] and "try --timestep auto (3 physics substeps" in warned[0]
    line = next(x for x in cap.out.splitlines() if x.startswith("UNSTABLE"))
    assert line.startswith("UNSTABLE: diverged at t = 0.0043 s (numerical divergence: |qacc| ")  # when, which check
    assert "at joint mat_spring_" in line and "above this leg's analytic stable step 9.29e-05 s" in line  # why
    assert line.endswith("try --timestep auto (3 physics substeps of 3.33e-05 s per 0.0001 s control period)")
    # the same leg at --timestep auto: no warning, it hops, exit 0
    assert main([*argv, "--timestep", "auto"]) == 0
    cap = capsys.readouterr()
    assert "warning" not in cap.err and "UNSTABLE" not in cap.out and "1 hop cycles scored" in cap.out


def test_progress_stops_at_the_divergence_not_at_a_chunks_end(capsys):
    """CFRP diverges at 2.1 ms: the progress line says "stopped" there
    (it said 1/2 sim s, the end of the first progress chunk)."""
    from mat_hopper.cli import main

    assert main(["simulate", "--design", "CFRP", "--duration", "2", "--transient", "1"]) == 1
    err = capsys.readouterr().err
    assert "CFRP: stopped, 0.0021/2 sim s" in err and "CFRP: done" not in err


def test_hop_cycles_before_a_divergence_are_not_called_results(capsys):
    # the five-segment leg diverges at 0.0043 s at the authors' 1e-4 s step
    assert main(["simulate", *FIVE, "--duration", "2", "--transient", "1", "--no-progress"]) == 1
    out = capsys.readouterr().out
    assert "scored after 1 s, before the divergence at t = 0.0043 s: not results" in out
