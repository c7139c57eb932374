"""Is three segments enough? The paper's leg cut into N = 1 ... 24 segments.

A leg of N segments is the same leg cut finer only when its mass and its
axial stiffness do not change with N: here every run uses the mass-
conserving segment geometry (``segment_mass="leg"``), the physical
``axial`` convention (k = E A N / L per segment) and automatic physics
substeps (``timestep_s="auto"``: the controller keeps its 1e-4 s period,
the physics takes the substeps each leg's analytic bound needs). Graded
legs with N != 3 are the 3-segment gradient resampled by cell averages
(:meth:`mat_hopper.core.materials.LegDesign.resample`: density by the
length-weighted mean, so the mass is conserved; modulus by the harmonic
mean, so the series compliance is conserved).

The runs go through :mod:`mat_hopper.experiments.runner` (the one cache and
pool); :func:`cost_table` reports each N's physics steps, and
:func:`step_cost` measures the wall time of a physics step on this machine
(a measurement for the reader, never part of a result).
"""

from __future__ import annotations

import time
from dataclasses import dataclass, replace

import pandas as pd

from ..core.behaviours import behaviour as get_behaviour
from ..core.materials import parse_design
from ..physics.modes import axial_modes
from .profiles import Profile, get_profile, resolve_profile
from .runner import RunSpec, run_grid

DESIGNS = ("SS", "PVC", "rho-inc")
BEHAVIOURS = ("forward", "ramp")
METRICS = ("tracking_error_m", "power_w", "hop_height_m")


@dataclass(frozen=True)
class ConvergencePlan:
    """What the convergence study runs under one profile: segment counts,
    run length and transient (s). The paper profile runs 10 s (about six
    scored hops after 4 s): N = 24 needs up to about a hundred physics
    substeps per control period."""

    segments: tuple[int, ...]
    duration_s: float
    transient_s: float


PLANS = {
    "paper": ConvergencePlan((1, 2, 3, 6, 12, 24), 10.0, 4.0),
    "quick": ConvergencePlan((1, 3, 6, 12), 3.0, 1.2),
}


def plan_for(profile: Profile | str | None) -> ConvergencePlan:
    """The convergence plan of a profile: :data:`PLANS` by the profile's name.

    Args:
        profile: a Profile or its name.

    Returns:
        The :class:`ConvergencePlan` of ``paper`` or ``quick``; a profile of any
        other name gets the ``quick`` plan.

    Raises:
        ValueError: an unknown profile name, or None
            (:func:`~mat_hopper.experiments.profiles.get_profile`).
    """
    prof = get_profile(profile)
    return PLANS.get(prof.name, PLANS["quick"])


def tasks(profile=None, designs=DESIGNS, behaviours=BEHAVIOURS, plan: ConvergencePlan | None = None) -> list:
    """RunSpecs of every (design, behaviour, N): axial convention, auto
    substeps, mass-conserving segments; labels experiment, profile, design,
    behaviour, n_segments, substeps, timestep_s.

    Args:
        profile: a Profile or its name (the entry points, e.g. :func:`run`, resolve
            $MAT_HOPPER_PROFILE);
            its ``axial`` form (:meth:`Profile.for_convention`) gives the settings.
        designs: design names (:func:`mat_hopper.core.materials.parse_design`), each
            resampled to every N (:meth:`LegDesign.resample`).
        behaviours: behaviour names.
        plan: segment counts, run length and transient (s); None: :func:`plan_for`
            the profile.

    Returns:
        list of RunSpec, design-major, then N, then behaviour; the run length
        and transient are the plan's. Labels: experiment ("convergence"),
        profile, design (the name given, not the resampled leg's), behaviour,
        n_segments, substeps (physics steps per control period) and
        timestep_s (the physics step, s).

    Raises:
        ValueError: an unknown profile, design or behaviour, or a segment count
            outside [1, 64].
    """
    prof = get_profile(profile)
    plan = plan or plan_for(prof)
    axial = prof.for_convention("axial")
    out = []
    for name in designs:
        base = parse_design(name)
        for n in plan.segments:
            leg = base.resample(n)
            settings = replace(axial.sim_settings(design=leg), duration_s=plan.duration_s, transient_s=plan.transient_s)
            for b in behaviours:
                labels = {
                    "experiment": "convergence",
                    "profile": prof.name,
                    "design": name,
                    "behaviour": b,
                    "n_segments": n,
                    "substeps": settings.substeps,
                    "timestep_s": settings.timestep_s,
                }
                out.append(RunSpec(leg, get_behaviour(b), settings, labels))
    return out


def run(profile=None, *, cache_dir=None, workers: int | None = None, progress: bool = False, **kw) -> dict:
    """Run (or load) the study: {"hops": per-hop table, "runs": one row per
    run}. A task that raised raises RuntimeError.

    Args:
        profile: a Profile or its name (None: $MAT_HOPPER_PROFILE, else ``paper``).
        cache_dir: the result cache folder (default: $MAT_HOPPER_CACHE, else
            ``results/cache``).
        workers: local worker processes (default: every core this process may use).
        progress: show a progress bar.
        **kw: passed to :func:`tasks`: ``designs``, ``behaviours``, ``plan``.

    Returns:
        dict with ``"hops"`` (the grid's per-hop table, labels of :func:`tasks`
        in front) and ``"runs"`` (the grid's summary, one row per run: the
        labels, the run summary with ``mean_tracking_error_m``,
        ``mean_power_w``, ``mean_hop_height_m``, ``duration_s``, ...,
        ``status``, ``error``, ``key``).

    Raises:
        RuntimeError: a task raised (its error text, the first three named).
        ValueError: as :func:`tasks`, invalid `workers`, or $MAT_HOPPER_CACHE
            set but empty.
    """
    res = run_grid(
        tasks(resolve_profile(profile), **kw), cache_dir, workers=workers, progress=progress, desc="convergence"
    )
    if res.n_failed:
        bad = res.summary[res.summary["status"] == "failed"]
        raise RuntimeError("convergence: runs failed: " + "; ".join(map(str, bad["error"].head(3))))
    return {"hops": res.tables, "runs": res.summary}


def metrics_table(runs: pd.DataFrame) -> pd.DataFrame:
    """Mean tracking error (mm), hip power (W) and hop height (m) per
    design, behaviour and N, with each one's change (%) against N = 24 (or
    the largest N run), the finest leg standing for the continuum.

    Args:
        runs: the ``"runs"`` table of :func:`run`: columns design, behaviour,
            n_segments, status, mean_tracking_error_m, mean_power_w and
            mean_hop_height_m.

    Returns:
        DataFrame, per (design, behaviour) group sorted by n_segments: design,
        behaviour, n_segments, status, tracking_error_m (m, as in `runs`),
        power_w (W), hop_height_m (m), and ``<metric>_vs_finest_pct`` for each
        of the three: 100 (value / value at the group's largest N - 1). An
        empty `runs` gives the selected, renamed columns without the
        ``_vs_finest_pct`` ones.
    """
    cols = {"mean_tracking_error_m": "tracking_error_m", "mean_power_w": "power_w", "mean_hop_height_m": "hop_height_m"}
    t = runs[["design", "behaviour", "n_segments", "status", *cols]].rename(columns=cols)
    out = []
    for _, g in t.groupby(["design", "behaviour"], sort=False):
        g = g.sort_values("n_segments")
        finest = g.iloc[-1]
        for m in METRICS:
            g[f"{m}_vs_finest_pct"] = 100.0 * (g[m] / finest[m] - 1.0)
        out.append(g)
    return pd.concat(out, ignore_index=True) if out else t


def cost_table(runs: pd.DataFrame) -> pd.DataFrame:
    """Per design and N: physics substeps per 1e-4 s control period and the
    physics steps of one run (duration / step).

    Args:
        runs: the ``"runs"`` table of :func:`run`: columns design, n_segments,
            substeps, duration_s and timestep_s (s).

    Returns:
        DataFrame sorted by design and n_segments: design, n_segments,
        substeps and physics_steps (duration_s / timestep_s, rounded to an
        integer), each the largest over the design's behaviours.
    """
    t = runs.assign(physics_steps=(runs["duration_s"] / runs["timestep_s"]).round().astype(int))
    return t.groupby(["design", "n_segments"], sort=True)[["substeps", "physics_steps"]].max().reset_index()


def step_cost(design: str = "SS", segments=(1, 3, 6, 12, 24), seconds: float = 0.05) -> pd.DataFrame:
    """Wall time of one physics step (us) and of one simulated second (s)
    per N, timed here on a short forward run of each leg (axial, auto
    substeps; the first, compiling call untimed). A measurement of this
    machine, which drifts: read it as ratios between N.

    Args:
        design: a design name (:func:`mat_hopper.core.materials.parse_design`),
            resampled to each N.
        segments: the segment counts N to time.
        seconds: simulated seconds of each timed run (s).

    Returns:
        DataFrame, one row per N: design, n_segments, substeps (physics steps
        per control period), us_per_step (wall time of the whole timed
        ``simulate`` call / its physics steps, microseconds) and
        wall_s_per_simulated_s (wall s / `seconds`).

    Raises:
        ValueError: an unknown design, a segment count outside [1, 64], or
            invalid settings (e.g. `seconds` <= 0) from
            :func:`mat_hopper.core.sim.simulate`.
    """
    from ..core.sim import simulate

    rows = []
    simulate(design, "forward", duration_s=0.01, transient_s=0.0)  # compile the loop
    for n in segments:
        leg = parse_design(design).resample(n)
        t0 = time.perf_counter()
        r = simulate(leg, "forward", duration_s=seconds, transient_s=0.0, timestep_s="auto", convention="axial")
        wall = time.perf_counter() - t0
        steps = r.settings.n_steps
        rows.append(
            {
                "design": design,
                "n_segments": n,
                "substeps": r.settings.substeps,
                "us_per_step": 1e6 * wall / steps,
                "wall_s_per_simulated_s": wall / seconds,
            }
        )
    return pd.DataFrame(rows)


def modes_table(designs=("SS", "PVC"), segments=(1, 2, 3, 4, 6, 8, 12, 16, 24, 32)) -> pd.DataFrame:
    """Mode 1 of the lumped chain against the continuum rod per N (axial
    convention, mass-conserving segments): design, n_segments, chain_hz,
    rod_hz, error_pct (:func:`mat_hopper.physics.modes.axial_modes`).

    Args:
        designs: names of single-material elastic designs
            (:func:`mat_hopper.core.materials.parse_design`).
        segments: the segment counts N.

    Returns:
        DataFrame, one row per design and N (design-major): design,
        n_segments, chain_hz (the lumped chain's mode 1, Hz), rod_hz (the
        continuum rod's, Hz) and error_pct (100 (chain_hz / rod_hz - 1)).

    Raises:
        ValueError: an unknown design, a graded or rigid one
            (:func:`mat_hopper.physics.modes.axial_modes` needs a uniform elastic rod),
            or a segment count outside [1, 64].
    """
    rows = []
    for d in designs:
        for n in segments:
            m = axial_modes(parse_design(d, n_segments=n), convention="axial", n_modes=1).iloc[0]
            rows.append({"design": d, "n_segments": n, **m.drop("mode").to_dict()})
    return pd.DataFrame(rows)
