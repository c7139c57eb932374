"""The experiment types and the paper's design grids, as data.

An :class:`Experiment` is designs x behaviours (its runs are
:class:`~mat_hopper.experiments.runner.RunSpec`); a :class:`StabilityMap` is
mono-material legs over a density x modulus grid. Experiments 1-3 are the
paper's grids; every number comes from :mod:`mat_hopper.core.reference`.
:mod:`mat_hopper.experiments.paper` re-exports every name here.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

from ..core import reference as ref
from ..core.behaviours import BEHAVIOUR_NAMES
from ..core.behaviours import behaviour as get_behaviour
from ..core.materials import LegDesign, Material, paper_designs
from ..physics.porosity import DEFAULT_POROSITY_MODEL, check_porosity_model, porous_modulus
from .profiles import FIGURE_REPLICATES, Profile, check_replicates, get_profile
from .runner import RunSpec

UNPERTURBED = -1


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
    """Designs x behaviours: the runs of one experiment. ``figure_only``: no
    paired test reads its replicates (a figure of means), so it runs at most
    :data:`~mat_hopper.experiments.profiles.FIGURE_REPLICATES` of the seeds
    asked for, the first ones."""

    name: str
    title: str
    points: tuple[DesignPoint, ...]
    behaviours: tuple[str, ...]
    baselines: tuple[str, ...] = ()
    figure_only: bool = False

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
        if self.figure_only:
            replicates = min(replicates, FIGURE_REPLICATES)
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


def experiment_2_gibson_ashby() -> Experiment:
    """Experiment 2 with porosity that softens: a density point below the
    base material's is that solid made porous (Gibson-Ashby, E = E_s
    (rho / rho_s)^2; :func:`experiment_2`).

    Only a figure and its means read it (chapter 7), so it runs the figure's
    seeds (``figure_only``).

    Returns:
        The :class:`Experiment` ``exp2-gibson-ashby``.
    """
    return replace(experiment_2("gibson-ashby"), figure_only=True)
