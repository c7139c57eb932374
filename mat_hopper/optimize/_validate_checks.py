"""The checks of a front's validation: their settings, the controls and the run specs.

A front design is run again under each check of :data:`CHECKS` (the
nominal run, seeded replicates on seeds 0..n-1, every other behaviour, a
2e-5 s physics step with and without the 1e-4 s control period, the axial
springs at their automatic step), its controls (mass-matched leg, rigid
twin, homogeneous legs of its mass) and the paper's designs on the same
replicates, so that every comparison can be paired by seed. Time steps in
s, moduli in GPa. Used by :mod:`mat_hopper.optimize.validate`.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ..analysis import paired
from ..core.behaviours import BEHAVIOUR_NAMES
from ..core.behaviours import behaviour as get_behaviour
from ..core.control_legs import mass_matched, rigid_twin
from ..core.materials import LegDesign, paper_designs
from ..core.timestep import FINE_SUBSTEPS, FINE_TIMESTEP_S, resolve_timestep
from ..experiments.runner import RunSpec
from ..util.keys import design_key
from ._objective import Objective

NOMINAL, REPLICATE, BEHAVIOUR = "nominal", "replicate", "behaviour"
FINE_CONTROL, FINE_PLAIN, AXIAL = "step 2e-5 s, control 1e-4 s", "step 2e-5 s", "axial"
CHECKS = (NOMINAL, REPLICATE, BEHAVIOUR, FINE_CONTROL, FINE_PLAIN, AXIAL)
CONFIDENCE = 0.95
ALPHA = 0.05
CONTROL_KINDS = {"mass": "mass-matched", "rigid": "rigid twin"}
HOMOGENEOUS = "homogeneous"  # comparator kind: homogeneous legs of the design's mass, a range of moduli
HOMOGENEOUS_MODULI_GPA = (1.0, 10.0, 100.0, 1000.0)  # spans the search space's 0.1-1000 GPa in decades
EQUIVALENCE_MARGIN = paired.EQUIVALENCE_MARGIN
# domination rules (mat_hopper.optimize.validate): "margin" (default) asks non-inferiority on every
# objective beyond the significant one; "significance" only the absence of a significant advantage
DOMINANCE_RULES = ("margin", "significance")
DEFAULT_DOMINANCE = "margin"


def check_dominance(rule: str) -> str:
    """`rule` if it is one of :data:`DOMINANCE_RULES`.

    Args:
        rule: a domination rule's name.

    Returns:
        The name.

    Raises:
        ValueError: an unknown rule (the message lists the known ones).
    """
    if rule not in DOMINANCE_RULES:
        raise ValueError(f"unknown dominance rule {rule!r}; known: {', '.join(DOMINANCE_RULES)}")
    return rule


def check_settings(design: LegDesign, objective: Objective) -> dict:
    """{check: SimSettings} of the study's behaviours for one design (:data:`CHECKS`).

    Args:
        design: the LegDesign (needed for the automatic time step of the
            ``auto`` and ``axial`` settings).
        objective: the study's objective (its profile, convention and
            segment-mass convention).

    Returns:
        A dict of four SimSettings, the same for every behaviour:
        ``nominal`` (the objective's settings), ``step 2e-5 s, control 1e-4
        s`` (2e-5 s step, 5 substeps, sensor latency of 5 steps), ``step
        2e-5 s`` (2e-5 s step) and ``axial`` (the ``axial`` convention at
        its automatic time step and substeps,
        :func:`mat_hopper.core.timestep.resolve_timestep`).
    """
    base = objective.sim_settings(design=design)
    dt, k = resolve_timestep("auto", design, "axial", objective.segment_mass)
    return {
        NOMINAL: base,
        FINE_CONTROL: replace(base, timestep_s=FINE_TIMESTEP_S, substeps=FINE_SUBSTEPS, sensor_timing=FINE_SUBSTEPS),
        FINE_PLAIN: replace(base, timestep_s=FINE_TIMESTEP_S),
        AXIAL: replace(base, convention="axial", timestep_s=dt, substeps=k),
    }


def homogeneous_legs(design: LegDesign, moduli_gpa=HOMOGENEOUS_MODULI_GPA) -> dict:
    """Homogeneous legs of `design`'s leg mass across moduli: the best a
    single material of that mass can do is among them, so a gradient that
    none of them dominates offers what no homogeneous leg of its mass does.

    Args:
        design: the leg whose mass (mean density) they share.
        moduli_gpa: their moduli, GPa.

    Returns:
        {"E=<modulus>": LegDesign}, every segment at the design's mean
        density (the same leg mass under the ``leg`` segment-mass rule).
    """
    rho = float(np.mean(design.densities_g_cm3))
    n = design.n_segments
    return {
        f"E={e:g}": LegDesign.from_properties([rho] * n, [float(e)] * n, name=f"homogeneous {rho:.3g} g/cm3 E={e:g}")
        for e in moduli_gpa
    }


def _controls(name: str, design: LegDesign) -> dict:
    """{label: LegDesign} of a front design's controls that differ from it
    in physics (a homogeneous leg is its own mass-matched leg; a rigid leg
    its own twin), and, for a gradient, the homogeneous legs of its mass
    (:func:`homogeneous_legs`, labels ``homogeneous E=...``)."""
    out = {}
    for kind, make in (("mass", mass_matched), ("rigid", rigid_twin)):
        try:
            c = make(design)
        except ValueError:  # e.g. no series-equivalent modulus in range
            continue
        if design_key(c) != design_key(design):
            out[kind] = c
    if is_gradient(design):
        out.update({f"{HOMOGENEOUS} {k}": leg for k, leg in homogeneous_legs(design).items()})
    return out


def validation_tasks(front: dict, objective: Objective, replicates: int, paper: dict | None = None) -> list:
    """RunSpecs of every check of every `front` design ({name: LegDesign}),
    the replicates of each front design's controls, and the replicates
    (and nominal runs) of the `paper` designs (default: all nine).
    Replicate seeds 0..n-1 (:meth:`Profile.replicate`): never the search's
    (1000..).

    Args:
        front: {name: LegDesign} of the front designs.
        objective: the study's objective (profile, behaviours, settings).
        replicates: perturbed replicates per design and behaviour (seeds
            0 .. replicates - 1); not checked here.
        paper: {name: LegDesign} of the paper designs compared against;
            None (the default) for :func:`mat_hopper.core.materials.paper_designs`.

    Returns:
        A list of RunSpec, labels role (``front``, ``paper`` or ``control``),
        design, behaviour, check (one of :data:`CHECKS`), replicate (-1 for
        an unperturbed run), control_of (the front design's name, or "") and
        control (``mass``, ``rigid``, ``homogeneous E=<GPa>``, or ""). Front
        designs: the replicates and every :func:`check_settings` check on the
        study's behaviours, and the nominal run on each other behaviour;
        their controls (named ``<name>~<kind>``;
        :func:`mat_hopper.core.control_legs.mass_matched` and
        :func:`mat_hopper.core.control_legs.rigid_twin` where they differ in physics,
        and the homogeneous legs of a gradient): the replicates; paper
        designs: the replicates and the nominal run.
    """
    tasks = []
    others = [b for b in BEHAVIOUR_NAMES if b not in objective.behaviours]
    paper = paper_designs() if paper is None else paper
    prof = objective.profile

    def add(role, name, design, beh, settings, check, rep=-1, of="", kind=""):
        labels = {"role": role, "design": name, "behaviour": beh, "check": check, "replicate": rep}
        labels.update({"control_of": of, "control": kind})
        tasks.append(RunSpec(design, get_behaviour(beh), settings, labels))

    def replicates_of(role, name, d, of="", kind=""):
        for b in objective.behaviours:
            for r in range(replicates):
                add(role, name, d, b, objective.sim_settings(prof.replicate(r), d), REPLICATE, r, of, kind)

    for role, designs in (("front", front), ("paper", paper)):
        for name, d in designs.items():
            replicates_of(role, name, d)
            for b in objective.behaviours:
                if role == "paper":
                    add(role, name, d, b, objective.sim_settings(design=d), NOMINAL)
                    continue
                for check, st in check_settings(d, objective).items():
                    add(role, name, d, b, st, check)
            if role == "front":
                for b in others:
                    add(role, name, d, b, objective.sim_settings(design=d), BEHAVIOUR)
                for kind, c in _controls(name, d).items():
                    replicates_of("control", f"{name}~{kind}", c, name, kind)
    return tasks


def is_gradient(design: LegDesign) -> bool:
    """Whether a design's segments differ (in density or modulus).

    Args:
        design: the LegDesign.

    Returns:
        True when two of its segments have different (density, modulus)
        pairs (a rigid segment's modulus is None); False for a homogeneous leg.
    """
    return len(set(zip(design.densities_g_cm3, design.moduli_gpa))) > 1
