"""The hips' flight PD on a leg that bends, as a sampled-data loop.

In flight the controller holds each hip torque, ``gear (-kp theta - kd
theta')``, over one control period (a zero-order hold) and reads the hip
angle and rate fresh at the next. Under a bending convention the leg's
hinges carry modes of 0.5-25 kHz (:func:`mat_hopper.core.stable_step.model_frequencies`),
near or above the authors' 10 kHz control rate. A mode that the hold
samples close to a multiple of the control rate aliases to a low
frequency, where the PD's phase pumps it: the loop grows from round-off
within milliseconds of the start, whatever the physics step. Measured on
uniform PVC-density legs (1.39 g/cm^3) under ``bending`` with the stiff
contact, 8 s forward: 300, 400 and (at 4.43 g/cm^3) 1000 GPa diverge in
the first 20 ms at the 1e-4 s control period, 100-200, 1000 and 2000 GPa
do not; the loop below is unstable in exactly those cases at 1e-4 s, and
stable for all of them at 3.3e-5 s. It is not a bound on the frequency
alone (1000 GPa at 1.39 g/cm^3 is stable at 1e-4 s, 300 GPa is not).

So the loop is checked as it is: the leg linearised at its start pose
(:class:`mat_hopper.core.lumped.LumpedHopper`: MuJoCo's joint-space
inertia M, the joints' stiffness K and damping D of the model), the hips
driven through the hold, and the closed loop's one-period map
``Phi - Gamma F`` (exact for the linear plant: the matrix exponential of
the continuous system over one period, so independent of the physics
substeps). The loop is stable when its spectral radius is at most 1 (the
floating base's rigid modes sit at 1). The damping is the authors' (1 N m
s/rad on a hinge): a loss-factor leg damps more, so the check errs on the
safe side for it.
"""

from __future__ import annotations

import numpy as np
import scipy.linalg

from . import reference as ref
from .lumped import LumpedHopper
from .mjcf import FOOT_SPRING, HIP_JOINTS

RADIUS_TOL = 1e-9  # spectral radius above 1 + this: the loop grows
PERIOD_MARGIN = 0.1  # auto's control period must leave the loop stable within +-10 % of it


def joint_damping(hopper: LumpedHopper) -> np.ndarray:
    """The joints' damping as :mod:`mat_hopper.core.mjcf` sets it under the
    authors' damping: the hips ``HIP_DAMPING`` (20), the foot spring
    ``FOOT_SPRING_DAMPING`` (10), every other sprung joint
    ``JOINT_DAMPING_DEFAULT`` (1), the free base 0.

    Args:
        hopper: the linearised hopper.

    Returns:
        (nv,) damping in MuJoCo's dof order, N s/m or N m s/rad.
    """
    out = np.zeros(len(hopper.dofs))
    for i, d in enumerate(hopper.dofs):
        if d.name in HIP_JOINTS:
            out[i] = ref.HIP_DAMPING
        elif d.name == FOOT_SPRING:
            out[i] = ref.FOOT_SPRING_DAMPING
        elif d.stiffness > 0:
            out[i] = ref.JOINT_DAMPING_DEFAULT
    return out


def flight_loop_radius(
    hopper: LumpedHopper,
    period_s: float,
    flight_kp: float = ref.FLIGHT_KP,
    flight_kd: float = ref.FLIGHT_KD,
    gear: float = ref.HIP_GEAR,
) -> float:
    """Spectral radius of the hips' sampled flight PD loop over one control
    period (module doc): at most 1 the loop is stable, above it grows by
    that factor per period.

    Args:
        hopper: the linearised hopper (its convention sets the hinges).
        period_s: the control period, s, > 0.
        flight_kp, flight_kd: the flight PD's gains before the gear, per rad
            and per rad/s (the authors' 10 and 0.1).
        gear: the hip actuators' gear (600).

    Returns:
        The spectral radius of Phi - Gamma F, dimensionless.
    """
    M, K, D = hopper.mass_matrix(), np.diag(hopper.stiffness()), np.diag(joint_damping(hopper))
    n = len(M)
    Minv = np.linalg.inv(M)
    hips = [hopper.dof(name) for name in HIP_JOINTS]
    # continuous plant x = (q, q'), input the two hip commands; one augmented
    # exponential gives the hold's Phi and Gamma (Van Loan 1978)
    aug = np.zeros((2 * n + 2, 2 * n + 2))
    aug[:n, n : 2 * n] = np.eye(n)
    aug[n : 2 * n, :n] = -Minv @ K
    aug[n : 2 * n, n : 2 * n] = -Minv @ D
    aug[n : 2 * n, 2 * n :] = Minv[:, hips] * gear
    step = scipy.linalg.expm(aug * period_s)
    phi, gamma = step[: 2 * n, : 2 * n], step[: 2 * n, 2 * n :]
    feedback = np.zeros((2, 2 * n))
    for row, dof in enumerate(hips):
        feedback[row, dof], feedback[row, n + dof] = flight_kp, flight_kd
    return float(np.abs(np.linalg.eigvals(phi - gamma @ feedback)).max())


def flight_loop_stable(hopper: LumpedHopper, period_s: float, margin: float = 0.0, **gains) -> bool:
    """Whether the hips' flight loop is stable at a control period.

    Args:
        hopper: the linearised hopper.
        period_s: the control period, s.
        margin: with `margin` > 0 the loop must also be stable at
            ``period_s (1 -+ margin)`` (the modes move as the leg swings from
            its start pose).
        gains: flight_kp, flight_kd, gear, as :func:`flight_loop_radius`.

    Returns:
        True when the spectral radius is at most 1 (+ RADIUS_TOL) at each period.
    """
    periods = (period_s,) if margin <= 0 else (period_s * (1 - margin), period_s, period_s * (1 + margin))
    return all(flight_loop_radius(hopper, p, **gains) <= 1.0 + RADIUS_TOL for p in periods)
