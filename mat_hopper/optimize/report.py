"""A study's outputs: tables, Pareto front, hypervolume, importances, replay.

``mat-hopper optimize --report NAME`` writes into ``STUDIES_DIR/NAME-report``
(or ``--out``):

- ``trials.csv``: one row per trial (state, feasibility, objectives, hop
  height, constraint values, per-segment density g/cm^3 and modulus GPa,
  parameters, worker, error), ordered by trial number;
- ``pareto.csv``: the non-dominated feasible designs, with the percent
  change of tracking error and power against the paper's SS and rho-inc
  (the study's own runs of them, or, when its space cannot express them,
  runs made here with the study's settings and kept in the study);
- ``pareto.png``: power against tracking error, feasible, infeasible,
  the Pareto front and the paper's designs marked;
- ``hypervolume.csv`` / ``.png``: hypervolume of the feasible front after
  each trial, against a reference point 10 % beyond the worst feasible
  value of each objective (both objectives minimized);
- ``importances.csv`` / ``.png``: Optuna's parameter importances
  (PED-ANOVA) for each objective.

``--replay TRIAL`` rebuilds the trial's design from its parameters and
simulates it again with the study's settings (bit-identical to the stored
values, by the determinism of the simulator); with ``--render`` it also
calls ``mat-hopper render`` on it when :mod:`mat_hopper.viz.render` exists.
"""

from __future__ import annotations

import os
import warnings

import numpy as np
import optuna
import pandas as pd
from optuna.trial import TrialState

from ..atomic import atomic_path, write_csv
from ..materials import LegDesign, paper_designs
from ._study import CONFIG_ATTR, RESULT_ATTR, StudyConfig, _quiet
from ._objective import CONSTRAINTS, OBJECTIVES, evaluate
from ._space import describe, resample
from ._storage import ERROR_ATTR, FAIL_REASON_ATTR, PAPER_ATTR, WORKER_ATTR

BASELINES = ("SS", "rho-inc")
HV_MARGIN = 0.1


def load(name: str, storage) -> tuple[optuna.Study, StudyConfig]:
    _quiet()
    study = optuna.load_study(study_name=name, storage=storage)
    key = study.user_attrs.get(CONFIG_ATTR)
    if not key:
        raise ValueError(f"study {name!r} was not made by mat-hopper optimize (no {CONFIG_ATTR})")
    return study, StudyConfig.from_key(name, key)


# --- tables -----------------------------------------------------------------

def trials_frame(study: optuna.Study, config: StudyConfig) -> pd.DataFrame:
    """One row per trial (see module doc). No wall-clock columns."""
    rows = []
    space = config.space
    for t in sorted(study.get_trials(deepcopy=False), key=lambda t: t.number):
        ua = t.user_attrs
        res = ua.get(RESULT_ATTR) or {}
        row = {"trial": t.number, "state": t.state.name, "paper_design": ua.get(PAPER_ATTR, ""),
               "design": res.get("design", ""), "feasible": bool(res.get("feasible", False)),
               "tracking_error_m": np.nan, "power_w": np.nan,
               "hop_height_m": res.get("hop_height_m") if res.get("hop_height_m") is not None else np.nan,
               "total_mass_kg": res.get("total_mass_kg", np.nan)}
        if t.state == TrialState.COMPLETE and t.values is not None:
            row.update(dict(zip(OBJECTIVES, t.values)))
        c = t.constraints
        row.update({f"constraint_{n}": c.get(n, np.nan) for n in CONSTRAINTS})
        try:
            design = space.design(t.params)
            for i, m in enumerate(design.segments, 1):
                row[f"seg{i}_rho_g_cm3"] = m.density_g_cm3
                row[f"seg{i}_e_gpa"] = m.modulus_gpa
            if not row["design"]:
                row["design"] = design.name
        except ValueError:
            pass                                  # a trial that never got its parameters
        row.update({f"param_{k}": v for k, v in sorted(t.params.items())})
        w = ua.get(WORKER_ATTR) or {}
        row["worker"] = f"{w.get('host', '')}:{w.get('pid', '')}" if w else ""
        row["error"] = ua.get(ERROR_ATTR, "") or ua.get(FAIL_REASON_ATTR, "")
        row["retry_of"] = t.system_attrs.get("failed_trial", np.nan)
        rows.append(row)
    return pd.DataFrame(rows)


def nondominated(values: np.ndarray) -> np.ndarray:
    """Mask of the rows no other row dominates (all objectives minimized;
    of identical rows, the first is kept)."""
    v = np.asarray(values, float)
    keep = np.ones(len(v), bool)
    for i in range(len(v)):
        others = np.delete(np.arange(len(v)), i)
        le = np.all(v[others] <= v[i], axis=1)
        lt = np.any(v[others] < v[i], axis=1)
        same_before = np.all(v[others] == v[i], axis=1) & (others < i)
        if np.any(le & lt) or np.any(same_before):
            keep[i] = False
    return keep


def feasible_complete(frame: pd.DataFrame) -> pd.DataFrame:
    if frame.empty:
        return frame
    return frame[(frame["state"] == "COMPLETE") & frame["feasible"].astype(bool)]


def pareto_frame(frame: pd.DataFrame, baselines: dict | None = None) -> pd.DataFrame:
    """Non-dominated feasible trials, by tracking error, with percent changes
    against each baseline ({name: (tracking_error_m, power_w)})."""
    ok = feasible_complete(frame)
    if ok.empty:
        return ok.copy()
    front = ok[nondominated(ok[list(OBJECTIVES)].to_numpy())].sort_values("tracking_error_m").copy()
    for name, vals in (baselines or {}).items():
        for obj, base in zip(OBJECTIVES, vals):
            col = f"{obj.rsplit('_', 1)[0]}_vs_{name}_pct"
            front[col] = 100.0 * (front[obj] - base) / abs(base) if base else np.nan
    cols = ["trial", "design", "paper_design", *OBJECTIVES, "hop_height_m"]
    cols += [c for c in front.columns if c.endswith("_pct")]
    cols += [c for c in front.columns if c.startswith("seg") and c not in cols]
    return front[cols].reset_index(drop=True)


def hypervolume_2d(points: np.ndarray, reference) -> float:
    """Area dominated by `points` (n x 2, minimized) and bounded by `reference`."""
    p = np.asarray(points, float).reshape(-1, 2)
    r = np.asarray(reference, float)
    p = p[np.all(p < r, axis=1)]
    if len(p) == 0:
        return 0.0
    p = p[np.lexsort((p[:, 1], p[:, 0]))]
    area, best_y = 0.0, r[1]
    for x, y in p:
        if y < best_y:
            area += (r[0] - x) * (best_y - y)
            best_y = y
    return float(area)


def hypervolume_history(frame: pd.DataFrame, reference=None) -> tuple[pd.DataFrame, tuple]:
    """Hypervolume of the feasible complete trials up to each trial number,
    and the reference point used (default: worst feasible value of each
    objective plus 10 % of its range)."""
    ok = feasible_complete(frame)
    if ok.empty:
        return pd.DataFrame(columns=["trial", "hypervolume"]), ()
    vals = ok[list(OBJECTIVES)].to_numpy(float)
    if reference is None:
        lo, hi = vals.min(axis=0), vals.max(axis=0)
        span = np.where(hi > lo, hi - lo, np.maximum(np.abs(hi), 1e-12))
        reference = tuple(float(v) for v in hi + HV_MARGIN * span)
    trials = frame.sort_values("trial")["trial"].to_numpy()
    ok_trials = ok["trial"].to_numpy()
    out = []
    for n in trials:
        out.append({"trial": int(n), "hypervolume": hypervolume_2d(vals[ok_trials <= n], reference)})
    return pd.DataFrame(out), tuple(reference)


def importances(study: optuna.Study) -> pd.DataFrame:
    """Parameter importances (Optuna's default, PED-ANOVA) per objective;
    empty when the study is too small."""
    rows = []
    complete = study.get_trials(deepcopy=False, states=(TrialState.COMPLETE,))
    if len(complete) < 4:
        return pd.DataFrame(columns=["objective", "param", "importance"])
    for i, obj in enumerate(OBJECTIVES):
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                imp = optuna.importance.get_param_importances(study, target=lambda t, i=i: t.values[i])
        except (ValueError, RuntimeError, ZeroDivisionError):
            continue
        rows += [{"objective": obj, "param": k, "importance": float(v)} for k, v in imp.items()]
    return pd.DataFrame(rows, columns=["objective", "param", "importance"])


def baselines(study: optuna.Study, config: StudyConfig, frame: pd.DataFrame) -> dict:
    """(tracking_error_m, power_w) of SS and rho-inc under the study's
    settings: its enqueued run, or a run made now and kept in the study."""
    out = {}
    for name in BASELINES:
        rows = frame[(frame["paper_design"] == name) & (frame["state"] == "COMPLETE")] if not frame.empty else frame
        if len(rows):
            out[name] = tuple(float(rows.iloc[0][o]) for o in OBJECTIVES)
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


# --- plots ------------------------------------------------------------------

def _save(fig, path: str) -> None:
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=130, bbox_inches="tight")


def plot_pareto(frame: pd.DataFrame, front: pd.DataFrame, base: dict, path: str, title: str) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6.4, 4.8))
    done = frame[frame["state"] == "COMPLETE"] if not frame.empty else frame
    ok = feasible_complete(frame)
    bad = done[~done["feasible"].astype(bool)] if not done.empty else done
    shown = pd.concat([ok, done[done["paper_design"] != ""]]) if not done.empty else done
    if not ok.empty:
        ax.scatter(ok["tracking_error_m"], ok["power_w"], s=14, c="tab:blue", alpha=0.6, label=f"feasible ({len(ok)})")
    if not bad.empty:
        ax.scatter(bad["tracking_error_m"], bad["power_w"], s=14, c="0.6", marker="x", alpha=0.6,
                   label=f"infeasible ({len(bad)})")
    if not front.empty:
        ax.plot(front["tracking_error_m"], front["power_w"], "-o", c="tab:red", ms=5, drawstyle="steps-post",
                label=f"Pareto front ({len(front)})")
    for _, r in done[done["paper_design"] != ""].iterrows() if not done.empty else ():
        ax.scatter([r["tracking_error_m"]], [r["power_w"]], marker="*", s=160, c="gold", edgecolors="k", zorder=5)
        ax.annotate(r["paper_design"] + ("" if r["feasible"] else " (infeasible)"),
                    (r["tracking_error_m"], r["power_w"]), textcoords="offset points", xytext=(6, 6), fontsize=8)
    for name, (te, pw) in base.items():
        if done.empty or name not in set(done["paper_design"]):
            ax.scatter([te], [pw], marker="*", s=160, c="white", edgecolors="k", zorder=5)
            ax.annotate(f"{name} (baseline run)", (te, pw), textcoords="offset points", xytext=(6, 6), fontsize=8)
            shown = pd.concat([shown, pd.DataFrame({"tracking_error_m": [te], "power_w": [pw]})])
    if len(shown):
        for axis, col, setter in ((0, "tracking_error_m", ax.set_xlim), (1, "power_w", ax.set_ylim)):
            lo, hi = float(shown[col].min()), float(shown[col].max())
            pad = 0.08 * (hi - lo) if hi > lo else 0.1 * abs(hi) + 1e-12
            setter(lo - pad, hi + pad)
    ax.set_xlabel("tracking error (m, mean over hop cycles)")
    ax.set_ylabel("hip power (W, mean over hop cycles)")
    ax.set_title(title, fontsize=10)
    ax.legend(fontsize=8, loc="best")
    _save(fig, path)
    plt.close(fig)


def plot_hypervolume(hv: pd.DataFrame, path: str, title: str) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6.4, 3.6))
    if len(hv):
        ax.step(hv["trial"], hv["hypervolume"], where="post")
    ax.set_xlabel("trial")
    ax.set_ylabel("hypervolume (m W)")
    ax.set_title(title, fontsize=10)
    _save(fig, path)
    plt.close(fig)


def plot_importances(imp: pd.DataFrame, path: str, title: str) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, len(OBJECTIVES), figsize=(10, 3.8), sharey=False, layout="constrained")
    for ax, obj in zip(np.atleast_1d(axes), OBJECTIVES):
        d = imp[imp["objective"] == obj].sort_values(["importance", "param"]) if len(imp) else imp
        if len(d):
            ax.barh(d["param"], d["importance"], color="tab:blue")
        ax.set_title(obj, fontsize=9)
        ax.set_xlabel("importance")
        ax.tick_params(axis="y", labelsize=7)
    fig.suptitle(title, fontsize=10)
    _save(fig, path)
    plt.close(fig)


# --- the report -------------------------------------------------------------

def write_report(name: str, storage, out_dir: str) -> dict:
    """Every output of the module doc, written into out_dir. Returns
    {output name: path} and the tables."""
    study, config = load(name, storage)
    os.makedirs(out_dir, exist_ok=True)
    frame = trials_frame(study, config)
    base = baselines(study, config, frame)
    front = pareto_frame(frame, base)
    hv, ref_point = hypervolume_history(frame)
    imp = importances(study)
    paths = {k: os.path.join(out_dir, f) for k, f in (
        ("trials", "trials.csv"), ("pareto", "pareto.csv"), ("pareto_plot", "pareto.png"),
        ("hypervolume", "hypervolume.csv"), ("hypervolume_plot", "hypervolume.png"),
        ("importances", "importances.csv"), ("importances_plot", "importances.png"))}
    write_csv(frame, paths["trials"])
    write_csv(front, paths["pareto"])
    write_csv(hv, paths["hypervolume"])
    write_csv(imp, paths["importances"])
    beh = ",".join(config.objective.behaviours)
    what = f"{name}: {beh}, {config.objective.profile.name} profile, {config.space.n_segments} segments"
    plot_pareto(frame, front, base, paths["pareto_plot"], what)
    ref_text = ", ".join(f"{v:.4g}" for v in ref_point)
    plot_hypervolume(hv, paths["hypervolume_plot"], f"{what}\nreference point ({ref_text})")
    plot_importances(imp, paths["importances_plot"], what)
    return {"paths": paths, "trials": frame, "pareto": front, "hypervolume": hv, "importances": imp,
            "baselines": base, "reference": ref_point}


def cmd_report(name: str, storage, args) -> int:
    out = args.out or os.path.join(args.studies_dir, f"{name}-report")
    rep = write_report(name, storage, out)
    frame, front = rep["trials"], rep["pareto"]
    states = frame["state"].value_counts().to_dict() if len(frame) else {}
    n_ok = len(feasible_complete(frame))
    print(f"study {name}: {len(frame)} trials {states}, {n_ok} feasible, {len(front)} on the Pareto front")
    for b, (te, pw) in rep["baselines"].items():
        print(f"  {b}: tracking error {te:.4g} m, power {pw:.4g} W")
    if len(front):
        cols = [c for c in front.columns if not c.startswith("seg")]
        print(front[cols].to_string(index=False, float_format=lambda v: f"{v:.4g}"))
    for k, p in rep["paths"].items():
        print(f"wrote {p}")
    return 0


def replay(name: str, storage, number: int):
    """(trial, design, fresh Evaluation) for trial `number` of study `name`."""
    study, config = load(name, storage)
    trials = [t for t in study.get_trials(deepcopy=False) if t.number == number]
    if not trials:
        raise ValueError(f"study {name!r} has no trial {number} (trials 0..{len(study.trials) - 1})")
    t = trials[0]
    design = config.space.design(t.params, name=f"{name}#{number}")
    return t, design, evaluate(design, config.objective), config


def cmd_replay(name: str, storage, args) -> int:
    t, design, ev, config = replay(name, storage, args.replay)
    print(f"trial {t.number} ({t.state.name}) of {name}: {describe(design.segments)}")
    for i, m in enumerate(design.segments, 1):
        print(f"  segment {i}: {m.density_g_cm3:.6g} g/cm^3, {m.modulus_gpa:.6g} GPa ({m.name})")
    for r in ev.per_behaviour:
        print(f"  {r['behaviour']}: tracking error {r['tracking_error_m']:.6g} m, power {r['power_w']:.6g} W, "
              f"hop height {r['hop_height_m']:.4g} m over {r['n_hops']} hops, "
              f"{'upright' if r['upright'] else 'UNSTABLE'}")
    print(f"objectives {ev.values[0]:.6g} m, {ev.values[1]:.6g} W; "
          f"{'feasible' if ev.feasible else 'infeasible'} (constraints {ev.constraints[0]:.4g}, {ev.constraints[1]:g})")
    if t.state == TrialState.COMPLETE:
        same = tuple(t.values) == tuple(ev.values)
        print("replay matches the stored values exactly" if same else
              f"replay differs from the stored values {tuple(t.values)}")
    if args.render:
        return _render(design, config, args)
    return 0 if t.state != TrialState.COMPLETE or tuple(t.values) == tuple(ev.values) else 1


def _render(design: LegDesign, config: StudyConfig, args) -> int:
    """Gait tiles and a 10 s video of the replayed design on each behaviour,
    in --out or the studies folder: <study>-trial<N>-<behaviour>-*."""
    from ..cli import main
    dens = ",".join(repr(float(m.density_g_cm3)) for m in design.segments)
    mods = ",".join("rigid" if m.modulus_gpa is None else repr(float(m.modulus_gpa)) for m in design.segments)
    folder = args.out or args.studies_dir
    code = 0
    for b in config.objective.behaviours:
        stem = os.path.join(folder, f"{args.study}-trial{args.replay}-{b}")
        argv = ["render", "--density", dens, "--modulus", mods, "--behaviour", b,
                "--convention", config.objective.convention, "--tiles", f"{stem}-tiles.png",
                "--video", f"{stem}.mp4"]
        print("mat-hopper " + " ".join(argv))
        try:
            code = max(code, int(main(argv) or 0))
        except SystemExit as e:
            code = max(code, int(e.code or 0))
    return code
