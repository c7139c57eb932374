"""The paper's four experiments, as data (run profiles:
:mod:`mat_hopper.experiments.profiles`).

An experiment is designs x behaviours x settings, nothing more; the runner
(:mod:`mat_hopper.experiments.runner`) turns it into cached, parallel runs. Every
number comes from :mod:`mat_hopper.core.reference`.

- ``exp1``: mono-materials MD, PVC, Al, Ti, SS x the four behaviours (20 runs).
- ``exp2``: one property at a time around PVC, Al, Ti and SS (the sweeps
  of docs/reference-hopper.md: 36 points), forward hopping; each point is compared with its base
  material (the sweep point whose value is the base material's own).
- ``exp3``: gradients rho-inc, rho-dec, PVC-Ti-SS, SS-Ti-PVC x four
  behaviours (16 runs), beside the baselines MD and SS (8 runs, the very
  runs of exp1: the cache holds them once).
- ``stability``: the stable time step over the density x modulus
  grid (20 x 20 in the paper profile), see :mod:`mat_hopper.physics.stability`.

The book's extra checks run through the same runner: the stable time step
under both stiffness conventions (:func:`convention_stability`), perturbed
replicates hopping in place (:func:`in_place_replicates`), the authors'
wall-clock path (:func:`clock_drift`) and the headline under the axial
convention (:func:`axial_check`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import pandas as pd

from ..core import reference as ref
from ..core.behaviours import BEHAVIOUR_NAMES
from ..core.behaviours import behaviour as get_behaviour
from ..core.materials import REPRODUCTION_CONVENTIONS, LegDesign, Material, paper_designs, parse_design
from ..core.timestep import AUTO, is_auto
from ..physics.porosity import DEFAULT_POROSITY_MODEL, check_porosity_model, porous_modulus
from . import robustness
from .profiles import Profile, check_replicates, get_profile
from .runner import FAILED, RunSpec, run_grid

UNPERTURBED = -1


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
    tags: tuple = ()  # ((column, value), ...)

    def labels(self) -> dict:
        return {
            "design": self.label,
            **dict(self.tags),
            "densities_g_cm3": _fmt(self.design.densities_g_cm3),
            "moduli_gpa": _fmt(self.design.moduli_gpa),
        }


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
                    pert = None if rep == UNPERTURBED else profile.replicate(rep)
                    labels = {
                        "experiment": self.name,
                        "profile": profile.name,
                        "convention": profile.convention,
                        "sensor_timing": profile.sensor_timing.name,
                        "design": point.label,
                        "behaviour": beh.name,
                        "replicate": rep,
                        **point.labels(),
                    }
                    out.append(RunSpec(point.design, beh, profile.sim_settings(pert, design=point.design), labels))
        return out


@dataclass(frozen=True)
class StabilityMap:
    """The stable-time-step map: mono-material legs over a density x
    modulus grid (sizes from the profile)."""

    name: str = "stability"
    title: str = "Stable time step over density x modulus"
    n_segments: int = ref.REFERENCE_SEGMENTS

    def axes(self, profile: Profile | str | None = None):
        from ..physics.stability import stability_grid

        return stability_grid(get_profile(profile).stability_grid_size)

    def tasks(self, profile: Profile | str | None = None, replicates: int = 0) -> list:
        """One StabilitySpec per grid cell (replicates do not apply)."""

        profile = get_profile(profile)
        dens, mods = self.axes(profile)
        out = []
        for d in dens:
            for e in mods:
                d, e = float(d), float(e)
                design = LegDesign((Material(f"rho{d:g}-E{e:g}", d, e),) * self.n_segments, name=f"rho={d:g} E={e:g}")
                labels = {
                    "experiment": self.name,
                    "profile": profile.name,
                    "convention": profile.convention,
                    "design": design.name,
                    "density_g_cm3": d,
                    "modulus_gpa": e,
                }
                out.append(profile.stability_spec(design, labels))
        return out


def experiment_1() -> Experiment:
    """Mono-materials on all four behaviours.

    Returns:
        The :class:`Experiment` ``exp1``: the five mono-material legs of
        :data:`mat_hopper.core.reference.MONO_MATERIALS` (MD, PVC, Al, Ti, SS; label
        column ``group`` = ``mono``) x static, forward, ramp and circle, with
        MD as its baseline.
    """
    designs = paper_designs()
    points = tuple(DesignPoint(designs[n], n, (("group", "mono"),)) for n in ref.MONO_MATERIALS)
    return Experiment("exp1", "Mono-materials x four behaviours", points, BEHAVIOUR_NAMES, ("MD",))


SWEEP_SHORT = {"density": "rho", "modulus": "E"}


def experiment_2(porosity_model: str = DEFAULT_POROSITY_MODEL) -> Experiment:
    """One property at a time around PVC, Al, Ti and SS, forward hopping.

    Args:
        porosity_model: ``independent`` (the paper's: a density point changes
            the density only) or ``gibson-ashby`` (a density point below the base
            material's is that solid made porous, E = E_s (rho / rho_s)^2,
            :func:`mat_hopper.physics.porosity.porous_modulus`; points above keep E_s);
            any case (:func:`mat_hopper.physics.porosity.check_porosity_model`): the
            name and labels carry its canonical spelling.

    Returns:
        The :class:`Experiment` ``exp2`` (``exp2-<porosity_model>`` for a model
        other than the default) on the ``forward`` behaviour: every point of
        :data:`mat_hopper.core.reference.SWEEPS`, plus the base material's own value
        where a sweep lacks it, as a 3-segment mono-material leg.

        Labels: sweep_base (the material), sweep_property (density|modulus),
        sweep_value, density_g_cm3, modulus_gpa (the segment's modulus as
        simulated), is_base (the point that is the base material itself; its
        design label is the material's name), porosity_model; and group
        (``"<base> <property>"``).

    Raises:
        ValueError: an unknown porosity model.
    """
    porosity_model = check_porosity_model(porosity_model)
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
                if prop == "density":
                    e = porous_modulus(designs[base].segments[0], rho, porosity_model)
                if is_base:
                    design, label = designs[base], base
                else:
                    label = f"{base} {SWEEP_SHORT[prop]}={v:g}"
                    if e != e0 and prop == "density":
                        label += f" (E={e:.3g})"
                    design = LegDesign.mono(Material(label, rho, e), ref.REFERENCE_SEGMENTS)
                tags = (
                    ("group", f"{base} {prop}"),
                    ("sweep_base", base),
                    ("sweep_property", prop),
                    ("sweep_value", float(v)),
                    ("density_g_cm3", float(rho)),
                    ("modulus_gpa", float(e)),
                    ("is_base", bool(is_base)),
                    ("porosity_model", porosity_model),
                )
                points.append(DesignPoint(design, label, tags))
    name = "exp2" if porosity_model == DEFAULT_POROSITY_MODEL else f"exp2-{porosity_model}"
    return Experiment(name, "One property at a time, forward hopping", tuple(points), ("forward",))


def experiment_3() -> Experiment:
    """Functional gradients on all four behaviours, with MD and SS.

    Returns:
        The :class:`Experiment` ``exp3``: rho-inc, rho-dec, PVC-Ti-SS and
        SS-Ti-PVC (label column ``group`` = ``gradient``) and MD and SS
        (``group`` = ``baseline``) x static, forward, ramp and circle, with
        baselines MD and SS.
    """
    designs = paper_designs()
    grads = ("rho-inc", "rho-dec", "PVC-Ti-SS", "SS-Ti-PVC")
    points = tuple(DesignPoint(designs[n], n, (("group", "gradient"),)) for n in grads)
    points += tuple(DesignPoint(designs[n], n, (("group", "baseline"),)) for n in ("MD", "SS"))
    return Experiment(
        "exp3", "Functional gradients x four behaviours, against MD and SS", points, BEHAVIOUR_NAMES, ("MD", "SS")
    )


@dataclass(frozen=True)
class RobustnessStudy:
    """How robust the paper's numbers are (book chapter "How robust are the
    paper's numbers?"): the runs the quantitative claims rest on under
    other sensor latencies, the axial convention, finer steps and perturbed
    replicates (:mod:`mat_hopper.experiments.robustness`, analysed in
    :mod:`mat_hopper.analysis.robustness`)."""

    name: str = "robustness"
    max_replicates: int = 3  # replicate variants shown beside the others (the claims use all of them)

    def tasks(self, profile: Profile | str | None = None, replicates: int = 0) -> list:
        profile = get_profile(profile)
        n = min(check_replicates(replicates), self.max_replicates)
        substeps = profile.substep_studies  # the axial and 2e-5 s variants (the quick profile leaves them out)
        conventions = ("paper", "axial") if substeps else ("paper",)
        return robustness.tasks(profile, robustness.variants(conventions=conventions, replicates=n, timesteps=substeps))


@dataclass(frozen=True)
class ControlsStudy:
    """Material or mass? The claims' designs beside their rigid twins and
    mass- and inertia-matched legs on shared seeds
    (:mod:`mat_hopper.experiments.controls`; the claims table's beyond-mass
    columns). Needs replicates: at least 2 (the profile's by default)."""

    name: str = "controls"

    def tasks(self, profile: Profile | str | None = None, replicates: int = 0) -> list:
        from .controls import control_tasks

        profile = get_profile(profile)
        n = check_replicates(replicates) or profile.replicates
        return control_tasks(profile, replicates=max(n, 2))


def experiment_2_gibson_ashby() -> Experiment:
    """Experiment 2 with porosity that softens: a density point below the
    base material's is that solid made porous (Gibson-Ashby, E = E_s
    (rho / rho_s)^2; :func:`experiment_2`).

    Returns:
        The :class:`Experiment` ``exp2-gibson-ashby``.
    """
    return experiment_2("gibson-ashby")


EXPERIMENTS = {
    "exp1": experiment_1,
    "exp2": experiment_2,
    "exp3": experiment_3,
    "stability": StabilityMap,
    "robustness": RobustnessStudy,
    "controls": ControlsStudy,
    "exp2-gibson-ashby": experiment_2_gibson_ashby,
}
EXPERIMENT_NAMES = tuple(EXPERIMENTS)
# Every spelling :func:`experiment_name` reads (any case), per experiment, the
# first the one messages lead with: the one table of the parser, the
# command's --help and its errors (an alias the help does not list is one a
# user cannot know, e.g. "4" for the stability map).
EXPERIMENT_SPELLINGS = {
    "exp1": ("1", "exp1"),
    "exp2": ("2", "exp2"),
    "exp3": ("3", "exp3"),
    "stability": ("stability", "4", "stab"),
    "robustness": ("robustness", "robust"),
    "controls": ("controls", "control"),
    "exp2-gibson-ashby": ("2-gibson-ashby", "2ga", "exp2-gibson-ashby"),
}
_SPELLING_TO_NAME = {sp: key for key, sps in EXPERIMENT_SPELLINGS.items() for sp in sps}


def experiment_spellings() -> str:
    """Every accepted spelling of every experiment, for help and errors.

    Returns:
        One line: each experiment's leading spelling with its others in
        parentheses, in :data:`EXPERIMENTS` order, e.g. ``"1 (exp1), ...,
        stability (4, stab), ..."``.
    """
    return ", ".join(f"{sps[0]} ({', '.join(sps[1:])})" for sps in EXPERIMENT_SPELLINGS.values())


def experiment_name(text: str) -> str:
    """Canonical name: '1' or 'exp1' -> 'exp1'; 'stability' (or 'stab', '4').

    Args:
        text: an experiment's name or alias, any case, blanks trimmed: a
            spelling of :data:`EXPERIMENT_SPELLINGS` (``1``, ``exp1``, ...,
            ``stability``/``4``/``stab``, ``robustness``/``robust``,
            ``controls``/``control``, ``2-gibson-ashby``/``2ga``).

    Returns:
        The key of :data:`EXPERIMENTS` (e.g. ``"exp1"``, ``"stability"``).

    Raises:
        ValueError: an unknown name, listing every accepted spelling.
    """
    key = _SPELLING_TO_NAME.get(str(text).strip().lower())
    if key is None:
        raise ValueError(f"unknown experiment {text!r}; accepted: {experiment_spellings()}")
    return key


def parse_experiments(text: str | None) -> list[str]:
    """'1,2,3,stability' -> ['exp1', 'exp2', 'exp3', 'stability'] (order
    kept, duplicates dropped); None or 'all': all seven (with robustness,
    controls and experiment 2 under Gibson-Ashby porosity).

    Args:
        text: comma-separated names or aliases (:func:`experiment_name`);
            None or ``"all"`` (any case) for every experiment.

    Returns:
        list of canonical names (keys of :data:`EXPERIMENTS`).

    Raises:
        ValueError: an unknown name, no name at all (e.g. ``""`` or ``","``),
            or ``all`` combined with other names (``"all,1"``).
    """
    if text is None or str(text).strip().lower() == "all":
        return list(EXPERIMENT_NAMES)
    if "all" in (p.strip().lower() for p in str(text).split(",")):
        raise ValueError(f"experiments: 'all' cannot be combined with other experiments, got {text!r}")
    names = [experiment_name(p) for p in str(text).split(",") if p.strip()]
    if not names:
        raise ValueError("experiments: give at least one of 1, 2, 3, stability")
    return list(dict.fromkeys(names))


def get_experiment(name: str) -> Experiment | StabilityMap | RobustnessStudy | ControlsStudy:
    """An experiment by name (see :func:`experiment_name`).

    Args:
        name: an experiment's name or alias (:func:`experiment_name`).

    Returns:
        A new :class:`Experiment` (``exp1``, ``exp2``, ``exp3``,
        ``exp2-gibson-ashby``), :class:`StabilityMap`, :class:`RobustnessStudy`
        or :class:`ControlsStudy`.

    Raises:
        ValueError: an unknown name.
    """
    return EXPERIMENTS[experiment_name(name)]()


# ---------------------------------------------------------------------------
# the book's extra checks (each through the runner: cached, in parallel)


def convention_tasks(
    names=("MD", "PVC", "Al", "Ti", "SS"), profile: str | Profile | None = None, conventions=REPRODUCTION_CONVENTIONS
) -> list:
    """Stable-time-step measurements (runner tasks, cached) of designs
    (names as :func:`~mat_hopper.core.materials.parse_design` reads them, or
    LegDesigns; default the mono-materials) under each convention, with
    the profile's try
    length, tolerance and tries (no 20-step reference scan).

    Args:
        names: design names or LegDesigns.
        profile: a Profile or its name (None: $MAT_HOPPER_PROFILE, else ``paper``).
        conventions: stiffness conventions (:data:`mat_hopper.core.materials.CONVENTIONS`).

    Returns:
        list of :class:`~mat_hopper.physics.stability.StabilitySpec`, convention-major;
        labels: experiment (``"conventions"``), profile, convention, design.

    Raises:
        ValueError: an unknown profile, design or convention.
    """

    prof = get_profile(profile)
    out = []
    for conv in conventions:
        for n in names:
            d = parse_design(n) if isinstance(n, str) else n
            labels = {"experiment": "conventions", "profile": prof.name, "convention": conv, "design": d.name}
            out.append(prof.stability_spec(d, labels, convention=conv, scan=False))
    return out


def convention_stability(
    names=("MD", "PVC", "Al", "Ti", "SS"),
    profile: str | Profile | None = None,
    conventions=REPRODUCTION_CONVENTIONS,
    *,
    cache_dir=None,
    workers: int | None = None,
) -> pd.DataFrame:
    """Largest stable time step per design (see :func:`convention_tasks`)
    and convention: measured (the bracket [max_stable_timestep_s,
    unstable_timestep_s] of :mod:`mat_hopper.physics.stability`) and estimated
    (analytic_timestep_s, 2 / w_max of the leg's spring chain;
    controller_timestep_s, the limit 2 I / c of the controller's explicit
    stance attitude damping, the same for every leg), one row each, with
    the stiffest material spring (material_spring_n_m; nan for the rigid
    MD leg).

    Args:
        names: design names or LegDesigns.
        profile: a Profile or its name (None: $MAT_HOPPER_PROFILE, else ``paper``).
        conventions: stiffness conventions.
        cache_dir: the result cache folder (default: $MAT_HOPPER_CACHE, else
            ``results/cache``).
        workers: local worker processes (default: every core this process may use).

    Returns:
        DataFrame in the order of :func:`convention_tasks`: design, convention,
        material_spring_n_m (N/m), analytic_timestep_s, controller_timestep_s,
        max_stable_timestep_s and unstable_timestep_s (s; nan where the
        search found no such step).

    Raises:
        RuntimeError: a measurement raised (each failed design and convention
            named with its error).
        ValueError: as :func:`convention_tasks`, invalid `workers`, or
            $MAT_HOPPER_CACHE set but empty.
    """
    res = run_grid(
        convention_tasks(names, profile, conventions), cache_dir, workers=workers, progress=False, desc="conventions"
    )
    s = res.summary
    if (s["status"] == FAILED).any():
        bad = s[s["status"] == FAILED]
        raise RuntimeError(
            "stability measurement failed: "
            + "; ".join(f"{r.design} ({r.convention}): {r.error}" for r in bad.itertuples())
        )
    keep = [
        "design",
        "convention",
        "max_material_spring_n_m",
        "analytic_timestep_s",
        "controller_timestep_s",
        "max_stable_timestep_s",
        "unstable_timestep_s",
    ]
    out = s[keep].rename(columns={"max_material_spring_n_m": "material_spring_n_m"})
    return out.reset_index(drop=True)


def in_place_replicates(
    profile: str | Profile | None = None,
    n: int | None = None,
    *,
    behaviour: str = "static",
    cache_dir=None,
    workers: int | None = None,
) -> pd.DataFrame:
    """Experiment 1's five legs hopping in place (or on `behaviour`), the
    unperturbed run and n perturbed replicates each (seeds 0..n-1,
    :meth:`~mat_hopper.core.perturbations.Perturbation.replicate`; n from the
    profile's ``replicates`` by default), run or loaded through the
    result cache. Returns the per-hop table (column ``replicate``, -1 for
    the unperturbed run), for :func:`mat_hopper.analysis.stats.compare_replicates`.

    Args:
        profile: a Profile or its name (None: $MAT_HOPPER_PROFILE, else ``paper``).
        n: perturbed replicates per leg (an integer >= 0; None: the
            profile's ``replicates``).
        behaviour: the behaviour name.
        cache_dir: the result cache folder (default: $MAT_HOPPER_CACHE, else
            ``results/cache``).
        workers: local worker processes (default: every core this process may use).

    Returns:
        DataFrame, one row per scored hop: the labels of
        :meth:`Experiment.tasks` (experiment ``exp1``, profile, convention,
        sensor_timing, design, behaviour, replicate, group, densities_g_cm3,
        moduli_gpa), the hop metrics and the cache ``key``.

    Raises:
        RuntimeError: a run raised (the count and up to three error texts).
        ValueError: an unknown profile or behaviour, an `n` that is not an
            integer >= 0, invalid `workers`, or $MAT_HOPPER_CACHE set but empty.
    """
    profile = get_profile(profile)
    n = profile.replicates if n is None else n
    exp = replace(experiment_1(), behaviours=(behaviour,))
    res = run_grid(exp.tasks(profile, n), cache_dir, workers=workers, progress=False)
    if res.n_failed:
        raise RuntimeError(f"{res.n_failed} replicate run(s) failed: {res.summary['error'].dropna().unique()[:3]}")
    return res.tables


CLOCK_FACTORS = (1.0, 1.5, 2.0)


def clock_drift(
    profile: str | Profile | None = None,
    designs=("MD", "SS"),
    factors=CLOCK_FACTORS,
    behaviour: str = "forward",
    *,
    cache_dir=None,
    workers: int | None = None,
) -> pd.DataFrame:
    """What the authors' wall-clock desired path does. Their loop sleeps to
    stay in real time, so on a machine that simulates r times slower than
    real time the desired path advances r times faster in simulated time.
    We emulate that by commanding r times the paper's speed (r = 1: the
    paper's protocol, our default) under the book's profile, duration and
    transient unchanged. Runs through the runner (cached in `cache_dir`). One row per
    design and factor: clock_factor, speed_m_s, status, n_hops,
    mean_tracking_error_m, mean_power_w.

    Args:
        profile: a Profile or its name (None: $MAT_HOPPER_PROFILE, else ``paper``).
        designs: design names (a mono-material name gives its 3-segment leg)
            or LegDesigns.
        factors: clock factors r, finite numbers > 0 (the commanded speed is
            r x the paper's 0.05 m/s).
        behaviour: the behaviour name, any case (recorded by its canonical
            name).
        cache_dir: the result cache folder (default: $MAT_HOPPER_CACHE, else
            ``results/cache``).
        workers: local worker processes (default: every core this process may use).

    Returns:
        DataFrame, design-major: design, clock_factor, speed_m_s (m/s),
        status, n_hops, mean_tracking_error_m (m) and mean_power_w (W).

    Raises:
        ValueError: a factor that is not a finite number > 0, an unknown
            profile, design or behaviour, invalid `workers`, or
            $MAT_HOPPER_CACHE set but empty.
        RuntimeError: a run raised (the errors joined).
    """
    profile = get_profile(profile)
    tasks = []
    for d in designs:
        design = LegDesign.mono(d) if isinstance(d, str) and d in ref.MONO_MATERIALS else d
        if isinstance(design, str):
            design = parse_design(design)
        for r in factors:
            if not (isinstance(r, (int, float)) and math.isfinite(r) and r > 0):
                raise ValueError(f"clock factors must be finite numbers > 0, got {r!r}")
            beh = get_behaviour(behaviour, speed_m_s=ref.SPEED_M_S * float(r))
            labels = {
                "experiment": "clock",
                "profile": profile.name,
                "design": design.name,
                "behaviour": beh.name,
                "clock_factor": float(r),
                "speed_m_s": beh.speed_m_s,
            }
            tasks.append(RunSpec(design, beh, profile.sim_settings(design=design), labels))
    res = run_grid(tasks, cache_dir, workers=workers, progress=False, desc="clock")
    s = res.summary
    if (s["status"] == FAILED).any():
        raise RuntimeError("clock_drift: runs failed: " + "; ".join(s.loc[s["status"] == FAILED, "error"]))
    return s[
        ["design", "clock_factor", "speed_m_s", "status", "n_hops", "mean_tracking_error_m", "mean_power_w"]
    ].reset_index(drop=True)


def axial_check(
    profile: str | Profile | None = None,
    designs=("MD", "SS", "rho-inc"),
    behaviour: str = "ramp",
    *,
    timestep_s: float | None = None,
    cache_dir=None,
    workers: int | None = None,
) -> dict:
    """The paper's headline comparison under the physical (axial) stiffness
    convention. The axial springs need a smaller time step: by default the
    profile's ``axial_timestep_s`` (the step ``mat-hopper reproduce
    --conventions`` uses; chapter 3 measures the stable steps). Runs, through the
    runner (cached), every design in three settings: the paper's
    convention at the profile's step (the runs of experiments 1 and 3),
    the paper's convention at the axial run's physics step and substeps
    (what the step alone changes), and the axial convention there (what
    the convention changes). With ``"auto"`` each design gets the substeps
    its axial springs need while the controller keeps its 1e-4 s period. A rigid leg has no springs, so its small-step run
    stands for both conventions. Returns {"timestep_s", "hops" (per-hop
    table with ``setting`` ("paper, profile step", "paper, axial's steps",
    "axial, axial's steps"), ``timestep_s`` and ``substeps`` columns),
    "runs"}.

    Args:
        profile: a Profile or its name (None: $MAT_HOPPER_PROFILE, else ``paper``).
        designs: design names (:func:`mat_hopper.core.materials.parse_design`).
        behaviour: the behaviour name.
        timestep_s: the axial runs' physics step (s), or ``"auto"`` (any
            case); None: the profile's ``axial_timestep_s``.
        cache_dir: the result cache folder (default: $MAT_HOPPER_CACHE, else
            ``results/cache``).
        workers: local worker processes (default: every core this process may use).

    Returns:
        dict: ``"timestep_s"`` (``"auto"`` or the step as a float, s),
        ``"hops"`` (the per-hop table; labels experiment ``axial-check``,
        profile, convention, design, behaviour, setting, timestep_s,
        substeps) and ``"runs"`` (one summary row per design and setting,
        with status, error and key). The settings are named after the
        profile's convention (``paper`` for the shipped profiles).

    Raises:
        RuntimeError: a run raised (the errors joined).
        ValueError: an unknown profile, design or behaviour, an invalid time
            step, invalid `workers`, or $MAT_HOPPER_CACHE set but empty.
    """
    prof = get_profile(profile)
    legs = {d: parse_design(d) for d in designs}
    if timestep_s is None:
        timestep_s = prof.axial_timestep_s
    if is_auto(timestep_s):  # any case, blanks trimmed: stored as AUTO
        timestep_s = AUTO
    beh = get_behaviour(behaviour)
    plan = []
    for d, leg in legs.items():
        base = prof.sim_settings(design=leg)
        axial = prof.for_convention("axial")
        if timestep_s != AUTO:
            axial = replace(axial, timestep_s=float(timestep_s))
        axial = axial.sim_settings(design=leg)
        small = replace(axial, convention=prof.convention)  # the same steps, the paper's convention
        plan += [(d, base, f"{prof.convention}, profile step"), (d, small, f"{prof.convention}, axial's steps")]
        # a rigid leg has no springs: its small-step run stands for both conventions (one cached run)
        rigid = all(m.rigid for m in leg.segments)
        plan.append((d, small if rigid else axial, "axial, axial's steps"))
    tasks = []
    for d, st, setting in plan:
        labels = {
            "experiment": "axial-check",
            "profile": prof.name,
            "convention": st.convention,
            "design": d,
            "behaviour": beh.name,
            "setting": setting,
            "timestep_s": st.timestep_s,
            "substeps": st.substeps,
        }
        tasks.append(RunSpec(legs[d], beh, st, labels))
    res = run_grid(tasks, cache_dir, workers=workers, progress=False, desc="axial")
    if (res.summary["status"] == FAILED).any():
        raise RuntimeError(
            "axial_check: runs failed: " + "; ".join(res.summary.loc[res.summary["status"] == FAILED, "error"])
        )
    hops, runs = res.tables, res.summary
    return {"timestep_s": timestep_s if timestep_s == AUTO else float(timestep_s), "hops": hops, "runs": runs}
