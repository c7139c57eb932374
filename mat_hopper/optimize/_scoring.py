"""Noise-aware and mass-aware scores: replicates on common random numbers,
a risk measure over them, and the leg-mass constraint.

Replicates. One unperturbed run of a deterministic simulator is one draw:
a 1 um start offset moves the metrics by 0.3 %, while the seeded
replicates of :meth:`mat_hopper.core.perturbations.Perturbation.replicate`
spread them by about 30 %. A study that keeps the best of many single
draws keeps lucky draws (the winner's curse). With ``replicates = K > 0``
every trial runs each of its behaviours under the same K perturbations,
seeds :data:`SEARCH_SEED_START` .. :data:`SEARCH_SEED_START` + K - 1: common
random numbers, so that two trials differ by their designs alone and
their scores are paired, replicate by replicate. The search's seeds lie
apart from the seeds 0, 1, ... that the book's robustness study and the
front's validation (:mod:`mat_hopper.optimize.validate`) draw, so a front
is validated on seeds the search never saw. ``replicates = 0`` is one
unperturbed run per behaviour (a single draw).

Each replicate's value of an objective is the mean over the trial's
behaviours (each behaviour weighs the same) of that replicate's run. The
trial's objective is then, over the K replicate values,

``mean``
    their mean, with its standard error ``s / sqrt(K)`` (``scipy.stats.sem``);
``cvar``
    their conditional value at risk at level alpha (:func:`cvar`): the mean
    of the worst ``1 - alpha`` fraction (the highest values: every objective
    is minimized), with its bootstrap standard error
    (``scipy.stats.bootstrap``, seeded).

The standard errors are kept on the trial (user attr ``standard_error``,
{objective: SE}; None with one replicate) with the replicate values, so that
later comparisons can pair them.

Leg mass. Mass alone explains most of tracking error, so a search over
density is mostly a search over mass. With ``leg_mass`` set (a paper
design's name, whose leg mass becomes the target, or a mass in kg) each
trial gets the constraint ``leg_mass``: ``|m - target| - tolerance`` (kg,
<= 0 feasible), m the leg's mass: the leg body's subtree of MuJoCo's
compiled model (hip stub, material segments, foot), the leg mass that
``simulate``, ``batch`` and the controls report
(:func:`mat_hopper.core.control_legs.mass_properties`: one definition). The
tolerance defaults to :data:`DEFAULT_LEG_MASS_TOLERANCE` of the target.
Every trial records its leg mass, constrained or not.
"""

from __future__ import annotations

import functools
import math

import numpy as np

from ..core.materials import LegDesign, paper_designs
from ..core.perturbations import Perturbation
from ..util.parsing import did_you_mean, is_decimal, is_real, parse_name, parse_number

RISKS = ("mean", "cvar")
# K from the noise study (benchmarks/noise.py; its figures in docs/optimizer.md,
# "Noise-aware scores"): a mean over 4 replicates halves one replicate's
# standard error, pairing on common seeds about halves a difference's
# variance again, and each further halving of the error costs 4 times the runs.
DEFAULT_REPLICATES = 4
MAX_REPLICATES = 64
LEG_MASS_CONSTRAINT = "leg_mass"
SEARCH_SEED_START = 1000  # the search's replicate seeds: SEARCH_SEED_START + 0 .. K - 1
DEFAULT_CVAR_ALPHA = 0.75  # with K = 4: the worst replicate
DEFAULT_LEG_MASS_TOLERANCE = 0.05  # of the target mass
# kg, the largest leg_mass target (and tolerance) accepted: just above the
# heaviest leg any accepted design can have, 269 kg (the densest accepted
# material, 30 g/cm^3 = DENSITY_RANGE_G_CM3's top, in MAX_SEGMENTS = 64
# segments under the capsule convention; 29 kg under the leg convention; SS,
# the paper's heaviest, 7.9 kg). A target above it no design can reach, and a
# tolerance above it constrains nothing (tests/optimize/test_scoring.py checks
# the heaviest leg stays below it).
MAX_LEG_MASS_KG = 300.0
N_BOOT = 2000  # bootstrap resamples of a CVaR's standard error
SE_ATTR = "standard_error"  # trial user attr: {objective: standard error}


def replicate_seeds(replicates: int) -> tuple[int, ...]:
    """The perturbation seeds of every trial of a study with `replicates`
    replicates (the same for every trial: common random numbers).

    Args:
        replicates: the study's number of replicates K (0: none).

    Returns:
        The seeds SEARCH_SEED_START .. SEARCH_SEED_START + K - 1 (1000,
        1001, ...), as a tuple of ints; empty for 0 replicates.
    """
    return tuple(SEARCH_SEED_START + r for r in range(replicates))


def perturbations(replicates: int, scored_window_s: tuple[float, float]) -> list[Perturbation | None]:
    """The perturbations a trial runs under: [None] (one unperturbed run)
    for 0 replicates, else one :meth:`Perturbation.replicate` per seed, its
    push inside ``scored_window_s`` (the profile's (transient_s,
    duration_s), s)."""
    if replicates == 0:
        return [None]
    return [Perturbation.replicate(s, scored_window_s) for s in replicate_seeds(replicates)]


def cvar(values, alpha: float) -> float:
    """Empirical conditional value at risk of minimized `values` at level
    `alpha` in [0, 1): the mean of the upper ``1 - alpha`` tail of their
    empirical distribution, the boundary sample taken in part (Rockafellar
    and Uryasev 2000, eq. for discrete distributions). alpha = 0 gives the
    mean; alpha -> 1 the maximum.

    Ours: neither scipy nor numpy has it (``scipy.stats`` has quantiles and
    trimmed means, not tail means).

    Args:
        values: 1-D array-like of finite numbers (n >= 1).
        alpha: level in [0, 1).

    Returns:
        float, in the units of `values`.

    Raises:
        ValueError: empty `values`, or `alpha` outside [0, 1).
    """
    v = np.sort(np.asarray(values, float).ravel())[::-1]  # worst first
    if len(v) == 0:
        raise ValueError("values: need at least one value")
    if not (is_real(alpha) and 0 <= alpha < 1):
        raise ValueError(f"alpha must be in [0, 1), got {alpha!r}")
    tail = (1.0 - alpha) * len(v)  # samples in the tail, fractional
    whole = int(math.floor(tail + 1e-12))
    weights = np.zeros(len(v))
    weights[:whole] = 1.0
    if whole < len(v):
        weights[whole] = tail - whole
    return float(np.dot(weights, v) / tail)


def score(values, risk: str = "mean", alpha: float = DEFAULT_CVAR_ALPHA) -> tuple[float, float]:
    """One objective over replicates: (value, standard error) by `risk`
    (module doc); the SE is nan for one value.

    Args:
        values: 1-D array-like, one finite value per replicate.
        risk: "mean" or "cvar", any case.
        alpha: the CVaR level (risk "cvar").

    Returns:
        (value, standard error), floats in the units of `values`.

    Raises:
        ValueError: an unknown `risk`, or a bad `alpha`.
    """
    from scipy import stats

    risk = parse_name(risk, RISKS, "risk")
    v = np.asarray(values, float).ravel()
    if risk == "mean":
        value = float(v.mean())
        se = float(stats.sem(v)) if len(v) > 1 else math.nan
    elif risk == "cvar":
        value = cvar(v, alpha)
        if len(v) > 1 and not np.all(v == v[0]):
            res = stats.bootstrap(
                (v,),
                lambda x, axis: np.apply_along_axis(cvar, axis, x, alpha),
                n_resamples=N_BOOT,
                vectorized=True,
                random_state=0,
                method="percentile",
            )
            se = float(res.standard_error)
        else:
            se = 0.0 if len(v) > 1 else math.nan
    else:
        raise ValueError(f"unknown risk {risk!r}; accepted: {', '.join(RISKS)}")
    return value, se


def leg_mass_kg(design: LegDesign, segment_mass: str) -> float:
    """kg, the leg's mass, as every other table of the package counts it
    (:func:`mat_hopper.core.control_legs.mass_properties`).

    Args:
        design: the LegDesign.
        segment_mass: the segment-mass convention (``leg`` or ``capsule``,
            any case).

    Returns:
        The mass of the leg body's subtree in MuJoCo's compiled model, kg
        (float): the hip stub, the material segments and the foot (SS:
        0.254 + 7.854 + 0.164 + 0.5 = 8.772 kg); the base is not included.
        Until this session the optimizer counted the material segments
        only (SS 7.854 kg) under the same name.

    Raises:
        ValueError: a design that is not a LegDesign, or an unknown
            segment-mass convention.
    """
    from ..core.control_legs import mass_properties  # controls imports the model builder: import when used

    return float(mass_properties(design, segment_mass).leg_mass_kg)


def check_leg_mass(value):
    """`leg_mass` as the objective stores it: None, a paper design's name
    (case as the paper writes it), or a mass in kg, a float in
    (0, :data:`MAX_LEG_MASS_KG`]. ValueError otherwise."""
    if value is None:
        return None
    if isinstance(value, str):
        text = value.strip()
        names = {n.lower(): n for n in paper_designs()}
        if text.lower() in names:
            return names[text.lower()]
        if not is_decimal(text):  # a mass is an ASCII decimal (mat_hopper.util.parsing): not "٣", "1_0" or "inf"
            hint = did_you_mean(text, paper_designs())
            raise ValueError(
                f"leg_mass: a paper design ({', '.join(paper_designs())}) or the leg's mass in kg as a bare "
                f"number (e.g. 6.5), got {text!r}" + (f"; {hint}" if hint else "")
            )
        value = parse_number(text, "leg_mass", unit="kg")
    if not is_real(value) or not math.isfinite(value) or value <= 0:
        raise ValueError(f"leg_mass must be a paper design's name or a finite mass > 0 kg, got {value!r}")
    if value > MAX_LEG_MASS_KG:
        raise ValueError(
            f"leg_mass must be a paper design's name or a mass in (0, {MAX_LEG_MASS_KG:g}] kg (above the heaviest "
            f"leg any design can have), got {value!r}"
        )
    return float(value)


def leg_mass_target_kg(leg_mass, n_segments: int, segment_mass: str) -> float:
    """kg, the target of a `leg_mass` setting for legs of `n_segments`: the
    named paper design resampled to that many segments, or the mass given."""
    if isinstance(leg_mass, str):
        from ._space import resample

        ref_design = LegDesign(resample(paper_designs()[leg_mass], n_segments), name=leg_mass)
        return leg_mass_kg(ref_design, segment_mass)
    return float(leg_mass)


@functools.lru_cache(maxsize=64)
def leg_mass_model(n_segments: int, segment_mass: str) -> tuple[float, float]:
    """The leg's mass as a function of its segments' densities: ``fixed +
    per * sum(rho_i)`` (kg, rho in g/cm^3), exact for the model's leg (the
    hip stub and the foot do not depend on the materials; each material
    segment's mass is linear in its density, the same factor for every
    segment of an N-segment leg: :func:`mat_hopper.core.materials.segment_masses`).

    Args:
        n_segments: the leg's number of material segments.
        segment_mass: the segment-mass convention (``leg`` or ``capsule``).

    Returns:
        (fixed_kg, per_g_cm3_kg): the mass that no density changes, kg, and
        each segment's mass per g/cm^3 of its density, kg.
    """
    from ..core.materials import Material, segment_masses

    unit = LegDesign(tuple(Material(f"unit{i}", 1.0, 1.0) for i in range(n_segments)), name="unit")
    per = segment_masses(unit, segment_mass)
    return leg_mass_kg(unit, segment_mass) - float(sum(per)), float(per[0])


def leg_mass_target(objective, n_segments: int) -> tuple[float, float] | None:
    """kg, (target, tolerance) of the objective's ``leg_mass`` constraint
    for legs of `n_segments` (the tolerance defaulting to
    DEFAULT_LEG_MASS_TOLERANCE of the target); None when the objective does
    not constrain the mass."""
    if objective.leg_mass is None:
        return None
    target = leg_mass_target_kg(objective.leg_mass, n_segments, objective.segment_mass)
    tol = objective.leg_mass_tolerance_kg
    return target, DEFAULT_LEG_MASS_TOLERANCE * target if tol is None else tol


def leg_mass_band_kg(objective, n_segments: int) -> tuple[float, float] | None:
    """kg, the leg masses the ``leg_mass`` constraint accepts for legs of
    `n_segments`: (target - tolerance, target + tolerance); None when the
    objective does not constrain the mass."""
    held = leg_mass_target(objective, n_segments)
    return None if held is None else (held[0] - held[1], held[0] + held[1])


def leg_mass_violation(mass_kg: float, target_kg: float, tolerance_kg: float) -> float:
    """kg, the ``leg_mass`` constraint: ``|mass - target| - tolerance`` (<= 0 feasible)."""
    return float(abs(mass_kg - target_kg) - tolerance_kg)


def mass_constraints(objective, design: LegDesign | None, mass_kg: float) -> tuple[float, ...]:
    """The ``leg_mass`` constraint value of a design of mass `mass_kg` (kg)
    as a 1-tuple, or () when `objective` does not constrain the mass.
    ValueError when it does and no design is given."""
    if objective.leg_mass is None:
        return ()
    if design is None:
        raise ValueError("design: needed to score the leg_mass constraint")
    return (leg_mass_violation(mass_kg, *leg_mass_target(objective, design.n_segments)),)


def replicate_values(rows: list[dict], objectives: tuple[str, ...]) -> list[tuple[float, ...]]:
    """Per replicate (rows grouped by their ``replicate`` seed, in order of
    first appearance; absent: one unperturbed run), the mean over its
    behaviours of each objective."""
    groups: dict[int, list[dict]] = {}
    for r in rows:
        groups.setdefault(int(r.get("replicate", -1)), []).append(r)
    return [tuple(float(np.mean([r[o] for r in g])) for o in objectives) for g in groups.values()]


def behaviour_heights(rows: list[dict]) -> list[float]:
    """Per behaviour (in order), the mean hop height (m) over its
    replicates; nan where any replicate scored no hop cycle."""
    groups: dict[str, list[dict]] = {}
    for r in rows:
        groups.setdefault(r["behaviour"], []).append(r)
    out = []
    for g in groups.values():
        out.append(float(np.mean([r["hop_height_m"] for r in g])) if all(r["n_hops"] for r in g) else math.nan)
    return out


def check_objective(objective) -> None:
    """The noise- and mass-aware fields of an Objective; ValueError naming
    the field."""
    k = objective.replicates
    if isinstance(k, bool) or not isinstance(k, (int, np.integer)) or not 0 <= k <= MAX_REPLICATES:
        raise ValueError(f"replicates must be an integer in [0, {MAX_REPLICATES}] (0: one unperturbed run), got {k!r}")
    if objective.risk not in RISKS:
        raise ValueError(f"unknown risk {objective.risk!r}; accepted: {', '.join(RISKS)}")
    a = objective.cvar_alpha
    if isinstance(a, bool) or not isinstance(a, (int, float)) or not 0 <= a < 1:
        raise ValueError(f"cvar_alpha must be in [0, 1), got {a!r}")
    if objective.risk == "cvar" and k < 2:
        raise ValueError(f"risk cvar needs replicates >= 2, got {k}")
    tol = objective.leg_mass_tolerance_kg
    if tol is not None:
        if isinstance(tol, bool) or not isinstance(tol, (int, float)) or not math.isfinite(tol) or tol <= 0:
            raise ValueError(f"leg_mass_tolerance_kg must be a finite number > 0 kg, got {tol!r}")
        if tol > MAX_LEG_MASS_KG:
            raise ValueError(
                f"leg_mass_tolerance_kg must be in (0, {MAX_LEG_MASS_KG:g}] kg (a wider tolerance constrains "
                f"nothing), got {tol!r}"
            )
        if objective.leg_mass is None:
            raise ValueError("leg_mass_tolerance_kg needs leg_mass (a target)")


def key_fields(objective) -> dict:
    """The noise- and mass-aware fields of an objective's key, each only when
    it differs from a single-draw, mass-free objective (so a study keyed
    without them keeps its key)."""
    out = {}
    if objective.replicates:
        out["replicates"] = int(objective.replicates)
        out["replicate_seed_start"] = SEARCH_SEED_START
    if objective.risk != "mean":
        out["risk"] = objective.risk
        out["cvar_alpha"] = float(objective.cvar_alpha)
    if objective.leg_mass is not None:
        out["leg_mass"] = objective.leg_mass
        out["leg_mass_tolerance_kg"] = objective.leg_mass_tolerance_kg
    return out


def from_key_fields(key: dict) -> dict:
    """Objective keyword arguments of :func:`key_fields`' entries (absent:
    one unperturbed run, mean, no mass constraint)."""
    if key.get("replicates") and key.get("replicate_seed_start", SEARCH_SEED_START) != SEARCH_SEED_START:
        raise ValueError(
            f"study draws its replicates from seed {key['replicate_seed_start']}, this version from {SEARCH_SEED_START}"
        )
    return {
        "replicates": int(key.get("replicates", 0)),
        "risk": key.get("risk", "mean"),
        "cvar_alpha": float(key.get("cvar_alpha", DEFAULT_CVAR_ALPHA)),
        "leg_mass": key.get("leg_mass"),
        "leg_mass_tolerance_kg": key.get("leg_mass_tolerance_kg"),
    }
