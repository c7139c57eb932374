"""One leg against baselines and its own controls, paired, in one call.

:func:`compare_design` runs a design, the baseline legs named (MD, SS, any
design name) and the design's controls (:mod:`mat_hopper.core.control_legs`:
its rigid twin, its mass-matched and its inertia-matched leg) on one
behaviour, all on the same settings and seeds, and returns one row per
comparator: the paired percent change of the design against it in
tracking error, hip power and hop height, with interval and verdict.

Alike in everything but the leg:

- one time step for all. A number is used as it is; under ``"auto"`` each
  leg's own automatic step is found
  (:func:`mat_hopper.core.timestep.auto_timestep`) and the finest of them,
  with its physics substeps, is applied to every leg, so that a design
  that needs 5e-5 s is never set beside a control run at 1e-4 s;
- the same seeds, 0..N-1: replicate k of every leg is the profile's
  perturbation k (:meth:`mat_hopper.experiments.profiles.Profile.replicate`),
  so the runs are paired by construction;
- one cache and one pool (:func:`mat_hopper.experiments.runner.run_grid`):
  a second call loads every run, and a control whose physics is another
  leg's is computed once.

Statistics are the book's paired rules, not new ones
(:mod:`mat_hopper.analysis.paired`): per comparator and metric
:func:`~mat_hopper.analysis.paired.paired_effect` (log ratio of run means
per seed, t interval, the larger of the paired t and the exact sign-flip
p), Holm's correction over the comparators of one metric (one family per
metric), significance only where the family can reach it with the
sign-flip test (:func:`~mat_hopper.analysis.paired.reachable`), and
:func:`~mat_hopper.analysis.paired.conclusion` with the +-10 % equivalence
margin. Where the seeds are too few for any difference to be significant
(2 seeds: the exact sign-flip p is at least 0.5), a verdict that would be
``not enough evidence`` says instead that the comparison is untestable
with n seeds, and how many replicates would make it testable.

What is not compared: a run that diverged, fell over or failed is no
result; it is left out and named (``attrs["left_out"]``). Its seed drops
from the pairs of that comparator (from every comparator, where the
design's own run is out); a comparator with no usable run gives no row. A
comparator that is the design itself (the rigid twin of a rigid leg, the
mass-matched leg of a homogeneous one, a baseline of the same
properties) or a control that cannot be built (no linear density profile
matches the inertia inside the accepted densities) is named and left out
too.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from ..analysis.paired import (
    CONFIDENCE,
    NOT_ENOUGH,
    conclusion,
    min_replicates,
    paired_effect,
    reachable,
)
from ..analysis.stats import unusable_runs
from ..core.behaviours import DEFAULT_BEHAVIOUR
from ..core.behaviours import behaviour as get_behaviour
from ..core.control_legs import CONTROLS, control
from ..core.materials import LegDesign, parse_design
from ..core.sim import SimSettings, sim_settings
from ..core.timestep import AUTO, is_auto
from ..physics.metrics import holm
from ..util.limits import check_total_steps
from .controls import BASELINES
from .profiles import resolve_profile
from .runner import OK, RunSpec, run_grid

# The metrics compared, and how the table names them.
COMPARE_METRICS = ("tracking_error_m", "power_w", "hop_height_m")
METRIC_LABELS = {"tracking_error_m": "tracking error", "power_w": "hip power", "hop_height_m": "hop height"}
DESIGN, BASELINE, CONTROL = "design", "baseline", "control"
NONE = "none"  # --baseline none, --controls none: no comparator of that kind
EXPERIMENT = "compare"
# Per metric, the columns of a row (prefixed with the metric's name).
METRIC_COLUMNS = ("mean", "mean_comparator", "method", "pct_change", "ci_low", "ci_high", "p", "p_holm", "verdict")


@dataclass(frozen=True)
class Leg:
    """One leg of a comparison: its design, its role (design, baseline,
    control) and its kind (the baseline's name as given, or the control
    kind)."""

    design: LegDesign
    role: str
    kind: str

    @property
    def name(self) -> str:
        return self.design.name


@dataclass
class ComparePlan:
    """Everything :func:`compare_design` runs, checked before any work.

    design: the design's leg; comparators: the legs it is compared with,
    in order (baselines, then controls); left_out: legs named but not run
    (dicts: leg, role, seeds, why, all); settings: one SimSettings per seed (the
    same for every leg); finest: the leg whose automatic step set the
    step (None for a number); tasks: the grid."""

    design: Leg
    comparators: list
    left_out: list
    behaviour: object
    profile: object
    replicates: int
    settings: list
    finest: str | None
    tasks: list = field(default_factory=list)

    @property
    def timestep_s(self) -> float:
        return self.settings[0].timestep_s

    @property
    def substeps(self) -> int:
        return self.settings[0].substeps


def split_names(text) -> list[str]:
    """A comma list of design names, split at the commas outside
    parentheses (``custom(1.39/70,8/rigid)`` is one name), blanks trimmed.

    Args:
        text: e.g. ``"SS,Ti"``.

    Returns:
        list of str (empty items kept, for the caller to refuse).
    """
    return [p.strip() for p in re.split(r",(?![^()]*\))", str(text))]


def _names(value, what: str) -> list:
    """`value` as a list of items: None -> None (the default), a string ->
    its comma list (``none``: no item), a sequence as it is. Empty items
    are refused."""
    if value is None:
        return None
    items = split_names(value) if isinstance(value, str) else list(value)
    if len(items) == 1 and isinstance(items[0], str) and items[0].strip().lower() == NONE:
        return []
    if any(isinstance(i, str) and not i.strip() for i in items):
        raise ValueError(f"{what} must be comma-separated names, got {value!r} (an empty item)")
    return items


def _same_leg(a: LegDesign, b: LegDesign) -> bool:
    """Whether two designs are the same physics (densities and moduli; the name is a label)."""
    if a.n_segments != b.n_segments:
        return False
    if any((x is None) != (y is None) for x, y in zip(a.moduli_gpa, b.moduli_gpa)):
        return False
    mods = [(x, y) for x, y in zip(a.moduli_gpa, b.moduli_gpa) if x is not None]
    return bool(
        np.allclose(a.densities_g_cm3, b.densities_g_cm3, rtol=1e-9, atol=0)
        and all(math.isclose(x, y, rel_tol=1e-9) for x, y in mods)
    )


def _baseline_legs(design: LegDesign, baselines) -> list[Leg]:
    items = _names(BASELINES if baselines is None else baselines, "baselines")
    legs, seen = [], {}
    for item in items:
        try:  # a single material gets as many segments as the design
            d = item if isinstance(item, LegDesign) else parse_design(str(item), n_segments=design.n_segments)
        except ValueError as e:
            raise ValueError(f"baselines: {e}") from None
        key = d.name.lower()
        if key in seen:
            raise ValueError(f"baselines: {seen[key]!r} and {item!r} name the same design; give each once")
        seen[key] = item
        legs.append(Leg(d, BASELINE, d.name))
    return legs


def _control_kinds(controls) -> list[str]:
    items = _names(CONTROLS if controls is None else controls, "controls")
    kinds = []
    for item in items:
        kind = next((c for c in CONTROLS if c == str(item).strip().lower()), None)
        if kind is None:
            raise ValueError(f"controls: unknown control {item!r}; accepted: {', '.join(CONTROLS)} (or {NONE})")
        if kind in kinds:
            raise ValueError(f"controls: {kind!r} is named twice; give each control once")
        kinds.append(kind)
    return kinds


def _comparators(design: LegDesign, baselines, controls, segment_mass: str) -> tuple[list, list]:
    """(legs to compare with, legs named but left out with why)."""
    legs, out = list(_baseline_legs(design, baselines)), []
    for kind in _control_kinds(controls):
        try:
            legs.append(Leg(control(design, kind, segment_mass), CONTROL, kind))
        except ValueError as e:  # a property of the design, not bad input: named, and the rest compared
            why = f"cannot be built: {e}"
            out.append({"leg": f"{design.name}~{kind}", "role": CONTROL, "seeds": [], "why": why, "all": True})
    if not legs and not out:
        raise ValueError("baselines and controls are both none: give at least one comparator")
    kept = []
    for leg in legs:
        if _same_leg(leg.design, design):
            why = "the same leg as the design (same densities and moduli): nothing to compare"
            out.append({"leg": leg.name, "role": leg.role, "seeds": [], "why": why, "all": True})
        else:
            kept.append(leg)
    if not kept:  # known before any run: a refusal, as simulate --control refuses it
        why = "; ".join(f"{o['leg']}: {o['why']}" for o in out)
        raise ValueError(f"nothing to compare, every comparator is left out before any run ({why})")
    return kept, out


def _run_settings(legs, profile, replicates: int, timestep_s, **common) -> tuple[list[SimSettings], str | None]:
    """One SimSettings per seed, the same for every leg, and the leg whose
    automatic step is the finest (None for a numeric step)."""
    finest = None
    step_of = None
    if is_auto(timestep_s):
        timestep_s = AUTO
        steps = [(sim_settings(leg.design, timestep_s=AUTO, **common).timestep_s, i) for i, leg in enumerate(legs)]
        step_of = legs[min(steps)[1]].design  # the finest; the first such leg on a tie
        finest = step_of.name
    window = (common["transient_s"], common["duration_s"])  # this run's scored window, not the profile's
    pert = [profile.replicate(seed, window) for seed in range(replicates)]
    out = [sim_settings(step_of, timestep_s=timestep_s, perturbation=p, **common) for p in pert]
    return out, finest


def plan_compare(
    design,
    *,
    baselines=None,
    controls=None,
    behaviour: str = DEFAULT_BEHAVIOUR,
    profile=None,
    replicates: int | None = None,
    timestep_s=None,
    convention: str | None = None,
    sensor_timing=None,
    segment_mass: str | None = None,
    damping: str | None = None,
    contact: str | None = None,
    duration_s: float | None = None,
    transient_s: float | None = None,
) -> ComparePlan:
    """The legs, settings and grid of :func:`compare_design` (same
    arguments), every input checked and the run size limited
    (:func:`mat_hopper.util.limits.check_total_steps`) before any work.

    Args:
        design: the leg (a LegDesign or a design name); the other arguments
            as :func:`compare_design`.

    Returns:
        ComparePlan.

    Raises:
        ValueError: as :func:`compare_design`.
    """
    profile = resolve_profile(profile)
    if not isinstance(design, LegDesign):
        try:
            design = parse_design(str(design))
        except ValueError as e:
            raise ValueError(f"design: {e}") from None
    beh = get_behaviour(behaviour)
    n = profile.replicates if replicates is None else replicates
    if isinstance(n, bool) or not isinstance(n, int | np.integer) or n < 2:
        raise ValueError(f"replicates must be an integer >= 2 (paired seeds per leg), got {n!r}")
    n = int(n)
    segment_mass = profile.segment_mass if segment_mass is None else segment_mass
    legs, left_out = _comparators(design, baselines, controls, segment_mass)
    convention = profile.convention if convention is None else convention
    if timestep_s is None:  # the profile's step for this convention (auto substeps for the stiff ones)
        timestep_s = profile.for_convention(convention).timestep_s
    common = {
        "duration_s": profile.duration_s if duration_s is None else duration_s,
        "transient_s": profile.transient_s if transient_s is None else transient_s,
        "convention": convention,
        "record_rate_hz": profile.record_rate_hz,
        "sensor_timing": profile.sensor_timing if sensor_timing is None else sensor_timing,
        "segment_mass": segment_mass,
        "replicate_protocol": profile.replicate_protocol,
    }
    for name, value in (("damping", damping), ("contact", contact)):
        if value is not None:  # else the model's default
            common[name] = value
    me = Leg(design, DESIGN, design.name)
    settings, finest = _run_settings([me, *legs], profile, n, timestep_s, **common)
    s = settings[0]
    check_total_steps(
        (1 + len(legs)) * n * s.n_steps,
        f"replicates={n}: {1 + len(legs)} legs x {n} seeds x {s.n_steps:.3g} physics steps "
        f"({s.duration_s:g} s at {s.timestep_s:g} s)",
        "fewer replicates, comparators or a shorter run",
    )
    plan = ComparePlan(me, legs, left_out, beh, profile, n, settings, finest)
    for leg in [me, *legs]:
        for seed, st in enumerate(settings):
            labels = {
                "experiment": EXPERIMENT,
                "profile": profile.name,
                "convention": st.convention,
                "design": leg.name,
                "behaviour": beh.name,
                "replicate": seed,
                "role": leg.role,
                "kind": leg.kind,
            }
            plan.tasks.append(RunSpec(leg.design, beh, st, labels))
    return plan


def untestable(n_pairs: int, family_size: int, alpha: float = 0.05) -> str:
    """The verdict where no difference can be significant with `n_pairs`
    seeds in a family of `family_size` comparisons.

    Args:
        n_pairs: paired seeds available.
        family_size: comparisons in the Holm family.
        alpha: the family's significance level.

    Returns:
        The verdict text, naming the seeds needed (:func:`min_replicates`),
        or, with no pair at all, that no seed scored a hop cycle.

    >>> untestable(2, 1)
    'untestable with n = 2 seeds; use --replicates 6 or more'
    """
    if n_pairs == 0:  # no seed of both legs scored a hop cycle: more seeds of the same runs cannot help
        return "untestable: no paired seed has a scored hop cycle"
    k = min_replicates(family_size, alpha)
    seeds = "seed" if n_pairs == 1 else "seeds"
    more = f"use --replicates {k} or more" if k is not None else "use more replicates"
    return f"untestable with n = {n_pairs} {seeds}; {more}"


def _usable(summary: pd.DataFrame, plan: ComparePlan) -> tuple[pd.DataFrame, list]:
    """(the usable runs' rows, the left-out legs: one dict per leg with
    unusable runs)."""
    bad = unusable_runs(summary)
    why_of = dict(zip(bad["key"], bad["why"])) if len(bad) else {}
    if "error" in summary.columns:  # a failed run: its error text
        for k, err in zip(summary["key"], summary["error"]):
            if k in why_of and why_of[k] == "failed" and str(err):
                why_of[k] = f"failed: {err}"
    ok = summary["status"].astype(str).eq(OK) & ~summary["key"].isin(set(why_of))
    left = []
    for (name, role), g in summary[~ok].groupby(["design", "role"], sort=False):
        g = g.sort_values("replicate")
        seeds = [int(s) for s in g["replicate"]]
        first = why_of.get(g["key"].iloc[0], str(g["status"].iloc[0]))
        all_out = len(seeds) == plan.replicates
        left.append({"leg": name, "role": role, "seeds": seeds, "why": first, "all": all_out})
    return summary[ok], left


def _pairs(runs: pd.DataFrame, leg: Leg, metric: str) -> pd.Series:
    """The leg's run means of `metric`, indexed by seed."""
    g = runs[(runs["design"] == leg.name) & (runs["role"] == leg.role)]
    return pd.Series(g[f"mean_{metric}"].to_numpy(float), index=g["replicate"].astype(int).to_numpy())


def _rows(runs: pd.DataFrame, plan: ComparePlan, metrics, confidence: float) -> list[dict]:
    """One dict per comparator that shares usable seeds with the design:
    paired effects per metric (before Holm)."""
    st = plan.settings[0]
    rows = []
    for leg in plan.comparators:
        row = {
            "design": plan.design.name,
            "comparator": leg.name,
            "role": leg.role,
            "kind": leg.kind,
            "behaviour": plan.behaviour.name,
            "profile": plan.profile.name,
            "convention": st.convention,
            "timestep_s": st.timestep_s,
            "substeps": st.substeps,
        }
        shared = _pairs(runs, plan.design, metrics[0]).index.intersection(_pairs(runs, leg, metrics[0]).index)
        if len(shared) == 0:
            continue  # no usable run of this comparator (or of the design) at a common seed: named, no row
        row["n_pairs"] = 0
        row["seeds"] = " ".join(str(s) for s in sorted(shared))
        for m in metrics:
            a, b = _pairs(runs, plan.design, m), _pairs(runs, leg, m)
            eff = paired_effect(a, b, confidence=confidence)  # Series: paired on the seed
            row["n_pairs"] = max(row["n_pairs"], eff["n_pairs"])
            row[f"{m}_mean"] = float(a.loc[shared].mean())
            row[f"{m}_mean_comparator"] = float(b.loc[shared].mean())
            for c in ("method", "pct_change", "ci_low", "ci_high", "p"):
                row[f"{m}_{c}"] = eff[c]
        rows.append(row)
    return rows


def _verdicts(table: pd.DataFrame, metrics, alpha: float, margin) -> pd.DataFrame:
    """Holm over the comparators of each metric, the reachability guard and
    the verdict (module doc): analysis.paired's rules, as compare_paired
    applies them."""
    m_family = len(table)
    for m in metrics:
        table[f"{m}_p_holm"] = holm(table[f"{m}_p"].to_numpy(float))
        can = [reachable(int(n), m_family, alpha) for n in table["n_pairs"]]
        verdicts = []
        for p, ok, lo, hi, n in zip(
            table[f"{m}_p_holm"], can, table[f"{m}_ci_low"], table[f"{m}_ci_high"], table["n_pairs"]
        ):
            v = conclusion(p if ok and p < alpha else math.nan, lo, hi, alpha=alpha, margin=margin)
            verdicts.append(untestable(int(n), m_family, alpha) if v == NOT_ENOUGH and not ok else v)
        table[f"{m}_verdict"] = verdicts
    return table


def _columns(metrics) -> list[str]:
    head = ["design", "comparator", "role", "kind", "behaviour", "profile", "convention", "timestep_s", "substeps"]
    return [*head, "n_pairs", "seeds", *(f"{m}_{c}" for m in metrics for c in METRIC_COLUMNS)]


def compare_design(
    design,
    *,
    baselines=None,
    controls=None,
    behaviour: str = DEFAULT_BEHAVIOUR,
    profile=None,
    replicates: int | None = None,
    timestep_s=None,
    convention: str | None = None,
    sensor_timing=None,
    segment_mass: str | None = None,
    damping: str | None = None,
    contact: str | None = None,
    duration_s: float | None = None,
    transient_s: float | None = None,
    metrics=COMPARE_METRICS,
    alpha: float = 0.05,
    confidence: float = CONFIDENCE,
    margin=None,
    cache_dir=None,
    workers: int | None = None,
    progress: bool = False,
) -> pd.DataFrame:
    """A design against baselines and its own controls, paired on shared
    seeds, at one time step (module doc).

    Args:
        design: a LegDesign or a design name (:func:`mat_hopper.core.materials.parse_design`).
        baselines: design names (a sequence, or a comma string such as
            ``"SS,Ti"``; a single material gets the design's segment count)
            or LegDesigns; ``"none"`` or ``()``: none. Default MD and SS.
        controls: control kinds (``rigid``, ``mass``, ``inertia``; any case;
            a sequence or comma string); ``"none"`` or ``()``: none. Default all three.
        behaviour: a behaviour name (default ``forward``).
        profile: a Profile or its name (default $MAT_HOPPER_PROFILE, else
            ``paper``): run length, transient, record rate, seeds' perturbations.
        replicates: seeds 0..N-1 per leg (default the profile's; >= 2).
        timestep_s: a physics step (s) for every leg, or ``"auto"``: the
            finest automatic step of the legs, for every leg; default the
            profile's step for the convention.
        convention: stiffness convention (default the profile's).
        sensor_timing, segment_mass, damping, contact: as
            :class:`~mat_hopper.core.sim.SimSettings` (default the profile's; damping and
            contact the model's).
        duration_s, transient_s: run length and transient, s (default the profile's).
        metrics: run-mean metrics compared (default tracking error, hip power, hop height).
        alpha, confidence, margin: significance level of the Holm-adjusted p, confidence of the
            paired interval, equivalence margin as a fraction (default +-10 %).
        cache_dir: the result cache (default $MAT_HOPPER_CACHE, else results/cache).
        workers: local processes (default every core).
        progress: show a progress bar.

    Returns:
        DataFrame, one row per comparator with usable runs (baselines
        first): design, comparator, role (baseline or control), kind,
        behaviour, profile, convention, timestep_s, substeps (the same in
        every row), n_pairs, seeds (the design's usable seeds), and per
        metric ``<metric>_mean`` (the design's runs), ``_mean_comparator``,
        ``_method``, ``_pct_change``, ``_ci_low``, ``_ci_high`` (%),
        ``_p``, ``_p_holm`` and ``_verdict`` (``difference``, ``no
        difference``, ``not enough evidence``, or ``untestable with n = 2
        seeds; use --replicates 6 or more``). ``attrs``: ``left_out`` (list of
        dicts: leg, role, seeds, why, all (no run of it is left); a diverged,
        fallen or failed run, an identical or unbuildable comparator), ``timestep_s``, ``substeps``,
        ``finest`` (the leg whose automatic step was taken, or None),
        ``replicates``, ``n_cached``, ``n_computed``.

    Raises:
        ValueError: an unknown design, baseline, control kind, behaviour,
            profile or convention, a name given twice, no comparator,
            replicates < 2 or not an integer, a bad setting, or a run above
            the limit of physics steps; naming the argument.
    """
    plan = plan_compare(
        design,
        baselines=baselines,
        controls=controls,
        behaviour=behaviour,
        profile=profile,
        replicates=replicates,
        timestep_s=timestep_s,
        convention=convention,
        sensor_timing=sensor_timing,
        segment_mass=segment_mass,
        damping=damping,
        contact=contact,
        duration_s=duration_s,
        transient_s=transient_s,
    )
    return run_plan(
        plan,
        metrics=metrics,
        alpha=alpha,
        confidence=confidence,
        margin=margin,
        cache_dir=cache_dir,
        workers=workers,
        progress=progress,
    )


def run_plan(
    plan: ComparePlan,
    *,
    metrics=COMPARE_METRICS,
    alpha: float = 0.05,
    confidence: float = CONFIDENCE,
    margin=None,
    cache_dir=None,
    workers: int | None = None,
    progress: bool = False,
) -> pd.DataFrame:
    """Run a :func:`plan_compare` plan through the cache and pool
    (:func:`mat_hopper.experiments.runner.run_grid`) and return its paired
    table.

    Args:
        plan: the :class:`ComparePlan`; the other arguments as :func:`compare_design`.

    Returns:
        The paired table of :func:`paired_table`.
    """
    res = run_grid(plan.tasks, cache_dir, workers=workers, progress=progress, desc="compare")
    return paired_table(res.summary, plan, metrics=metrics, alpha=alpha, confidence=confidence, margin=margin, grid=res)


def paired_table(
    summary: pd.DataFrame,
    plan: ComparePlan,
    *,
    metrics=COMPARE_METRICS,
    alpha=0.05,
    confidence=CONFIDENCE,
    margin=None,
    grid=None,
) -> pd.DataFrame:
    """The table of :func:`compare_design` from a run summary of the plan's
    grid (one row per run: design, role, replicate, status, key,
    ``mean_<metric>``).

    Args:
        summary: the grid's summary (:attr:`mat_hopper.experiments.runner.GridResult.summary`).
        plan: the :class:`ComparePlan` the grid ran.
        metrics, alpha, confidence, margin: as :func:`compare_design`.
        grid: the GridResult, for the cached and computed counts (optional).

    Returns:
        DataFrame: as :func:`compare_design`.
    """
    metrics = tuple(metrics)
    runs, left = _usable(summary, plan)
    table = pd.DataFrame(_rows(runs, plan, metrics, confidence))
    if len(table):
        table = _verdicts(table, metrics, alpha, margin)
        table = table[_columns(metrics)]
    else:
        table = pd.DataFrame(columns=_columns(metrics))
    table.attrs.update(
        left_out=[*plan.left_out, *left],
        timestep_s=plan.timestep_s,
        substeps=plan.substeps,
        finest=plan.finest,
        replicates=plan.replicates,
        n_cached=None if grid is None else grid.n_cached,
        n_computed=None if grid is None else grid.n_computed,
    )
    return table
