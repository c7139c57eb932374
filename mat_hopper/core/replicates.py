"""When a replicate's perturbations begin: one named setting,
``SimSettings.replicate_protocol``.

A replicate (:meth:`mat_hopper.core.perturbations.Perturbation.replicate`)
draws a start offset and tilt, a push and sensor noise from its seed. The
protocol says when they act:

``authors``
    from step 0: the base starts offset (m) and tilted (rad), the sensor
    noise runs from the first step, the push falls where it was drawn.
    Replicates differ from the first step and share nothing. Default.
``branch``
    the run is unperturbed up to the end of the transient (``transient_s``)
    and every perturbation begins there: the start offset and tilt become a
    velocity kick of the base at ``transient_s`` (:func:`branch_kick`), the
    sensor noise is switched on at ``transient_s`` (the very rows the
    ``authors`` replicate reads at those times), and the push falls where it
    was drawn, which must be inside the scored window. Every replicate of a
    design therefore shares the prefix [0, transient_s) with the unperturbed
    run, which is simulated once and forked
    (:meth:`mat_hopper.core.sim.RolloutRunner.fork_as`).
``branch-settled``
    as ``branch``, but the perturbations begin at a fraction
    (:data:`BRANCH_SETTLE_FRACTION`, one half) of the transient, not at its
    end: 10 s into the paper's 20 s transient, so the replicates of a design
    share the prefix [0, transient_s / 2). No excess of the kick's response
    is left by the scored window (static hopping without the push, 10
    seeds: under ``branch`` MD's tracking error is 5.8 mm in the window's
    first 5 s against 3.2 mm under ``authors``, and at their level in the
    next 5 s; under ``branch-settled`` the first 5 s read 3.3 mm; the
    records' ``replicate-protocol-kick-paper.csv``).

Neither branching protocol is the book's: measured against the recorded
claims at the paper profile, each changes three of the 101 control
comparisons' verdict words (docs/conventions.md). What they change besides
the steps:

- a fall or divergence inside the shared prefix is one outcome, copied to
  every replicate of the design, not independent replicates;
- the kick lands at one clock time, so it meets each design at its own hop
  phase: a design and its control on the same seed may be kicked one in
  stance, the other in flight.

The kick. An offset of the start pose has no physical counterpart
part-way through a run (moving the hopper in stance would sink its foot into
the terrain), so a branching replicate turns it into the velocity that would
carry the base through the same offset in :data:`BRANCH_KICK_TIME_S` (0.5 s,
about one hop cycle): the base's x and y velocities change by offset / 0.5 s
(m/s) and its roll and pitch rates by tilt / 0.5 s (rad/s), at once. The
replicate's 5 mm and 0.5 deg standard deviations become 0.01 m/s and 0.0175
rad/s (1 deg/s): on the 17-24 kg hopper a horizontal impulse of about 0.2 N s
from the x and y velocities (proportional to the hopper's mass), below the
replicate's push (5 N for 0.1 s, 0.5 N s); the roll and pitch rates add
momentum of the leg about the hip, not counted in it. Only the base joints'
velocities change and the leg's joints keep theirs relative to the base: in
flight the whole hopper moves with the kick; in stance the foot's velocity
changes too and the contact resists it, so there it is not a free blow.
"""

from __future__ import annotations

import math
from dataclasses import replace
from typing import NamedTuple

import numpy as np

from ..util.parsing import parse_name
from ._loop import NO_NOISE_EVERY, Disturbance
from .perturbations import NO_PUSH

__all__ = [
    "BRANCHING_PROTOCOLS",
    "BRANCH_KICK_TIME_S",
    "BRANCH_SETTLE_FRACTION",
    "DEFAULT_REPLICATE_PROTOCOL",
    "REPLICATE_PROTOCOLS",
    "Draws",
    "branch_kick",
    "branch_step",
    "branch_time_s",
    "check_branch_fork",
    "check_push",
    "check_replicate_protocol",
    "is_branching",
    "kick_base",
    "replicate_draws",
]

REPLICATE_PROTOCOLS = ("authors", "branch", "branch-settled")
DEFAULT_REPLICATE_PROTOCOL = "authors"
# branch-settled: the perturbations begin at this fraction of transient_s; the rest of the
# transient lets the kick's response settle before scoring (module doc)
BRANCH_SETTLE_FRACTION = 0.5
# The protocols whose replicates share an unperturbed prefix and are forked from it, each
# with the fraction of transient_s at which its perturbations begin: the one table.
_BRANCH_AT_FRACTION = {"branch": 1.0, "branch-settled": BRANCH_SETTLE_FRACTION}
BRANCHING_PROTOCOLS = tuple(_BRANCH_AT_FRACTION)
# s: the branch protocol's kick carries the base through the start offset in this time (module doc).
BRANCH_KICK_TIME_S = 0.5


def check_replicate_protocol(protocol) -> str:
    """The replicate protocol named (case-insensitive, blanks trimmed), as
    spelled in :data:`REPLICATE_PROTOCOLS`.

    Args:
        protocol: ``"authors"``, ``"branch"`` or ``"branch-settled"``, any case.

    Returns:
        The name as spelled in :data:`REPLICATE_PROTOCOLS` (``"Branch"`` gives ``"branch"``).

    Raises:
        ValueError: an empty name or one not in :data:`REPLICATE_PROTOCOLS` (the message lists them).
    """
    return parse_name(protocol, REPLICATE_PROTOCOLS, "replicate_protocol")


def is_branching(protocol) -> bool:
    """Whether the replicates of a protocol share an unperturbed prefix
    (:data:`BRANCHING_PROTOCOLS`).

    Args:
        protocol: a protocol's canonical name (or None).

    Returns:
        True for ``branch`` and ``branch-settled``.
    """
    return protocol in BRANCHING_PROTOCOLS


def branch_time_s(settings) -> float:
    """When a branching replicate's perturbations begin, s (module doc).

    Args:
        settings: a SimSettings (its ``transient_s`` and ``replicate_protocol``).

    Returns:
        ``transient_s`` under ``branch``; ``BRANCH_SETTLE_FRACTION *
        transient_s`` under ``branch-settled`` (10 s of the paper's 20 s).

    Raises:
        ValueError: a protocol that does not branch.
    """
    protocol = settings.replicate_protocol
    if protocol not in _BRANCH_AT_FRACTION:
        raise ValueError(
            f"replicate_protocol {protocol!r} does not branch (branching: {', '.join(BRANCHING_PROTOCOLS)})"
        )
    return _BRANCH_AT_FRACTION[protocol] * float(settings.transient_s)


def branch_step(branch_s: float, timestep_s: float) -> int:
    """The physics step at which a branching replicate's perturbations begin:
    the first step at or after ``branch_s`` (:func:`branch_time_s`).

    Args:
        branch_s: the branch time, s (>= 0).
        timestep_s: the physics step, s (> 0).

    Returns:
        round(branch_s / timestep_s): 200000 for the paper's 20 s at 1e-4 s.

    >>> branch_step(20.0, 1e-4)
    200000
    """
    return int(round(branch_s / timestep_s))


def branch_kick(start_xy_m, tilt_rad) -> tuple[float, float, float, float]:
    """The velocity kick of the base that stands for a replicate's start
    offset and tilt under ``branch`` (module doc).

    Args:
        start_xy_m: the drawn start offset (dx, dy), m.
        tilt_rad: the drawn start tilt (roll, pitch), rad.

    Returns:
        (dvx m/s, dvy m/s, droll rad/s, dpitch rad/s): each drawn value
        divided by :data:`BRANCH_KICK_TIME_S`.

    Raises:
        ValueError: a value that is not finite.

    >>> branch_kick((0.005, -0.01), (0.0, 0.01))
    (0.01, -0.02, 0.0, 0.02)
    """
    values = [float(v) for v in (*start_xy_m, *tilt_rad)]
    if len(values) != 4 or not all(math.isfinite(v) for v in values):
        raise ValueError(f"branch_kick needs a finite (dx, dy) in m and (roll, pitch) in rad, got {values!r}")
    dvx, dvy, droll, dpitch = (v / BRANCH_KICK_TIME_S for v in values)
    return dvx, dvy, droll, dpitch


def check_push(settings) -> None:
    """Check that a perturbation's push can act: its window lies inside the
    run, and under a branching protocol after the unperturbed prefix (a push
    drawn outside either would be lost without a word).

    Args:
        settings: the :class:`~mat_hopper.core.sim.SimSettings`.

    Raises:
        ValueError: a push whose window ends after ``duration_s``, or under
            ``branch`` or ``branch-settled`` starts before the branch time
            (:func:`branch_time_s`), naming both and the scored window to
            draw it from.
    """
    p = settings.perturbation
    if p is None or p.push_force_n <= 0:
        return
    a, b = p.push_window_s
    fix = (
        f"draw the replicate from this run's scored window, Perturbation.replicate(seed, "
        f"({settings.transient_s:g}, {settings.duration_s:g}))"
    )
    if b > settings.duration_s:
        may = "will never act" if a >= settings.duration_s else "may fall after the run's end"
        raise ValueError(
            f"the push window ({a:g}, {b:g}) s ends after the run ({settings.duration_s:g} s), so the push {may}: {fix}"
        )
    if is_branching(settings.replicate_protocol) and a < branch_time_s(settings):
        raise ValueError(
            f"replicate_protocol {settings.replicate_protocol!r} perturbs only from {branch_time_s(settings):g} s: "
            f"the push window ({a:g}, {b:g}) s must start there or later: {fix}"
        )


class Draws(NamedTuple):
    """A run's perturbation as the rollout applies it: the start offset (m)
    and tilt (rad) of its first pose, the disturbance from step 0, and under
    a branching protocol the disturbance from ``branch_at`` on (``scored``) and the
    kick (:func:`branch_kick`; ``branch_at`` -1 and both None otherwise)."""

    start_xy_m: tuple
    tilt_rad: tuple
    disturbance: Disturbance
    scored: Disturbance | None
    kick: tuple | None
    branch_at: int


def replicate_draws(settings) -> Draws:
    """The draws of `settings`' perturbation (:meth:`Perturbation.draw`),
    placed by its replicate protocol (module doc).

    Args:
        settings: the :class:`~mat_hopper.core.sim.SimSettings`.

    Returns:
        :class:`Draws`: no perturbation, a start at rest and no noise nor
        push; ``authors``, the drawn start, noise and push from step 0;
        ``branch`` and ``branch-settled``, an unperturbed start and prefix,
        then from the branch time (:func:`branch_time_s`) the drawn noise and
        push and the kick.
    """
    p, zero = settings.perturbation, (0.0, 0.0)
    quiet = Disturbance(NO_PUSH, np.zeros((1, 6)), NO_NOISE_EVERY)
    if p is None:
        return Draws(zero, zero, quiet, None, None, -1)
    offset, tilt, push, noise, every = p.draw(settings.duration_s, settings.timestep_s)
    drawn = Disturbance(push, noise, every)
    if not is_branching(settings.replicate_protocol):
        return Draws(offset, tilt, drawn, None, None, -1)
    return Draws(
        zero, zero, quiet, drawn, branch_kick(offset, tilt), branch_step(branch_time_s(settings), settings.timestep_s)
    )


def kick_base(qvel: np.ndarray, base_dof: int, kick) -> None:
    """Add a :func:`branch_kick` to the base joints' velocities, in place.

    Args:
        qvel: MuJoCo's ``data.qvel``.
        base_dof: the first of the base's 6 joints in qvel (x, y, z, roll, pitch, yaw).
        kick: (dvx m/s, dvy m/s, droll rad/s, dpitch rad/s).
    """
    for k, dv in zip((0, 1, 3, 4), kick):
        qvel[base_dof + k] += dv


def check_branch_fork(parent, settings, step: int, pending: bool) -> None:
    """Check that a running rollout may be forked into a branching replicate
    (:meth:`mat_hopper.core.sim.RolloutRunner.fork_as`).

    Args:
        parent: the running rollout's SimSettings.
        settings: the replicate's SimSettings.
        step: the running rollout's physics step.
        pending: whether the running rollout is still unperturbed (no
            perturbation, or a branching one not yet begun).

    Raises:
        ValueError: `settings` not branching, differing from `parent` in
            more than the perturbation, or the rollout past its prefix.
    """
    if not is_branching(getattr(settings, "replicate_protocol", None)):
        raise ValueError(f"fork_as needs the SimSettings of a branching run (replicate_protocol {BRANCHING_PROTOCOLS})")
    if type(settings) is not type(parent) or replace(settings, perturbation=None) != replace(parent, perturbation=None):
        raise ValueError("fork_as: the settings may differ from the running rollout's only in the perturbation")
    prefix_end = branch_step(branch_time_s(settings), settings.timestep_s)
    if step > prefix_end or not pending:
        raise ValueError(f"fork_as: the rollout is past its unperturbed prefix (step {step}, prefix {prefix_end})")
