"""What one rollout recorded: :class:`Rollout` (made by
:func:`mat_hopper.core.sim.simulate`), its channels as named views in SI units."""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np

from ..util.parsing import is_real
from . import reference as ref
from ._loop import CHANNELS, C
from .behaviours import Behaviour
from .controller import LIFTOFF, TOUCHDOWN
from .materials import LegDesign

__all__ = [
    "FELL_TILT_DEG",
    "SUSPECT_APEX_MARGIN_M",
    "DivergenceWarning",
    "FallWarning",
    "Rollout",
    "SuspectWarning",
    "hop_cycles",
]

# A base tilted further than this is falling (a hopping base pitches up to
# about 45 deg and recovers): what tells a fall from a numerical divergence.
FELL_TILT_DEG = 60.0

# A run that did not diverge is numerically suspect when a scored hop apex
# exceeds the controller's target by more than this, m. The controller only
# adds the energy that its thrust adaptation asks for, so an apex far above
# the target is energy the integrator made up: a step just below the
# analytic stable bound (the measured bound is about 0.85 of it) corrupts
# the numbers without blowing up. Measured at the default 1e-4 s step, 6 s
# runs scored after 1 s: the paper's nine designs and the catalogue's
# materials at 3 segments on every behaviour reach at most 1.26 m against a
# 1 m target (a soft leg still settling; after the paper's 20 s transient
# they hold 1 m to within 0.01 m), while corrupted runs reach 3.8 m
# (Ti, 4 segments) and 7.4 m (8 g/cm^3, 260 GPa): 0.5 m sits twice the
# healthy excess above it and far below the corrupted ones.
SUSPECT_APEX_MARGIN_M = 0.5


class DivergenceWarning(RuntimeWarning):
    """A run diverged numerically (a NaN or inf, or |qacc| > 1e6): it ended
    early, and what it recorded stops there (:meth:`Rollout.divergence_message`
    says when, why and what to try)."""


class SuspectWarning(RuntimeWarning):
    """A run ended without divergence but its numbers are corrupted: a
    scored hop apex lies far above the controller's target
    (:data:`SUSPECT_APEX_MARGIN_M`), energy the integrator made up at a step
    near the leg's stable bound (:meth:`Rollout.suspect_message` says when,
    why and what to try)."""


class FallWarning(RuntimeWarning):
    """A run did not diverge but the hopper fell (base tilt past
    :data:`FELL_TILT_DEG`): hop cycles after the fall are not scored."""


@dataclass(eq=False)
class Rollout:
    """What one rollout recorded (made by :func:`mat_hopper.core.sim.simulate`).

    ``data`` holds every channel of :data:`mat_hopper.core.sim.CHANNELS` as
    columns; the properties below are named views in SI units. Events are
    the state machine's switches: ``touchdown_times_s``, ``liftoff_times_s``
    and the controller's own ``hop_heights_m`` (one per touchdown after the
    first lift-off).

    Args:
        design: the leg.
        behaviour: the desired path and terrain.
        settings: the run's SimSettings.
        data: (n, len(CHANNELS)) samples at ``settings.record_rate_hz``.
        events: (m, 3) switches: time s, kind (touchdown or lift-off), hop height m.
        diverged_step: the physics step of numerical divergence, -1 if none.
        total_mass_kg: the robot's mass as MuJoCo computes it, kg.
        spring_stiffness_n_m: the material springs' stiffnesses, N/m, hip to foot.
        qpos: (n, nq) joint positions, if recorded (``record_qpos=True``).
        stress: (n, N, 4) per-segment stress, Pa (columns
            :data:`mat_hopper.core._loop.STRESS_COLUMNS`), or None.
        divergence_reason: why the run diverged (which check: NaN or inf,
            or |qacc| > 1e6 and where; the step above the analytic bound if
            it is), None for a stable run.
    """

    design: LegDesign
    behaviour: Behaviour
    settings: object  # the run's mat_hopper.core.sim.SimSettings (sim imports this module, not the reverse)
    data: np.ndarray
    events: np.ndarray
    diverged_step: int
    total_mass_kg: float
    spring_stiffness_n_m: tuple
    qpos: np.ndarray | None = None  # (n, nq) joint positions, if recorded
    # (n, N, 4) per-segment stress, Pa (mat_hopper.core._loop.STRESS_COLUMNS)
    stress: np.ndarray | None = None
    divergence_reason: str | None = None  # which check, and the step above the analytic bound if it is

    def __getitem__(self, channel: str) -> np.ndarray:
        return self.data[:, C[channel]]

    # --- named views ---
    @property
    def time(self) -> np.ndarray:
        """s"""
        return self.data[:, C["t"]]

    @property
    def base_pos(self) -> np.ndarray:
        """m, world frame (n, 3)"""
        return self.data[:, C["x"] : C["z"] + 1]

    @property
    def base_vel(self) -> np.ndarray:
        """m/s, world frame (n, 3)"""
        return self.data[:, C["vx"] : C["vz"] + 1]

    @property
    def base_acc(self) -> np.ndarray:
        """m/s^2, world frame (n, 3)"""
        return self.data[:, C["ax"] : C["az"] + 1]

    @property
    def desired_pos(self) -> np.ndarray:
        """m (n, 2)"""
        return self.data[:, C["x_des"] : C["y_des"] + 1]

    @property
    def desired_vel(self) -> np.ndarray:
        """m/s (n, 2)"""
        return self.data[:, C["vx_des"] : C["vy_des"] + 1]

    @property
    def hip_angle(self) -> np.ndarray:
        """rad, (hip_y, hip_x) (n, 2)"""
        return self.data[:, C["hip_y"] : C["hip_x"] + 1]

    @property
    def hip_rate(self) -> np.ndarray:
        """rad/s, (hip_y, hip_x) (n, 2)"""
        return self.data[:, C["hip_y_rate"] : C["hip_x_rate"] + 1]

    @property
    def ctrl(self) -> np.ndarray:
        """Controls in actuator space, (hip_y, hip_x, thrust) (n, 3): the
        hips' before their gear of 600, the thrust in N (gear 1)."""
        return self.data[:, C["ctrl_hip_y"] : C["ctrl_thrust"] + 1]

    @property
    def hip_torque(self) -> np.ndarray:
        """N m, joint space (hip_y, hip_x) (n, 2): MuJoCo's qfrc_actuator at
        the hip joints, i.e. gear x control."""
        return self.data[:, C["torque_hip_y"] : C["torque_hip_x"] + 1]

    @property
    def thrust_force(self) -> np.ndarray:
        """N, joint space: the thrust actuator's force on the foot spring (n,)."""
        return self.data[:, C["force_thrust"]]

    @property
    def hip_power(self) -> np.ndarray:
        """W, mechanical power of each hip actuator, joint torque x joint
        rate (hip_y, hip_x) (n, 2)."""
        return self.hip_torque * self.hip_rate

    @property
    def touch(self) -> np.ndarray:
        """N"""
        return self.data[:, C["touch"]]

    @property
    def touch_toggles(self) -> np.ndarray:
        """The touch sensor's on/off switches (> 0 N is on) at the physics
        rate since the previous sample, counted on the reading the
        controller gets (:data:`mat_hopper.core._loop.CHANNELS`) (n,)."""
        return self.data[:, C["touch_toggles"]]

    @property
    def foot_clearance_min_m(self) -> np.ndarray:
        """m, the least distance between the foot and the terrain at the
        physics rate since the previous sample (n,); negative: the foot's
        penetration into the ground."""
        return self.data[:, C["foot_clearance_min"]]

    @property
    def phase(self) -> np.ndarray:
        """0 flight, 1 stance"""
        return self.data[:, C["phase"]]

    @property
    def thrust(self) -> np.ndarray:
        """N, the adaptive thrust setting F"""
        return self.data[:, C["thrust_setting"]]

    @property
    def touchdown_times_s(self) -> np.ndarray:
        return self.events[self.events[:, 1] == TOUCHDOWN, 0]

    @property
    def liftoff_times_s(self) -> np.ndarray:
        return self.events[self.events[:, 1] == LIFTOFF, 0]

    @property
    def hop_heights_m(self) -> np.ndarray:
        h = self.events[self.events[:, 1] == TOUCHDOWN, 2]
        return h[np.isfinite(h)]

    # --- outcome ---
    @property
    def stable(self) -> bool:
        """True when the run reached its end without numerical divergence."""
        return self.diverged_step < 0

    @property
    def diverged(self) -> bool:
        """True when the run ended early on a numerical divergence (not :attr:`stable`)."""
        return not self.stable

    @property
    def diverged_at_s(self) -> float | None:
        """Simulated time (s) of divergence, or None."""
        return None if self.stable else self.diverged_step * self.settings.timestep_s

    @property
    def fell_at_s(self) -> float | None:
        """Simulated time (s) of the first sample whose base tilt (roll and
        pitch together) exceeds :data:`FELL_TILT_DEG`, or None."""
        tilt = np.degrees(np.hypot(self.data[:, C["roll"]], self.data[:, C["pitch"]]))
        over = np.flatnonzero(tilt > FELL_TILT_DEG)
        return float(self.data[over[0], C["t"]]) if len(over) else None

    @property
    def suspect_apex(self) -> tuple[float, float] | None:
        """The first scored hop apex (time s, height m) above the target by
        more than :data:`SUSPECT_APEX_MARGIN_M` in a run that did not
        diverge: touchdowns at or after ``settings.transient_s`` and before
        any fall. None when there is none (or the run diverged)."""
        if self.diverged:
            return None
        ev = self.events[(self.events[:, 1] == TOUCHDOWN) & (self.events[:, 0] >= self.settings.transient_s)]
        fell = self.fell_at_s
        if fell is not None:
            ev = ev[ev[:, 0] <= fell]
        limit = self.settings.controller.hop_height_target_m + SUSPECT_APEX_MARGIN_M
        over = np.flatnonzero(np.isfinite(ev[:, 2]) & (ev[:, 2] > limit))
        return (float(ev[over[0], 0]), float(ev[over[0], 2])) if len(over) else None

    @property
    def suspect(self) -> bool:
        """True when the run did not diverge but its numbers are corrupted
        (:attr:`suspect_apex`): treat it like a diverged run."""
        return self.suspect_apex is not None

    def suspect_message(self, auto_hint: str = 'timestep_s="auto"') -> str | None:
        """One line on a numerically suspect run: when (t, s), why (the apex
        against the target, m) and what to try; None for a run that is not.

        Args:
            auto_hint: how the reader asks for the automatic step:
                ``timestep_s="auto"`` (the API, default) or ``--timestep auto``.
        """
        apex = self.suspect_apex
        if apex is None:
            return None
        target = self.settings.controller.hop_height_target_m
        return (
            f"numerically suspect: a hop apex of {apex[1]:.2f} m at t = {apex[0]:.3f} s, more than "
            f"{SUSPECT_APEX_MARGIN_M:g} m above the {target:g} m target (energy the integrator made up at a "
            f"physics step of {self.settings.timestep_s:.3g} s near the leg's stable step); its numbers are "
            f"corrupted: rerun with {auto_hint} or a smaller step"
        )

    def warn_if_suspect(self, what: str = "", stacklevel: int = 1) -> Rollout:
        """A :class:`SuspectWarning` with :meth:`suspect_message` (and `what`)
        when the run is numerically suspect, and a :class:`FallWarning` when
        the hopper fell without diverging; nothing else (a diverged run is
        :meth:`warn_if_diverged`'s).

        Args:
            what: a clause added to the message, or "".
            stacklevel: as :func:`warnings.warn`'s, counted from the caller.

        Returns:
            This rollout.
        """
        tail = f"; {what}" if what else ""
        if self.suspect:
            warnings.warn(f"{self.design.name}: {self.suspect_message()}{tail}", SuspectWarning, stacklevel + 1)
        if self.stable and self.fell_at_s is not None:
            warnings.warn(f"{self.design.name}: {self.fall_message()}{tail}", FallWarning, stacklevel + 1)
        return self

    def fall_message(self) -> str | None:
        """One line on a fall without divergence (when, s), None otherwise."""
        fell = self.fell_at_s
        if self.diverged or fell is None:
            return None
        return (
            f"the hopper fell (base tilted past {FELL_TILT_DEG:g} deg at t = {fell:.3f} s); "
            "hop cycles after the fall are not scored"
        )

    def divergence_message(self, auto_hint: str = 'timestep_s="auto"') -> str | None:
        """One line on a divergence: when (t, s), why (:attr:`divergence_reason`)
        and what to try (:func:`mat_hopper.core.timestep.remedies`: the stiff
        contact for a bending leg on the default soft one, the automatic step).

        Args:
            auto_hint: how the reader asks for the automatic step:
                ``timestep_s="auto"`` (the API, default) or ``--timestep auto``.

        Returns:
            ``"diverged at t = 0.0043 s (numerical divergence: ...); try ..."``,
            or None for a stable run.
        """
        if self.stable:
            return None
        from .timestep import remedies

        reason = self.divergence_reason or "numerical divergence: |qacc| > 1e6 or NaN"
        fix = remedies(self.design, self.settings, auto_hint)
        return f"diverged at t = {self.diverged_at_s:.4f} s ({reason})" + (f"; {fix}" if fix else "")

    def warn_if_diverged(self, what: str = "", stacklevel: int = 1) -> Rollout:
        """A :class:`DivergenceWarning` with :meth:`divergence_message` (and
        `what`, e.g. what a table holds) when the run diverged; nothing else.

        Args:
            what: a clause added to the message, or "".
            stacklevel: as :func:`warnings.warn`'s, counted from the caller
                of this method (1: the caller's line).

        Returns:
            This rollout.
        """
        if self.diverged:
            text = f"{self.design.name}: {self.divergence_message()}" + (f"; {what}" if what else "")
            warnings.warn(text, DivergenceWarning, stacklevel + 1)
        return self

    @property
    def upright(self) -> bool:
        """Stable and the base ended above 0.1 m (the paper's criterion)."""
        return self.stable and len(self.data) > 0 and self.data[-1, C["z"]] > ref.STABLE_MIN_BASE_Z

    def to_frame(self):
        """All channels as a pandas DataFrame, one row per sample."""
        import pandas as pd

        return pd.DataFrame(self.data, columns=list(CHANNELS))


def check_transient(transient_s) -> float | None:
    """A scoring transient: None (the run's own), or a finite number >= 0 s.

    Args:
        transient_s: None, or the time (s) before which hop cycles are not
            scored: an int or a float.

    Returns:
        None, or `transient_s` as a float, s.

    Raises:
        ValueError: a bool, a string or other non-number, nan, inf or a
            negative value (nan scored no hop at all: an empty table, silently).
    """
    if transient_s is None:
        return None
    ok = is_real(transient_s)
    x = float(transient_s) if ok else float("nan")
    if not (np.isfinite(x) and x >= 0):
        raise ValueError(f"transient_s must be None (the run's) or a finite number >= 0 s, got {transient_s!r}")
    return x


def check_transient_within(rollout: Rollout, transient_s) -> float | None:
    """A scoring transient (:func:`check_transient`) that leaves part of
    the run to score: before the run's planned end, ``settings.duration_s``
    (a transient at or past it scored nothing: an empty table, silently).

    Args:
        rollout: a :class:`Rollout`.
        transient_s: None (the run's own), or the time (s) before which hop
            cycles are not scored.

    Returns:
        None, or `transient_s` as a float, s.

    Raises:
        ValueError: what :func:`check_transient` refuses, or a transient
            at or beyond the run's duration (naming both).
    """
    x = check_transient(transient_s)
    duration = float(rollout.settings.duration_s)
    if x is not None and x >= duration:
        raise ValueError(
            f"transient_s {x:g} s is at or beyond the run's end (duration {duration:g} s): nothing would be scored; "
            "give a transient below the duration"
        )
    return x


def hop_cycles(rollout: Rollout, transient_s: float | None = None) -> np.ndarray:
    """The scored hop cycles of a rollout, lift-off to lift-off: those
    starting at or after the transient and, where the hopper fell
    (:attr:`Rollout.fell_at_s`), ending before the fall: a cycle the fall
    cuts through is a tumble, not a hop (its "power" reaches 1e5-1e6 W).
    A diverged run's records stop at the divergence, so its cycles do too.

    Args:
        rollout: a :class:`Rollout`.
        transient_s: cycles starting before it (s) are not scored, a finite
            number >= 0; None: the rollout's own ``settings.transient_s``.

    Returns:
        (k, 2) array of (start, end) times in s; (0, 2) with fewer than two
        lift-offs.

    Raises:
        ValueError: `transient_s` not None nor a finite number >= 0 s
            (:func:`check_transient`), or at or beyond the run's end
            (:func:`check_transient_within`).
    """
    transient_s = check_transient_within(rollout, transient_s)
    transient = rollout.settings.transient_s if transient_s is None else transient_s
    lo = rollout.liftoff_times_s
    if len(lo) < 2:
        return np.zeros((0, 2))
    cyc = np.column_stack([lo[:-1], lo[1:]])
    cyc = cyc[cyc[:, 0] >= transient]
    fell = rollout.fell_at_s
    return cyc if fell is None else cyc[cyc[:, 1] <= fell]


def divergence_reason(rollout: Rollout, model, data) -> str | None:
    """Why a rollout diverged, from the state the divergence check stopped
    at: which check fired (a NaN or inf, naming the joint; or
    |qacc| > :data:`mat_hopper.core.reference.DIVERGENCE_QACC`, naming the
    joint and the value), whether the hopper had fallen first (base tilt
    past :data:`FELL_TILT_DEG`), and the step above the leg's analytic bound
    if it is (:func:`mat_hopper.core.timestep.stable_step_excess`); for a
    bending leg on the default soft contact, that contact's measured cause
    (:func:`mat_hopper.core.timestep.soft_contact_cause`).

    Args:
        rollout: the :class:`Rollout` (its design, settings and records).
        model: the run's ``mujoco.MjModel`` (for the joints' names).
        data: the run's ``mujoco.MjData`` as the loop left it, at the step
            of divergence.

    Returns:
        One clause, ``"numerical divergence: |qacc| 3.1e+07 > 1e+06 at joint
        mat_spring_2; the physics step ... above ..."``; None for a stable run.
    """
    if rollout.stable:
        return None
    from .timestep import soft_contact_cause, stable_step_excess

    qacc, qpos = np.asarray(data.qacc), np.asarray(data.qpos)
    joint = lambda jid: model.joint(int(jid)).name or f"#{int(jid)}"
    if not np.isfinite(qacc).all():
        why = f"NaN or inf in qacc at joint {joint(model.dof_jntid[np.flatnonzero(~np.isfinite(qacc))[0]])}"
    elif not np.isfinite(qpos).all():
        at = np.searchsorted(model.jnt_qposadr, np.flatnonzero(~np.isfinite(qpos))[0], side="right") - 1
        why = f"NaN or inf in qpos at joint {joint(at)}"
    else:
        i = int(np.argmax(np.abs(qacc)))
        why = f"|qacc| {abs(qacc[i]):.3g} > {ref.DIVERGENCE_QACC:.0e} at joint {joint(model.dof_jntid[i])}"
    parts = [f"numerical divergence: {why}"]
    fell = rollout.fell_at_s
    if fell is not None and fell < rollout.diverged_at_s:
        parts.append(f"after a fall: the base tilted past {FELL_TILT_DEG:g} deg at t = {fell:.3f} s")
    excess = stable_step_excess(rollout.design, rollout.settings)
    cause = None if excess else soft_contact_cause(rollout.design, rollout.settings)
    return "; ".join(parts + [c for c in (cause, excess) if c])
