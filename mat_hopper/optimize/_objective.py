"""What the optimizer minimizes, and the run profiles it simulates with.

Objectives (all minimized): two or three metrics of the named table
:data:`mat_hopper.physics.run_metrics.METRICS` (``Objective.objectives``),
from the per-hop metrics of :mod:`mat_hopper.physics.metrics` over the hop cycles
after the transient. The default, :data:`OBJECTIVES`:

1. ``tracking_error_m``: mean planar distance base - desired path (m);
2. ``power_w``: mean hip mechanical power (W).

Others: ``power_total_w`` (all three actuators, thrust included, W),
``energy_per_hop_j`` (J), ``peak_stress_pa`` (Pa), ``damage_per_hop``
(Miner damage) and ``leg_mass_kg`` (kg). A default objective's key has
no ``objectives`` entry, so a study keyed without the setting keeps its
key.

With several behaviours, each objective is the plain mean over the
behaviours of each behaviour's mean (every behaviour weighs the same,
whatever its number of hops). With ``replicates = K > 0`` (default 4) that
mean is taken per seeded replicate, on the same seeds for every trial, and
the objective is the mean or the CVaR over the replicates
(:mod:`mat_hopper.optimize._scoring`, which also adds the ``leg_mass``
constraint). Constraints (Optuna convention: <= 0 is
feasible):

- ``hop_height``: |mean hop height - 1 m| - 0.05 m, the worst behaviour;
- ``unstable``: 1 when any run diverged or ended with the base below
  0.1 m (:attr:`Rollout.upright` false), else 0;
- only when the objective asks for them (so studies without them keep
  their two constraints): ``peak_stress`` with
  ``max_yield_fraction`` f, the worst behaviour's largest segment peak
  stress over its yield strength minus f (f = 0.5: peak stress <= yield / 2);
  ``fatigue_life`` with ``min_hops_to_failure`` N, log10 N - log10(hops to
  failure), the worst behaviour's (:mod:`mat_hopper.physics.fatigue`; a run with no
  modelled stress, e.g. a rigid leg, is feasible; a run that fell is not).
  Stress is the ``bending`` conventions' business: under ``paper`` and
  ``axial`` only axial stress is modelled.

A run that diverged, fell (base below 0.1 m at the end) or scored no hop
cycle still gets finite objective values, the same quantities over every
finite recorded sample of the run
(:func:`~mat_hopper.physics.run_metrics.run_values`), so the
samplers can model it; the constraints make it infeasible.

Profiles are :mod:`mat_hopper.experiments.paper`' (one setting for the whole
package): ``paper`` is the paper's protocol (60 s runs, 20 s transient,
1e-4 s step); ``quick`` (12 s runs, 4 s transient) is for CI and first
looks: the hop height is still settling then, so quick results rank
designs roughly, not finally. Under the ``axial`` convention trials run at
the profile's axial time step.

Equal legs only: an objective records the segment-mass convention
(``segment_mass``, :data:`mat_hopper.core.materials.SEGMENT_MASSES`; default
``leg``: a leg's mass does not depend on its number of segments) and the
leg's total material length (:data:`LEG_MATERIAL_LENGTH_M`, 0.3 m at any
N) in its key, so a study never mixes trials of legs of different length
or mass convention: resuming with other settings is refused with one
error (:func:`mat_hopper.optimize._study.create_or_load`).
"""

from __future__ import annotations

import contextlib
import math
import warnings
from dataclasses import dataclass, field

import mujoco
import numpy as np

from ..core import reference as ref
from ..core.behaviours import BEHAVIOUR_NAMES
from ..core.behaviours import behaviour as get_behaviour
from ..core.materials import (
    DEFAULT_SEGMENT_MASS,
    LegDesign,
    check_convention,
    check_segment_mass,
)
from ..core.rollout import hop_cycles
from ..core.sim import RolloutRunner
from ..experiments.profiles import Profile, resolve_profile
from ..physics.fatigue import fatigue_summary
from ..physics.metrics import hop_table
from ..physics.run_metrics import DEFAULT_OBJECTIVES, NO_DATA_VALUE, parse_objectives, run_values
from ..util.parsing import is_real, parse_name
from . import _scoring

OBJECTIVES = DEFAULT_OBJECTIVES  # the default objectives (tracking error m, hip power W)
CONSTRAINTS = ("hop_height", "unstable")
STRESS_CONSTRAINTS = ("peak_stress", "fatigue_life")  # each only when asked (module doc)
RESULT_ATTR = "result"  # the trial user attr holding its Evaluation (record_evaluation)
HOP_HEIGHT_TOLERANCE_M = 0.05
CHUNK_S = 0.5  # simulated s per compiled chunk (lets the heartbeat thread run)
LEG_MATERIAL_LENGTH_M = ref.MATERIAL_LENGTH  # total length of the material segments, any N
# The stress constraints' accepted ranges. max_yield_fraction F in
# (0, 10]: a peak stress over about 3 x yield already passes the ultimate
# strength of every catalogue material (the largest ultimate / yield ratio is
# aluminium's, 2.97; mat_hopper.physics.fatigue), so a larger F lets broken legs
# through and constrains nothing. min_hops_to_failure N in [1, 1e20]: a life
# under one hop is no life, and 1e20 hops (1.6e12 years at 2 hops a second)
# is 1e13 times past the end of the S-N data (1e7 cycles), where Basquin's
# line is an extrapolation a larger N cannot sharpen.
MAX_YIELD_FRACTION = 10.0
HOPS_TO_FAILURE_RANGE = (1.0, 1e20)


@dataclass(frozen=True)
class Objective:
    """What the optimizer minimizes (by default tracking error and hip power),
    under a hop-height and a stability constraint (module doc).

    Args:
        behaviours: behaviours to run (names).
        profile: the run profile (duration, transient, time step,
            convention, segment mass), a Profile or its name; None (default):
            $MAT_HOPPER_PROFILE, else ``paper``
            (:func:`~mat_hopper.experiments.profiles.resolve_profile`).
        convention: the stiffness convention, any case (None: the profile's).
        hop_height_target_m, hop_height_tolerance_m: the hop height constraint, m.
        segment_mass: the segment mass convention (None: the profile's).
        replicates: perturbed replicates per behaviour on common random
            numbers (0: one unperturbed run; :mod:`mat_hopper.optimize._scoring`).
        risk: how replicates are scored, ``"mean"`` or ``"cvar"``, any case
            (stored as spelled in :data:`mat_hopper.optimize._scoring.RISKS`).
        cvar_alpha: the CVaR's tail fraction.
        leg_mass: None (unconstrained), a paper design's name or a mass in kg.
        leg_mass_tolerance_kg: the leg mass constraint's tolerance, kg (None:
            DEFAULT_LEG_MASS_TOLERANCE of the target).
        max_yield_fraction, min_hops_to_failure: the stress constraints
            (module doc; None: off): F in (0, :data:`MAX_YIELD_FRACTION`]
            and N in :data:`HOPS_TO_FAILURE_RANGE` ([1, 1e20] hops).
        objectives: the metrics minimized, two or three names of
            :data:`~mat_hopper.physics.run_metrics.METRICS` (a sequence or a
            comma-separated string, any case; default :data:`OBJECTIVES`).

    Raises:
        ValueError: an unknown behaviour, convention, risk or objective, or a
            value out of range (naming it).
    """

    behaviours: tuple[str, ...] = ("ramp",)
    profile: Profile | str | None = None  # None: $MAT_HOPPER_PROFILE, else paper
    convention: str | None = None  # None: the profile's
    hop_height_target_m: float = ref.HOP_HEIGHT_TARGET
    hop_height_tolerance_m: float = HOP_HEIGHT_TOLERANCE_M
    segment_mass: str | None = None  # None: the profile's
    max_yield_fraction: float | None = None  # peak stress <= this x yield (e.g. 0.5)
    min_hops_to_failure: float | None = None  # fatigue life of at least this many hops
    # noise- and mass-aware scores (mat_hopper.optimize._scoring)
    replicates: int = _scoring.DEFAULT_REPLICATES  # 0: one unperturbed run per behaviour
    risk: str = "mean"
    cvar_alpha: float = _scoring.DEFAULT_CVAR_ALPHA
    leg_mass: str | float | None = None  # None: unconstrained; a paper design's name or kg
    leg_mass_tolerance_kg: float | None = None  # None: DEFAULT_LEG_MASS_TOLERANCE of the target
    objectives: tuple[str, ...] = OBJECTIVES  # minimized metrics (mat_hopper.physics.run_metrics)

    def __post_init__(self):
        behs = self.behaviours
        if isinstance(behs, str):
            behs = tuple(b for b in behs.split(","))
        behs = tuple(str(b).strip().lower() for b in behs)
        if not behs or any(not b for b in behs):
            raise ValueError(f"behaviours: give one or more of {', '.join(BEHAVIOUR_NAMES)}")
        for b in behs:
            if b not in BEHAVIOUR_NAMES:
                from ..util.parsing import did_you_mean

                hint = f"; {did_you_mean(b, BEHAVIOUR_NAMES)}" if did_you_mean(b, BEHAVIOUR_NAMES) else ""
                raise ValueError(f"unknown behaviour {b!r}; accepted: {', '.join(BEHAVIOUR_NAMES)}{hint}")
        if len(set(behs)) != len(behs):
            raise ValueError(f"behaviours: each at most once, got {','.join(behs)}")
        object.__setattr__(self, "behaviours", behs)
        object.__setattr__(self, "objectives", parse_objectives(self.objectives))
        if self.profile is not None and not isinstance(self.profile, (Profile, str)):
            raise ValueError(f"profile must be a Profile or a profile name, got {type(self.profile).__name__}")
        object.__setattr__(self, "profile", resolve_profile(self.profile))
        # every run setting not given is the profile's (its run settings are canonical)
        if self.convention is None:
            object.__setattr__(self, "convention", self.profile.convention)
        else:
            object.__setattr__(self, "convention", check_convention(self.convention))
        if self.segment_mass is None:
            object.__setattr__(self, "segment_mass", self.profile.segment_mass)
        else:
            object.__setattr__(self, "segment_mass", check_segment_mass(self.segment_mass))
        for name in ("hop_height_target_m", "hop_height_tolerance_m"):
            v = getattr(self, name)
            if not is_real(v) or not math.isfinite(v) or v <= 0:
                raise ValueError(f"{name} must be a finite number > 0 m, got {v!r}")
        for name, (lo, hi), low_open in (
            ("max_yield_fraction", (0.0, MAX_YIELD_FRACTION), True),
            ("min_hops_to_failure", HOPS_TO_FAILURE_RANGE, False),
        ):
            v = getattr(self, name)
            ok = v is None or (not isinstance(v, bool) and isinstance(v, (int, float)) and math.isfinite(v))
            if not ok or (v is not None and not ((lo < v if low_open else lo <= v) and v <= hi)):
                rng = f"{'(' if low_open else '['}{lo:g}, {hi:g}]"
                raise ValueError(f"{name} must be a finite number in {rng} or None, got {v!r}")
        object.__setattr__(self, "risk", parse_name(self.risk, _scoring.RISKS, "risk"))
        _scoring.check_objective(self)
        object.__setattr__(self, "leg_mass", _scoring.check_leg_mass(self.leg_mass))

    @property
    def constraint_names(self) -> tuple[str, ...]:
        """The constraints of this objective's trials: CONSTRAINTS, plus ``leg_mass`` when set, then the stress constraints asked for."""
        extra = (self.max_yield_fraction, self.min_hops_to_failure)
        stress = tuple(n for n, v in zip(STRESS_CONSTRAINTS, extra) if v is not None)
        return CONSTRAINTS + ((_scoring.LEG_MASS_CONSTRAINT,) if self.leg_mass is not None else ()) + stress

    def key(self) -> dict:
        return {
            "behaviours": list(self.behaviours),
            "profile": self.profile.key_dict(),
            "convention": self.convention,
            "hop_height_target_m": self.hop_height_target_m,
            "hop_height_tolerance_m": self.hop_height_tolerance_m,
            "segment_mass": self.segment_mass,
            "leg_material_length_m": LEG_MATERIAL_LENGTH_M,
            **{
                k: getattr(self, k)
                for k in ("max_yield_fraction", "min_hops_to_failure")
                if getattr(self, k) is not None
            },
            **_scoring.key_fields(self),
            # only when not the default: a default objective's key has no "objectives" entry
            **({"objectives": list(self.objectives)} if self.objectives != OBJECTIVES else {}),
        }

    @classmethod
    def from_key(cls, key: dict) -> Objective:
        """The objective of a stored key. A key without ``segment_mass``
        reads as the default; the stored key still lacks the field, so
        resuming that study is refused (module doc)."""
        return cls(
            behaviours=tuple(key["behaviours"]),
            profile=Profile(**key["profile"]),
            convention=key["convention"],
            hop_height_target_m=key["hop_height_target_m"],
            hop_height_tolerance_m=key["hop_height_tolerance_m"],
            segment_mass=key.get("segment_mass", DEFAULT_SEGMENT_MASS),
            max_yield_fraction=key.get("max_yield_fraction"),
            min_hops_to_failure=key.get("min_hops_to_failure"),
            **_scoring.from_key_fields(key),
            objectives=tuple(key.get("objectives", OBJECTIVES)),
        )

    def sim_settings(self, perturbation=None, design=None):
        """The SimSettings of a run of this objective: its profile under its
        convention and segment mass (`design`: needed when the time step is
        ``"auto"``, as under ``axial``)."""
        prof = self.profile.for_convention(self.convention)
        return prof.sim_settings(perturbation, design=design, segment_mass=self.segment_mass)


@dataclass
class Evaluation:
    """One design's outcome.

    Args:
        values: objective values in the objective's order (``objective_names``).
        constraints: constraint values in ``constraint_names`` order (<= 0 feasible).
        hop_height_m: the mean hop height, m.
        per_behaviour: one row (dict) per behaviour run.
        total_mass_kg: the robot's mass, kg.
        simulated_s: simulated time of all its runs, s.
        standard_errors: per objective, over replicates (nan: one run).
        replicate_values: per replicate, per objective.
        leg_mass_kg: the leg's mass, kg (:func:`~mat_hopper.optimize._scoring.leg_mass_kg`).
        constraint_names, objective_names: what ``constraints`` and ``values`` hold.
    """

    values: tuple[float, ...]
    constraints: tuple[float, ...]
    hop_height_m: float
    per_behaviour: list[dict] = field(default_factory=list)
    total_mass_kg: float = float("nan")
    simulated_s: float = 0.0
    standard_errors: tuple[float, ...] = ()  # per objective, over replicates (nan: one run)
    replicate_values: list[list[float]] = field(default_factory=list)  # per replicate, per objective
    leg_mass_kg: float = float("nan")
    constraint_names: tuple[str, ...] = CONSTRAINTS
    objective_names: tuple[str, ...] = OBJECTIVES

    @property
    def feasible(self) -> bool:
        return all(c <= 0 for c in self.constraints)


def whole_run_value(mean: float) -> float:
    """A whole-run mean as an objective value: capped at NO_DATA_VALUE, and
    NO_DATA_VALUE when the run recorded no finite sample (mean is nan)."""
    return float(min(mean, NO_DATA_VALUE)) if math.isfinite(mean) else NO_DATA_VALUE


def scored_by_hops(n_hops: int, upright: bool) -> bool:
    """Whether a run's objective values are its per-hop means (it scored
    hop cycles and ended upright) rather than its whole-run means.

    Args:
        n_hops: the hop cycles the run scored after the transient.
        upright: whether it ended upright (:attr:`Rollout.upright`).

    Returns:
        True when both hold.
    """
    return n_hops > 0 and upright


def run_behaviour(
    design: LegDesign, behaviour_name: str, objective: Objective, *, tick=None, perturbation=None
) -> dict:
    """Simulate one behaviour in chunks of CHUNK_S simulated s (calling
    tick() between chunks), under `perturbation` (None: unperturbed), and
    score it: every metric of :data:`~._metrics.METRICS` (whatever the
    objective minimizes, so that a cached run serves any objective); the
    row's ``replicate`` is the perturbation's seed (-1: none)."""
    settings = objective.sim_settings(perturbation, design=design)
    runner = RolloutRunner(design, get_behaviour(behaviour_name), settings)
    chunk = max(1, int(round(CHUNK_S / settings.timestep_s)))
    while not runner.done:
        runner.advance(chunk)
        if tick is not None:
            tick()
    rollout = runner.result()
    hops = hop_table(rollout, warn=False)  # a diverged trial is scored as one (upright False)
    ok = bool(rollout.upright)
    height = float(hops["hop_height_m"].mean()) if len(hops) else float("nan")
    life = fatigue_summary(rollout, hop_cycles(rollout))
    mass = _scoring.leg_mass_kg(design, objective.segment_mass)
    return {
        "behaviour": behaviour_name,
        **run_values(rollout, hops, life, mass, scored_by_hops(len(hops), ok)),
        "hop_height_m": height,
        "n_hops": int(len(hops)),
        "stable": bool(rollout.stable),
        "upright": ok,
        "diverged_at_s": rollout.diverged_at_s,
        "simulated_s": float(runner.step * settings.timestep_s),
        "total_mass_kg": float(rollout.total_mass_kg),
        "yield_ratio": life["yield_ratio"],
        "hops_to_failure": life["hops_to_failure"],
        "replicate": -1 if perturbation is None else int(perturbation.seed),
    }


@contextlib.contextmanager
def mujoco_warnings_to(sink: list):
    """Collect MuJoCo's warnings (e.g. of a diverging design) in `sink`
    instead of printing them and appending to MUJOCO_LOG.TXT in the
    current folder; the previous handler is restored after."""
    old = mujoco.get_mju_user_warning()
    mujoco.set_mju_user_warning(sink.append)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", UserWarning)  # the same text, raised at model compile
            yield sink
    finally:
        mujoco.set_mju_user_warning(old)


def evaluate(design: LegDesign, objective: Objective, *, tick=None) -> Evaluation:
    """Run `design` on every behaviour of `objective`, under each of its
    replicates' perturbations (:func:`mat_hopper.optimize._scoring.perturbations`),
    and aggregate (module doc).

    Args:
        design: the leg.
        objective: what to run and score.
        tick: called once per run done (progress), or None.

    Returns:
        An :class:`Evaluation`: objective values (the objective's metrics),
        constraint values (<= 0 feasible), hop height m, per-run rows
        (MuJoCo warnings counted in ``mujoco_warnings``, not printed).
    """
    rows = []
    for pert in _scoring.perturbations(objective.replicates, objective.profile.scored_window_s):
        for b in objective.behaviours:
            with mujoco_warnings_to([]) as sink:
                row = run_behaviour(design, b, objective, tick=tick, perturbation=pert)
            row["mujoco_warnings"] = len(sink)
            rows.append(row)
    return aggregate(rows, objective, design)


def aggregate(rows: list[dict], objective: Objective, design: LegDesign | None = None) -> Evaluation:
    """One design's Evaluation from its per-run rows (keys behaviour, each
    of the objective's metrics, hop_height_m, n_hops, upright, simulated_s,
    total_mass_kg, and replicate: the seed, -1 or absent for an unperturbed
    run), as the module doc and :mod:`~mat_hopper.optimize._scoring` define
    it: each replicate's value is the mean over behaviours, the objective
    the objective's risk measure over replicates; the hop height constraint
    takes each behaviour's mean height over replicates. `design` gives the
    leg mass (needed when the objective constrains it). Used by the CPU path
    (:func:`evaluate`) and the batch paths alike."""
    names = objective.objectives
    per_rep = _scoring.replicate_values(rows, names)
    scored = [_scoring.score([v[i] for v in per_rep], objective.risk, objective.cvar_alpha) for i in range(len(names))]
    values = tuple(v for v, _ in scored)
    target, tol = objective.hop_height_target_m, objective.hop_height_tolerance_m
    height_violation = max(
        (abs(h - target) - tol) if math.isfinite(h) else target - tol for h in _scoring.behaviour_heights(rows)
    )
    unstable = 0.0 if all(r["upright"] for r in rows) else 1.0
    heights = [r["hop_height_m"] for r in rows if r["n_hops"]]
    mass = _scoring.leg_mass_kg(design, objective.segment_mass) if design is not None else float("nan")
    constraints = (float(height_violation), unstable) + _scoring.mass_constraints(objective, design, mass)
    return Evaluation(
        values=values,
        constraints=(*constraints, *_stress_constraints(rows, objective)),
        hop_height_m=float(np.mean(heights)) if heights else float("nan"),
        per_behaviour=rows,
        total_mass_kg=rows[0]["total_mass_kg"],
        simulated_s=float(sum(r["simulated_s"] for r in rows)),
        standard_errors=tuple(se for _, se in scored),
        replicate_values=[list(v) for v in per_rep],
        leg_mass_kg=mass,
        constraint_names=objective.constraint_names,
        objective_names=names,
    )


def _stress_constraints(rows: list[dict], objective: Objective) -> list[float]:
    """The stress constraints the objective asks for (module doc), worst
    behaviour; rows without the stress fields (another backend) are
    infeasible."""
    out = []
    if objective.max_yield_fraction is not None:
        ratios = [r.get("yield_ratio", math.inf) if r["upright"] else math.inf for r in rows]
        ratios = [0.0 if isinstance(x, float) and math.isnan(x) else x for x in ratios]
        out.append(float(min(max(ratios) - objective.max_yield_fraction, NO_DATA_VALUE)))
    if objective.min_hops_to_failure is not None:
        lives = [r.get("hops_to_failure", 0.0) if r["upright"] else 0.0 for r in rows]
        lives = [math.inf if isinstance(x, float) and math.isnan(x) else x for x in lives]
        worst = min(lives)
        gap = math.log10(objective.min_hops_to_failure) - (math.log10(worst) if worst > 0 else -NO_DATA_VALUE)
        out.append(float(min(max(gap, -NO_DATA_VALUE), NO_DATA_VALUE)))
    return out


# --- the record of an evaluation on its trial ---------------------------------


def _finite(x):
    return None if x is None or (isinstance(x, float) and not math.isfinite(x)) else x


def result_attr(design, ev) -> dict:
    """A trial's ``result`` user attr from its Evaluation (JSON-safe: nan and
    inf stored as None); every path that tells a trial writes it this way."""
    return {
        "feasible": ev.feasible,
        "hop_height_m": _finite(ev.hop_height_m),
        "design": design.name,
        "total_mass_kg": ev.total_mass_kg,
        "simulated_s": ev.simulated_s,
        "leg_mass_kg": _finite(ev.leg_mass_kg),
        "replicate_values": ev.replicate_values,
        "per_behaviour": [{k: _finite(v) for k, v in r.items()} for r in ev.per_behaviour],
    }


def record_evaluation(trial, design, ev) -> None:
    """Set the trial's constraints, its ``result`` user attr and its
    ``standard_error`` user attr ({objective: SE}, None with one run)."""
    for name, value in zip(ev.constraint_names, ev.constraints):
        trial.set_constraint(name, value)
    trial.set_user_attr(RESULT_ATTR, result_attr(design, ev))
    trial.set_user_attr(_scoring.SE_ATTR, {k: _finite(v) for k, v in zip(ev.objective_names, ev.standard_errors)})
