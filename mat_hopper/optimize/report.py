"""A study's outputs: tables, Pareto front, hypervolume, importances, replay.

``mat-hopper optimize --report NAME`` writes into ``STUDIES_DIR/NAME-report``
(or ``--out``):

- ``trials.csv``: one row per trial (state, feasibility, objectives, hop
  height, constraint values, per-segment density g/cm^3 and modulus GPa,
  parameters, worker, error), ordered by trial number;
- ``pareto.csv``: the non-dominated feasible designs, with the percent
  change of each objective against the paper's SS and rho-inc
  (the study's own runs of them, or, when its space cannot express them,
  runs made here with the study's settings and kept in the study);
- ``pareto.png``: the second objective against the first (with three
  objectives, one panel per pair), feasible, infeasible, the Pareto front
  and the paper's designs marked;
- ``hypervolume.csv`` / ``.png``: hypervolume of the feasible front after
  each trial, against a reference point 10 % beyond the worst feasible
  value of each objective (every objective minimized; any number of them,
  :func:`hypervolume`);
- ``importances.csv`` / ``.png``: Optuna's parameter importances
  (PED-ANOVA) for each objective.

``--replay TRIAL`` rebuilds the trial's design from its parameters and
simulates it again with the study's settings (bit-identical to the stored
values, by the determinism of the simulator); with ``--render`` it also
renders it (:func:`mat_hopper.viz.render.render_files`).

The objectives are the study's (``Objective.objectives``, default tracking
error and hip power; :mod:`mat_hopper.physics.run_metrics`). The Pareto
front is Optuna's ``study.best_trials``; the hypervolume and importance
plots are ``optuna.visualization.matplotlib``'s (n objectives). The Pareto
plot is ours: Optuna's cannot mark the paper's designs and baselines.
"""

from __future__ import annotations

import os
import re
import warnings

import numpy as np
import optuna
import pandas as pd
from optuna.trial import TrialState

from ..core.materials import LegDesign, paper_designs
from ..physics.run_metrics import METRICS
from ..util.atomic import write_csv
from ..util.change import percent_change
from ..viz import study as study_plots
from ..viz.style import save_figure
from ._objective import OBJECTIVES, RESULT_ATTR, Objective, evaluate
from ._scoring import SE_ATTR, leg_mass_kg
from ._space import resample
from ._storage import ERROR_ATTR, FAIL_REASON_ATTR, PAPER_ATTR, WORKER_ATTR
from ._study import CONFIG_ATTR, RunOptions, StudyConfig, _quiet, load_existing

BASELINES = ("SS", "rho-inc")
HV_MARGIN = 0.1


def load(name: str, storage) -> tuple[optuna.Study, StudyConfig]:
    """A study of ours and the config it was created with (Optuna's logging
    set to warnings only).

    Args:
        name: the study's name.
        storage: an Optuna storage or a storage URL (as
            ``optuna.load_study`` takes it).

    Returns:
        (the ``optuna.Study``, its :class:`StudyConfig`, rebuilt from the
        study's user attr ``mat_hopper_config``).

    Raises:
        ValueError: no study named `name` in `storage` (the message lists
            the studies present), or the study has no ``mat_hopper_config``
            (not made by ``mat-hopper optimize``).
    """
    _quiet()
    study = load_existing(name, storage)
    key = study.user_attrs.get(CONFIG_ATTR)
    if not key:
        raise ValueError(f"study {name!r} was not made by mat-hopper optimize (no {CONFIG_ATTR})")
    return study, StudyConfig.from_key(name, key)


# --- tables -----------------------------------------------------------------


def trials_frame(study: optuna.Study, config: StudyConfig) -> pd.DataFrame:
    """One row per trial (see module doc), queued trials not yet run (WAITING)
    left out. No wall-clock columns.

    Args:
        study: an ``optuna.Study`` of ours.
        config: its :class:`StudyConfig`.

    Returns:
        The trials table, columns as the module doc lists them (units in the names).
    """
    rows = []
    space, objectives = config.space, config.objective.objectives
    states = tuple(s for s in TrialState if s != TrialState.WAITING)
    for t in sorted(study.get_trials(deepcopy=False, states=states), key=lambda t: t.number):
        ua = t.user_attrs
        res = ua.get(RESULT_ATTR) or {}
        row = {
            "trial": t.number,
            "state": t.state.name,
            "paper_design": ua.get(PAPER_ATTR, ""),
            "design": res.get("design", ""),
            "feasible": bool(res.get("feasible", False)),
            **dict.fromkeys(objectives, np.nan),
            "hop_height_m": res.get("hop_height_m") if res.get("hop_height_m") is not None else np.nan,
            "total_mass_kg": res.get("total_mass_kg", np.nan),
            "leg_mass_kg": np.nan,
        }
        if t.state == TrialState.COMPLETE and t.values is not None:
            row.update(dict(zip(objectives, t.values)))
        se = ua.get(SE_ATTR) or {}
        row.update({f"{o}_se": np.nan if se.get(o) is None else se[o] for o in objectives})
        c = t.constraints
        row.update({f"constraint_{n}": c.get(n, np.nan) for n in config.objective.constraint_names})
        try:
            design = space.design(t.params)
            row["leg_mass_kg"] = leg_mass_kg(design, config.objective.segment_mass)  # the objective's too
            for i, m in enumerate(design.segments, 1):
                row[f"seg{i}_rho_g_cm3"] = m.density_g_cm3
                row[f"seg{i}_e_gpa"] = m.modulus_gpa
            if not row["design"]:
                row["design"] = design.name
        except ValueError:
            pass  # a trial that never got its parameters
        row.update({f"param_{k}": v for k, v in sorted(t.params.items())})
        w = ua.get(WORKER_ATTR) or {}
        row["worker"] = f"{w.get('host', '')}:{w.get('pid', '')}" if w else ""
        row["error"] = ua.get(ERROR_ATTR, "") or ua.get(FAIL_REASON_ATTR, "")
        row["retry_of"] = t.system_attrs.get("failed_trial", np.nan)
        rows.append(row)
    return pd.DataFrame(rows)


def feasible_complete(frame: pd.DataFrame) -> pd.DataFrame:
    """The rows of a trials table that are complete and feasible.

    Args:
        frame: :func:`trials_frame`'s table (columns ``state`` and
            ``feasible`` at least, unless empty).

    Returns:
        The rows with state ``COMPLETE`` and a true ``feasible``, index
        kept; `frame` itself when it is empty.
    """
    if frame.empty:
        return frame
    return frame[(frame["state"] == "COMPLETE") & frame["feasible"].astype(bool)]


def pareto_frame(
    frame: pd.DataFrame, baselines: dict | None = None, *, best=None, objectives=OBJECTIVES
) -> pd.DataFrame:
    """The Pareto front, by its first objective. Of trials with identical
    objective values (a design evaluated twice, e.g. a retried trial) the
    first is kept: Optuna lists every copy.

    Args:
        frame: :func:`trials_frame`'s table.
        baselines: {name: objective values in `objectives` order} to compare against, or None.
        best: the front's trial numbers, from Optuna's ``study.best_trials``
            (complete, feasible, non-dominated).
        objectives: the study's objectives (``Objective.objectives``).

    Returns:
        The front's rows, with percent changes against each baseline
        (``<stem>_vs_<name>_pct``, the stem the metric's name without its
        unit: ``tracking_error_vs_SS_pct``).
    """
    objectives = tuple(objectives)
    ok = feasible_complete(frame)
    if ok.empty or not best:
        return ok.iloc[0:0].copy()
    front = ok[ok["trial"].isin(set(best))].sort_values("trial")
    front = front.drop_duplicates(subset=list(objectives), keep="first")
    front = front.sort_values(objectives[0], kind="stable").copy()
    for name, vals in (baselines or {}).items():
        for obj, base in zip(objectives, vals):
            front[f"{METRICS[obj].stem}_vs_{name}_pct"] = percent_change(front[obj].to_numpy(float), base)
    cols = ["trial", "design", "paper_design", *objectives, *(f"{o}_se" for o in objectives), "hop_height_m"]
    cols = list(dict.fromkeys(c for c in cols + ["leg_mass_kg"] if c in front.columns))  # an older table may lack some
    cols += [c for c in front.columns if c.endswith("_pct")]
    cols += [c for c in front.columns if c.startswith("seg") and c not in cols]
    return front[cols].reset_index(drop=True)


def hypervolume(points, reference) -> float:
    """Volume dominated by `points` (n x d, every objective minimized) and
    bounded by `reference` (d values), exact, for any d >= 1.

    Ours because Optuna's public API only plots the hypervolume history
    (``optuna.visualization.matplotlib.plot_hypervolume_history``, used for
    the figure; its computation is private) and no hypervolume package is
    installed. Slicing (Zitzler's HSO): sort by the last objective; between
    one point's value and the next, the dominated region's cross-section is
    the (d - 1)-dimensional hypervolume of the points seen so far. d = 2 is
    the usual staircase sweep. Cost O(n^(d-1) log n): fronts of tens of
    points in 2 or 3 objectives take milliseconds.

    Args:
        points: (n, d) array-like (n may be 0).
        reference: (d,) the bounding point; points not strictly below it in
            every objective add nothing.

    Returns:
        float, in the product of the objectives' units.
    """
    r = np.asarray(reference, float).ravel()
    p = np.asarray(points, float).reshape(-1, len(r))
    p = p[np.all(p < r, axis=1)]
    if len(p) == 0:
        return 0.0
    if len(r) == 1:
        return float(r[0] - p[:, 0].min())
    if len(r) == 2:  # staircase: by x, add each point's strip below the best y so far
        p = p[np.lexsort((p[:, 1], p[:, 0]))]
        area, best_y = 0.0, r[1]
        for x, y in p:
            if y < best_y:
                area += (r[0] - x) * (best_y - y)
                best_y = y
        return float(area)
    p = p[np.argsort(p[:, -1], kind="stable")]
    volume = 0.0
    for i in range(len(p)):  # the slab from this point's last value to the next one's (or the reference)
        top = p[i + 1, -1] if i + 1 < len(p) else r[-1]
        if top > p[i, -1]:
            volume += hypervolume(p[: i + 1, :-1], r[:-1]) * (top - p[i, -1])
    return float(volume)


def hypervolume_2d(points: np.ndarray, reference) -> float:
    """:func:`hypervolume` in two objectives.

    Args:
        points: (n, 2) minimized objective values.
        reference: (2,) the bounding point.

    Returns:
        The area dominated by `points` and bounded by `reference`.
    """
    return hypervolume(np.asarray(points, float).reshape(-1, 2), reference)


def hypervolume_history(frame: pd.DataFrame, reference=None, objectives=OBJECTIVES) -> tuple[pd.DataFrame, tuple]:
    """Hypervolume of the feasible complete trials up to each trial number.

    Args:
        frame: :func:`trials_frame`'s table.
        reference: the reference point (None: the worst feasible value of
            each objective plus HV_MARGIN of its range).
        objectives: the study's objectives (the table's columns used).

    Returns:
        (a table of trial, hypervolume; the reference point as a tuple, ()
        without a feasible trial).
    """
    ok = feasible_complete(frame)
    if ok.empty:
        return pd.DataFrame(columns=["trial", "hypervolume"]), ()
    vals = ok[list(objectives)].to_numpy(float)
    if reference is None:
        lo, hi = vals.min(axis=0), vals.max(axis=0)
        span = np.where(hi > lo, hi - lo, np.maximum(np.abs(hi), 1e-12))
        reference = tuple(float(v) for v in hi + HV_MARGIN * span)
    trials = frame.sort_values("trial")["trial"].to_numpy()
    ok_trials = ok["trial"].to_numpy()
    out = []
    for n in trials:
        out.append({"trial": int(n), "hypervolume": hypervolume(vals[ok_trials <= n], reference)})
    return pd.DataFrame(out), tuple(reference)


MIN_SAMPLED_TRIALS = 4  # sampled (not enqueued) finished trials before importances mean anything


def enough_for_importances(study: optuna.Study) -> bool:
    """Whether the study has MIN_SAMPLED_TRIALS finished trials its sampler
    chose: the enqueued paper designs (user attr ``paper_design``, up to 8
    of them) say nothing about which parameter matters, so a study that
    has run only those (e.g. ``--trials 6``) gets no importances.

    Args:
        study: an ``optuna.Study``.

    Returns:
        True when at least MIN_SAMPLED_TRIALS (4) of its COMPLETE trials
        have no (or an empty) ``paper_design`` user attr.
    """
    complete = study.get_trials(deepcopy=False, states=(TrialState.COMPLETE,))
    return sum(1 for t in complete if not t.user_attrs.get("paper_design")) >= MIN_SAMPLED_TRIALS


def importances(study: optuna.Study) -> pd.DataFrame:
    """Parameter importances (Optuna's default, PED-ANOVA) per objective;
    empty until the sampler has chosen MIN_SAMPLED_TRIALS finished trials.

    Args:
        study: an ``optuna.Study`` of ours; its ``metric_names`` (else the
            default objectives) name the objectives, in order.

    Returns:
        A pandas DataFrame with columns ``objective``, ``param`` and
        ``importance`` (float), one row per objective and parameter in
        Optuna's order; an objective whose importances Optuna cannot
        compute (ValueError, RuntimeError or ZeroDivisionError) is left out,
        and the table is empty (with these columns) when
        :func:`enough_for_importances` is False.
    """
    rows = []
    if not enough_for_importances(study):
        return pd.DataFrame(columns=["objective", "param", "importance"])
    for i, obj in enumerate(study.metric_names or OBJECTIVES):
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                imp = optuna.importance.get_param_importances(study, target=lambda t, i=i: t.values[i])
        except (ValueError, RuntimeError, ZeroDivisionError):
            continue
        rows += [{"objective": obj, "param": k, "importance": float(v)} for k, v in imp.items()]
    return pd.DataFrame(rows, columns=["objective", "param", "importance"])


def baselines(study: optuna.Study, config: StudyConfig, frame: pd.DataFrame) -> dict:
    """The objective values (the study's objectives, in order) of SS and
    rho-inc under the study's settings: its enqueued run, or a run made now
    and kept in the study.

    Args:
        study: the ``optuna.Study``; a run made now is stored in its user
            attr ``baseline:<name>``, and read from there on later calls.
        config: its :class:`StudyConfig`.
        frame: :func:`trials_frame`'s table: the first COMPLETE row whose
            ``paper_design`` is the baseline's name gives its values.

    Returns:
        {``"SS"``: values, ``"rho-inc"``: values}, each a tuple of floats
        in the order of ``config.objective.objectives`` (their units). A
        baseline neither in `frame` nor in the study's user attrs is
        resampled to the study's number of segments and evaluated now
        (:func:`~mat_hopper.optimize._objective.evaluate`).
    """
    out, objectives = {}, config.objective.objectives
    for name in BASELINES:
        rows = frame[(frame["paper_design"] == name) & (frame["state"] == "COMPLETE")] if not frame.empty else frame
        if len(rows):
            out[name] = tuple(float(rows.iloc[0][o]) for o in objectives)
            continue
        key = f"baseline:{name}"
        if key in study.user_attrs:
            out[name] = tuple(study.user_attrs[key])
            continue
        design = LegDesign(resample(paper_designs()[name], config.space.n_segments), name=name)
        ev = evaluate(design, config.objective)
        study.set_user_attr(key, list(ev.values))
        out[name] = ev.values
    return out


# --- the report -------------------------------------------------------------


def write_report(name: str, storage, out_dir: str) -> dict:
    """Every output of the module doc, written into `out_dir`.

    Args:
        name: the study's name.
        storage: its Optuna storage.
        out_dir: the folder (made if needed).

    Returns:
        {output name: path} and the tables (trials, pareto, baselines, ...).

    Raises:
        ValueError: no such study or not ours.
    """
    study, config = load(name, storage)
    os.makedirs(out_dir, exist_ok=True)
    objectives = config.objective.objectives
    frame = trials_frame(study, config)
    base = baselines(study, config, frame)
    front = pareto_frame(frame, base, best=[t.number for t in study.best_trials], objectives=objectives)
    hv, ref_point = hypervolume_history(frame, objectives=objectives)
    imp = importances(study)
    paths = {
        k: os.path.join(out_dir, f)
        for k, f in (
            ("trials", "trials.csv"),
            ("pareto", "pareto.csv"),
            ("pareto_plot", "pareto.png"),
            ("hypervolume", "hypervolume.csv"),
            ("hypervolume_plot", "hypervolume.png"),
            ("importances", "importances.csv"),
            ("importances_plot", "importances.png"),
        )
    }
    write_csv(frame, paths["trials"])
    write_csv(front, paths["pareto"])
    write_csv(hv, paths["hypervolume"])
    write_csv(imp, paths["importances"])
    beh = ",".join(config.objective.behaviours)
    what = f"{name}: {beh}, {config.objective.profile.name} profile, {config.space.n_segments} segments"
    axes = [(o, METRICS[o].axis_label) for o in objectives]
    fig = study_plots.pareto_figure(frame, front, base, what, axes=axes)
    save_figure(fig, paths["pareto_plot"], formats=("png",), dpi=130)
    ref_text = ", ".join(f"{v:.4g}" for v in ref_point)
    unit = " ".join(METRICS[o].unit for o in objectives if METRICS[o].unit != "1") or "1"
    save_figure(
        study_plots.hypervolume_figure(study, ref_point, f"{what}\nreference point ({ref_text})", unit=unit),
        paths["hypervolume_plot"],
        formats=("png",),
        dpi=130,
    )
    note = (
        None
        if enough_for_importances(study)
        else f"no importances: fewer than {MIN_SAMPLED_TRIALS} finished trials chosen by the sampler\n"
        "(the enqueued paper designs are not samples)"
    )
    fig = study_plots.importances_figure(study, what, note=note)
    save_figure(fig, paths["importances_plot"], formats=("png",), dpi=130)
    return {
        "paths": paths,
        "trials": frame,
        "pareto": front,
        "hypervolume": hv,
        "importances": imp,
        "baselines": base,
        "reference": ref_point,
    }


def replay(name: str, storage, number: int):
    """Replay one trial of a study: its design simulated afresh.

    Args:
        name: the study's name.
        storage: its Optuna storage (:func:`open_storage`).
        number: the trial's number.

    Returns:
        (the FrozenTrial, its LegDesign, a fresh :class:`Evaluation`, the study's
        :class:`StudyConfig`): compare the fresh values with the stored ones.

    Raises:
        ValueError: no such study, not ours, or no such trial.
    """
    t, design, config = trial_design(name, storage, number)
    return t, design, evaluate(design, config.objective), config


def trial_design(name: str, storage, number: int):
    """(FrozenTrial, LegDesign, StudyConfig) of trial `number` of study
    `name` (its design named ``name#number``), for :func:`replay` and
    ``optimize --export``.

    Args:
        name: the study's name.
        storage: its Optuna storage or storage URL.
        number: the trial's number.

    Returns:
        (the trial as an Optuna ``FrozenTrial``, the LegDesign its
        parameters describe in the study's space, the study's
        :class:`StudyConfig`).

    Raises:
        ValueError: no such study (the message lists the studies present),
            not ours, no such trial, a trial that has not run yet (queued,
            or running before its design is drawn: its state named), or a
            trial without the space's parameters.
    """
    study, config = load(name, storage)
    trials = [t for t in study.get_trials(deepcopy=False) if t.number == number]
    if not trials:
        raise ValueError(f"study {name!r} has no trial {number} (trials 0..{len(study.trials) - 1})")
    t = trials[0]
    if not t.params and t.state in (TrialState.WAITING, TrialState.RUNNING):  # queued, or not yet suggested
        what = "queued" if t.state == TrialState.WAITING else "started but its design not yet drawn"
        raise ValueError(
            f"study {name!r}: trial {number} has not run yet (state {t.state.name}: {what}); it has no design "
            "to replay or export"
        )
    return t, config.space.design(t.params, name=f"{name}#{number}"), config


# --- the book's study ----------------------------------------------------------


STUDY_TRIALS = {"paper": 200, "quick": 32}  # trials of the book's own study, per profile
STUDY_BATCH = 8  # trials asked before the first is told (one grid of runs)
STUDY_SAMPLER = "tpe"  # the best of benchmarks/sampler.py's side-by-side comparison
STUDY_BEHAVIOURS = ("ramp",)
# Chapter 9's study keeps one unperturbed run per trial until the chapter is
# rewritten around noise-aware scores and racing (issue #22, items 2 and 9):
# its text, figures and runtime budget describe single draws.
STUDY_REPLICATES = 0


def book_study(
    profile=None,
    *,
    studies_dir="studies",
    out_dir="results/study",
    trials: int | None = None,
    behaviours=STUDY_BEHAVIOURS,
    seed: int = 0,
    ashby_classes=(),
    sampler: str = STUDY_SAMPLER,
    batch: int = STUDY_BATCH,
    cache_dir=None,
    workers: int | None = None,
    objectives=OBJECTIVES,
) -> dict:
    """Run (or resume, or just load) the book's design study, then write its report.

    The study (:func:`mat_hopper.optimize.run_study`): continuous
    density and modulus per segment (3 segments; in the hulls of
    `ashby_classes` when given), `objectives` (tracking error and hip power) on `behaviours`
    under the profile, the paper's nine designs first (the rigid MD as a
    baseline run), in batches through the runner's cache and pool, so the
    study is the same on any machine. Its name carries a digest of the
    settings, sampler, seed and batch, so changed settings start a new study
    instead of clashing with an old one.

    Args:
        profile: a Profile or its name (None: $MAT_HOPPER_PROFILE, else paper).
        studies_dir: the folder of ``<name>.db``.
        out_dir: where :func:`write_report` writes.
        trials: the study's size (None: :data:`STUDY_TRIALS` of the profile).
        behaviours: behaviour names.
        seed: the sampler's seed.
        ashby_classes: material classes whose hulls bound the search.
        sampler: an Optuna sampler's name.
        batch: trials per batch.
        cache_dir, workers: the runner's cache folder and processes.
        objectives: the metrics minimized (default tracking error and hip
            power, whose study names are unchanged by the setting).

    Returns:
        The report dict (``trials``, ``pareto``, ``baselines``, ``hypervolume``,
        ``importances``, ``paths``) plus ``name``, ``url`` and ``config``.

    Raises:
        ValueError: bad settings (naming them), before any run.
    """
    import hashlib
    import json

    from ..experiments.profiles import get_profile
    from ._driver import run_study
    from ._space import SearchSpace
    from ._storage import default_url

    profile = get_profile(profile)
    n = STUDY_TRIALS.get(profile.name, STUDY_TRIALS["quick"]) if trials is None else int(trials)
    objective = Objective(
        behaviours=tuple(behaviours), profile=profile, replicates=STUDY_REPLICATES, objectives=objectives
    )
    space = SearchSpace(ashby_classes=ashby_classes)
    probe = StudyConfig("probe", space, objective)
    run_key = {"config": probe.key(), "sampler": sampler, "seed": seed, "batch": batch}
    digest = hashlib.sha256(json.dumps(run_key, sort_keys=True).encode()).hexdigest()[:8]
    classes = f"-{'-'.join(space.ashby_classes)}" if space.ashby_classes else ""
    config = StudyConfig(f"book-{'-'.join(objective.behaviours)}-{profile.name}{classes}-{digest}", space, objective)
    os.makedirs(studies_dir, exist_ok=True)
    url = default_url(config.name, str(studies_dir))
    options = RunOptions(
        trials=n,
        workers=workers,
        sampler=sampler,
        seed=seed,
        storage=url,
        progress=False,
        batch_size=batch,
        cache_dir=None if cache_dir is None else str(cache_dir),
    )
    run_study(config, options)
    report = write_report(config.name, url, str(out_dir))
    report.update(name=config.name, url=url, config=config)
    return report


def front_table(front: pd.DataFrame, objectives=None) -> pd.DataFrame:
    """A Pareto table for the page: a design a reader can build
    (``mat-hopper optimize --export TRIAL`` writes it).

    Args:
        front: :func:`pareto_frame`'s table.
        objectives: the study's objectives (None: those whose standard-error
            column the table has, else tracking error and hip power).

    Returns:
        trial, the paper's design it is (if any), each objective in its
        display unit (tracking error mm, hip power mW, peak stress MPa, ...),
        their standard errors (a noise-aware study's), hop height (m), the
        percent changes against the baselines, the leg's mass (kg) and each
        segment's density (g/cm^3) and modulus (GPa), base to foot, with
        short column names.
    """
    if objectives is None:
        objectives = tuple(m for m in METRICS if f"{m}_se" in front.columns) or OBJECTIVES
    metrics = [METRICS[o] for o in objectives]
    out = pd.DataFrame({"trial": front["trial"].astype(int)})
    out["paper design"] = front.get("paper_design", pd.Series([""] * len(front))).fillna("").to_numpy()
    for m in metrics:
        out[f"{m.label} ({m.display_unit})"] = front[m.name] * m.display_scale
    for m in metrics:  # a noise-aware study's standard errors
        col = f"{m.name}_se"
        if m.noisy and col in front.columns and front[col].notna().any():
            out[f"{m.short} SE ({m.display_unit})"] = front[col] * m.display_scale
    out["hop height (m)"] = front["hop_height_m"]
    shorts = {m.stem: m.short for m in METRICS.values()}
    for col in front.columns:
        hit = re.fullmatch(r"(.+)_vs_(.+)_pct", col)
        if hit and hit.group(1) in shorts:
            out[f"{shorts[hit.group(1)]} vs {hit.group(2)} (%)"] = front[col]
    out["leg mass (kg)"] = front["leg_mass_kg"] if "leg_mass_kg" in front.columns else np.nan
    i = 1
    while f"seg{i}_rho_g_cm3" in front.columns:
        out[f"seg {i} density (g/cm^3)"] = front[f"seg{i}_rho_g_cm3"]
        out[f"seg {i} modulus (GPa)"] = front[f"seg{i}_e_gpa"]
        i += 1
    return out.reset_index(drop=True)


def front_designs(front: pd.DataFrame, k: int | None = None, *, skip_paper: bool = True) -> dict[str, LegDesign]:
    """The designs of a Pareto table, for :func:`mat_hopper.viz.maps.designs_figure`.

    Args:
        front: a table with ``seg{i}_rho_g_cm3`` and ``seg{i}_e_gpa`` columns.
        k: at most this many, by tracking error (None: all).
        skip_paper: leave out the paper's own designs (a non-empty ``paper_design``).

    Returns:
        {"#<trial>": LegDesign}.
    """
    rows = front.sort_values("tracking_error_m") if "tracking_error_m" in front.columns else front
    if skip_paper and "paper_design" in rows.columns:
        rows = rows[rows["paper_design"].fillna("").astype(str) == ""]
    if k is not None:
        rows = rows.head(int(k))
    out = {}
    for r in rows.to_dict("records"):
        i, dens, mods = 1, [], []
        while f"seg{i}_rho_g_cm3" in r and pd.notna(r[f"seg{i}_rho_g_cm3"]):
            dens.append(float(r[f"seg{i}_rho_g_cm3"]))
            e = r.get(f"seg{i}_e_gpa")
            mods.append(None if e is None or pd.isna(e) else float(e))
            i += 1
        if not dens:
            raise ValueError("front_designs: the table has no seg1_rho_g_cm3 column")
        name = f"#{int(r['trial'])}" if "trial" in r else f"design {len(out) + 1}"
        out[name] = LegDesign.from_properties(dens, mods, name=name)
    return out
