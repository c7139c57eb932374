"""The crossed legs' runs: the library builds the very runs chapter 9c and
the bending benchmark built inline, so their cached results are found again.

The references below are the old inline constructions, copied as they were
(chapter 9c's cell and ``benchmarks/crossed_legs_bending.py``'s ``tasks``)."""

from dataclasses import replace

import pytest

from mat_hopper.core.behaviours import behaviour
from mat_hopper.core.materials import LegDesign, parse_design
from mat_hopper.core.timestep import auto_timestep
from mat_hopper.experiments import crossed_legs
from mat_hopper.experiments.profiles import get_profile
from mat_hopper.experiments.runner import RunSpec


def _chapter_9c_tasks(profile):
    rho, ss = parse_design("rho-inc"), parse_design("SS")
    crossed = {
        "rho-inc": rho,
        f"rho-inc at {ss.moduli_gpa[0]:g} GPa": LegDesign.from_properties(
            rho.densities_g_cm3, ss.moduli_gpa, name=f"rho-inc-at-{ss.moduli_gpa[0]:g}GPa"
        ),
        f"SS at {rho.moduli_gpa[0]:g} GPa": LegDesign.from_properties(
            ss.densities_g_cm3, rho.moduli_gpa, name=f"SS-at-{rho.moduli_gpa[0]:g}GPa"
        ),
        "SS": ss,
    }
    substeps = max(auto_timestep(leg)[0] for leg in crossed.values())
    tasks = []
    for name, leg in crossed.items():
        for seed in range(profile.replicates):
            settings = profile.sim_settings(profile.replicate(seed), design=leg)
            settings = replace(settings, substeps=substeps, timestep_s=settings.timestep_s / substeps)
            tasks.append(RunSpec(leg, behaviour("ramp"), settings, {"leg": name, "replicate": seed}))
    return tasks


def _bending_benchmark_tasks(profile, convention, contact):
    rho, ss = parse_design("rho-inc"), parse_design("SS")
    legs = {
        "rho-inc": rho,
        "rho-inc at 193 GPa": LegDesign.from_properties(rho.densities_g_cm3, ss.moduli_gpa, name="rho-inc-at-193GPa"),
        "SS at 70 GPa": LegDesign.from_properties(ss.densities_g_cm3, rho.moduli_gpa, name="SS-at-70GPa"),
        "SS": ss,
    }
    autos = [auto_timestep(leg, convention, contact=contact) for leg in legs.values()]
    period = min(k * dt for k, dt in autos)
    dt = min(dt for _, dt in autos)
    substeps = max(1, round(period / dt))
    out = []
    for name, leg in legs.items():
        for seed in range(profile.replicates):
            s = profile.sim_settings(profile.replicate(seed), design=leg)
            s = replace(s, convention=convention, contact=contact, timestep_s=period / substeps, substeps=substeps)
            out.append(RunSpec(leg, behaviour("ramp"), s, {"leg": name, "replicate": seed}))
    return out, period, substeps


def _keyed(tasks):
    return [(t.key(), t.labels) for t in tasks]


@pytest.mark.parametrize("profile", ["quick", "paper"])
def test_tasks_are_chapter_9c_runs(profile):
    ours = crossed_legs.tasks(profile)
    assert _keyed(ours) == _keyed(_chapter_9c_tasks(get_profile(profile)))
    assert len(ours) == 4 * get_profile(profile).replicates
    # the keys tell the legs apart and the seeds apart (the comparison above is not vacuous)
    assert len({t.key() for t in ours}) == len(ours)


def test_common_step_tasks_are_the_bending_benchmark_runs():
    ours = crossed_legs.common_step_tasks("quick", "bending", "stiff")
    ref, period, substeps = _bending_benchmark_tasks(get_profile("quick"), "bending", "stiff")
    assert _keyed(ours) == _keyed(ref)
    assert crossed_legs.common_step("bending", "stiff") == (period, substeps)
    # one step for every leg, and not chapter 9c's (a different rule, different runs)
    assert {(t.settings.timestep_s, t.settings.substeps) for t in ours} == {(period / substeps, substeps)}
    assert not {t.key() for t in ours} & {t.key() for t in crossed_legs.tasks("quick")}


def test_legs_and_contrasts_name_the_factorial():
    legs = crossed_legs.legs()
    assert list(legs) == ["rho-inc", "rho-inc at 193 GPa", "SS at 70 GPa", "SS"]
    assert [d.name for d in legs.values()] == ["rho-inc", "rho-inc-at-193GPa", "SS-at-70GPa", "SS"]
    # each crossed leg keeps one design's densities and takes the other's modulus
    assert legs["rho-inc at 193 GPa"].densities_g_cm3 == legs["rho-inc"].densities_g_cm3
    assert legs["rho-inc at 193 GPa"].moduli_gpa == legs["SS"].moduli_gpa
    assert legs["SS at 70 GPa"].densities_g_cm3 == legs["SS"].densities_g_cm3
    assert legs["SS at 70 GPa"].moduli_gpa == legs["rho-inc"].moduli_gpa
    assert crossed_legs.CONTRASTS == {
        "claim: rho-inc against SS": ("rho-inc", "SS"),
        "modulus 70 vs 193 GPa, at rho-inc's densities": ("rho-inc", "rho-inc at 193 GPa"),
        "modulus 70 vs 193 GPa, at SS's densities": ("SS at 70 GPa", "SS"),
        "densities rho-inc vs SS, at 70 GPa": ("rho-inc", "SS at 70 GPa"),
        "densities rho-inc vs SS, at 193 GPa": ("rho-inc at 193 GPa", "SS"),
    }
    assert crossed_legs.CLAIM in crossed_legs.CONTRASTS
