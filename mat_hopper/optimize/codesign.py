"""Does control erase material? Controller gains tuned per material, then the materials compared again.

The paper compares legs under one controller whose gains were tuned for
none of them. A material difference that a few gains can make up is a
difference of tuning, not of material. This module gives each material
its own gains and compares again:

1. **Tune.** For each design, a small seeded Optuna study (single
   objective, TPE, :data:`TRIALS` trials, the authors' gains enqueued
   first) over the controller's foot-placement gain and stance attitude
   gains (:data:`GAIN_BOUNDS`, log scale, about the authors' values), on
   one behaviour, on screening runs: the profile's settings with the
   quick profile's run length and transient (12 s, scored after 4 s;
   :func:`screen_profile`), as racing's rung 0 screens. A tuning ranks
   gains; the comparison (step 2) measures them at full length. Score: the sum of tracking
   error and hip power, each relative to the same design's at the authors'
   gains, ``J = e / e0 + P / P0`` (2 at the authors' gains; lower is
   better on the two together, neither can be bought with the other
   unnoticed). Constraints: the run must stay upright without divergence
   and hop within 5 cm of the 1 m target, or no farther from it than at
   the authors' gains (short runs are still settling). Trials run
   in batches through the result runner (ask a batch, run it as one grid,
   tell in order): the same trials on any machine, every run cached, so a
   rerun costs nothing.
2. **Compare.** Every design at the authors' gains and at its own best
   gains, on perturbed replicates (the profile's ``replicates``),
   compared against the baseline (MD) on replicate means with
   :func:`mat_hopper.analysis.stats.compare_replicates` (percent change
   with a bootstrap interval, Holm-corrected Mann-Whitney U; one family per
   gain setting).

A material difference *survives* tuning when its percent change against
the baseline has a 95 % interval clear of zero, with the same sign, at the
authors' gains and at the designs' own gains (:func:`answer`).
"""

from __future__ import annotations

import math
import numbers
from dataclasses import dataclass, replace

import numpy as np
import optuna
import pandas as pd

from ..analysis.stats import compare_replicates
from ..core import reference as ref
from ..core.behaviours import behaviour as get_behaviour
from ..core.controller import ControllerSettings
from ..core.materials import MONO_NAMES, LegDesign, parse_design
from ..core.perturbations import Perturbation
from ..experiments.profiles import Profile, get_profile, resolve_profile
from ..experiments.runner import FAILED, OK, Runner, RunSpec
from ._objective import HOP_HEIGHT_TOLERANCE_M
from ._study import _quiet

# Searched gains, log scale: about a decade around the authors' values
# (foot placement 0.05 s, stance kp 4, kd 1). Stance kd above about 2
# breaks the delayed-damping bound at the 1e-4 s step (mat_hopper.physics.modes):
# those trials diverge and come out infeasible.
GAIN_BOUNDS = {
    "foot_placement_gain": (0.01, 0.25),
    "stance_kp": (0.5, 40.0),
    "stance_kd": (0.1, 4.0),
}
TRIALS = 24
BATCH = 8
BEHAVIOUR = "forward"
BASELINE = "MD"
DEFAULT, TUNED = "authors' gains", "own gains"


@dataclass(frozen=True)
class Tuning:
    """One design's tuning: the best gains, their score and the study."""

    design: str
    gains: dict
    score: float
    default: dict  # tracking_error_m, power_w at the authors' gains
    best: dict  # tracking_error_m, power_w at the best gains
    trials: pd.DataFrame


def _score_row(summary: dict, target_m: float) -> dict:
    ok = summary.get("status") == OK and summary.get("n_hops", 0) > 0
    h = summary.get("mean_hop_height_m", math.nan)
    return {
        "tracking_error_m": float(summary.get("mean_tracking_error_m", math.nan)),
        "power_w": float(summary.get("mean_power_w", math.nan)),
        "hop_height_m": float(h),
        "upright": bool(ok),
        "height_error_m": abs(h - target_m) if ok and np.isfinite(h) else math.inf,
    }


def _check_int(value, name: str, lowest: int | None = None) -> int:
    """`value` as an int: an integer (not a bool), >= `lowest` where given;
    ValueError otherwise (a count that would loop forever or be silently
    truncated)."""
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        bound = f" >= {lowest}" if lowest is not None else ""
        raise ValueError(f"{name} must be an integer{bound}, got {value!r}")
    if lowest is not None and value < lowest:
        raise ValueError(f"{name} must be an integer >= {lowest}, got {value!r}")
    return int(value)


def _settings(profile: Profile, gains: dict, perturbation=None, design=None):
    st = profile.sim_settings(perturbation, design=design)
    return replace(st, controller=replace(ControllerSettings(), **gains))


def authors_gains() -> dict:
    """The authors' values of the searched gains, the first trial of every tuning.

    Returns:
        dict {gain name of :data:`GAIN_BOUNDS`: its value in
        :mod:`mat_hopper.core.reference`} (foot_placement_gain in s).
    """
    return {k: float(getattr(ref, k.upper())) for k in GAIN_BOUNDS}


def screen_profile(profile: Profile) -> Profile:
    """The profile a tuning screens gains on: `profile` with the quick
    profile's run length and transient where they are shorter (its other
    settings, the step and conventions, unchanged).

    Args:
        profile: the study's Profile.

    Returns:
        A Profile: duration_s and transient_s at most the quick profile's (s).
    """
    quick = get_profile("quick")
    duration_s, transient_s = min(profile.duration_s, quick.duration_s), min(profile.transient_s, quick.transient_s)
    if (duration_s, transient_s) == (profile.duration_s, profile.transient_s):
        return profile
    return replace(profile, duration_s=duration_s, transient_s=transient_s)


def tuning_task(design: LegDesign, behaviour, profile: Profile, gains: dict, trial: int) -> RunSpec:
    """One tuning trial's run (:func:`tune`'s task), a screening run
    (:func:`screen_profile`).

    Args:
        design: the leg.
        behaviour: the Behaviour tuned on.
        profile: the study's Profile (its screen runs the trial).
        gains: the trial's gains ({name of :data:`GAIN_BOUNDS`: value}).
        trial: the trial's number (its label).

    Returns:
        The RunSpec, labelled ``{"trial": trial}``.
    """
    return RunSpec(design, behaviour, _settings(screen_profile(profile), gains, design=design), {"trial": trial})


def comparison_tasks(legs: dict, profile: Profile, behaviour, replicates: int, tuned: dict | None = None) -> list:
    """The replicate runs of :func:`codesign`'s comparison (module doc, step 2).

    Args:
        legs: {design name: LegDesign}.
        profile: the Profile of the runs.
        behaviour: the Behaviour compared on.
        replicates: seeds per design and gain setting (0 .. replicates - 1).
        tuned: {design name: its tuned gains}; None: the runs at the authors'
            gains only (the tuned gains are known once the tuning ran).

    Returns:
        list of RunSpec, design-major, then gain setting, then seed; labels
        experiment (the gain setting), profile, design, replicate.
    """
    tasks = []
    for name, leg in legs.items():
        settings = ((DEFAULT, {}),) if tuned is None else ((DEFAULT, {}), (TUNED, tuned[name]))
        for setting, gains in settings:
            for r in range(replicates):
                st = _settings(profile, gains, Perturbation.replicate(r, profile.scored_window_s), leg)
                labels = {"experiment": setting, "profile": profile.name, "design": name, "replicate": r}
                tasks.append(RunSpec(leg, behaviour, st, labels))
    return tasks


def tune(
    design: LegDesign | str,
    *,
    profile: Profile | str | None = None,
    behaviour: str = BEHAVIOUR,
    trials: int = TRIALS,
    batch: int = BATCH,
    seed: int = 0,
    runner: Runner | None = None,
) -> Tuning:
    """Tune one design's gains (module doc, step 1). `runner`: a
    :class:`~mat_hopper.experiments.runner.Runner` to reuse (its cache and
    pool); default a fresh one on the default cache.

    Args:
        design: a LegDesign or a design name (``"SS"``, ``"rho-inc"``, ...).
        profile: a Profile or its name; None (the default) for
            $MAT_HOPPER_PROFILE, else ``paper``.
        behaviour: the behaviour tuned on (default ``forward``).
        trials: the study's trials, the authors' gains first (an int >= 1;
            default :data:`TRIALS`, 24).
        batch: trials asked and run together per round (an int >= 1;
            default :data:`BATCH`, 8).
        seed: the TPE sampler's seed (an int; default 0).
        runner: a Runner to reuse (not closed here); None (the default) for a
            fresh ``Runner(progress=False)``, closed at the end.

    Returns:
        A :class:`Tuning`: ``design`` (its name), ``gains`` (the best
        feasible trial's {``foot_placement_gain`` (s), ``stance_kp``,
        ``stance_kd``}), ``score`` (its J, 2 at the authors' gains),
        ``default`` and ``best`` ({``tracking_error_m`` (m), ``power_w``
        (W)} at the authors' and at the best gains) and ``trials`` (one row
        per trial: trial, the three gains, tracking_error_m, power_w,
        hop_height_m, upright, height_error_m, score).

    Raises:
        ValueError: `trials` or `batch` not an integer >= 1, `seed` not an
            integer, an unknown design name, profile or behaviour.
        RuntimeError: a tuning run failed, or the design falls or diverges
            at the authors' gains.
    """
    trials, batch = _check_int(trials, "trials", 1), _check_int(batch, "batch", 1)
    seed = _check_int(seed, "seed")
    design = parse_design(design) if isinstance(design, str) else design
    profile = resolve_profile(profile)
    beh = get_behaviour(behaviour)
    target = ControllerSettings().hop_height_target_m
    own = runner is None
    runner = runner or Runner(progress=False)
    _quiet()
    sampler = optuna.samplers.TPESampler(seed=seed, multivariate=True, constant_liar=True)
    study = optuna.create_study(direction="minimize", sampler=sampler)
    study.enqueue_trial(authors_gains())
    base = None
    rows = []
    try:
        while len(study.trials) < trials:
            asked = [study.ask() for _ in range(min(batch, trials - len(study.trials)))]
            gains = [{k: t.suggest_float(k, *GAIN_BOUNDS[k], log=True) for k in GAIN_BOUNDS} for t in asked]
            tasks = [tuning_task(design, beh, profile, g, t.number) for t, g in zip(asked, gains)]
            res = runner.run(tasks, desc=f"tuning {design.name}")
            for t, g, summ in zip(asked, gains, res.summary.to_dict("records")):
                if summ.get("status") == FAILED:
                    raise RuntimeError(f"tuning run failed: {summ.get('error')}")
                r = _score_row(summ, target)
                if base is None:  # trial 0: the authors' gains, the reference of the score
                    if not r["upright"]:
                        raise RuntimeError(f"{design.name} falls or diverges at the authors' gains on {behaviour}")
                    base = r
                finite = np.isfinite(r["tracking_error_m"]) and np.isfinite(r["power_w"])
                score = (
                    r["tracking_error_m"] / base["tracking_error_m"] + r["power_w"] / base["power_w"] if finite else 1e6
                )
                t.set_constraint("unstable", 0.0 if r["upright"] else 1.0)
                allowed = max(HOP_HEIGHT_TOLERANCE_M, base["height_error_m"])
                t.set_constraint("hop_height", float(min(r["height_error_m"] - allowed, 1.0)))
                study.tell(t, score)
                rows.append({"trial": t.number, **g, **r, "score": score})
    finally:
        if own:
            runner.close()
    table = pd.DataFrame(rows)
    best = study.best_trial  # feasible trials only (Optuna)
    b = table[table["trial"] == best.number].iloc[0]
    return Tuning(
        design=design.name,
        gains=dict(best.params),
        score=float(best.value),
        default={k: base[k] for k in ("tracking_error_m", "power_w")},
        best={k: float(b[k]) for k in ("tracking_error_m", "power_w")},
        trials=table,
    )


def codesign(
    designs=MONO_NAMES,
    *,
    profile: Profile | str | None = None,
    behaviour: str = BEHAVIOUR,
    trials: int = TRIALS,
    replicates: int | None = None,
    seed: int = 0,
    cache_dir=None,
    workers: int | None = None,
    baseline: str = BASELINE,
) -> dict:
    """Tune every design, then compare all at the authors' gains and at
    their own (module doc). Returns ``gains`` (one row per design: best
    gains, score, tracking and power at both), ``hops`` (per-hop table of
    the replicate runs, ``experiment`` = the gain setting),
    ``comparison`` (:func:`compare_replicates` against `baseline`),
    ``tunings`` ({design: Tuning}) and ``answer`` (text).

    Args:
        designs: design names or LegDesigns (default the paper's mono-material
            designs, :data:`mat_hopper.core.materials.MONO_NAMES`); keyed by the
            name given or the LegDesign's name.
        profile: a Profile or its name; None (the default) for
            $MAT_HOPPER_PROFILE, else ``paper``.
        behaviour: the behaviour tuned and compared on (default ``forward``).
        trials: each design's tuning trials (an int >= 1; default
            :data:`TRIALS`, 24).
        replicates: perturbed replicates per design and gain setting (an
            int >= 2); None (the default) for the profile's ``replicates``.
        seed: the tuning samplers' seed (an int; default 0); the
            replicates' seeds are 0 .. replicates - 1.
        cache_dir: the runner's cache folder; None (the default) for the
            runner's default ($MAT_HOPPER_CACHE, else results/cache).
        workers: the runner's local processes; None (the default) for all
            cores.
        baseline: the design compared against (default ``MD``); must be one
            of `designs` (by name).

    Returns:
        A dict: ``gains`` (DataFrame, one row per design: design, the three
        best gains, score, and ``tracking_error_m`` (m) and ``power_w`` (W)
        at the authors' and at the own gains), ``hops`` (the runner's
        per-hop table, with labels experiment, profile, design, replicate),
        ``comparison`` (:func:`compare_replicates`'s table on
        tracking_error_m and power_w), ``tunings`` ({design name: Tuning}),
        ``survival`` (:func:`survival`'s table) and ``answer`` (str,
        :func:`answer`).

    Raises:
        ValueError: `replicates` not an integer >= 2, `trials` not one >= 1,
            `seed` not an integer, a baseline not among the designs, an unknown
            design name, profile or behaviour (all before any run), or :func:`tune`'s.
        RuntimeError: a comparison run failed, or :func:`tune`'s.
    """
    profile = resolve_profile(profile)
    n = profile.replicates if replicates is None else _check_int(replicates, "replicates")
    if n < 2:
        raise ValueError(f"comparing materials needs at least 2 replicates, got {n}")
    _check_int(trials, "trials", 1)  # tune's checks, before any runner or run
    _check_int(seed, "seed")
    legs = {d if isinstance(d, str) else d.name: parse_design(d) if isinstance(d, str) else d for d in designs}
    if baseline not in legs:
        raise ValueError(f"baseline {baseline!r} must be one of the designs ({', '.join(legs)})")
    beh = get_behaviour(behaviour)
    with Runner(cache_dir, workers=workers, progress=False) as runner:
        tunings = {
            name: tune(leg, profile=profile, behaviour=behaviour, trials=trials, seed=seed, runner=runner)
            for name, leg in legs.items()
        }
        tasks = comparison_tasks(legs, profile, beh, n, {name: t.gains for name, t in tunings.items()})
        res = runner.run(tasks, desc="materials at their own gains")
    if res.n_failed:
        raise RuntimeError(f"{res.n_failed} comparison run(s) failed")
    hops = res.tables
    comparison = compare_replicates(hops, baseline, metrics=("tracking_error_m", "power_w"))
    gains = pd.DataFrame(
        [
            {
                "design": name,
                **{k: t.gains[k] for k in GAIN_BOUNDS},
                "score": t.score,
                "tracking_error_m (authors' gains)": t.default["tracking_error_m"],
                "tracking_error_m (own gains)": t.best["tracking_error_m"],
                "power_w (authors' gains)": t.default["power_w"],
                "power_w (own gains)": t.best["power_w"],
            }
            for name, t in tunings.items()
        ]
    )
    out = {"gains": gains, "hops": hops, "comparison": comparison, "tunings": tunings}
    out["survival"] = survival(comparison)
    out["answer"] = answer(out["survival"], hops, baseline)
    return out


def survival(comparison: pd.DataFrame) -> pd.DataFrame:
    """One row per design and metric: percent change against the baseline
    with its interval at the authors' and at the design's own gains, and
    whether the difference is clear at each and survives (module doc).

    Args:
        comparison: :func:`compare_replicates`'s table from :func:`codesign`:
            columns experiment (``authors' gains`` or ``own gains``), design,
            metric, pct_change, ci_low and ci_high (%); the first row of each
            (experiment, design, metric) is read.

    Returns:
        A pandas DataFrame, one row per (design, metric) at the authors'
        gains: design, metric, ``change (%) authors``, ``ci_low (%)
        authors``, ``ci_high (%) authors``, ``clear authors`` (bool: the
        interval excludes zero), the same four for ``own``, and
        ``survives`` (bool: clear at the authors' gains, and clear with the
        same sign at the own gains).

    Raises:
        KeyError: `comparison` lacks the authors' gains, or the own gains'
            row of a design and metric it has at the authors' gains.
    """
    rows = []
    c = comparison.set_index(["experiment", "design", "metric"])
    for design, metric in c.loc[DEFAULT].index.unique():
        row = {"design": design, "metric": metric}
        clear = {}
        for setting in (DEFAULT, TUNED):
            r = c.loc[(setting, design, metric)]
            r = r.iloc[0] if isinstance(r, pd.DataFrame) else r
            tag = "authors" if setting == DEFAULT else "own"
            row[f"change (%) {tag}"] = r["pct_change"]
            row[f"ci_low (%) {tag}"] = r["ci_low"]
            row[f"ci_high (%) {tag}"] = r["ci_high"]
            lo, hi = r["ci_low"], r["ci_high"]
            clear[setting] = 1 if lo > 0 else -1 if hi < 0 else 0
            row[f"clear {tag}"] = clear[setting] != 0
        row["survives"] = clear[DEFAULT] != 0 and clear[DEFAULT] == clear[TUNED]
        rows.append(row)
    return pd.DataFrame(rows)


def spread(hops: pd.DataFrame, metric: str = "tracking_error_m") -> dict:
    """{gain setting: (max - min) / min of the designs' means of replicate
    means}: how far apart the materials are.

    Args:
        hops: a per-hop table with columns experiment (the gain setting),
            design, replicate and `metric`.
        metric: the metric column (default ``tracking_error_m``).

    Returns:
        {gain setting: spread}, the spread a float ratio (0.25 is 25 %),
        in the order pandas groups the settings.
    """
    out = {}
    for setting, g in hops.groupby("experiment"):
        m = g.groupby(["design", "replicate"])[metric].mean().groupby("design").mean()
        out[setting] = float((m.max() - m.min()) / m.min())
    return out


def answer(surv: pd.DataFrame, hops: pd.DataFrame, baseline: str = BASELINE) -> str:
    """The chapter's plain answer from the survival table and the spread.

    Args:
        surv: :func:`survival`'s table.
        hops: the per-hop table (:func:`spread` of its tracking error, at
            each gain setting).
        baseline: the baseline's name, as the text names it (default ``MD``).

    Returns:
        A paragraph (str): how many of the clear differences at the
        authors' gains survive, the spread of tracking error (%) at both
        gain settings (nan where a setting is missing), then the verdict.
    """
    clear = surv[surv["clear authors"]]
    kept = clear[clear["survives"]]
    sp = spread(hops)
    head = (
        f"{len(kept)} of {len(clear)} clear material differences against {baseline} "
        f"(95 % intervals clear of zero at the authors' gains) keep their sign and stay clear at each "
        f"material's own gains. The spread of tracking error across the materials is "
        f"{100 * sp.get(DEFAULT, math.nan):.0f} % at the authors' gains and "
        f"{100 * sp.get(TUNED, math.nan):.0f} % at their own."
    )
    if len(clear) == 0:
        return head + " No material differs clearly at the authors' gains, so there is nothing for control to erase."
    if len(kept) == len(clear):
        verdict = " Control does not erase material: every clear difference survives tuning."
    elif len(kept) == 0:
        verdict = " Control erases material: no clear difference survives tuning."
    else:
        lost = ", ".join(f"{r.design} {r.metric}" for r in clear[~clear["survives"]].itertuples())
        verdict = f" Control erases some of it: {lost} no longer differ clearly."
    return head + verdict
