"""The paper's four experiments, as data, and the run profiles.

An experiment is designs x behaviours x settings, nothing more; the runner
(:mod:`mat_hopper.experiments.runner`) turns it into cached, parallel runs. Every
number comes from :mod:`mat_hopper.reference`.

- ``exp1``: mono-materials MD, PVC, Al, Ti, SS x the four behaviours (20 runs).
- ``exp2``: one property at a time around PVC, Al, Ti and SS (the spec's
  sweeps: 36 points), forward hopping; each point is compared with its base
  material (the sweep point whose value is the base material's own).
- ``exp3``: gradients rho-inc, rho-dec, PVC-Ti-SS, SS-Ti-PVC x four
  behaviours (16 runs), beside the baselines MD and SS (8 runs, the very
  runs of exp1: the cache holds them once).
- ``stability``: the stable time step over the spec's density x modulus
  grid (20 x 20 in the paper profile), see :mod:`mat_hopper.stability`.

A :class:`Profile` fixes duration, transient and time step of every run,
and the stability map's size and tries. ``paper`` is the paper's protocol;
``quick`` is for CI and first looks. ``MAT_HOPPER_PROFILE`` picks the
default. Results carry a ``profile`` column.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass, replace

from .. import reference as ref
from ..behaviours import BEHAVIOUR_NAMES, behaviour as get_behaviour
from ..materials import LegDesign, Material, check_convention, paper_designs
from ..perturbations import Perturbation
from .runner import RunSpec
from ..sim import SimSettings

PROFILE_ENV = "MAT_HOPPER_PROFILE"
UNPERTURBED = -1


# ---------------------------------------------------------------------------
# profiles


def check_replicates(replicates) -> int:
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
    also run the spec's 20-step protocol; record_rate_hz: samples per
    simulated second; convention: modulus-to-stiffness convention;
    axial_timestep_s: the time step (s) of runs under the ``axial``
    convention, whose springs (k = E A / L, SS 3.8e9 N/m) diverge at the
    paper's 1e-4 s: every catalogue design is stable at 2e-5 s;
    book_replicates: perturbed replicate runs per design where the book
    compares replicates (hopping in place, chapter 6). With n per design
    the smallest Holm-adjusted p of that family of four comparisons is
    4 x 2 / C(2n, n): 0.11 at n = 4, 0.032 at n = 5, 0.0087 at n = 6; the
    paper profile's 6 leaves room below 0.05 for runs that do not
    separate perfectly, the quick profile's 3 cannot reach it."""

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
    axial_timestep_s: float = 2e-5
    book_replicates: int = 6

    def __post_init__(self):
        if not isinstance(self.name, str) or not self.name:
            raise ValueError(f"profile name must be a non-empty string, got {self.name!r}")
        self.sim_settings()            # validates duration, transient, time step, convention
        if int(self.stability_grid_size) < 1:
            raise ValueError(f"stability_grid_size must be >= 1, got {self.stability_grid_size!r}")
        if not self.stability_duration_s > 0:
            raise ValueError(f"stability_duration_s must be > 0 s, got {self.stability_duration_s!r}")
        if not self.stability_tolerance > 1:
            raise ValueError(f"stability_tolerance must be a factor > 1, got {self.stability_tolerance!r}")
        check_replicates(self.book_replicates)
        if int(self.stability_max_iter) < 0:
            raise ValueError(f"stability_max_iter must be >= 0, got {self.stability_max_iter!r}")

    def for_convention(self, convention: str) -> "Profile":
        """This profile under another stiffness convention (and its time step)."""
        check_convention(convention)
        if convention == self.convention:
            return self
        dt = self.axial_timestep_s if convention == "axial" else ref.TIMESTEP_S
        return replace(self, convention=convention, timestep_s=dt)

    def sim_settings(self, perturbation: Perturbation | None = None) -> SimSettings:
        return SimSettings(duration_s=self.duration_s, timestep_s=self.timestep_s, transient_s=self.transient_s,
                           convention=self.convention, record_rate_hz=self.record_rate_hz,
                           perturbation=perturbation)


PROFILES = {
    "paper": Profile("paper", ref.DURATION_S, ref.TRANSIENT_S, ref.TIMESTEP_S, ref.STABILITY_GRID_SIZE,
                     ref.STABILITY_TEST_DURATION_S),
    "quick": Profile("quick", 12.0, 4.0, ref.TIMESTEP_S, 4, 1.0, stability_tolerance=1.5, book_replicates=3),
}


def get_profile(name: str | Profile | None = None) -> Profile:
    """A profile by name (``paper`` or ``quick``); None: $MAT_HOPPER_PROFILE,
    else ``paper``. A Profile is returned as is."""
    if isinstance(name, Profile):
        return name
    if name is None:
        name = os.environ.get(PROFILE_ENV) or "paper"
    key = str(name).strip().lower()
    if key not in PROFILES:
        src = f" (from ${PROFILE_ENV})" if name == os.environ.get(PROFILE_ENV) else ""
        raise ValueError(f"unknown profile {name!r}{src}; accepted: {', '.join(PROFILES)}")
    return PROFILES[key]


# ---------------------------------------------------------------------------
# experiments


def _fmt(values) -> str:
    return "/".join("rigid" if v is None else f"{v:g}" for v in values)


@dataclass(frozen=True)
class DesignPoint:
    """One design of an experiment: the leg, its label in the tables, and
    extra label columns (e.g. the sweep it belongs to)."""

    design: LegDesign
    label: str
    tags: tuple = ()      # ((column, value), ...)

    def labels(self) -> dict:
        return {"design": self.label, **dict(self.tags),
                "densities_g_cm3": _fmt(self.design.densities_g_cm3), "moduli_gpa": _fmt(self.design.moduli_gpa)}


@dataclass(frozen=True)
class Experiment:
    """Designs x behaviours: the runs of one experiment."""

    name: str
    title: str
    points: tuple[DesignPoint, ...]
    behaviours: tuple[str, ...]
    baselines: tuple[str, ...] = ()

    def __post_init__(self):
        if not self.points or not self.behaviours:
            raise ValueError(f"experiment {self.name}: designs and behaviours must not be empty")
        for b in self.behaviours:
            get_behaviour(b)

    @property
    def n_runs(self) -> int:
        """Runs per replicate set (designs x behaviours)."""
        return len(self.points) * len(self.behaviours)

    def tasks(self, profile: Profile | str | None = None, replicates: int = 0) -> list[RunSpec]:
        """One RunSpec per design, behaviour and replicate: the unperturbed
        run (replicate -1) and, for replicates N > 0, seeds 0..N-1 with
        :meth:`Perturbation.replicate`."""
        profile = get_profile(profile)
        replicates = check_replicates(replicates)
        out = []
        for point in self.points:
            for bname in self.behaviours:
                beh = get_behaviour(bname)
                for rep in [UNPERTURBED, *range(replicates)]:
                    pert = None if rep == UNPERTURBED else Perturbation.replicate(rep)
                    labels = {"experiment": self.name, "profile": profile.name, "convention": profile.convention,
                              "design": point.label, "behaviour": beh.name, "replicate": rep, **point.labels()}
                    out.append(RunSpec(point.design, beh, profile.sim_settings(pert), labels))
        return out


@dataclass(frozen=True)
class StabilityMap:
    """The stable-time-step map: mono-material legs over a density x
    modulus grid (sizes from the profile)."""

    name: str = "stability"
    title: str = "Stable time step over density x modulus"
    n_segments: int = ref.REFERENCE_SEGMENTS

    def axes(self, profile: Profile | str | None = None):
        from ..stability import stability_grid
        return stability_grid(get_profile(profile).stability_grid_size)

    def tasks(self, profile: Profile | str | None = None, replicates: int = 0) -> list:
        """One StabilitySpec per grid cell (replicates do not apply)."""
        from ..stability import StabilitySpec
        profile = get_profile(profile)
        dens, mods = self.axes(profile)
        out = []
        for d in dens:
            for e in mods:
                d, e = float(d), float(e)
                design = LegDesign((Material(f"rho{d:g}-E{e:g}", d, e),) * self.n_segments,
                                   name=f"rho={d:g} E={e:g}")
                labels = {"experiment": self.name, "profile": profile.name, "convention": profile.convention,
                          "design": design.name, "density_g_cm3": d, "modulus_gpa": e}
                out.append(StabilitySpec(design, duration_s=profile.stability_duration_s,
                                         tolerance=profile.stability_tolerance,
                                         max_iter=profile.stability_max_iter, scan=profile.stability_scan,
                                         convention=profile.convention, labels=labels))
        return out


def experiment_1() -> Experiment:
    """Mono-materials on all four behaviours."""
    designs = paper_designs()
    points = tuple(DesignPoint(designs[n], n, (("group", "mono"),)) for n in ref.MONO_MATERIALS)
    return Experiment("exp1", "Mono-materials x four behaviours", points, BEHAVIOUR_NAMES, ("MD",))


SWEEP_SHORT = {"density": "rho", "modulus": "E"}


def experiment_2() -> Experiment:
    """One property at a time around PVC, Al, Ti and SS, forward hopping.

    Labels: sweep_base (the material), sweep_property (density|modulus),
    sweep_value, density_g_cm3, modulus_gpa, is_base (the point that is the
    base material itself; its design label is the material's name)."""
    designs = paper_designs()
    points = []
    for base, sweeps in ref.SWEEPS.items():
        rho0, e0 = ref.MONO_MATERIALS[base]
        for prop in ("density", "modulus"):
            values = tuple(sweeps[prop])
            own = rho0 if prop == "density" else e0
            if not any(math.isclose(v, own) for v in values):
                values = tuple(sorted(values + (own,)))
            for v in values:
                is_base = math.isclose(v, own)
                rho, e = (v, e0) if prop == "density" else (rho0, v)
                if is_base:
                    design, label = designs[base], base
                else:
                    label = f"{base} {SWEEP_SHORT[prop]}={v:g}"
                    design = LegDesign.mono(Material(label, rho, e), ref.REFERENCE_SEGMENTS)
                tags = (("group", f"{base} {prop}"), ("sweep_base", base), ("sweep_property", prop),
                        ("sweep_value", float(v)), ("density_g_cm3", float(rho)), ("modulus_gpa", float(e)),
                        ("is_base", bool(is_base)))
                points.append(DesignPoint(design, label, tags))
    return Experiment("exp2", "One property at a time, forward hopping", tuple(points), ("forward",))


def experiment_3() -> Experiment:
    """Functional gradients on all four behaviours, with MD and SS."""
    designs = paper_designs()
    grads = ("rho-inc", "rho-dec", "PVC-Ti-SS", "SS-Ti-PVC")
    points = tuple(DesignPoint(designs[n], n, (("group", "gradient"),)) for n in grads)
    points += tuple(DesignPoint(designs[n], n, (("group", "baseline"),)) for n in ("MD", "SS"))
    return Experiment("exp3", "Functional gradients x four behaviours, against MD and SS", points,
                      BEHAVIOUR_NAMES, ("MD", "SS"))


EXPERIMENTS = {"exp1": experiment_1, "exp2": experiment_2, "exp3": experiment_3, "stability": StabilityMap}
EXPERIMENT_NAMES = tuple(EXPERIMENTS)


def experiment_name(text: str) -> str:
    """Canonical name: '1' or 'exp1' -> 'exp1'; 'stability' (or 'stab', '4')."""
    key = str(text).strip().lower()
    alias = {"1": "exp1", "2": "exp2", "3": "exp3", "4": "stability", "stab": "stability"}
    key = alias.get(key, key)
    if key not in EXPERIMENTS:
        raise ValueError(f"unknown experiment {text!r}; accepted: 1, 2, 3, stability (or {', '.join(EXPERIMENTS)})")
    return key


def parse_experiments(text: str | None) -> list[str]:
    """'1,2,3,stability' -> ['exp1', 'exp2', 'exp3', 'stability'] (order
    kept, duplicates dropped); None or 'all': all four."""
    if text is None or str(text).strip().lower() == "all":
        return list(EXPERIMENT_NAMES)
    names = [experiment_name(p) for p in str(text).split(",") if p.strip()]
    if not names:
        raise ValueError("experiments: give at least one of 1, 2, 3, stability")
    return list(dict.fromkeys(names))


def get_experiment(name: str) -> Experiment | StabilityMap:
    """An experiment by name (see :func:`experiment_name`)."""
    return EXPERIMENTS[experiment_name(name)]()
