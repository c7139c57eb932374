"""A study's trials as tables: every trial, the feasible Pareto front, and the front as a reader builds it.

:func:`trials_frame` is one row per trial (state, feasibility and why
not, objectives (empty for a trial that diverged), hop height in m, constraint values, per-segment density in g/cm^3 and
modulus in GPa, parameters, worker, error); :func:`pareto_frame` the
non-dominated feasible designs with their percent change against
baselines; :func:`front_table` that front in display units for a page, and
:func:`front_designs` its legs. Re-exported by
:mod:`mat_hopper.optimize.report`.
"""

from __future__ import annotations

import re

import numpy as np
import optuna
import pandas as pd
from optuna.trial import TrialState

from ..core.materials import LegDesign
from ..physics.run_metrics import METRICS
from ..util.change import percent_change
from ._feasibility import trial_outcome
from ._objective import OBJECTIVES, RESULT_ATTR
from ._scoring import SE_ATTR, leg_mass_kg
from ._storage import ERROR_ATTR, FAIL_REASON_ATTR, PAPER_ATTR, WORKER_ATTR
from ._study import StudyConfig


def trials_frame(study: optuna.Study, config: StudyConfig) -> pd.DataFrame:
    """One row per trial (module doc), queued trials not yet run (WAITING)
    left out. No wall-clock columns. A trial whose runs diverged has its
    objective columns empty (NaN): the values Optuna holds for it are
    whole-run means of a run cut short, kept for the sampler, which would
    look better than any feasible trial's, and so are its standard errors,
    hop height (m) and constraint values other than ``unstable``;
    ``not_feasible_because`` names
    why a trial is not feasible (``diverged``, ``fell``, ..., and for a
    trial racing stopped on a screening rung ``diverged (screening
    rung)`` or ``pruned by racing (ranked out)``; empty when it is).

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
        why = trial_outcome(t, config.objective.constraint_names)
        row["not_feasible_because"] = why or ""
        diverged = (why or "").startswith("diverged")  # also "diverged (screening rung)"
        if t.state == TrialState.COMPLETE and t.values is not None and not diverged:
            row.update(dict(zip(objectives, t.values)))  # a diverged run's values are for the sampler only: empty
        se = {} if diverged else ua.get(SE_ATTR) or {}
        row.update({f"{o}_se": np.nan if se.get(o) is None else se[o] for o in objectives})
        c = t.constraints
        row.update({f"constraint_{n}": c.get(n, np.nan) for n in config.objective.constraint_names})
        if diverged:  # every number measured on runs cut short is empty; "unstable" says they diverged
            row["hop_height_m"] = np.nan
            row.update({f"constraint_{n}": np.nan for n in config.objective.constraint_names if n != "unstable"})
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
