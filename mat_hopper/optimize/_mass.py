"""A study held to a leg mass: the band it accepts, the masses its search
space can reach, and what is done with designs outside the band.

The ``leg_mass`` constraint (:mod:`mat_hopper.optimize._scoring`) accepts
legs of mass target +- tolerance. A space of N segments reaches the
masses from every continuous segment at its density floor (and every
catalogue segment at its lightest material) to all at their ceiling
(:func:`leg_mass_range_kg`: the leg's mass is linear in its densities).
Hence, before any work (:func:`check_mass_band`, a ValueError naming the
setting):

- a band that holds every mass the space reaches makes the constraint
  void (its tolerance at or above the larger distance from the target to
  either end of the range): refused, naming the tolerance below which it
  constrains;
- a band that holds none of them leaves no design feasible: refused.

Then:

- the sampler proposes designs inside the band
  (:class:`~mat_hopper.optimize._space.MassHold`, made here by
  :func:`mass_hold`);
- the paper's designs outside the band are not enqueued
  (:func:`queued_seeds` names them, with their masses): they would be
  simulated only to be infeasible, and would take trials from the study;
- any other design outside the band (a catalogue or Ashby-class space
  the hold cannot steer, a re-queued trial of an older study) is skipped
  before any run: its trial fails with the reason
  (:func:`outside_band`; user attr ``skipped``), and counts as finished,
  as a run that raised does.
"""

from __future__ import annotations

from ..core import reference as ref
from ..core.materials import LegDesign, material
from . import _scoring
from ._space import MassHold, SearchSpace

# What a leg's mass counts (mat_hopper.optimize._scoring.leg_mass_kg), said wherever a mass is asked for:
# the leg alone, not the hopper, whose base adds its two capsules.
LEG_MASS_SCOPE = f"the leg from hip stub to foot, without the base's {2 * ref.BASE_CAPSULE_MASS:g} kg"
SKIPPED_ATTR = "skipped"  # trial user attr: why its design was never run (outside the leg-mass band)
BAND_MARGIN = 1e-9  # relative: the sampled masses stay this far inside the band (round-off of the mass model)


def leg_mass_range_kg(space: SearchSpace, segment_mass: str) -> tuple[float, float]:
    """kg, the lightest and heaviest leg of `space`: continuous segments
    at the density bounds, catalogue segments at their lightest and
    heaviest material (:func:`~mat_hopper.optimize._scoring.leg_mass_model`).

    Args:
        space: the search space.
        segment_mass: the segment-mass convention.

    Returns:
        (min, max) leg mass, kg.
    """
    fixed, per = _scoring.leg_mass_model(space.n_segments, segment_mass)
    cat = [material(m).density_g_cm3 for m in space.materials]
    lo = hi = 0.0
    for kind in space.kinds:
        a, b = space.density_g_cm3 if kind == "continuous" else (min(cat), max(cat))
        lo, hi = lo + a, hi + b
    return fixed + per * lo, fixed + per * hi


def check_mass_band(space: SearchSpace, objective) -> None:
    """Refuse a leg-mass constraint that is void or that no design meets (module doc).

    Args:
        space: the study's search space.
        objective: its objective (``leg_mass``, ``leg_mass_tolerance_kg``).

    Raises:
        ValueError: naming ``leg_mass_tolerance_kg`` (void: the band holds
            every leg the space has; the message gives the largest
            tolerance that still constrains) or ``leg_mass`` (no leg of
            the space in the band).
    """
    held = _scoring.leg_mass_target(objective, space.n_segments)
    if held is None:
        return
    target, tol = held
    lo, hi = leg_mass_range_kg(space, objective.segment_mass)
    void = max(target - lo, hi - target)
    if tol >= void:
        given = "" if objective.leg_mass_tolerance_kg is not None else " (the default, 5 % of the target)"
        raise ValueError(
            f"leg_mass_tolerance_kg {tol:.4g} kg{given} makes the leg-mass constraint void: every leg of the "
            f"search space ({lo:.4g} to {hi:.4g} kg) lies within {target:.4g} +- {tol:.4g} kg; give a tolerance "
            f"below {void:.4g} kg, or no leg_mass"
        )
    if target + tol < lo or target - tol > hi:
        raise ValueError(
            f"leg_mass {target:.4g} +- {tol:.4g} kg: no leg of the search space is in that band (its legs weigh "
            f"{lo:.4g} to {hi:.4g} kg, {LEG_MASS_SCOPE}); change leg_mass, leg_mass_tolerance_kg or the density "
            "bounds"
        )


def mass_hold(space: SearchSpace, objective) -> MassHold | None:
    """The :class:`~mat_hopper.optimize._space.MassHold` of a mass-held
    study: the band within the reachable masses, BAND_MARGIN inside; None
    without a leg-mass constraint."""
    band = _scoring.leg_mass_band_kg(objective, space.n_segments)
    if band is None:
        return None
    lo, hi = leg_mass_range_kg(space, objective.segment_mass)
    a, b = max(band[0], lo), min(band[1], hi)
    if a > b:  # no leg of the space in the band (a stored study of an older version): nothing to hold
        return None
    pad = BAND_MARGIN * max(abs(a), abs(b))
    a, b = (a + pad, b - pad) if b - a > 2 * pad else (a, b)
    fixed, per = _scoring.leg_mass_model(space.n_segments, objective.segment_mass)
    return MassHold((a, b), fixed, per)


def outside_band(design: LegDesign, objective) -> str | None:
    """Why `design` is skipped before any run: its leg mass outside the
    objective's band (text naming both); None when it is inside, or the
    objective does not constrain the mass."""
    band = _scoring.leg_mass_band_kg(objective, design.n_segments)
    if band is None:
        return None
    mass = _scoring.leg_mass_kg(design, objective.segment_mass)
    if band[0] <= mass <= band[1]:
        return None
    return f"leg mass {mass:.4g} kg outside the leg-mass band {band[0]:.4g} to {band[1]:.4g} kg: not run"


def queued_seeds(space: SearchSpace, objective) -> tuple[list, list]:
    """The paper's designs a study enqueues, and those it leaves out.

    Args:
        space: the study's search space.
        objective: its objective.

    Returns:
        (kept, left_out): kept as :meth:`SearchSpace.seeds` gives them,
        (name, params); left_out as (name, leg mass in kg) for each design
        the space expresses whose leg mass lies outside the leg-mass band
        (empty without a leg-mass constraint).
    """
    seeds = space.seeds()
    band = _scoring.leg_mass_band_kg(objective, space.n_segments)
    if band is None:
        return seeds, []
    kept, left = [], []
    for name, params in seeds:
        mass = _scoring.leg_mass_kg(space.design(params, name=name), objective.segment_mass)
        if band[0] <= mass <= band[1]:
            kept.append((name, params))
        else:
            left.append((name, mass))
    return kept, left


def left_out_text(left_out: list, objective, n_segments: int) -> str:
    """One line naming the paper designs left out of the queue (module doc).

    Args:
        left_out: (name, leg mass in kg) of each design left out.
        objective: the study's Objective (its leg-mass band).
        n_segments: segments per leg of the study's space.

    Returns:
        The line, or "" when none was left out.
    """
    if not left_out:
        return ""
    lo, hi = _scoring.leg_mass_band_kg(objective, n_segments)
    names = ", ".join(f"{n} ({m:.4g} kg)" for n, m in left_out)
    return f"paper designs not queued, their leg mass outside the band {lo:.4g} to {hi:.4g} kg: {names}"
