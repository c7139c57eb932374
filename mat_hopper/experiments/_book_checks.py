"""The book's extra checks, each through the runner (cached, in parallel).

The stable time step under both stiffness conventions
(:func:`convention_stability`), perturbed replicates hopping in place
(:func:`in_place_replicates`), the authors' wall-clock path
(:func:`clock_drift`) and the headline under the axial convention
(:func:`axial_check`). :mod:`mat_hopper.experiments.paper` re-exports every
name here.
"""

from __future__ import annotations

import math
from dataclasses import replace

import pandas as pd

from ..core import reference as ref
from ..core.behaviours import behaviour as get_behaviour
from ..core.materials import REPRODUCTION_CONVENTIONS, LegDesign, parse_design
from ..core.timestep import AUTO, is_auto
from ..util.parsing import is_real
from ._experiments import experiment_1
from .profiles import Profile, get_profile, resolve_profile
from .runner import FAILED, RunSpec, run_grid


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
        profile: a Profile or its name (:func:`convention_stability` resolves $MAT_HOPPER_PROFILE).
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
        convention_tasks(names, resolve_profile(profile), conventions),
        cache_dir,
        workers=workers,
        progress=False,
        desc="conventions",
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


def in_place_tasks(profile: str | Profile, n: int | None = None, behaviour: str = "static") -> list:
    """The runs of :func:`in_place_replicates`: experiment 1's five legs on
    one behaviour, the unperturbed run and n perturbed replicates each.

    Args:
        profile: a Profile or its name (:func:`in_place_replicates` resolves
            $MAT_HOPPER_PROFILE).
        n: perturbed replicates per leg (an integer >= 0; None: the
            profile's ``replicates``).
        behaviour: the behaviour name.

    Returns:
        list of RunSpec (:meth:`Experiment.tasks`'s, experiment ``exp1``).

    Raises:
        ValueError: an unknown profile or behaviour, or an `n` that is not an
            integer >= 0.
    """
    profile = get_profile(profile)
    n = profile.replicates if n is None else n
    return replace(experiment_1(), behaviours=(behaviour,)).tasks(profile, n)


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
    res = run_grid(in_place_tasks(resolve_profile(profile), n, behaviour), cache_dir, workers=workers, progress=False)
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
    tasks = clock_tasks(resolve_profile(profile), designs, factors, behaviour)
    res = run_grid(tasks, cache_dir, workers=workers, progress=False, desc="clock")
    s = res.summary
    if (s["status"] == FAILED).any():
        raise RuntimeError("clock_drift: runs failed: " + "; ".join(s.loc[s["status"] == FAILED, "error"]))
    return s[
        ["design", "clock_factor", "speed_m_s", "status", "n_hops", "mean_tracking_error_m", "mean_power_w"]
    ].reset_index(drop=True)


def clock_tasks(
    profile: str | Profile, designs=("MD", "SS"), factors=CLOCK_FACTORS, behaviour: str = "forward"
) -> list:
    """The runs of :func:`clock_drift`: each design at r times the paper's
    commanded speed, for every clock factor r.

    Args:
        profile: a Profile or its name (:func:`clock_drift` resolves $MAT_HOPPER_PROFILE).
        designs: design names or LegDesigns.
        factors: clock factors r, finite numbers > 0.
        behaviour: the behaviour name.

    Returns:
        list of RunSpec, design-major; labels experiment (``"clock"``),
        profile, design, behaviour, clock_factor, speed_m_s (m/s).

    Raises:
        ValueError: a factor that is not a finite number > 0, an unknown
            profile, design or behaviour.
    """
    profile = get_profile(profile)
    tasks = []
    for d in designs:
        design = LegDesign.mono(d) if isinstance(d, str) and d in ref.MONO_MATERIALS else d
        if isinstance(design, str):
            design = parse_design(design)
        for r in factors:
            if not (is_real(r) and math.isfinite(r) and r > 0):
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
    return tasks


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
    prof = resolve_profile(profile)
    timestep_s = _axial_step(prof, timestep_s)
    tasks = axial_check_tasks(prof, designs, behaviour, timestep_s=timestep_s)
    res = run_grid(tasks, cache_dir, workers=workers, progress=False, desc="axial")
    if (res.summary["status"] == FAILED).any():
        raise RuntimeError(
            "axial_check: runs failed: " + "; ".join(res.summary.loc[res.summary["status"] == FAILED, "error"])
        )
    hops, runs = res.tables, res.summary
    return {"timestep_s": timestep_s if timestep_s == AUTO else float(timestep_s), "hops": hops, "runs": runs}


def _axial_step(prof: Profile, timestep_s):
    """The axial runs' step: `timestep_s`, or the profile's axial_timestep_s; "auto" (any case) as AUTO."""
    if timestep_s is None:
        timestep_s = prof.axial_timestep_s
    return AUTO if is_auto(timestep_s) else timestep_s  # any case, blanks trimmed: stored as AUTO


def axial_check_tasks(
    profile: str | Profile, designs=("MD", "SS", "rho-inc"), behaviour: str = "ramp", *, timestep_s=None
) -> list:
    """The runs of :func:`axial_check`: every design in its three settings.

    Args:
        profile: a Profile or its name (:func:`axial_check` resolves $MAT_HOPPER_PROFILE).
        designs: design names (:func:`mat_hopper.core.materials.parse_design`).
        behaviour: the behaviour name.
        timestep_s: the axial runs' physics step (s), or ``"auto"``; None: the
            profile's ``axial_timestep_s``.

    Returns:
        list of RunSpec, three per design (labels as :func:`axial_check`'s
        ``"hops"``: experiment ``axial-check``, profile, convention, design,
        behaviour, setting, timestep_s, substeps).

    Raises:
        ValueError: an unknown profile, design or behaviour, or an invalid time step.
    """
    prof = get_profile(profile)
    timestep_s = _axial_step(prof, timestep_s)
    legs = {d: parse_design(d) for d in designs}
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
    return tasks
