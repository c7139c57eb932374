"""Run profiles: how long and how fine every run of a reproduction is.

``paper`` is the paper's protocol; ``quick`` is for CI and first looks.
``MAT_HOPPER_PROFILE`` picks the default. Results carry a ``profile``
column.
"""

from __future__ import annotations

from dataclasses import dataclass, fields, replace

import pandas as pd

from ..core import reference as ref
from ..core.controller import SensorTiming
from ..core.materials import BENDING_CONVENTIONS, DEFAULT_SEGMENT_MASS, check_convention, check_segment_mass
from ..core.perturbations import Perturbation
from ..core.sim import SimSettings, sim_settings
from ..core.timestep import AUTO, is_auto

PROFILE_ENV = "MAT_HOPPER_PROFILE"


def check_replicates(replicates) -> int:
    """Check a replicate count.

    Args:
        replicates: perturbed replicate runs per design and behaviour.

    Returns:
        `replicates` unchanged.

    Raises:
        ValueError: a bool, a value that is not an ``int`` (``3.0``, ``"3"``)
            or one < 0.
    """
    if isinstance(replicates, bool) or not isinstance(replicates, int) or replicates < 0:
        raise ValueError(f"replicates must be an integer >= 0 (runs per design and behaviour), got {replicates!r}")
    return replicates


@dataclass(frozen=True)
class Profile:
    """How long and how fine every run of a reproduction is.

    duration_s, transient_s, timestep_s: each hopping run (s);
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
    say so."""

    name: str
    duration_s: float
    transient_s: float
    timestep_s: float = ref.TIMESTEP_S
    stability_grid_size: int = ref.STABILITY_GRID_SIZE
    stability_duration_s: float = ref.STABILITY_TEST_DURATION_S
    stability_tolerance: float = 1.25
    stability_max_iter: int = 10
    stability_scan: bool = True
    record_rate_hz: float = 1000.0
    convention: str = "paper"
    axial_timestep_s: float | str = AUTO
    replicates: int = 10
    sensor_timing: SensorTiming = SensorTiming()
    segment_mass: str = DEFAULT_SEGMENT_MASS
    push_scale: float = 1.0
    substep_studies: bool = True

    def __post_init__(self):
        if not isinstance(self.name, str) or not self.name:
            raise ValueError(f"profile name must be a non-empty string, got {self.name!r}")
        object.__setattr__(self, "sensor_timing", SensorTiming(self.sensor_timing))
        object.__setattr__(self, "segment_mass", check_segment_mass(self.segment_mass))
        object.__setattr__(self, "convention", check_convention(self.convention))
        for name in ("timestep_s", "axial_timestep_s"):
            value = getattr(self, name)
            if is_auto(value):  # any case: stored as AUTO
                object.__setattr__(self, name, AUTO)
            elif isinstance(value, str):
                raise ValueError(f"{name} must be a number (s) or {AUTO!r}, got {value!r}")
        if not is_auto(self.timestep_s):
            self.sim_settings()  # validates duration, transient, time step, convention
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
    def scored_window_s(self) -> tuple[float, float]:
        """(transient_s, duration_s), s: the hops that are scored; replicate
        pushes are drawn inside it (:meth:`Perturbation.replicate`)."""
        return (self.transient_s, self.duration_s)

    def replicate(self, seed: int) -> Perturbation:
        """Replicate `seed`'s perturbation under this profile.

        Args:
            seed: the replicate's seed (>= 0; shared across designs, so
                comparisons on it are paired).

        Returns:
            The :class:`~mat_hopper.core.perturbations.Perturbation`: its push
            drawn inside the scored window, push_scale x the book's 5 N.
        """
        return Perturbation.replicate(seed, self.scored_window_s, push_scale=self.push_scale)

    def key_dict(self) -> dict:
        """Every field as a cache or study key records it (a sensor timing by its name)."""
        return {f.name: _shown(getattr(self, f.name)) for f in fields(self)}

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

    def sim_settings(self, perturbation: Perturbation | None = None, design=None) -> SimSettings:
        """The SimSettings of one run. With ``timestep_s="auto"`` the
        physics substeps depend on the leg: pass its ``design``."""
        return sim_settings(
            design,
            duration_s=self.duration_s,
            timestep_s=self.timestep_s,
            transient_s=self.transient_s,
            convention=self.convention,
            record_rate_hz=self.record_rate_hz,
            perturbation=perturbation,
            sensor_timing=self.sensor_timing,
            segment_mass=self.segment_mass,
        )


PROFILES = {
    "paper": Profile(
        "paper", ref.DURATION_S, ref.TRANSIENT_S, ref.TIMESTEP_S, ref.STABILITY_GRID_SIZE, ref.STABILITY_TEST_DURATION_S
    ),
    # CI's smoke build: short runs, 2 seeds (the fewest paired comparisons take), no substep studies
    "quick": Profile(
        "quick", 12.0, 4.0, ref.TIMESTEP_S, 4, 1.0, stability_tolerance=1.5, replicates=2, substep_studies=False
    ),
}


def get_profile(name: str | Profile | None = None) -> Profile:
    """A profile by name (``paper`` or ``quick``); None: $MAT_HOPPER_PROFILE,
    else ``paper``. A Profile is returned as is.

    Args:
        name: ``"paper"`` or ``"quick"`` (any case, blanks trimmed), a
            Profile, or None.

    Returns:
        The :class:`Profile` (the shared instance of :data:`PROFILES` for a name).

    Raises:
        ValueError: an unknown name (naming $MAT_HOPPER_PROFILE when it came
            from there), or $MAT_HOPPER_PROFILE set but empty.
    """
    if isinstance(name, Profile):
        return name
    src = ""
    if name is None:  # set but empty is an error naming the variable, not the paper profile
        from ..util.parsing import env_value

        name = env_value(PROFILE_ENV, f"accepted: {', '.join(PROFILES)}")
        src = f" (from ${PROFILE_ENV})" if name is not None else ""
        name = "paper" if name is None else name
    key = str(name).strip().lower()
    if key not in PROFILES:
        raise ValueError(f"unknown profile {name!r}{src}; accepted: {', '.join(PROFILES)}")
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
        stability_duration_s, replicates, push_scale): columns ``setting``,
        ``meaning`` (with its unit), ``this build`` and ``paper`` (a sensor
        timing by its name).

    Raises:
        ValueError: as :func:`get_profile`.
    """
    prof = get_profile(profile)
    paper = PROFILES["paper"]
    rows = [
        {"setting": f, "meaning": m, "this build": _shown(getattr(prof, f)), "paper": _shown(getattr(paper, f))}
        for f, m in _PROFILE_FIELDS
    ]
    return pd.DataFrame(rows)


def _shown(value):
    """A profile value as its table shows it (a sensor timing by its name)."""
    return value.name if isinstance(value, SensorTiming) else value
