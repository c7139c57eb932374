"""The controls experiment: every design beside its controls, on shared seeds.

For the designs the paper's material claims name, each behaviour and
replicate seeds 0..n-1 (the profile's ``replicates``; the same seeds for
every design, so comparisons are paired), one run of the design and one of
each control (:mod:`mat_hopper.core.control_legs`): its rigid twin, its mass-matched
leg and its inertia-matched leg. The baselines of the claims (MD, SS) run
on the same seeds. Runs go through the one cache and pool
(:mod:`mat_hopper.experiments.runner`): a control whose physics is the
design's own (the mass-matched leg of a homogeneous design is the design)
is computed once.

:func:`attribution_tasks` is the attribution factorial: mass distribution
(the designs' densities) x springs (rigid, ``paper``, ``axial``), see
:func:`mat_hopper.analysis.attribution.attribution`.
"""

from __future__ import annotations

from dataclasses import replace

from ..core.behaviours import behaviour as get_behaviour
from ..core.control_legs import CONTROLS, check_control, control
from ..core.materials import parse_design
from .profiles import FIGURE_REPLICATES, check_replicates, get_profile, resolve_profile
from .runner import RunSpec, run_grid

# The designs of the paper's material and gradient claims, and their baselines.
CLAIM_DESIGNS = ("PVC", "Al", "Ti", "SS", "rho-inc", "rho-dec")
BASELINES = ("MD", "SS")
BEHAVIOURS = ("static", "forward", "ramp", "circle")
NO_CONTROL = "none"
# Control kinds whose comparisons no paired test reads: the inertia-matched leg
# enters no verdict (the claims read the rigid twin and the mass-matched leg),
# only an interval shown beside them; it runs at most FIGURE_REPLICATES (3) of
# the seeds the others run, the first ones.
FIGURE_KINDS = ("inertia",)


def _replicates(profile, replicates):
    n = profile.replicates if replicates is None else check_replicates(replicates, minimum=2)
    if n < 2:
        raise ValueError(f"paired comparisons need replicates >= 2, got {n}")
    return n


def control_tasks(
    profile=None,
    designs=CLAIM_DESIGNS,
    behaviours=BEHAVIOURS,
    kinds=CONTROLS,
    replicates=None,
    baselines=BASELINES,
    figure_seeds: bool = True,
) -> list[RunSpec]:
    """RunSpecs of designs, their controls and the baselines on shared seeds.

    Args:
        profile: a Profile or its name (:func:`run_controls` resolves $MAT_HOPPER_PROFILE).
        designs: design names (:func:`mat_hopper.core.materials.parse_design`).
        behaviours: behaviour names.
        kinds: control kinds (``rigid``, ``mass``, ``inertia``; any case).
        replicates: seeds per run (an integer >= 2; default: the profile's).
        figure_seeds: the kinds of :data:`FIGURE_KINDS` (the inertia-matched
            leg) run at most
            :data:`~mat_hopper.experiments.profiles.FIGURE_REPLICATES` (3) of
            those seeds, the first ones, whatever `replicates` says; False:
            every kind all of them.
        baselines: designs run without controls (the claims' baselines).

    Returns:
        list of RunSpec; labels: experiment ("controls"), profile,
        convention, sensor_timing (its name, e.g. ``"authors"``), design
        (the control's name for a control), behaviour, replicate,
        control_of (the design), control (kind as spelled in
        :data:`~mat_hopper.core.control_legs.CONTROLS`, or "none"). Names are
        recorded in their canonical spelling.

    Raises:
        ValueError: unknown design, behaviour or kind, or replicates < 2.
    """
    profile = get_profile(profile)
    n = _replicates(profile, replicates)
    kinds = [check_control(k) for k in kinds]
    runs = [(parse_design(b), b, NO_CONTROL) for b in baselines]
    for name in designs:
        d = parse_design(name)
        if name not in baselines:
            runs.append((d, name, NO_CONTROL))
        for k in kinds:
            runs.append((control(d, k, profile.segment_mass), name, k))
    out = []
    for design, of, kind in runs:
        seeds = min(n, FIGURE_REPLICATES) if figure_seeds and kind in FIGURE_KINDS else n
        for bname in behaviours:
            beh = get_behaviour(bname)
            for rep in range(seeds):
                pert = profile.replicate(rep)
                labels = {
                    "experiment": "controls",
                    "profile": profile.name,
                    "convention": profile.convention,
                    "sensor_timing": profile.sensor_timing.name,
                    "design": design.name,
                    "behaviour": beh.name,
                    "replicate": rep,
                    "control_of": of,
                    "control": kind,
                }
                out.append(RunSpec(design, beh, profile.sim_settings(pert, design=design), labels))
    return out


def run_controls(profile=None, *, cache_dir=None, workers=None, progress: bool = False, **kw):
    """Run :func:`control_tasks` (cached). Returns the GridResult: ``tables``
    the per-hop rows, ``summary`` one row per run.

    Args:
        profile: a Profile or its name (default: $MAT_HOPPER_PROFILE, else ``paper``).
        cache_dir: the result cache folder (default: $MAT_HOPPER_CACHE, else
            ``results/cache``).
        workers: local worker processes (an integer >= 1; default: every core
            this process may use).
        progress: show a progress bar.
        **kw: passed to :func:`control_tasks`: ``designs``, ``behaviours``,
            ``kinds``, ``replicates``, ``baselines``.

    Returns:
        The :class:`~mat_hopper.experiments.runner.GridResult`: ``tables`` the
        per-hop rows, ``summary`` one row per run, each with the task labels
        in front. A run that raised is a ``failed`` summary row (with its
        error text), not an exception.

    Raises:
        ValueError: an unknown profile, design, behaviour or control kind,
            replicates < 2 (:func:`control_tasks`), an empty grid,
            invalid `workers`, or $MAT_HOPPER_CACHE set but empty
            (:func:`~mat_hopper.experiments.runner.run_grid`).
    """
    tasks = control_tasks(resolve_profile(profile), **kw)
    return run_grid(tasks, cache_dir, workers=workers, progress=progress, desc="controls")


SPRINGS = ("rigid", "paper", "axial")
RIGID_AT_AXIAL_STEP = "rigid, axial step"  # the rigid leg at the axial run's physics substeps


def attribution_tasks(profile=None, designs=CLAIM_DESIGNS + ("MD",), behaviours=BEHAVIOURS, replicates=None):
    """The factorial mass distribution x springs on shared seeds.

    Per design: its rigid twin at the profile's step (``rigid``), the
    design with the authors' springs (``paper``), with physical axial
    springs (``axial``, at the axial convention's automatic substeps), and
    the rigid twin again at exactly the axial run's settings
    (``rigid, axial step``): so the axial springs are compared with a rigid
    leg at the same time step, not confounded with it. A design rigid
    throughout (MD) gives only its ``rigid`` cell: its "springs" levels
    would be rigid legs labelled as springs. A profile without
    ``substep_studies`` (the quick profile) runs no axial arms: rigid and
    ``paper`` only.

    Args:
        profile: a Profile or its name.
        designs: whose densities give the mass distributions.
        behaviours: behaviour names.
        replicates: seeds per cell (default: the profile's
            ``figure_replicates``, 3 in the paper profile: the regression
            clusters its errors by mass distribution, 7 clusters, so more
            seeds barely narrow it, and no paired test reads them; >= 2).

    Returns:
        list of RunSpec; labels as :func:`control_tasks` (sensor_timing by
        its name) plus ``springs``
        (rigid, paper, axial, rigid, axial step) and ``mass_of`` (the design
        whose densities).
    """
    profile = get_profile(profile)
    n = _replicates(profile, profile.figure_replicates if replicates is None else replicates)
    out = []
    for name in designs:
        d = parse_design(name)
        twin = control(d, "rigid", profile.segment_mass)
        rigid_only = all(e is None for e in d.moduli_gpa)
        cells = [("rigid", twin, profile.for_convention("paper"), twin)]
        if not rigid_only:
            cells.append(("paper", d, profile.for_convention("paper"), d))
        if not rigid_only and profile.substep_studies:  # the axial arms run at 3-8 substeps
            axial = profile.for_convention("axial")
            cells.append(("axial", d, axial, d))
            cells.append((RIGID_AT_AXIAL_STEP, twin, axial, d))  # settings (substeps) of the elastic design
        for springs, design, prof, step_of in cells:
            for bname in behaviours:
                beh = get_behaviour(bname)
                for rep in range(n):
                    labels = {
                        "experiment": "attribution",
                        "profile": profile.name,
                        "convention": prof.convention,
                        "sensor_timing": profile.sensor_timing.name,
                        "design": design.name,
                        "behaviour": beh.name,
                        "replicate": rep,
                        "mass_of": name,
                        "springs": springs,
                    }
                    pert = profile.replicate(rep)
                    out.append(RunSpec(design, beh, prof.sim_settings(pert, design=step_of), labels))
    return out


def run_attribution(profile=None, *, cache_dir=None, workers=None, progress: bool = False, **kw):
    """Run :func:`attribution_tasks` (cached); the GridResult.

    Args:
        profile: a Profile or its name (default: $MAT_HOPPER_PROFILE, else ``paper``).
        cache_dir: the result cache folder (default: $MAT_HOPPER_CACHE, else
            ``results/cache``).
        workers: local worker processes (an integer >= 1; default: every core
            this process may use).
        progress: show a progress bar.
        **kw: passed to :func:`attribution_tasks`: ``designs``, ``behaviours``,
            ``replicates``.

    Returns:
        The :class:`~mat_hopper.experiments.runner.GridResult`: ``tables`` the
        per-hop rows, ``summary`` one row per run, each with the task labels
        in front (``springs``, ``mass_of``, ...). A run that raised is a ``failed`` summary row (with its
        error text), not an exception.

    Raises:
        ValueError: an unknown profile, design or behaviour, replicates < 2
            (:func:`attribution_tasks`), an empty grid,
            invalid `workers`, or $MAT_HOPPER_CACHE set but empty
            (:func:`~mat_hopper.experiments.runner.run_grid`).
    """
    tasks = attribution_tasks(resolve_profile(profile), **kw)
    return run_grid(tasks, cache_dir, workers=workers, progress=progress, desc="attribution")


PUSH_SCALES = (0.0, 1.0, 2.0)  # times REPLICATE_PUSH_FORCE_N: no push, the book's, twice it


def push_scale_tasks(profile=None, designs=("SS", "rho-inc"), behaviour="ramp", scales=PUSH_SCALES, replicates=None):
    """Runs of a few designs at several push scales, on shared seeds: how a
    claim moves with the size of the perturbation.

    Args:
        profile: a Profile or its name.
        designs: design names.
        behaviour: a behaviour name.
        scales: push scales (>= 0; :meth:`Perturbation.replicate`).
        replicates: seeds per cell (default the profile's; >= 2).

    Returns:
        list of RunSpec; labels: experiment ("push_scale"), profile,
        convention, sensor_timing (its name, e.g. ``"authors"``), design,
        behaviour, replicate, push_scale.
    """
    profile = get_profile(profile)
    n = _replicates(profile, replicates)
    beh = get_behaviour(behaviour)
    out = []
    for name in designs:
        d = parse_design(name)
        for scale in scales:
            for rep in range(n):
                pert = replace(profile, push_scale=float(scale)).replicate(rep)
                labels = {
                    "experiment": "push_scale",
                    "profile": profile.name,
                    "convention": profile.convention,
                    "sensor_timing": profile.sensor_timing.name,
                    "design": d.name,
                    "behaviour": beh.name,
                    "replicate": rep,
                    "push_scale": float(scale),
                }
                out.append(RunSpec(d, beh, profile.sim_settings(pert, design=d), labels))
    return out


def run_push_scale(profile=None, *, cache_dir=None, workers=None, progress: bool = False, **kw):
    """Run :func:`push_scale_tasks` (cached); the GridResult.

    Args:
        profile: a Profile or its name (default: $MAT_HOPPER_PROFILE, else ``paper``).
        cache_dir: the result cache folder (default: $MAT_HOPPER_CACHE, else
            ``results/cache``).
        workers: local worker processes (an integer >= 1; default: every core
            this process may use).
        progress: show a progress bar.
        **kw: passed to :func:`push_scale_tasks`: ``designs``, ``behaviour``,
            ``scales``, ``replicates``.

    Returns:
        The :class:`~mat_hopper.experiments.runner.GridResult`: ``tables`` the
        per-hop rows, ``summary`` one row per run, each with the task labels
        in front (``push_scale``, ...). A run that raised is a ``failed`` summary row (with its
        error text), not an exception.

    Raises:
        ValueError: an unknown profile, design or behaviour, replicates < 2, a
            push scale that is not a finite number >= 0 (:func:`push_scale_tasks`),
            an empty grid,
            invalid `workers`, or $MAT_HOPPER_CACHE set but empty
            (:func:`~mat_hopper.experiments.runner.run_grid`).
    """
    tasks = push_scale_tasks(resolve_profile(profile), **kw)
    return run_grid(tasks, cache_dir, workers=workers, progress=progress, desc="push scale")
