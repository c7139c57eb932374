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

This module holds the registry of experiments by name (:data:`EXPERIMENTS`,
:func:`get_experiment`, :func:`parse_experiments`) and the robustness and
controls studies; it re-exports the experiment types and grids
(``_experiments``) and the book's checks (``_book_checks``), so every name
is imported from here.
"""

from __future__ import annotations

from dataclasses import dataclass

from . import robustness
from ._book_checks import (
    CLOCK_FACTORS,
    axial_check,
    axial_check_tasks,
    clock_drift,
    clock_tasks,
    convention_stability,
    convention_tasks,
    in_place_replicates,
    in_place_tasks,
)
from ._experiments import (
    SWEEP_SHORT,
    UNPERTURBED,
    DesignPoint,
    Experiment,
    StabilityMap,
    experiment_1,
    experiment_2,
    experiment_2_gibson_ashby,
    experiment_3,
)
from .profiles import Profile, check_replicates, get_profile

__all__ = [
    "CLOCK_FACTORS",
    "EXPERIMENTS",
    "EXPERIMENT_NAMES",
    "EXPERIMENT_SPELLINGS",
    "SWEEP_SHORT",
    "UNPERTURBED",
    "ControlsStudy",
    "DesignPoint",
    "Experiment",
    "RobustnessStudy",
    "StabilityMap",
    "axial_check",
    "axial_check_tasks",
    "clock_drift",
    "clock_tasks",
    "convention_stability",
    "convention_tasks",
    "experiment_1",
    "experiment_2",
    "experiment_2_gibson_ashby",
    "experiment_3",
    "experiment_name",
    "experiment_spellings",
    "get_experiment",
    "in_place_replicates",
    "in_place_tasks",
    "parse_experiments",
]


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
        from ..util.parsing import close_names

        near = dict.fromkeys(
            EXPERIMENT_SPELLINGS[_SPELLING_TO_NAME[s]][0] for s in close_names(text, _SPELLING_TO_NAME)
        )
        hint = f"; did you mean {' or '.join(near)}?" if near else ""
        raise ValueError(f"unknown experiment {text!r}; accepted: {experiment_spellings()}{hint}")
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
