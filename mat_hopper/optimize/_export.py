"""Designs a user can take away: a trial's leg as CSV and as MJCF.

``mat-hopper optimize --study NAME --export TRIAL [--out DIR]`` writes, into
DIR (default the studies folder):

``NAME-trialN.csv``
    one row: the design as :func:`mat_hopper.batch.designs_to_frame` writes
    it (``design``, ``density_i`` g/cm^3, ``modulus_i`` GPa, exact to the
    last bit: ``repr`` of each float), then the study's settings and the
    trial's record (study, trial, profile, convention, segment_mass,
    replicates, risk, behaviours, objectives, leg_mass_kg, feasible,
    not_feasible_because (as the report's trials.csv: ``diverged``,
    ``fell``, ...; empty for a feasible trial), each objective and its
    standard error; a trial whose runs diverged has them empty, as
    trials.csv: the values Optuna holds for it are means of runs cut short). ``mat-hopper simulate --design-csv`` and ``mat-hopper
    batch --designs-csv`` read it (they ignore the record's columns);
    simulating it with the study's settings reproduces the trial's metrics
    exactly (the simulator is deterministic).
``NAME-trialN-BEHAVIOUR.xml``
    the hopper with this leg (:func:`mat_hopper.core.model.build_spec`, the
    study's time step, stiffness and segment-mass conventions, the
    behaviour's terrain) written by MuJoCo's own XML writer
    (``mujoco.MjSpec.to_xml``), one file per behaviour of the study. The
    mechanism only, not the controller; MuJoCo's writer prints some numbers
    to 6 significant digits (spring stiffness, joint ranges), so the CSV,
    not the MJCF, is the exact record.
"""

from __future__ import annotations

import os

import optuna
import pandas as pd

from ..batch import designs_to_frame
from ..core.behaviours import behaviour as get_behaviour
from ..core.model import build_spec
from ..util.atomic import write_csv, write_text
from ._feasibility import fall_reason, trial_outcome
from ._objective import RESULT_ATTR
from ._scoring import SE_ATTR, leg_mass_kg


def design_frame(trial, design, config) -> pd.DataFrame:
    """The one-row table of the module doc (design columns first).

    Args:
        trial: the Optuna ``FrozenTrial``.
        design: its LegDesign.
        config: the study's :class:`~mat_hopper.optimize.StudyConfig`.

    Returns:
        A one-row pandas DataFrame: :func:`mat_hopper.batch.designs_to_frame`'s
        columns (design, density_i g/cm^3, modulus_i GPa, as ``repr``
        strings), then study, trial, state (the trial state's name),
        profile, convention, segment_mass, replicates, risk, behaviours and
        objectives (comma-separated), leg_mass_kg (the leg's, stub to
        foot, kg), feasible (bool, False without a stored result),
        not_feasible_because (:func:`~mat_hopper.optimize._feasibility.trial_outcome`,
        "" for a feasible trial), and per objective its value and
        ``<objective>_se`` (None when the trial is not COMPLETE, has no
        standard error, or diverged).
    """
    frame = designs_to_frame([design])
    ob = config.objective
    record = {
        "study": config.name,
        "trial": trial.number,
        "state": trial.state.name,
        "profile": ob.profile.name,
        "convention": ob.convention,
        "segment_mass": ob.segment_mass,
        "replicates": ob.replicates,
        "risk": ob.risk,
        "behaviours": ",".join(ob.behaviours),
        "objectives": ",".join(ob.objectives),
        "leg_mass_kg": leg_mass_kg(design, ob.segment_mass),
        "feasible": bool((trial.user_attrs.get(RESULT_ATTR) or {}).get("feasible", False)),
        "not_feasible_because": trial_outcome(trial, ob.constraint_names) or "",
    }
    diverged = record["not_feasible_because"].startswith("diverged")
    se = {} if diverged else trial.user_attrs.get(SE_ATTR) or {}
    names = ob.objectives
    scored = trial.state == optuna.trial.TrialState.COMPLETE and trial.values and not diverged
    values = trial.values if scored else [None] * len(names)
    for o, v in zip(names, values):
        record[o] = v
        record[f"{o}_se"] = se.get(o)
    for k, v in record.items():
        frame[k] = [v]
    return frame


def design_mjcf(design, config, behaviour: str) -> str:
    """MJCF text of the hopper with `design` under the study's settings, on
    `behaviour`'s terrain, from MuJoCo's XML writer.

    Args:
        design: the LegDesign.
        config: the study's :class:`~mat_hopper.optimize.StudyConfig`: its
            objective's profile gives the time step (s), stiffness convention
            and segment-mass convention.
        behaviour: a behaviour name (``static``, ``forward``, ``ramp`` or
            ``circle``); its ramp grade (deg) sets the terrain.

    Returns:
        The MJCF document (str), from ``mujoco.MjSpec.to_xml``.
    """
    ob = config.objective
    settings = ob.sim_settings(design=design)
    spec = build_spec(
        design,
        ramp_grade_deg=get_behaviour(behaviour).ramp_grade_deg,
        timestep_s=settings.timestep_s,
        convention=settings.convention,
        segment_mass=settings.segment_mass,
    )
    return spec.to_xml()


def export_trial(name: str, storage, number: int, out_dir: str) -> dict:
    """Write trial `number`'s design as CSV and MJCF into `out_dir` (module
    doc). Returns {"csv": path, "mjcf": {behaviour: path}, "design": LegDesign,
    "config": StudyConfig, "trial": FrozenTrial}; ValueError for a trial the
    study does not hold.

    Args:
        name: the study's name (also the stem of the files).
        storage: the study's Optuna storage or storage URL.
        number: the trial's number.
        out_dir: the folder written into (made if missing).

    Returns:
        A dict: ``csv`` (the path of ``<out_dir>/<name>-trial<number>.csv``),
        ``mjcf`` ({behaviour: path of ``<name>-trial<number>-<behaviour>.xml``},
        one per behaviour of the study), ``design`` (the LegDesign),
        ``config`` (the StudyConfig), ``trial`` (the FrozenTrial), ``why``
        (why it is not feasible, the CSV's not_feasible_because, or None)
        and ``runs`` (how its stored runs fell or diverged,
        ``diverged at t = 0.0009 s (ramp)``, or None:
        :func:`~mat_hopper.optimize._feasibility.fall_reason`).

    Raises:
        ValueError: no study named `name` (the message lists the studies
            present), a study not made by mat-hopper, a trial the study does
            not hold, or one without the space's parameters
            (:func:`mat_hopper.optimize.report.trial_design`).
    """
    from .report import trial_design  # report imports the package's plots; loaded on use

    t, design, config = trial_design(name, storage, number)
    os.makedirs(out_dir, exist_ok=True)
    stem = os.path.join(out_dir, f"{name}-trial{number}")
    csv_path = f"{stem}.csv"
    write_csv(design_frame(t, design, config), csv_path)
    mjcf = {}
    for b in config.objective.behaviours:
        path = f"{stem}-{b}.xml"
        write_text(design_mjcf(design, config, b), path)
        mjcf[b] = path
    why = trial_outcome(t, config.objective.constraint_names)
    runs = fall_reason((t.user_attrs.get(RESULT_ATTR) or {}).get("per_behaviour"))
    return {"csv": csv_path, "mjcf": mjcf, "design": design, "config": config, "trial": t, "why": why, "runs": runs}
