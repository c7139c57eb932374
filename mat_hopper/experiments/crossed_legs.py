"""The crossed legs: ρ-inc and SS with their moduli swapped, a 2 x 2 factorial.

ρ-inc and SS differ in both density profile and modulus (70 against
193 GPa), so their paired difference cannot say which of the two makes it.
Two crossed legs can: ρ-inc's densities at SS's modulus, and SS's
densities at ρ-inc's. Each differs from a paper design in its modulus
alone, and the four legs (:func:`legs`) make a factorial of mass
distribution x modulus, run on the ramp on the profile's replicate seeds
(paired). :data:`CONTRASTS` names the comparisons the factorial reads;
:func:`mat_hopper.analysis.factorial.factorial_effects` turns the runs'
means into their paired effects, Holm families and conclusions.

Two timing rules:

- :func:`tasks` (chapter 9c): the profile's convention and contact, the
  controller keeping its period, every leg at the physics substeps the
  stiffest needs (:func:`mat_hopper.core.timestep.auto_timestep`);
- :func:`common_step_tasks` (a convention and contact named, e.g. a
  bending leg on stiff contact): every leg at one control period and one
  physics step, the finest any of the four needs under ``timestep_s="auto"``,
  so they are compared alike.
"""

from __future__ import annotations

from dataclasses import replace

from ..core.behaviours import behaviour
from ..core.materials import LegDesign, parse_design
from ..core.timestep import auto_timestep
from .common_step import at_common_step
from .common_step import common_step as shared_step
from .profiles import get_profile
from .runner import RunSpec

BEHAVIOUR = "ramp"  # the behaviour of the abstract's claim (ρ-inc against SS)
CLAIM = "claim: rho-inc against SS"  # the contrast that is the claim itself, a Holm family of its own


def legs() -> dict[str, LegDesign]:
    """The four legs of the factorial, by label.

    Returns:
        dict, in this order: ``"rho-inc"``; ``"rho-inc at 193 GPa"``
        (ρ-inc's densities at SS's modulus); ``"SS at 70 GPa"`` (SS's
        densities at ρ-inc's modulus); ``"SS"``. The moduli in the labels are
        the designs' own (:func:`mat_hopper.core.materials.parse_design`);
        the crossed LegDesigns are named ``rho-inc-at-193GPa`` and
        ``SS-at-70GPa``.
    """
    rho, ss = parse_design("rho-inc"), parse_design("SS")
    return {
        "rho-inc": rho,
        f"rho-inc at {ss.moduli_gpa[0]:g} GPa": LegDesign.from_properties(
            rho.densities_g_cm3, ss.moduli_gpa, name=f"rho-inc-at-{ss.moduli_gpa[0]:g}GPa"
        ),
        f"SS at {rho.moduli_gpa[0]:g} GPa": LegDesign.from_properties(
            ss.densities_g_cm3, rho.moduli_gpa, name=f"SS-at-{rho.moduli_gpa[0]:g}GPa"
        ),
        "SS": ss,
    }


def _contrasts() -> dict[str, tuple[str, str]]:
    rho, rho_stiff, ss_soft, ss = legs()
    return {
        CLAIM: (rho, ss),
        "modulus 70 vs 193 GPa, at rho-inc's densities": (rho, rho_stiff),
        "modulus 70 vs 193 GPa, at SS's densities": (ss_soft, ss),
        "densities rho-inc vs SS, at 70 GPa": (rho, ss_soft),
        "densities rho-inc vs SS, at 193 GPa": (rho_stiff, ss),
    }


# label: (leg, against), leg labels of legs(). The claim, then the four factorial
# contrasts: each modulus contrast holds the densities, each density contrast the modulus.
CONTRASTS = _contrasts()


def shared_substeps() -> int:
    """The physics substeps per control period every leg takes in :func:`tasks`.

    ρ-inc's light segments on SS's stiff springs diverge at the paper's
    1e-4 s step within milliseconds, so all four legs take the substeps the
    stiffest needs under the default convention and contact
    (:func:`mat_hopper.core.timestep.auto_timestep`); the controller keeps its period.

    Returns:
        int >= 1.
    """
    return max(auto_timestep(leg)[0] for leg in legs().values())


def _labels(name: str, seed: int) -> dict:
    return {"leg": name, "replicate": seed}


def tasks(profile) -> list[RunSpec]:
    """The crossed legs' runs as chapter 9c runs them: the ramp, the profile's
    replicate seeds, the profile's control period split into
    :func:`shared_substeps` physics substeps.

    Args:
        profile: a Profile or its name (``"paper"``, ``"quick"``).

    Returns:
        list of RunSpec, leg by leg (the order of :func:`legs`), seed by seed;
        labels: leg (its label in :func:`legs`), replicate.

    Raises:
        ValueError: an unknown profile name.
    """
    profile = get_profile(profile)
    k = shared_substeps()
    out = []
    for name, leg in legs().items():
        for seed in range(profile.replicates):
            s = profile.sim_settings(profile.replicate(seed), design=leg)
            s = replace(s, substeps=k, timestep_s=s.timestep_s / k)
            out.append(RunSpec(leg, behaviour(BEHAVIOUR), s, _labels(name, seed)))
    return out


def common_step(convention: str, contact: str) -> tuple[float, int]:
    """One control period and one physics step for all four legs under a
    convention and a contact: the shortest control period and the shortest
    physics step any leg needs under ``timestep_s="auto"``
    (:func:`mat_hopper.core.timestep.auto_timestep`).

    Args:
        convention: the stiffness convention (e.g. ``"bending"``).
        contact: the contact setting (e.g. ``"stiff"``).

    Returns:
        (control period s, physics substeps per period >= 1); the physics
        step is period / substeps.

    Raises:
        ValueError: as :func:`~mat_hopper.core.timestep.auto_timestep` raises
            (unknown convention or contact).
    """
    return shared_step(legs().values(), convention, contact)


def common_step_tasks(profile, convention: str, contact: str) -> list[RunSpec]:
    """The crossed legs' runs under a named convention and contact, all at
    :func:`common_step`: the ramp, the profile's replicate seeds.

    Args:
        profile: a Profile or its name (``"paper"``, ``"quick"``).
        convention: the stiffness convention (e.g. ``"bending"``).
        contact: the contact setting (e.g. ``"stiff"``).

    Returns:
        list of RunSpec, leg by leg, seed by seed; labels: leg, replicate.

    Raises:
        ValueError: an unknown profile, convention or contact.
    """
    profile = get_profile(profile)
    period, k = common_step(convention, contact)
    out = []
    for name, leg in legs().items():
        for seed in range(profile.replicates):
            s = profile.sim_settings(profile.replicate(seed), design=leg)
            s = at_common_step(replace(s, convention=convention, contact=contact), period, k)
            out.append(RunSpec(leg, behaviour(BEHAVIOUR), s, _labels(name, seed)))
    return out
