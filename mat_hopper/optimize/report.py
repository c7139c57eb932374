"""A study's outputs: tables, Pareto front, hypervolume, importances, replay.

``mat-hopper optimize --report NAME`` writes into ``STUDIES_DIR/NAME-report``
(or ``--out``):

- ``trials.csv``: one row per trial (state, feasibility, objectives, hop
  height, constraint values, per-segment density g/cm^3 and modulus GPa,
  parameters, worker, error), ordered by trial number;
- ``pareto.csv``: the non-dominated feasible designs, with the percent
  change of each objective against the paper's SS and rho-inc
  (the study's own runs of them, or, when its space cannot express them,
  runs made here with the study's settings and kept in the study); a
  baseline whose runs fell or diverged, or (in a study held to a leg
  mass) whose leg lies outside the study's band, is left out, and the
  report says why (:func:`baseline_runs`);
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
import warnings

import optuna
import pandas as pd
from optuna.trial import TrialState

from ..core.materials import LegDesign, paper_designs
from ..physics.run_metrics import METRICS
from ..util.atomic import write_csv
from ..viz import study as study_plots
from ..viz.style import save_figure
from ._feasibility import fall_reason, feasibility
from ._hypervolume import HV_MARGIN, hypervolume, hypervolume_2d, hypervolume_history
from ._objective import OBJECTIVES, RESULT_ATTR, evaluate
from ._report_tables import feasible_complete, front_designs, front_table, pareto_frame, trials_frame
from ._scoring import leg_mass_band_kg, leg_mass_kg
from ._space import resample
from ._storage import PAPER_ATTR
from ._study import CONFIG_ATTR, StudyConfig, _quiet, load_existing

__all__ = [
    "BASELINES",
    "HV_MARGIN",
    "baseline_runs",
    "missing_baselines",
    "MIN_SAMPLED_TRIALS",
    "baselines",
    "enough_for_importances",
    "feasible_complete",
    "front_designs",
    "front_table",
    "hypervolume",
    "hypervolume_2d",
    "hypervolume_history",
    "importances",
    "load",
    "pareto_frame",
    "replay",
    "trial_design",
    "trials_frame",
    "write_report",
]

BASELINES = ("SS", "rho-inc")


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


def _scored_study(study: optuna.Study) -> optuna.Study:
    """An in-memory copy of `study`'s COMPLETE trials whose runs did not
    diverge: those whose values say something about their parameters."""
    out = optuna.create_study(directions=study.directions)
    out.add_trials(
        t
        for t in study.get_trials(deepcopy=False, states=(TrialState.COMPLETE,))
        if not (fall_reason((t.user_attrs.get(RESULT_ATTR) or {}).get("per_behaviour")) or "").startswith("diverged")
    )
    return out


def importances(study: optuna.Study) -> pd.DataFrame:
    """Parameter importances (Optuna's default, PED-ANOVA) per objective,
    over the finished trials whose runs did not diverge; empty until the sampler has chosen MIN_SAMPLED_TRIALS finished trials.

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
    scored = _scored_study(study)  # a diverged trial's values are whole-run means of runs cut short
    if not enough_for_importances(scored):
        return pd.DataFrame(columns=["objective", "param", "importance"])
    for i, obj in enumerate(study.metric_names or OBJECTIVES):
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                imp = optuna.importance.get_param_importances(scored, target=lambda t, i=i: t.values[i])
        except (ValueError, RuntimeError, ZeroDivisionError):
            continue
        rows += [{"objective": obj, "param": k, "importance": float(v)} for k, v in imp.items()]
    return pd.DataFrame(rows, columns=["objective", "param", "importance"])


def baseline_runs(study: optuna.Study, config: StudyConfig, frame: pd.DataFrame) -> tuple[dict, dict]:
    """SS and rho-inc under the study's settings, as comparators: the
    objective values of those whose runs stood, and why the others are
    left out. A run that fell or diverged is no baseline: its values are
    the whole-run means of a run that did not hop to its end (a leg that
    diverged at t = 0.004 s has a tracking error of 3 mm), and a percent
    change against them says nothing.

    Args:
        study: the ``optuna.Study``; a run made now is stored in its user
            attr ``baseline:<name>`` ({"values", "left_out"}), and read from
            there on later calls.
        config: its :class:`StudyConfig`.
        frame: :func:`trials_frame`'s table: the first COMPLETE row whose
            ``paper_design`` is the baseline's name is its run.

    Returns:
        ({name: values}, {name: reason}): the values a tuple of floats in
        the order of ``config.objective.objectives`` (their units); the
        reason as :func:`~mat_hopper.optimize._feasibility.fall_reason`
        gives it (``diverged at t = 0.0043 s (ramp)``). A baseline neither
        in `frame` nor stored (in this form) is resampled to the study's
        number of segments and evaluated now
        (:func:`~mat_hopper.optimize._objective.evaluate`).
    """
    values, left_out, objectives = {}, {}, config.objective.objectives
    for name in BASELINES:
        off_band = _outside_band(name, config)
        if off_band:  # a study held to a leg mass is compared with legs of that mass only
            left_out[name] = off_band
            continue
        rows = frame[(frame["paper_design"] == name) & (frame["state"] == "COMPLETE")] if not frame.empty else frame
        if len(rows):
            number = int(rows.iloc[0]["trial"])
            t = next(t for t in study.get_trials(deepcopy=False) if t.number == number)
            why = fall_reason((t.user_attrs.get(RESULT_ATTR) or {}).get("per_behaviour"))
            vals = tuple(float(rows.iloc[0][o]) for o in objectives)
        else:
            key = f"baseline:{name}"
            stored = study.user_attrs.get(key)
            if not isinstance(stored, dict):  # none, or values alone (no word on how the run ended)
                design = LegDesign(resample(paper_designs()[name], config.space.n_segments), name=name)
                ev = evaluate(design, config.objective)
                stored = {"values": list(ev.values), "left_out": fall_reason(ev.per_behaviour)}
                study.set_user_attr(key, stored)
            vals, why = tuple(stored["values"]), stored.get("left_out")
        if why is None:
            values[name] = vals
        else:
            left_out[name] = why
    return values, left_out


def _outside_band(name: str, config: StudyConfig) -> str | None:
    """Why baseline `name` is no comparator of a study held to a leg mass:
    its leg (at the study's number of segments) lies outside the band; None
    when it lies inside, or the study holds no mass."""
    band = leg_mass_band_kg(config.objective, config.space.n_segments)
    if band is None:
        return None
    design = LegDesign(resample(paper_designs()[name], config.space.n_segments), name=name)
    mass = leg_mass_kg(design, config.objective.segment_mass)
    if band[0] <= mass <= band[1]:
        return None
    return (
        f"its leg mass {mass:.3g} kg lies outside the study's band {band[0]:.3g} to {band[1]:.3g} kg "
        "(a comparison with a leg of another mass would mix the mass's effect into the material's)"
    )


def baselines(study: optuna.Study, config: StudyConfig, frame: pd.DataFrame) -> dict:
    """The objective values of SS and rho-inc under the study's settings,
    those whose runs stood (:func:`baseline_runs`, which also says why the
    others are left out).

    Args:
        study: the ``optuna.Study``.
        config: its :class:`StudyConfig`.
        frame: :func:`trials_frame`'s table.

    Returns:
        {name: values}, each a tuple of floats in the order of
        ``config.objective.objectives``; a baseline that fell or diverged
        is not in it.
    """
    return baseline_runs(study, config, frame)[0]


def missing_baselines(study: optuna.Study) -> list[str]:
    """The baselines a report must run (and store in the study, so it
    needs a writable storage): those the study did not run itself, and has
    not stored with how their run ended.

    Args:
        study: the Optuna study.

    Returns:
        The baselines' names (of :data:`BASELINES`), in their order.
    """
    have = {
        t.user_attrs.get(PAPER_ATTR)
        for t in study.get_trials(deepcopy=False, states=(TrialState.COMPLETE,))
        if t.user_attrs.get(PAPER_ATTR)
    }
    attrs = study.user_attrs
    return [b for b in BASELINES if b not in have and not isinstance(attrs.get(f"baseline:{b}"), dict)]


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
    base, left_out = baseline_runs(study, config, frame)  # a run that fell or diverged is no baseline
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
    drawn = frame.dropna(subset=list(objectives)) if not frame.empty else frame  # a diverged trial: no values
    with warnings.catch_warnings():  # every trial diverged: an empty plot, said by the feasibility line
        warnings.filterwarnings("ignore", "No artists with labels", UserWarning)
        fig = study_plots.pareto_figure(drawn, front, base, what, axes=axes)
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
        "baselines_left_out": left_out,
        "feasibility": feasibility(study, config),
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
