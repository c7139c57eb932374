"""The physics time step and the control period: the one place where
``timestep_s="auto"`` is resolved (:func:`resolve_timestep`), and the
finer step of the time-step checks.

``"auto"``: the controller keeps the authors' 1e-4 s period unless its own
explicit limit is smaller (a sensor delay, ``latency-L``, lowers it: at
latency 3 the period is 3.33e-05 s) or, under a bending convention, its
hips' sampled flight loop needs a shorter one (:mod:`mat_hopper.core.flight_loop`;
:func:`mat_hopper.core.stable_step.auto_control_period`), and the physics takes the fewest substeps of that period whose step is at
most AUTO_SAFETY (0.5) x the springs' explicit bound
(:func:`mat_hopper.core.stable_step.auto_substeps`).

Before any run, :func:`check_stable_step` compares the run's step and
control period with the leg's analytic bounds: one line (a warning, never
a refusal) naming ``timestep_s="auto"`` (``--timestep auto``) when either
lies above its bound.
"""

from __future__ import annotations

import functools
import math
import warnings

from . import reference as ref
from .contact import CONTACTS, DEFAULT_CONTACT
from .controller import DEFAULT_SENSOR_TIMING
from .conventions import BENDING_CONVENTIONS
from .materials import DEFAULT_CONVENTION, DEFAULT_SEGMENT_MASS, LegDesign, parse_design
from .stable_step import auto_substeps

__all__ = [
    "API_AUTO_HINT",
    "AUTO",
    "CLI_AUTO_HINT",
    "FINE_SUBSTEPS",
    "FINE_TIMESTEP_S",
    "StableStepWarning",
    "API_CONTACT_HINT",
    "CLI_CONTACT_HINT",
    "auto_suggestion",
    "contact_suggestion",
    "remedies",
    "soft_contact_cause",
    "soft_contact_note",
    "auto_timestep",
    "check_stable_step",
    "is_auto",
    "resolve_timestep",
    "stable_step_excess",
    "warn_stable_step",
]

AUTO = "auto"  # timestep_s="auto": physics substeps of the control period (resolve_timestep)
# The finer physics of the time-step checks (robustness study, optimizer validation):
# a 2e-5 s step, 5 substeps of the 1e-4 s control period (and, to keep the authors'
# 1e-4 s sensor delay, a latency of 5 physics steps).
FINE_TIMESTEP_S = 2e-5
FINE_SUBSTEPS = round(ref.TIMESTEP_S / FINE_TIMESTEP_S)


def _design(design) -> LegDesign:
    if isinstance(design, LegDesign):
        return design
    if isinstance(design, str):
        return parse_design(design)
    raise ValueError(f"design must be a LegDesign or a design name, got {design!r}")


def is_auto(timestep_s) -> bool:
    """Whether a time step is the word ``"auto"`` (any case, spaces ignored).

    Args:
        timestep_s: a time step as given: a number (s) or a string.

    Returns:
        True for a str equal to ``"auto"`` once leading and trailing blanks
        are stripped and case is folded; False otherwise (numbers included).
    """
    return isinstance(timestep_s, str) and timestep_s.strip().lower() == AUTO


def resolve_timestep(
    timestep_s,
    design=None,
    convention: str = DEFAULT_CONVENTION,
    segment_mass: str = DEFAULT_SEGMENT_MASS,
    sensor_timing: str | int = DEFAULT_SENSOR_TIMING,
    contact: str = DEFAULT_CONTACT,
) -> tuple[float, int]:
    """The one place where ``timestep_s="auto"`` is resolved.

    Args:
        timestep_s: a physics step in s, or ``"auto"``.
        design: the leg (a LegDesign or a name); needed for ``"auto"``.
        convention: the stiffness convention of the run.
        segment_mass: the segment mass convention of the run.
        sensor_timing: the run's sensor timing (the controller's limit).
        contact: the run's contact setting (its time constant's limit).

    Returns:
        (timestep_s, substeps): the step given and 1 substep, or for
        ``"auto"`` the control period (the authors' 1e-4 s unless the
        controller's own limit is smaller) split into the fewest substeps
        that keep the leg's springs stable and the contact's time constant
        honoured (:func:`auto_timestep`).

    Raises:
        ValueError: ``"auto"`` without a design, or another string.
    """
    if not isinstance(timestep_s, str):
        return timestep_s, 1
    if not is_auto(timestep_s):
        raise ValueError(f"timestep_s must be a number (s) or {AUTO!r}, got {timestep_s!r}")
    if design is None:
        raise ValueError("the time step is 'auto': pass the design (its substeps depend on it)")
    substeps, dt = auto_timestep(design, convention, segment_mass, sensor_timing, contact)
    return dt, substeps


def auto_timestep(
    design,
    convention: str = DEFAULT_CONVENTION,
    segment_mass: str = DEFAULT_SEGMENT_MASS,
    sensor_timing: str | int = DEFAULT_SENSOR_TIMING,
    contact: str = DEFAULT_CONTACT,
) -> tuple[int, float]:
    """(substeps, physics step s) for ``timestep_s="auto"``: the controller
    keeps its period (1e-4 s) unless its own explicit limit is smaller
    (:func:`mat_hopper.core.stable_step.auto_control_period`), and the physics takes
    the fewest substeps whose step is at most AUTO_SAFETY (0.5) x the
    springs' explicit bound (:func:`mat_hopper.core.stable_step.auto_substeps`).

    Args:
        design: the leg, a :class:`~mat_hopper.core.materials.LegDesign` or a
            design name (:func:`~mat_hopper.core.materials.parse_design`).
        convention: the stiffness convention of the run (default ``paper``).
        segment_mass: the segment-mass convention of the run (default
            ``leg``).
        sensor_timing: the run's sensor timing (the controller's limit;
            default ``"authors"``).
        contact: the run's contact setting (default ``"authors"``): the
            step is at most half its time constant
            (:func:`mat_hopper.core.contact.contact_max_timestep`).

    Returns:
        (substeps, timestep_s): the physics substeps per control period (an
        int >= 1) and the physics step, s.

    Raises:
        ValueError: a design that is neither a LegDesign nor a str, an
            unknown design name, more than 1000 substeps, or as
            :func:`mat_hopper.core.stable_step.auto_substeps` raises (unknown
            convention, segment mass, sensor timing or contact).
    """
    k, dt, _ = auto_substeps(_design(design), convention, segment_mass, sensor_timing=sensor_timing, contact=contact)
    return k, dt


# --- the stable-step check before a run -------------------------------------------
# The analytic bounds it compares with (mat_hopper.core.stable_step) are explicit
# stability limits of linearised models: a step above one is likely, not certain, to
# diverge (the measured stable steps lie within a factor 2 of the springs' bound), so
# the check warns and never refuses: the authors' 1e-4 s default stays, for fidelity.

API_AUTO_HINT = 'timestep_s="auto"'  # how the Python API asks for the automatic step
CLI_AUTO_HINT = "--timestep auto"  # how the command line asks for it


class StableStepWarning(RuntimeWarning):
    """A run's physics step (or control period) lies above the leg's
    analytic stable step (:func:`check_stable_step`): it may diverge."""


@functools.lru_cache(maxsize=256)
def _bounds(design: LegDesign, convention: str, segment_mass: str, stance_kd: float, latency: int) -> tuple:
    """(springs' bound 2 / w_max s, controller's limit s), cached: a batch
    or a sweep asks again for the same leg."""
    from .stable_step import stable_bounds

    return stable_bounds(design, convention, segment_mass, stance_kd, latency)  # no model is built


def stable_step_excess(design, settings) -> str | None:
    """What in a run's settings lies above the leg's analytic stable step.

    Compares the physics step ``settings.timestep_s`` with the springs'
    explicit bound 2 / w_max (:func:`mat_hopper.core.stable_step.estimate_timestep`)
    and the control period (``substeps`` x the step) with the controller's
    own limit (:func:`mat_hopper.core.stable_step.controller_timestep`, its
    stance damping read late; its hips' flight damping under a bending
    convention).

    Args:
        design: the leg, a LegDesign or a design name.
        settings: the run's :class:`~mat_hopper.core.sim.SimSettings` (its
            timestep_s, substeps, convention, segment_mass, sensor_timing and
            controller are read).

    Returns:
        None when both are within their bounds; else one clause naming each
        excess with both numbers, s (no fix: :func:`check_stable_step` adds it).

    Raises:
        ValueError: as the bounds' functions raise (an unknown design).
    """
    design = _design(design)
    dt = float(settings.timestep_s)
    period = dt * int(settings.substeps)
    kd = float(settings.controller.stance_kd)
    spring, control = _bounds(design, settings.convention, settings.segment_mass, kd, int(settings.sensor_timing))
    over = []
    if dt > spring:
        over.append(
            f"the physics step {dt:.3g} s is above this leg's analytic stable step {spring:.3g} s, "
            f"its springs' explicit bound 2 / w_max under convention {settings.convention}"
        )
    if period > control:
        over.append(
            f"the control period {period:.3g} s is above the controller's explicit limit {control:.3g} s, "
            f"its rate feedback under sensor timing {settings.sensor_timing}"
        )
    return " and ".join(over) or None


def auto_suggestion(design, settings, auto_hint: str = API_AUTO_HINT) -> str | None:
    """What to try instead of a run's step: the automatic one, when it
    differs from the run's.

    Args:
        design: the leg, a LegDesign or a design name.
        settings: the run's :class:`~mat_hopper.core.sim.SimSettings`.
        auto_hint: how the caller asks for the automatic step
            (:data:`API_AUTO_HINT` or :data:`CLI_AUTO_HINT`).

    Returns:
        ``"try <auto_hint> (k physics substeps of dt s per P s control
        period)"``; a sentence saying why it cannot help when it would need
        more than 1000 substeps; None when the run already takes that step
        and period.
    """
    design = _design(design)
    contact = getattr(settings, "contact", DEFAULT_CONTACT)
    try:
        k, dt = auto_timestep(design, settings.convention, settings.segment_mass, settings.sensor_timing, contact)
    except ValueError as e:
        return f"{auto_hint} cannot help: {e}"
    same = math.isclose(dt, settings.timestep_s, rel_tol=1e-9) and k == settings.substeps
    if same or dt > settings.timestep_s:
        return None
    return (
        f"try {auto_hint} ({k} physics substep{'s' if k > 1 else ''} of {dt:.3g} s per {k * dt:.3g} s control period)"
    )


API_CONTACT_HINT = 'contact="stiff"'  # how the Python API asks for the stiff contact
CLI_CONTACT_HINT = "--contact stiff"  # how the command line asks for it
_CONTACT_HINTS = {API_AUTO_HINT: API_CONTACT_HINT, CLI_AUTO_HINT: CLI_CONTACT_HINT}


def _rings_on_soft_contact(design, settings) -> bool:
    """Whether a run bends (a bending convention) on MuJoCo's default soft
    contact at a step within the leg's analytic bounds (a step above them
    is the likelier cause: :func:`stable_step_excess` says it)."""
    bends = getattr(settings, "convention", None) in BENDING_CONVENTIONS
    soft = getattr(settings, "contact", DEFAULT_CONTACT) == DEFAULT_CONTACT
    return bends and soft and stable_step_excess(design, settings) is None


def soft_contact_cause(design, settings) -> str | None:
    """The measured cause of a bending leg's fall or divergence on MuJoCo's
    default soft contact, or None for a run it does not apply to.

    On the authors' contact (a 0.02 s time constant) the foot sinks 11-24
    mm; the touch sensor releases while the foot is still deep, the hips'
    flight PD steps, and the step rings the leg's bending modes until a
    stiff leg falls or diverges (book/records: bending-mode-stiff.csv,
    bending-chatter-damping.csv). Smaller physics steps do not remove it.

    Args:
        design: the leg, a LegDesign or a design name.
        settings: the run's :class:`~mat_hopper.core.sim.SimSettings` (its
            convention, contact and step are read).

    Returns:
        One clause naming the cause, or None (an axial convention, a
        contact other than the default, or a step above the leg's analytic
        bounds, :func:`stable_step_excess`).
    """
    if not _rings_on_soft_contact(design, settings):
        return None
    return (
        "a leg that bends rings on MuJoCo's default soft contact (contact authors): the foot sinks 11-24 mm, "
        "the touch sensor releases while it is still deep and the hips' flight PD steps into the bending modes"
    )


def contact_suggestion(design, settings, contact_hint: str = API_CONTACT_HINT) -> str | None:
    """What to try for a bending leg on the default soft contact: the stiff
    contact, on which such legs stand (:func:`soft_contact_cause`).

    Args:
        design: the leg, a LegDesign or a design name.
        settings: the run's :class:`~mat_hopper.core.sim.SimSettings`.
        contact_hint: how the caller asks for the stiff contact
            (:data:`API_CONTACT_HINT` or :data:`CLI_CONTACT_HINT`).

    Returns:
        ``"try <contact_hint> (a 1 ms contact time constant)"``, or None
        where :func:`soft_contact_cause` is None.
    """
    if not _rings_on_soft_contact(design, settings):
        return None
    return f"try {contact_hint} (a {CONTACTS['stiff'][0] * 1e3:g} ms contact time constant)"


def soft_contact_note(design, settings, contact_hint: str = API_CONTACT_HINT) -> str | None:
    """Why a bending leg on the default soft contact fell, and what to try:
    :func:`soft_contact_cause` and :func:`contact_suggestion` in one clause,
    for a fall that did not diverge (a divergence says both in
    :meth:`mat_hopper.core.rollout.Rollout.divergence_message`).

    Args:
        design: the leg, a LegDesign or a design name.
        settings: the run's :class:`~mat_hopper.core.sim.SimSettings`.
        contact_hint: :data:`API_CONTACT_HINT` or :data:`CLI_CONTACT_HINT`.

    Returns:
        ``"<cause>; try <contact_hint> (...)"``, or None where it does not apply.
    """
    cause = soft_contact_cause(design, settings)
    return None if cause is None else f"{cause}; {contact_suggestion(design, settings, contact_hint)}"


def remedies(design, settings, auto_hint: str = API_AUTO_HINT) -> str | None:
    """Everything to try after a run that diverged or fell: the stiff
    contact for a bending leg on the default soft one
    (:func:`contact_suggestion`), then the automatic step where it differs
    from the run's (:func:`auto_suggestion`).

    Args:
        design: the leg, a LegDesign or a design name.
        settings: the run's :class:`~mat_hopper.core.sim.SimSettings`.
        auto_hint: :data:`API_AUTO_HINT` or :data:`CLI_AUTO_HINT`; the
            contact is named the same way (``contact="stiff"`` or
            ``--contact stiff``).

    Returns:
        The suggestions joined by "; ", or None when there is none.
    """
    contact_hint = _CONTACT_HINTS.get(auto_hint, CLI_CONTACT_HINT if auto_hint.startswith("--") else API_CONTACT_HINT)
    fixes = [contact_suggestion(design, settings, contact_hint), auto_suggestion(design, settings, auto_hint)]
    return "; ".join(f for f in fixes if f) or None


def check_stable_step(design, settings, *, auto_hint: str = API_AUTO_HINT) -> str | None:
    """The one check of a run's time step against the leg's analytic stable
    step, before any run (every command and :func:`mat_hopper.core.sim.simulate`).

    Args:
        design: the leg, a LegDesign or a design name.
        settings: the run's :class:`~mat_hopper.core.sim.SimSettings`.
        auto_hint: how the caller asks for the automatic step, named in the
            line (:data:`API_AUTO_HINT`, ``timestep_s="auto"``, by default;
            :data:`CLI_AUTO_HINT`, ``--timestep auto``, on the command line).

    Returns:
        None when the step and the control period are within their bounds
        (:func:`stable_step_excess`); else one line: what lies above which
        bound, that the run may diverge, and what to try (:func:`auto_suggestion`).

    Raises:
        ValueError: as the bounds' functions raise (an unknown design).

    >>> from mat_hopper.core.sim import SimSettings
    >>> check_stable_step("SS", SimSettings()) is None  # the authors' 1e-4 s step, below SS's 1.26e-4 s
    True
    >>> print(check_stable_step("WC", SimSettings()))  # doctest: +ELLIPSIS
    the physics step 0.0001 s is above this leg's analytic stable step 9.52e-05 s, ...: it may diverge; try timestep_s="auto" (3 physics substeps of 3.33e-05 s per 0.0001 s control period)
    """
    excess = stable_step_excess(design, settings)
    if excess is None:
        return None
    fix = auto_suggestion(design, settings, auto_hint) or f"a smaller step than {settings.timestep_s:g} s"
    return f"{excess}: it may diverge; {fix}"


def warn_stable_step(design, settings, stacklevel: int = 1) -> str | None:
    """:func:`check_stable_step`'s line as a :class:`StableStepWarning`, if any.

    Args:
        design: the leg, a LegDesign or a design name.
        settings: the run's :class:`~mat_hopper.core.sim.SimSettings`.
        stacklevel: as :func:`warnings.warn`'s, counted from the caller of
            this function (1: the caller's line).

    Returns:
        The line warned, or None.
    """
    note = check_stable_step(design, settings)
    if note:
        warnings.warn(note, StableStepWarning, stacklevel + 1)
    return note
