"""Fast headless rollouts in simulated time.

:func:`simulate` runs one design on one behaviour and returns a
:class:`Rollout` of arrays recorded at ``record_rate_hz`` (default 1 kHz).
The whole loop (MuJoCo step, controller, desired path, divergence check,
recording) is one numba-compiled function (:mod:`mat_hopper.core._loop`) that
calls libmujoco's ``mj_step1``/``mj_step2`` through ctypes on the Python
bindings' own buffers, so the rollout costs little more than the bare
physics.

Sensor timing (``SimSettings.sensor_timing``, recorded in every result):
by default ``"authors"``, the authors' loop, in which the controller sees
the base sensors one physics step old and the hips current; ``"fresh"``
reads the base from the current state; an integer latency L (physics
steps) generalises both. See :mod:`mat_hopper.core.controller` for exactly when
each reading is taken.

Numerical divergence (a NaN or inf, or |qacc| > 1e6) ends the run early and
marks it diverged with when and why (``Rollout.divergence_reason``); MuJoCo's
automatic reset is disabled so divergence can never pass unseen.

Set ``NUMBA_DISABLE_JIT=1`` to run the very same loop as plain Python.
"""

from __future__ import annotations

import copy
import logging
import math
from dataclasses import dataclass, field, fields

import mujoco
import numpy as np

from ..util.parsing import is_real
from . import reference as ref
from ._loop import (
    CHANNELS,
    HISTORY_WIDTH,
    JERK_CUTOFF_HZ,
    JERK_FILTER_ORDER,
    MJ_GEOM_DISTANCE,
    MJ_STEP1,
    MJ_STEP2,
    N_CHANNELS,
    RECORD_DTYPE,
    C,
    Path,
    Steps,
    StressProbe,
    apex_reference_of,
    buffers,
    contact_probe,
    jerk_filter,
    read_sensors,
    rollout_loop,
)
from .behaviours import behaviour as get_behaviour
from .contact import DEFAULT_CONTACT, check_contact
from .controller import (
    DEFAULT_APEX_REFERENCE,
    DEFAULT_SENSOR_TIMING,
    OUT_SIZE,
    ControllerSettings,
    SensorTiming,
    check_apex_reference,
    initial_state,
)
from .damping import DEFAULT_DAMPING, check_damping
from .materials import DEFAULT_CONVENTION, DEFAULT_SEGMENT_MASS, as_design, check_convention, check_segment_mass
from .model import check_timestep, prepare, stress_gains
from .perturbations import Perturbation
from .replicates import (
    DEFAULT_REPLICATE_PROTOCOL,
    check_branch_fork,
    check_push,
    check_replicate_protocol,
    kick_base,
    replicate_draws,
)
from .rollout import Rollout, divergence_reason
from .timestep import is_auto, resolve_timestep, warn_stable_step

__all__ = [
    "CHANNELS",
    "C",
    "JERK_CUTOFF_HZ",
    "JERK_FILTER_ORDER",
    "N_CHANNELS",
    "DEFAULT_RECORD_RATE_HZ",
    "SimSettings",
    "sim_settings",
    "RolloutRunner",
    "prepare",
    "simulate",
    "route_mujoco_warnings",
]

DEFAULT_RECORD_RATE_HZ = 1000.0
MAX_SUBSTEPS = 1000
# Run-size limits, checked before anything is allocated: 2e9 physics steps,
# 5e6 recorded samples (1.5 GB of records).
MAX_STEPS = 2_000_000_000
MAX_SAMPLES = 5_000_000
# Physics steps per call of the compiled loop. Python runs signal handlers
# (Ctrl-C, SIGTERM) only between calls, so every call must end within a
# fraction of a second of wall time at any time step: sized in steps, not
# simulated seconds, and scaled down for longer chains (a step's cost
# grows with the number of segments).
LOOP_CHUNK_STEPS = 20_000  # for legs of up to 3 segments


def loop_chunk_steps(n_segments: int) -> int:
    """Physics steps per compiled-loop call for a leg of n_segments.

    Args:
        n_segments: segments of the leg (values below 3 count as 3).

    Returns:
        :data:`LOOP_CHUNK_STEPS` x 3 // n_segments (integer division), at
        least 1000: 20000 for up to 3 segments, 1000 from 60 segments on.
    """
    return max(1000, LOOP_CHUNK_STEPS * 3 // max(3, int(n_segments)))


# The jerk low-pass (JERK_CUTOFF_HZ, jerk_filter) lives beside the loop that runs it (_loop).


_log = logging.getLogger("mat_hopper.mujoco")


def route_mujoco_warnings() -> None:
    """Send MuJoCo's warnings to logging (logger ``mat_hopper.mujoco``,
    level DEBUG) instead of stderr and a MUJOCO_LOG.TXT in the working
    folder. Divergence is detected and reported by the rollout itself. Not
    done on import (it is process-wide): the CLI calls it; a handler the
    user installed is left alone."""
    if mujoco.get_mju_user_warning() is None:
        mujoco.set_mju_user_warning(lambda msg: _log.debug("MuJoCo: %s", msg))


# ---------------------------------------------------------------------------


@dataclass(frozen=True)
class SimSettings:
    """Everything besides design and behaviour that changes a rollout: the
    one settings object (a batch, a profile and the CLI all build it with
    :func:`sim_settings`; copies are ``dataclasses.replace``).

    Args:
        duration_s: simulated run length, s (> transient_s, and at least
            one control period, :attr:`control_period_s`).
        timestep_s: physics step, s, in (0, 0.1]; ``"auto"`` is resolved
            by :func:`sim_settings` (:func:`resolve_timestep`), not here.
        transient_s: hop cycles starting before it are not scored, s.
        convention: modulus-to-stiffness convention, one of ``materials.CONVENTIONS``:
            ``"paper"``, ``"axial"``, ``"bending"``, ``"axial+bending"``;
            any case, stored as spelled there.
        record_rate_hz: recorded samples per simulated second, Hz.
        controller: the controller's gains.
        perturbation: seeded disturbances, or None.
        sensor_timing: when the controller's base readings are taken, stored
            as a :class:`~mat_hopper.core.controller.SensorTiming` (an integer latency
            in physics steps carrying its name): ``"authors"`` (default: one
            physics step old), ``"fresh"``, ``"latency-L"`` or an integer L.
        segment_mass: ``"leg"`` (default: mass independent of the number
            of segments, the authors' model at N = 3) or ``"capsule"`` (the
            authors' per-capsule density at any N; :mod:`mat_hopper.core.conventions`);
            any case, stored as spelled there.
        substeps: physics steps per control period, an integer in [1, 1000];
            the controller runs every ``substeps`` steps, i.e. with period
            :attr:`control_period_s` (1 by default: every step, as the
            authors' loop).
        damping: how the material springs dissipate, ``"authors"``
            (default: 1 N s/m, the authors' file) or ``"loss-factor"`` (each
            material's loss factor, :data:`mat_hopper.core.damping.LOSS_FACTORS`);
            any case, stored as spelled in :data:`mat_hopper.core.damping.DAMPINGS`.
        contact: ``"authors"`` (default: MuJoCo's solref 0.02 1), ``"stiff"`` (0.001 1) or ``"stiff-elliptic"`` (stiff, elliptic friction cones), any case (contact.CONTACTS).
        apex_reference: what the controller's hop height is measured from, ``"world"`` (default: world z, the
            authors') or ``"ground"`` (the terrain under the foot at lift-off); controller.APEX_REFERENCES.
        replicate_protocol: when the perturbation acts: ``"authors"`` (default, step 0), ``"branch"``
            or ``"branch-settled"`` (after an unperturbed prefix); any case (:mod:`mat_hopper.core.replicates`).

    Raises:
        ValueError: on any invalid value, naming the field.
    """

    duration_s: float = ref.DURATION_S
    timestep_s: float = ref.TIMESTEP_S
    transient_s: float = ref.TRANSIENT_S
    convention: str = DEFAULT_CONVENTION
    record_rate_hz: float = DEFAULT_RECORD_RATE_HZ
    controller: ControllerSettings = field(default_factory=ControllerSettings)
    perturbation: Perturbation | None = None
    sensor_timing: SensorTiming = SensorTiming()
    segment_mass: str = DEFAULT_SEGMENT_MASS
    substeps: int = 1
    damping: str = DEFAULT_DAMPING  # "authors" (1 N s/m) or "loss-factor" (damping.LOSS_FACTORS)
    contact: str = DEFAULT_CONTACT  # "authors" (solref 0.02 1), "stiff" (0.001 1), "stiff-elliptic" (contact.CONTACTS)
    apex_reference: str = DEFAULT_APEX_REFERENCE  # "world" or "ground" (controller.APEX_REFERENCES)
    replicate_protocol: str = DEFAULT_REPLICATE_PROTOCOL  # "authors" and the two branching ones (replicates)

    def __post_init__(self):
        # One check per field (a new field adds its own line); then the checks across fields.
        _check_substeps(self.substeps)
        object.__setattr__(self, "sensor_timing", SensorTiming(self.sensor_timing))
        object.__setattr__(self, "segment_mass", check_segment_mass(self.segment_mass))
        object.__setattr__(self, "damping", check_damping(self.damping))
        object.__setattr__(self, "contact", check_contact(self.contact))
        object.__setattr__(self, "apex_reference", check_apex_reference(self.apex_reference))
        object.__setattr__(self, "replicate_protocol", check_replicate_protocol(self.replicate_protocol))
        for name in ("duration_s", "timestep_s", "transient_s", "record_rate_hz"):
            v = getattr(self, name)
            if not is_real(v) or not math.isfinite(v):
                auto = (
                    " (or 'auto' through simulate() or sim_settings(), with the design)" if name == "timestep_s" else ""
                )
                raise ValueError(f"{name} must be a finite number{auto}, got {v!r}")
        check_timestep(self.timestep_s)
        if self.transient_s < 0:
            raise ValueError(f"transient must be >= 0 s, got {self.transient_s!r}")
        if not self.record_rate_hz > 0:
            raise ValueError(f"record_rate_hz must be > 0 Hz, got {self.record_rate_hz!r}")
        object.__setattr__(self, "convention", check_convention(self.convention))
        if not isinstance(self.controller, ControllerSettings):
            raise ValueError("controller must be a ControllerSettings")
        if self.perturbation is not None and not isinstance(self.perturbation, Perturbation):
            raise ValueError("perturbation must be a Perturbation or None")
        self._check_run_size()
        check_push(self)

    def _check_run_size(self) -> None:
        if not self.duration_s > self.transient_s:
            raise ValueError(f"duration must be > transient ({self.transient_s:g} s), got {self.duration_s!r} s")
        if self.duration_s < self.control_period_s:  # no step, or a part of one: an empty run
            of = f"{self.substeps} x timestep {self.timestep_s:g} s" if self.substeps > 1 else "the timestep"
            raise ValueError(
                f"duration must be at least one control period, {self.control_period_s:g} s ({of}), "
                f"got {self.duration_s:g} s"
            )
        if self.duration_s / self.timestep_s > MAX_STEPS:
            raise ValueError(
                f"duration / timestep = {self.duration_s / self.timestep_s:.3g} physics steps: over the "
                f"limit of {MAX_STEPS:.0e} (a longer duration_s or smaller timestep_s than supported)"
            )
        if self.n_steps / self.record_every > MAX_SAMPLES:
            raise ValueError(
                f"{self.n_steps / self.record_every:.3g} recorded samples: over the limit of "
                f"{MAX_SAMPLES:.0e}; lower record_rate_hz or duration_s"
            )

    @property
    def record_every(self) -> int:
        """Physics steps between recorded samples (>= 1)."""
        return max(1, int(round(1.0 / (self.record_rate_hz * self.timestep_s))))

    @property
    def n_steps(self) -> int:
        return int(round(self.duration_s / self.timestep_s))

    @property
    def control_period_s(self) -> float:
        """s, the controller's period: substeps x timestep_s."""
        return self.substeps * self.timestep_s

    def columns(self, *names: str) -> dict:
        """The named fields as result tables record them (a sensor timing by
        its name), for a table's setting columns; ValueError for an unknown name."""
        unknown = [n for n in names if n not in SETTING_NAMES]
        if unknown:
            raise ValueError(f"unknown setting(s) {', '.join(unknown)}; accepted: {', '.join(SETTING_NAMES)}")
        return {n: (self.sensor_timing.name if n == "sensor_timing" else getattr(self, n)) for n in names}

    @property
    def sensor_latency_steps(self) -> int:
        """Physics steps by which the controller's base readings lag (``int(sensor_timing)``)."""
        return int(self.sensor_timing)


SETTING_NAMES = tuple(f.name for f in fields(SimSettings))


def _check_substeps(substeps) -> None:
    if isinstance(substeps, bool) or not isinstance(substeps, (int, np.integer)) or not 1 <= substeps <= MAX_SUBSTEPS:
        raise ValueError(
            f"substeps must be an integer in [1, {MAX_SUBSTEPS}] (physics steps per control period), got {substeps!r}"
        )


def sim_settings(design=None, **settings) -> SimSettings:
    """The one builder of :class:`SimSettings`: every entry point (the CLI,
    :func:`simulate`, batches, profiles, the optimizer) calls it.

    Args:
        design: the leg, needed only when ``timestep_s="auto"``.
        **settings: any :class:`SimSettings` field; ``timestep_s`` may be
            ``"auto"`` (then ``substeps`` may not be given: it is chosen).

    Returns:
        The checked SimSettings.

    Raises:
        ValueError: an unknown field (named), ``substeps`` beside
            ``"auto"``, or any invalid value.

    >>> sim_settings(duration_s=2.0, transient_s=0.5, sensor_timing="fresh").sensor_timing.name
    'fresh'
    """
    unknown = sorted(set(settings) - set(SETTING_NAMES))
    if unknown:
        raise ValueError(f"unknown setting(s) {', '.join(unknown)}; accepted: {', '.join(SETTING_NAMES)}")
    if is_auto(settings.get("timestep_s")):
        if "substeps" in settings:
            raise ValueError("substeps cannot be given with timestep_s='auto' (auto chooses them)")
        settings["timestep_s"], settings["substeps"] = resolve_timestep(
            settings["timestep_s"],
            design,
            settings.get("convention", DEFAULT_CONVENTION),
            settings.get("segment_mass", DEFAULT_SEGMENT_MASS),
            settings.get("sensor_timing", DEFAULT_SENSOR_TIMING),
            settings.get("contact", DEFAULT_CONTACT),
        )
    if settings.get("controller") is None:
        settings.pop("controller", None)
    return SimSettings(**settings)


class RolloutRunner:
    """A rollout that advances in chunks of physics steps (see :func:`simulate`).

    Useful to inspect or snapshot the MuJoCo state part-way, or to
    :meth:`fork` it into runs that share a prefix; ``simulate`` runs it in
    one call of :meth:`advance`. record_qpos keeps every joint position at
    the record rate, which rendering needs."""

    def __init__(self, design, behaviour, settings: SimSettings, *, record_qpos: bool = False):
        if not isinstance(settings, SimSettings):
            raise ValueError(f"settings must be a SimSettings, got {type(settings).__name__}")
        self.design = as_design(design)
        self.behaviour = get_behaviour(behaviour)
        self.settings = settings
        offset, tilt = self._draw(settings)
        self.hopper, self.data = prepare(self.design, self.behaviour, settings, offset, tilt)
        n_rec = settings.n_steps // settings.record_every + 2
        self._rec = np.zeros(n_rec, RECORD_DTYPE)
        self._qpos = np.zeros((n_rec if record_qpos else 0, self.hopper.model.nq))
        lock = settings.controller.phase_lock_s
        n_ev = int(settings.duration_s / lock) + 16 if lock > 0 else settings.n_steps + 1
        self._events = np.zeros((n_ev, 3))
        adr, gain = stress_gains(self.hopper)
        self._probe = StressProbe(adr, gain, np.zeros(len(adr)))
        self._contact = contact_probe(self.hopper.model, self.data.sensordata[self.hopper.layout.touch] > 0.0)
        self._apex = apex_reference_of(self.hopper.model, settings.apex_reference, self.behaviour.ramp_grade_deg)
        self._stress = np.zeros((n_rec, len(adr), 4))
        self._state = initial_state(settings.controller)
        self._out = np.zeros(OUT_SIZE)  # the controller's last outputs, held between control updates
        self._gains = settings.controller.gains()
        # Reading history: every lagged reading starts as the start state's.
        self._history = np.zeros((settings.sensor_latency_steps + 1, HISTORY_WIDTH))
        read_sensors(self.data.sensordata, self.hopper.layout, self._history[0])
        self._history[1:] = self._history[0]
        self._buffers = buffers(self.data)
        beh = self.behaviour
        self._path = Path(beh.path_code, beh.path_params, beh.table_xy_m)
        self._jerk = jerk_filter(settings.timestep_s)
        self.step = 0
        self._n_rec = 0
        self._n_ev = 0
        self.diverged_step = -1

    def _draw(self, settings: SimSettings) -> tuple:
        """Set the disturbances of `settings`' perturbation (:func:`replicate_draws`;
        ``_branch_at`` -1: no branch pending); return the start (offset m, tilt rad)."""
        d = replicate_draws(settings)
        self._disturbance, self._scored, self._kick, self._branch_at = d.disturbance, d.scored, d.kick, d.branch_at
        return d.start_xy_m, d.tilt_rad

    @property
    def done(self) -> bool:
        return self.step >= self.settings.n_steps or self.diverged_step >= 0

    def fork(self) -> RolloutRunner:
        """An independent copy of this rollout at its current step, so that
        runs sharing a prefix simulate it once.

        The copy holds its own MuJoCo data (``mujoco.mj_copyData``: the
        whole state, contacts, sensors and applied forces, not only the
        integration state, since the loop reads the touch sensor before the
        next step refreshes it), controller state and outputs, reading
        history, filter and probe states, records and counters; it shares
        only what no step writes: the compiled model, the design, behaviour
        and settings, the disturbance's draws, the path and the gains.
        Advancing either one leaves the other as it was, and each ends
        bit-identical to a run that was never forked.

        Returns:
            A new :class:`RolloutRunner` at the same step.
        """
        twin = copy.copy(self)  # the shared, read-only parts; every mutable part replaced below
        twin.data = mujoco.MjData(self.hopper.model)
        mujoco.mj_copyData(twin.data, self.hopper.model, self.data)
        twin._buffers = buffers(twin.data)
        for name in ("_state", "_out", "_history", "_rec", "_qpos", "_events", "_stress"):
            setattr(twin, name, getattr(self, name).copy())
        twin._jerk = self._jerk._replace(state=self._jerk.state.copy())
        twin._contact = self._contact._replace(state=self._contact.state.copy())
        twin._probe = self._probe._replace(peak=self._probe.peak.copy())
        return twin

    def fork_as(self, settings: SimSettings) -> RolloutRunner:
        """A fork that goes on as another branching replicate of this run, whose replicates share the
        unperturbed prefix up to the branch time: simulated once, forked for each (:mod:`.replicates`).

        Args:
            settings: the replicate's SimSettings: this run's but for the perturbation, branching.

        Returns:
            A new :class:`RolloutRunner` at this step that ends bit-identical to one of `settings` run alone.

        Raises:
            ValueError: not branching, other settings, or a run past its prefix (:func:`check_branch_fork`).
        """
        pending = self.settings.perturbation is None or self._branch_at >= 0
        check_branch_fork(self.settings, settings, self.step, pending)
        twin = self.fork()
        twin.settings = settings
        twin._draw(settings)
        return twin

    def advance(self, n_steps: int | None = None) -> RolloutRunner:
        """Run up to n_steps more physics steps (all that remain by default)."""
        if self.done:
            return self
        remaining = self.settings.n_steps - self.step
        n = remaining if n_steps is None else min(int(n_steps), remaining)
        end = self.step + n
        while self.step < end and self.diverged_step < 0:  # signals are handled between chunks
            if self.step == self._branch_at:  # a branching replicate at its branch time: the kick, then noise, push
                kick_base(self.data.qvel, self.hopper.layout.base_dof, self._kick)
                self._disturbance, self._branch_at = self._scored, -1
            stop = end if self.step >= self._branch_at else min(end, self._branch_at)  # a chunk ends at the branch
            self._advance_chunk(min(stop - self.step, loop_chunk_steps(self.design.n_segments)))
        return self

    def _advance_chunk(self, n: int) -> None:
        hm, st = self.hopper, self.settings
        steps = Steps(self.step, n, st.timestep_s, st.record_every, ref.DIVERGENCE_QACC, st.substeps)
        n_rec, n_ev, bad = rollout_loop(
            MJ_STEP1,
            MJ_STEP2,
            MJ_GEOM_DISTANCE,
            hm.model._address,
            self.data._address,
            self._buffers,
            hm.layout,
            self._gains,
            self._path,
            self._disturbance,
            steps,
            self._history,
            self._state,
            self._out,
            self._jerk,
            self._rec[self._n_rec :],
            self._qpos[self._n_rec :],
            self._events[self._n_ev :],
            self._probe,
            self._stress[self._n_rec :],
            self._contact,
            self._apex,
        )
        self._n_rec += n_rec
        self._n_ev += n_ev
        if bad >= 0:
            self.diverged_step = int(bad)
        self.step += n

    def result(self) -> Rollout:
        data = self._rec[: self._n_rec].view(np.float64).reshape(self._n_rec, N_CHANNELS).copy()
        r = Rollout(
            self.design,
            self.behaviour,
            self.settings,
            data,
            self._events[: self._n_ev].copy(),
            self.diverged_step,
            self.hopper.total_mass_kg,
            self.hopper.spring_stiffness_n_m,
        )
        if len(self._qpos):
            r.qpos = self._qpos[: self._n_rec].copy()
        r.stress = self._stress[: self._n_rec].copy()
        r.divergence_reason = divergence_reason(r, self.hopper.model, self.data)  # the state the check stopped at
        return r


# simulate()'s keyword arguments that are SimSettings fields, in its signature's order.
_SETTING_ARGUMENTS = (
    "duration_s",
    "timestep_s",
    "transient_s",
    "convention",
    "sensor_timing",
    "controller",
    "record_rate_hz",
    "perturbation",
    "segment_mass",
    "substeps",
    "damping",
    "contact",
    "apex_reference",
    "replicate_protocol",
)


def simulate(
    design,
    behaviour,
    duration_s: float | None = None,
    timestep_s: float | str | None = None,
    *,
    transient_s: float | None = None,
    convention: str | None = None,
    sensor_timing: str | int | None = None,
    controller: ControllerSettings | None = None,
    record_rate_hz: float | None = None,
    perturbation: Perturbation | None = None,
    segment_mass: str | None = None,
    substeps: int | None = None,
    damping: str | None = None,
    contact: str | None = None,
    apex_reference: str | None = None,
    replicate_protocol: str | None = None,
    record_qpos: bool = False,
    settings: SimSettings | None = None,
    warn: bool = True,
) -> Rollout:
    """Run a design on a behaviour for ``duration_s`` simulated seconds.

    Every setting left at None takes :class:`SimSettings`' default (the
    paper's protocol: 60 s, 1e-4 s step, 20 s transient, the authors'
    sensor timing and stiffness convention).

    Args:
        design: a LegDesign or a name (``"SS"``, ``"PVC-Ti-SS"``, ``"rho-inc"``).
        behaviour: a Behaviour or ``"static"``, ``"forward"``, ``"ramp"``, ``"circle"``.
        duration_s: simulated run length, s.
        timestep_s: physics step, s, or ``"auto"``: physics substeps of the
            1e-4 s control period, chosen from the analytic bound
            (:func:`resolve_timestep`).
        transient_s: hop cycles starting before it are not scored, s (the
            run must outlast it).
        convention: ``"paper"``, ``"axial"``, ``"bending"`` or
            ``"axial+bending"``, any case (:data:`mat_hopper.core.materials.CONVENTIONS`).
        sensor_timing: ``"authors"``, ``"fresh"``, ``"latency-L"`` (any
            case) or an integer latency in physics steps.
        controller: the controller's gains (ControllerSettings).
        record_rate_hz: samples per simulated second, Hz (1 kHz).
        perturbation: seeded disturbances for replicates.
        segment_mass: ``"leg"`` or ``"capsule"``, any case.
        substeps: physics steps per control period (not with ``"auto"``).
        damping: ``"authors"`` (1 N s/m) or ``"loss-factor"``, any case
            (:mod:`mat_hopper.core.damping`).
        contact: ``"authors"`` or ``"stiff"``, any case (:mod:`mat_hopper.core.contact`).
        apex_reference: ``"world"`` or ``"ground"``, any case (:mod:`mat_hopper.core.controller`).
        replicate_protocol: ``"authors"``, ``"branch"``, ``"branch-settled"`` (:mod:`mat_hopper.core.replicates`).
        record_qpos: also keep all joint positions (``Rollout.qpos``, (n, nq)) for rendering.
        settings: a SimSettings giving all of the settings at once; then no
            other setting may be given.
        warn: a StableStepWarning before a run whose step lies above the leg's
            analytic bound, a DivergenceWarning after one that diverged, a
            SuspectWarning after one whose numbers are corrupted without
            diverging (:attr:`Rollout.suspect`), a FallWarning after a fall
            without divergence; False: none.

    Returns:
        The :class:`Rollout`. Divergence never raises: see :attr:`Rollout.diverged`.

    Raises:
        ValueError: settings given beside ``settings=`` (named), invalid
            settings, designs or behaviours.

    >>> r = simulate("SS", "forward", duration_s=0.5, transient_s=0.0)
    >>> r.settings.sensor_timing.name, r.data.shape[1] == len(CHANNELS)
    ('authors', True)
    """
    passed = locals()  # the keyword arguments, first thing: each setting given by name
    given = {name: passed[name] for name in _SETTING_ARGUMENTS if passed[name] is not None}
    if settings is not None:
        if given:
            raise ValueError(f"simulate: {', '.join(given)} given beside settings=; put them in the SimSettings")
        if not isinstance(settings, SimSettings):
            raise ValueError(f"settings must be a SimSettings, got {type(settings).__name__}")
    else:
        settings = sim_settings(as_design(design), **given)
    if warn:
        warn_stable_step(design, settings, stacklevel=2)
    rollout = RolloutRunner(design, behaviour, settings, record_qpos=record_qpos).advance().result()
    return rollout.warn_if_diverged(stacklevel=2).warn_if_suspect(stacklevel=2) if warn else rollout
