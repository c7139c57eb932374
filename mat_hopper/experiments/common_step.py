"""One physics step for legs compared together.

Under ``timestep_s="auto"`` each leg gets the control period and physics
substeps its own stability bound needs
(:func:`mat_hopper.core.timestep.auto_timestep`). Legs that a paired
comparison sets side by side must run alike, or the comparison carries
the step as well as the material: :func:`common_step` gives them the
shortest control period and the shortest physics step any of them needs,
and :func:`at_common_step` puts a run's settings on it.
"""

from __future__ import annotations

from dataclasses import replace

from ..core.timestep import auto_timestep

__all__ = ["at_common_step", "common_step"]


def common_step(legs, convention: str, contact: str, sensor_timing="authors") -> tuple[float, int]:
    """One control period and physics substeps for `legs` under a
    convention and a contact: the shortest period and the shortest physics
    step any of them needs under ``timestep_s="auto"``.

    Args:
        legs: the legs compared together (LegDesigns or design names; >= 1).
        convention: the stiffness convention (e.g. ``"bending"``).
        contact: the contact setting (e.g. ``"stiff"``).
        sensor_timing: the runs' sensor timing (the controller's limit).

    Returns:
        (control period s, physics substeps per period >= 1); the physics
        step is period / substeps.

    Raises:
        ValueError: no legs, or as :func:`~mat_hopper.core.timestep.auto_timestep`
            raises (unknown convention or contact).
    """
    autos = [auto_timestep(leg, convention, sensor_timing=sensor_timing, contact=contact) for leg in legs]
    if not autos:
        raise ValueError("common_step needs at least one leg")
    period = min(k * dt for k, dt in autos)
    dt = min(dt for _, dt in autos)
    return period, max(1, round(period / dt))


def at_common_step(settings, period_s: float, substeps: int):
    """A run's settings at a control period split into physics substeps.

    Args:
        settings: the run's SimSettings.
        period_s: the control period, s (from :func:`common_step`).
        substeps: physics steps per control period, >= 1 (from :func:`common_step`).

    Returns:
        A copy of `settings` with ``timestep_s = period_s / substeps`` and
        ``substeps``.
    """
    return replace(settings, timestep_s=period_s / substeps, substeps=substeps)
