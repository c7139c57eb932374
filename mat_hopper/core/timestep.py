"""The physics time step and the control period: the one place where
``timestep_s="auto"`` is resolved (:func:`resolve_timestep`), and the
finer step of the time-step checks.

``"auto"``: the controller keeps the authors' 1e-4 s period unless its own
explicit limit is smaller (:func:`mat_hopper.core.stable_step.auto_control_period`),
and the physics takes the fewest substeps of that period whose step is at
most AUTO_SAFETY (0.5) x the springs' explicit bound
(:func:`mat_hopper.core.stable_step.auto_substeps`).
"""

from __future__ import annotations

from . import reference as ref
from .controller import DEFAULT_SENSOR_TIMING
from .materials import DEFAULT_CONVENTION, DEFAULT_SEGMENT_MASS, LegDesign, parse_design
from .stable_step import auto_substeps

__all__ = ["AUTO", "FINE_SUBSTEPS", "FINE_TIMESTEP_S", "auto_timestep", "is_auto", "resolve_timestep"]

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
) -> tuple[float, int]:
    """The one place where ``timestep_s="auto"`` is resolved.

    Args:
        timestep_s: a physics step in s, or ``"auto"``.
        design: the leg (a LegDesign or a name); needed for ``"auto"``.
        convention: the stiffness convention of the run.
        segment_mass: the segment mass convention of the run.
        sensor_timing: the run's sensor timing (the controller's limit).

    Returns:
        (timestep_s, substeps): the step given and 1 substep, or for
        ``"auto"`` the control period (the authors' 1e-4 s unless the
        controller's own limit is smaller) split into the fewest substeps
        that keep the leg's springs stable (:func:`auto_timestep`).

    Raises:
        ValueError: ``"auto"`` without a design, or another string.
    """
    if not isinstance(timestep_s, str):
        return timestep_s, 1
    if not is_auto(timestep_s):
        raise ValueError(f"timestep_s must be a number (s) or {AUTO!r}, got {timestep_s!r}")
    if design is None:
        raise ValueError("the time step is 'auto': pass the design (its substeps depend on it)")
    substeps, dt = auto_timestep(design, convention, segment_mass, sensor_timing)
    return dt, substeps


def auto_timestep(
    design,
    convention: str = DEFAULT_CONVENTION,
    segment_mass: str = DEFAULT_SEGMENT_MASS,
    sensor_timing: str | int = DEFAULT_SENSOR_TIMING,
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

    Returns:
        (substeps, timestep_s): the physics substeps per control period (an
        int >= 1) and the physics step, s.

    Raises:
        ValueError: a design that is neither a LegDesign nor a str, an
            unknown design name, more than 1000 substeps, or as
            :func:`mat_hopper.core.stable_step.auto_substeps` raises (unknown
            convention, segment mass or sensor timing).
    """
    k, dt, _ = auto_substeps(_design(design), convention, segment_mass, sensor_timing=sensor_timing)
    return k, dt
