"""Run profiles: how long and how fine every run of a reproduction is.

``paper`` is the paper's protocol; ``quick`` is for CI and first looks.
``MAT_HOPPER_PROFILE`` picks the default, read at the entry points only
(:func:`resolve_profile`: the commands, :func:`mat_hopper.book.setup`, the
public API's runs); the functions below them take the :class:`Profile`
(or a name, :func:`get_profile`). A profile holds its run settings once,
as the :class:`~mat_hopper.core.sim.SimSettings` fields its runs take
(:attr:`Profile.run`). Results carry a ``profile`` column.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, fields, replace
from types import MappingProxyType

import pandas as pd

from ..core import reference as ref
from ..core.controller import SensorTiming
from ..core.materials import BENDING_CONVENTIONS, check_convention
from ..core.perturbations import Perturbation
from ..core.replicates import DEFAULT_REPLICATE_PROTOCOL
from ..core.sim import SimSettings, sim_settings
from ..core.timestep import AUTO, is_auto

PROFILE_ENV = "MAT_HOPPER_PROFILE"

# Seeds of a grid whose replicates no paired test reads: the attribution
# factorial, whose regression clusters its errors by mass distribution (7
# clusters: more seeds barely narrow the mass and inertia terms; its springs
# intervals are rough at 3). A paired verdict needs more (Profile.replicates,
# 10 in the paper profile: an exact sign-flip test on n pairs reaches
# p = 2 / 2^n at best), and so do experiment 2's sweeps, whose equal-mass
# slopes are tested per seed (analysis.beyond_mass.sweep_controls).
FIGURE_REPLICATES = 3


def check_replicates(replicates, minimum: int = 0) -> int:
    """Check a replicate count.

    Args:
        replicates: perturbed replicate runs per design and behaviour.
        minimum: the fewest the caller takes (2 for paired comparisons).

    Returns:
        `replicates` unchanged.

    Raises:
        ValueError: a bool, a value that is not an ``int`` (``3.0``, ``"3"``)
            or one below `minimum`.
    """
    if isinstance(replicates, bool) or not isinstance(replicates, int) or replicates < minimum:
        raise ValueError(
            f"replicates must be an integer >= {minimum} (runs per design and behaviour), got {replicates!r}"
        )
    return replicates


# Profile's arguments in their order: what key_dict records, in this order
# (study keys and result caches depend on it).
PROFILE_KEYS = (
    "name",
    "duration_s",
    "transient_s",
    "timestep_s",
    "stability_grid_size",
    "stability_duration_s",
    "stability_tolerance",
    "stability_max_iter",
    "stability_scan",
    "record_rate_hz",
    "convention",
    "axial_timestep_s",
    "replicates",
    "sensor_timing",
    "segment_mass",
    "push_scale",
    "substep_studies",
)
# Keys recorded only when not at their default (then after PROFILE_KEYS, as
# Profile's last arguments): a profile that leaves them keeps the study and
# cache keys it had before they existed.
OPTIONAL_KEYS = {"replicate_protocol": DEFAULT_REPLICATE_PROTOCOL}
# The SimSettings fields a profile sets for every run (Profile.run); a run
# adds the rest (its perturbation, controller, substeps, damping).
RUN_SETTINGS = (
    "duration_s",
    "transient_s",
    "timestep_s",
    "record_rate_hz",
    "convention",
    "sensor_timing",
    "segment_mass",
    "replicate_protocol",
)
# Every run setting but the run length and transient (which a profile must
# give) defaults to SimSettings' own default.
_RUN_DEFAULTS = {f.name: f.default for f in fields(SimSettings) if f.name in RUN_SETTINGS[2:]}


def _run_setting(name: str, doc: str) -> property:
    return property(lambda self: self.run[name], doc=f"{doc} (``run[{name!r}]``).")


@dataclass(frozen=True, init=False, repr=False, eq=False)
class Profile:
    """How long and how fine every run of a reproduction is.

    Positional and keyword arguments, in this order:
    name; duration_s, transient_s, timestep_s: each hopping run (s);
    stability_grid_size: the map is size x size designs;
    stability_duration_s: static hopping per stability try (s);
    stability_tolerance: bisection stops when the bracket is within this
    factor; stability_max_iter: bisection tries at most; stability_scan:
    also run the 20-step protocol of docs/reference-hopper.md; record_rate_hz: samples per
    simulated second; convention: modulus-to-stiffness convention (any
    case, stored as spelled in :data:`mat_hopper.core.materials.CONVENTIONS`);
    axial_timestep_s: the physics step of runs under the ``axial``
    convention, whose springs (k = E A / L, SS 3.8e9 N/m) diverge at the
    paper's 1e-4 s: ``"auto"`` (default) keeps the controller at its
    1e-4 s period and gives each design the physics substeps its analytic
    bound needs (:func:`mat_hopper.core.timestep.auto_timestep`; any case), or a
    number (s); sensor_timing: when the controller reads the base (``"authors"``,
    ``"fresh"``, ``"latency-L"``; :mod:`mat_hopper.core.controller`);
    segment_mass: ``"leg"`` or ``"capsule"``, any case (:mod:`mat_hopper.core.materials`);
    replicates: perturbed replicate runs per design and behaviour, the
    claims' inferential basis (``reproduce`` runs them for every hopping
    experiment) and chapter 6's. The replicates share their seeds across
    designs, so comparisons are paired; an exact sign-flip test on n pairs
    reaches p = 2 / 2^n at best (:func:`mat_hopper.analysis.paired.sign_flip_p`),
    and Holm's first threshold in a family of m comparisons is 0.05 / m:
    n = 10 (the paper profile's) reaches 0.002 and so serves families of
    up to 25 (the largest claim's is 16: 4 materials x 4 behaviours); the
    quick profile's 2 (p >= 0.5) can test nothing;
    push_scale: the replicates' push, times 5 N for 0.1 s (0: no push;
    :meth:`mat_hopper.core.perturbations.Perturbation.replicate`);
    substep_studies: whether to run the checks whose runs need physics
    substeps, each 5-8 times a run's cost: the robustness study's ``axial``
    and 2e-5 s time-step variants, and the material-or-mass factorial's
    axial arms (:func:`mat_hopper.experiments.controls.attribution_tasks`).
    The paper profile runs them; the quick profile (CI's book, a smoke
    build whose 2 seeds test nothing) leaves them out, and the chapters
    say so; replicate_protocol: when a replicate's perturbations begin,
    ``"authors"`` (default: from step 0), ``"branch"`` (from transient_s,
    after the unperturbed run's prefix, which the runner then computes once
    per design and behaviour: :mod:`mat_hopper.core.replicates`,
    :mod:`mat_hopper.experiments.groups`) or ``"branch-settled"`` (from
    half the transient); a key only when not ``authors``
    (:data:`OPTIONAL_KEYS`).

    The run settings (:data:`RUN_SETTINGS`: duration_s, transient_s,
    timestep_s, record_rate_hz, convention, sensor_timing, segment_mass) are
    held once, in :attr:`run`, as the :class:`~mat_hopper.core.sim.SimSettings`
    fields every run of the profile takes, checked and spelled by
    SimSettings itself (a timestep_s of ``"auto"`` as a 1e-4 s step: the
    auto control period is at most that); those left out take SimSettings'
    defaults. ``run=`` (keyword only: a mapping of run settings or a
    SimSettings) gives them at once; a run setting given by name overrides
    it, so ``dataclasses.replace(profile, duration_s=8.0)`` works. The
    properties ``duration_s``, ``convention``, ... read :attr:`run`.

    Raises:
        ValueError: an invalid value, naming the setting (a run setting as
            :class:`~mat_hopper.core.sim.SimSettings` names it).
        TypeError: duration_s or transient_s not given (and not in `run`).
    """

    name: str
    run: MappingProxyType  # RUN_SETTINGS -> value, as SimSettings stores it (timestep_s: a number or AUTO)
    stability_grid_size: int
    stability_duration_s: float
    stability_tolerance: float
    stability_max_iter: int
    stability_scan: bool
    axial_timestep_s: float | str
    replicates: int
    push_scale: float
    substep_studies: bool

    duration_s = _run_setting("duration_s", "Each hopping run's length, s")
    transient_s = _run_setting("transient_s", "Hop cycles starting before it are not scored, s")
    timestep_s = _run_setting("timestep_s", 'The physics step, s, or ``"auto"``')
    record_rate_hz = _run_setting("record_rate_hz", "Recorded samples per simulated second, Hz")
    convention = _run_setting("convention", "The stiffness convention, as spelled in CONVENTIONS")
    sensor_timing = _run_setting("sensor_timing", "When the controller reads the base (a SensorTiming)")
    segment_mass = _run_setting("segment_mass", "The segment-mass convention, as spelled in SEGMENT_MASSES")
    replicate_protocol = _run_setting("replicate_protocol", "When a replicate's perturbations begin")

    def __init__(
        self,
        name: str,
        duration_s: float | None = None,
        transient_s: float | None = None,
        timestep_s: float | str | None = None,
        stability_grid_size: int = ref.STABILITY_GRID_SIZE,
        stability_duration_s: float = ref.STABILITY_TEST_DURATION_S,
        stability_tolerance: float = 1.25,
        stability_max_iter: int = 10,
        stability_scan: bool = True,
        record_rate_hz: float | None = None,
        convention: str | None = None,
        axial_timestep_s: float | str = AUTO,
        replicates: int = 10,
        sensor_timing: SensorTiming | str | int | None = None,
        segment_mass: str | None = None,
        push_scale: float = 1.0,
        substep_studies: bool = True,
        replicate_protocol: str | None = None,
        *,
        run: Mapping | SimSettings | None = None,
    ):
        given = dict(
            duration_s=duration_s,
            transient_s=transient_s,
            timestep_s=timestep_s,
            record_rate_hz=record_rate_hz,
            convention=convention,
            sensor_timing=sensor_timing,
            segment_mass=segment_mass,
            replicate_protocol=replicate_protocol,
        )
        own = dict(
            name=name,
            stability_grid_size=stability_grid_size,
            stability_duration_s=stability_duration_s,
            stability_tolerance=stability_tolerance,
            stability_max_iter=stability_max_iter,
            stability_scan=stability_scan,
            axial_timestep_s=axial_timestep_s,
            replicates=replicates,
            push_scale=push_scale,
            substep_studies=substep_studies,
        )
        object.__setattr__(self, "run", MappingProxyType(_run_settings(run, given)))
        for key, value in own.items():
            object.__setattr__(self, key, value)
        self._check()

    def _check(self) -> None:
        """The profile's own settings (the run settings are SimSettings')."""
        if not isinstance(self.name, str) or not self.name:
            raise ValueError(f"profile name must be a non-empty string, got {self.name!r}")
        if is_auto(self.axial_timestep_s):  # any case: stored as AUTO
            object.__setattr__(self, "axial_timestep_s", AUTO)
        elif isinstance(self.axial_timestep_s, str):
            raise ValueError(f"axial_timestep_s must be a number (s) or {AUTO!r}, got {self.axial_timestep_s!r}")
        if int(self.stability_grid_size) < 1:
            raise ValueError(f"stability_grid_size must be >= 1, got {self.stability_grid_size!r}")
        if not self.stability_duration_s > 0:
            raise ValueError(f"stability_duration_s must be > 0 s, got {self.stability_duration_s!r}")
        if not self.stability_tolerance > 1:
            raise ValueError(f"stability_tolerance must be a factor > 1, got {self.stability_tolerance!r}")
        check_replicates(self.replicates)
        if not isinstance(self.substep_studies, bool):  # "False" (a string) would read as True
            raise ValueError(f"substep_studies must be True or False, got {self.substep_studies!r}")
        Perturbation.replicate(0, self.scored_window_s, push_scale=self.push_scale)  # checks push_scale
        if int(self.stability_max_iter) < 0:
            raise ValueError(f"stability_max_iter must be >= 0, got {self.stability_max_iter!r}")

    def _key(self) -> tuple:
        optional = tuple((k, getattr(self, k)) for k, default in OPTIONAL_KEYS.items() if getattr(self, k) != default)
        return tuple((k, getattr(self, k)) for k in PROFILE_KEYS) + optional

    def __eq__(self, other) -> bool:
        return self._key() == other._key() if isinstance(other, Profile) else NotImplemented

    def __hash__(self) -> int:
        return hash(self._key())

    def __repr__(self) -> str:
        return f"Profile({', '.join(f'{k}={v!r}' for k, v in self._key())})"

    def __reduce__(self):  # pickled as its key: Profile(**key_dict) rebuilds it
        return (_profile_from_key, (self.key_dict(),))

    def stability_spec(self, design, labels: dict, *, convention: str | None = None, scan: bool | None = None):
        """The stable-time-step measurement (a runner task) of one design under
        this profile: its try length, tolerance, tries and scan; `convention`
        and `scan` override the profile's."""
        from ..physics.stability import StabilitySpec

        return StabilitySpec(
            design,
            duration_s=self.stability_duration_s,
            tolerance=self.stability_tolerance,
            max_iter=self.stability_max_iter,
            scan=self.stability_scan if scan is None else scan,
            convention=self.convention if convention is None else convention,
            labels=labels,
        )

    @property
    def figure_replicates(self) -> int:
        """Seeds of a grid whose replicates no paired test reads:
        min(:attr:`replicates`, :data:`FIGURE_REPLICATES`). Derived, so not a
        key of its own."""
        return min(self.replicates, FIGURE_REPLICATES)

    @property
    def scored_window_s(self) -> tuple[float, float]:
        """(transient_s, duration_s), s: the hops that are scored; replicate
        pushes are drawn inside it (:meth:`Perturbation.replicate`)."""
        return (self.transient_s, self.duration_s)

    def replicate(self, seed: int, scored_window_s: tuple[float, float] | None = None) -> Perturbation:
        """Replicate `seed`'s perturbation under this profile.

        Args:
            seed: the replicate's seed (>= 0; shared across designs, so
                comparisons on it are paired).
            scored_window_s: (transient end, run end) in s of a run whose
                length is not the profile's (None: the profile's window).

        Returns:
            The :class:`~mat_hopper.core.perturbations.Perturbation`: its push
            drawn inside the scored window, push_scale x the book's 5 N.
        """
        window = self.scored_window_s if scored_window_s is None else scored_window_s
        return Perturbation.replicate(seed, window, push_scale=self.push_scale)

    def key_dict(self) -> dict:
        """Every setting as a cache or study key records it, in the order of
        :data:`PROFILE_KEYS`, then those of :data:`OPTIONAL_KEYS` not at their
        default (a sensor timing by its name); ``Profile(**key_dict)`` rebuilds
        an equal profile."""
        return {k: _shown(v) for k, v in self._key()}

    def for_convention(self, convention: str) -> Profile:
        """This profile under another stiffness convention (and its time step)."""
        convention = check_convention(convention)
        if convention == self.convention:
            return self
        if convention in BENDING_CONVENTIONS:  # the hinges' modes set the step
            dt = AUTO
        else:
            dt = self.axial_timestep_s if convention == "axial" else ref.TIMESTEP_S
        return replace(self, convention=convention, timestep_s=dt)

    def for_sensor_timing(self, sensor_timing) -> Profile:
        """This profile with the controller reading its base sensors at
        another moment (a name or a latency in physics steps)."""
        timing = SensorTiming(sensor_timing)
        return self if timing == self.sensor_timing else replace(self, sensor_timing=timing)

    def sim_settings(self, perturbation: Perturbation | None = None, design=None, **overrides) -> SimSettings:
        """The SimSettings of one run: :attr:`run`, then `overrides` (other
        SimSettings fields, e.g. ``segment_mass``), and `perturbation`. With
        ``timestep_s="auto"`` the physics substeps depend on the leg: pass
        its ``design`` (no model is built: :func:`mat_hopper.core.sim.sim_settings`)."""
        return sim_settings(design, **{**self.run, **overrides}, perturbation=perturbation)


def _run_settings(run, given: dict) -> dict:
    """A profile's run settings: SimSettings' defaults, then `run` (a mapping
    or a SimSettings), then those `given` by name (None: not given); checked
    and spelled by SimSettings (module doc)."""
    if isinstance(run, SimSettings):
        run = {k: getattr(run, k) for k in RUN_SETTINGS}
    run = {} if run is None else dict(run)
    unknown = sorted(set(run) - set(RUN_SETTINGS))
    if unknown:
        raise ValueError(f"run: unknown setting(s) {', '.join(unknown)}; a profile sets {', '.join(RUN_SETTINGS)}")
    values = {**_RUN_DEFAULTS, **run, **{k: v for k, v in given.items() if v is not None}}
    for k in ("duration_s", "transient_s"):
        if k not in values:
            raise TypeError(f"Profile needs {k} (s), by name or in run=")
    step = values["timestep_s"]
    if is_auto(step):  # any case: stored as AUTO
        values["timestep_s"] = AUTO
    elif isinstance(step, str):
        raise ValueError(f"timestep_s must be a number (s) or {AUTO!r}, got {step!r}")
    checked = SimSettings(**{**values, "timestep_s": ref.TIMESTEP_S if is_auto(step) else step})
    return {k: values[k] if k == "timestep_s" else getattr(checked, k) for k in RUN_SETTINGS}


def _profile_from_key(key: dict) -> Profile:
    return Profile(**key)


PROFILES = {
    "paper": Profile(
        "paper", ref.DURATION_S, ref.TRANSIENT_S, ref.TIMESTEP_S, ref.STABILITY_GRID_SIZE, ref.STABILITY_TEST_DURATION_S
    ),
    # CI's smoke build: short runs, 2 seeds (the fewest paired comparisons take), no substep studies
    "quick": Profile(
        "quick", 12.0, 4.0, ref.TIMESTEP_S, 4, 1.0, stability_tolerance=1.5, replicates=2, substep_studies=False
    ),
}


def get_profile(name: str | Profile) -> Profile:
    """A profile by name, or a Profile as is: below the entry points, never
    reading the environment (:func:`resolve_profile` does, at the entry points).

    Args:
        name: ``"paper"`` or ``"quick"`` (any case, blanks trimmed) or a Profile.

    Returns:
        The :class:`Profile` (the shared instance of :data:`PROFILES` for a name).

    Raises:
        ValueError: an unknown name, or None (no profile given: an entry point
            resolves $MAT_HOPPER_PROFILE first, :func:`resolve_profile`).
    """
    if isinstance(name, Profile):
        return name
    if name is None:
        raise ValueError(
            f"profile: none given; pass a Profile or its name ({', '.join(PROFILES)}); "
            f"${PROFILE_ENV} is read at the entry points (resolve_profile)"
        )
    return _named(name, "")


def resolve_profile(profile: str | Profile | None = None) -> Profile:
    """The run profile at an entry point (the commands, :func:`mat_hopper.book.setup`,
    the public API's runs): `profile` if given, else $MAT_HOPPER_PROFILE, else
    ``paper``. The one reader of $MAT_HOPPER_PROFILE; the functions below the
    entry points take the Profile it returns.

    Args:
        profile: ``"paper"`` or ``"quick"`` (any case, blanks trimmed), a
            Profile, or None.

    Returns:
        The :class:`Profile` (the shared instance of :data:`PROFILES` for a name).

    Raises:
        ValueError: an unknown name (naming $MAT_HOPPER_PROFILE when it came
            from there), or $MAT_HOPPER_PROFILE set but empty.
    """
    if profile is not None:
        return get_profile(profile)
    from ..util.parsing import env_value

    name = env_value(PROFILE_ENV, f"accepted: {', '.join(PROFILES)}")  # set but empty: an error naming it
    return PROFILES["paper"] if name is None else _named(name, f" (from ${PROFILE_ENV})")


def _named(name, src: str) -> Profile:
    key = str(name).strip().lower()
    if key not in PROFILES:
        from ..util.parsing import did_you_mean

        hint = f"; {did_you_mean(name, PROFILES)}" if did_you_mean(name, PROFILES) else ""
        raise ValueError(f"unknown profile {name!r}{src}; accepted: {', '.join(PROFILES)}{hint}")
    return PROFILES[key]


_PROFILE_FIELDS = (
    ("duration_s", "run length (s of simulated time)"),
    ("transient_s", "transient, hop cycles before it not scored (s)"),
    ("timestep_s", "physics time step (s)"),
    ("record_rate_hz", "recorded samples per simulated second (Hz)"),
    ("convention", "modulus-to-stiffness convention"),
    ("axial_timestep_s", "time step of runs under the axial convention (s, or auto substeps)"),
    ("sensor_timing", "when the controller reads the base sensors"),
    ("segment_mass", "segment mass convention"),
    ("stability_grid_size", "stable-time-step map: designs per axis"),
    ("stability_duration_s", "stable-time-step map: static hopping per try (s)"),
    ("replicates", "perturbed replicates per design and behaviour (claims, chapter 6)"),
    ("push_scale", "replicates' push, x 5 N for 0.1 s"),
    ("substep_studies", "robustness's axial and 2e-5 s variants, the factorial's axial arms"),
    (
        "replicate_protocol",
        "when replicates' perturbations begin (authors: step 0; branch: transient_s; branch-settled: transient_s / 2)",
    ),
)


def profile_table(profile: str | Profile | None = None) -> pd.DataFrame:
    """The profile's settings beside the paper's protocol (the ``paper``
    profile): columns setting, meaning, this build, paper.

    Args:
        profile: a Profile or its name (None: $MAT_HOPPER_PROFILE, else ``paper``).

    Returns:
        DataFrame, one row per setting shown (duration_s, transient_s,
        timestep_s, record_rate_hz, convention, axial_timestep_s,
        sensor_timing, segment_mass, stability_grid_size,
        stability_duration_s, replicates, push_scale, substep_studies,
        replicate_protocol): columns ``setting``, ``meaning`` (with its
        unit), ``this build`` and ``paper`` (a sensor timing by its name).

    Raises:
        ValueError: as :func:`resolve_profile`.
    """
    prof = resolve_profile(profile)
    paper = PROFILES["paper"]
    rows = [
        {"setting": f, "meaning": m, "this build": _shown(getattr(prof, f)), "paper": _shown(getattr(paper, f))}
        for f, m in _PROFILE_FIELDS
    ]
    return pd.DataFrame(rows)


def _shown(value):
    """A profile value as its table shows it (a sensor timing by its name)."""
    return value.name if isinstance(value, SensorTiming) else value
