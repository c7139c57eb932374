"""Validating a study's Pareto front: which designs survive a harder look?

A study scores each design by one deterministic run per behaviour, at the
paper's time step, under one stiffness convention. A front built that way
can hold designs that win by luck of the one run, or by a numerical
artefact. Each front design is therefore simulated again (every run is a
:class:`~mat_hopper.experiments.runner.RunSpec` through
:func:`~mat_hopper.experiments.runner.run_grid`: the one cache and pool):

``nominal``
    the unperturbed run at the profile's settings (a study with
    ``replicates = 0`` scored exactly this run; a noise-aware study scored
    the mean of its replicates on seeds 1000.., apart from the seeds here);
``replicate``
    seeded perturbed replicates
    (:meth:`~mat_hopper.perturbations.Perturbation.replicate`, seeds 0..n-1,
    n = the profile's ``replicates`` by default) on the study's
    behaviours; the paper's nine designs get the same replicates, for the
    comparison below;
``behaviour``
    every other behaviour (static, forward, ramp, circle, less the study's);
``step 2e-5 s, control 1e-4 s``
    physics at 2e-5 s with 5 substeps, so the controller keeps its 1e-4 s
    period and, with a 5-step sensor latency, the authors' physical sensor
    delay (1e-4 s): the same controller on converged physics;
``step 2e-5 s``
    a plain 2e-5 s step (controller every step, sensors one step old): what
    a finer time step of the authors' loop gives;
``axial``
    the physical k = E A / L springs with automatic physics substeps, as
    ``simulate(timestep_s="auto", convention="axial")`` runs them.

Survival. A design survives when

1. it is *stable everywhere*: every run above ends upright without
   numerical divergence (runner status ``ok``); and
2. it is *non-dominated by the paper's designs* under interval logic: on
   each objective, each design has the 95 % percentile-bootstrap interval
   of its mean over replicates (each replicate reduced to its mean over hop
   cycles, and over the study's behaviours); design P is *better* than A on
   an objective when P's interval lies wholly below A's, *no worse* when
   the intervals overlap or P is better. P dominates A when P is no worse on
   both objectives and better on at least one. Overlapping intervals are
   ties: a front design is dropped only when a paper design beats it
   clearly.

The paper's best designs are those of the nine that no other paper design
dominates in that sense. :func:`beats_paper` then answers the chapter's
question, per surviving design and each of the paper's best: the percent
change of each objective with its bootstrap interval
(:func:`mat_hopper.analysis.stats.bootstrap_pct_change`), and whether both
intervals lie wholly below zero.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pandas as pd

from ..analysis.stats import bootstrap_pct_change
from ..behaviours import BEHAVIOUR_NAMES
from ..behaviours import behaviour as get_behaviour
from ..experiments.runner import FAILED, OK, RunSpec, run_grid
from ..materials import LegDesign, paper_designs
from ..perturbations import Perturbation
from ..sim import FINE_SUBSTEPS, FINE_TIMESTEP_S, resolve_timestep
from ._objective import OBJECTIVES, Objective

NOMINAL, REPLICATE, BEHAVIOUR = "nominal", "replicate", "behaviour"
FINE_CONTROL, FINE_PLAIN, AXIAL = "step 2e-5 s, control 1e-4 s", "step 2e-5 s", "axial"
CHECKS = (NOMINAL, REPLICATE, BEHAVIOUR, FINE_CONTROL, FINE_PLAIN, AXIAL)
CONFIDENCE = 0.95
N_BOOT = 10000


def check_settings(design: LegDesign, objective: Objective) -> dict:
    """{check: SimSettings} of the study's behaviours for one design (module doc)."""
    base = objective.sim_settings(design=design)
    dt, k = resolve_timestep("auto", design, "axial", objective.segment_mass)
    return {
        NOMINAL: base,
        FINE_CONTROL: replace(base, timestep_s=FINE_TIMESTEP_S, substeps=FINE_SUBSTEPS, sensor_timing=FINE_SUBSTEPS),
        FINE_PLAIN: replace(base, timestep_s=FINE_TIMESTEP_S),
        AXIAL: replace(base, convention="axial", timestep_s=dt, substeps=k),
    }


def validation_tasks(front: dict, objective: Objective, replicates: int, paper: dict | None = None) -> list:
    """RunSpecs of every check of every `front` design ({name: LegDesign})
    and the replicates (and nominal runs) of the `paper` designs (default:
    all nine)."""
    tasks = []
    others = [b for b in BEHAVIOUR_NAMES if b not in objective.behaviours]
    paper = paper_designs() if paper is None else paper

    def add(role, name, design, beh, settings, check, rep=-1):
        labels = {"role": role, "design": name, "behaviour": beh, "check": check, "replicate": rep}
        tasks.append(RunSpec(design, get_behaviour(beh), settings, labels))

    for role, designs in (("front", front), ("paper", paper)):
        for name, d in designs.items():
            for b in objective.behaviours:
                for r in range(replicates):
                    pert = Perturbation.replicate(r, objective.profile.scored_window_s)
                    add(role, name, d, b, objective.sim_settings(pert, d), REPLICATE, r)
                if role == "paper":
                    add(role, name, d, b, objective.sim_settings(design=d), NOMINAL)
                    continue
                for check, st in check_settings(d, objective).items():
                    add(role, name, d, b, st, check)
            if role == "front":
                for b in others:
                    add(role, name, d, b, objective.sim_settings(design=d), BEHAVIOUR)
    return tasks


def mean_interval(values, *, seed: int = 0) -> tuple[float, float]:
    """The 95 % percentile-bootstrap interval of the mean (scipy.stats.bootstrap,
    N_BOOT resamples, seeded); (nan, nan) below 2 values, (v, v) when all
    values are equal."""
    from scipy.stats import bootstrap

    v = np.asarray(values, float)
    v = v[np.isfinite(v)]
    if len(v) < 2:
        return np.nan, np.nan
    if np.all(v == v[0]):
        return float(v[0]), float(v[0])
    res = bootstrap((v,), np.mean, n_resamples=N_BOOT, confidence_level=CONFIDENCE, method="percentile", rng=seed)
    return float(res.confidence_interval.low), float(res.confidence_interval.high)


def intervals(runs: pd.DataFrame, objective: Objective, seed: int = 0) -> pd.DataFrame:
    """Per design and objective: replicates n, mean of replicate means and
    its bootstrap interval (ci_low, ci_high), from the replicate runs of a
    validation's run table (a replicate is its mean over the study's
    behaviours; a replicate that fell or diverged counts as missing)."""
    reps = runs[(runs["check"] == REPLICATE) & (runs["status"] == OK)]
    rows = []
    for (role, design), g in reps.groupby(["role", "design"], sort=False):
        for obj in OBJECTIVES:
            per_rep = g.groupby("replicate")[f"mean_{obj}"].mean()
            per_rep = per_rep[g.groupby("replicate")["behaviour"].nunique() == len(objective.behaviours)]
            v = per_rep.to_numpy(float)
            lo, hi = mean_interval(v, seed=seed)
            rows.append(
                {
                    "role": role,
                    "design": design,
                    "objective": obj,
                    "n": len(v),
                    "mean": float(v.mean()) if len(v) else np.nan,
                    "ci_low": lo,
                    "ci_high": hi,
                }
            )
    return pd.DataFrame(rows)


def dominates(p: dict, a: dict) -> bool:
    """Interval dominance of P over A: p, a = {objective: (low, high)}
    (module doc; minimized objectives)."""
    better = [p[o][1] < a[o][0] for o in OBJECTIVES]
    no_worse = [better[i] or not (p[o][0] > a[o][1]) for i, o in enumerate(OBJECTIVES)]
    return all(no_worse) and any(better)


def _boxes(iv: pd.DataFrame, role: str) -> dict:
    out = {}
    for design, g in iv[iv["role"] == role].groupby("design", sort=False):
        g = g.set_index("objective")
        if g["n"].min() > 0 and np.isfinite(g[["ci_low", "ci_high"]].to_numpy()).all():
            out[design] = {o: (float(g.loc[o, "ci_low"]), float(g.loc[o, "ci_high"])) for o in OBJECTIVES}
    return out


def paper_best(iv: pd.DataFrame) -> list[str]:
    """The paper designs no other paper design dominates (interval logic)."""
    boxes = _boxes(iv, "paper")
    return [a for a in boxes if not any(dominates(boxes[p], boxes[a]) for p in boxes if p != a)]


def verdicts(runs: pd.DataFrame, iv: pd.DataFrame) -> pd.DataFrame:
    """One row per front design: stable under each check (True/False),
    stable everywhere, the paper designs that dominate it, survives."""
    front = runs[runs["role"] == "front"]
    boxes, paper = _boxes(iv, "front"), _boxes(iv, "paper")
    rows = []
    for design, g in front.groupby("design", sort=False):
        row = {"design": design}
        for check in CHECKS:
            sel = g[g["check"] == check]
            row[f"stable: {check}"] = bool(len(sel)) and bool((sel["status"] == OK).all())
        row["stable everywhere"] = all(row[f"stable: {c}"] for c in CHECKS)
        mine = boxes.get(design)
        dom = [p for p, box in paper.items() if mine is not None and dominates(box, mine)]
        row["dominated by"] = ", ".join(dom)
        row["survives"] = row["stable everywhere"] and mine is not None and not dom
        rows.append(row)
    return pd.DataFrame(rows)


def validate_front(
    front: dict,
    objective: Objective,
    *,
    replicates: int | None = None,
    cache_dir=None,
    workers: int | None = None,
    progress: bool = False,
    seed: int = 0,
) -> dict:
    """Run every check (module doc) of the `front` designs ({name:
    LegDesign}) and the paper's replicates, and judge them. Returns
    ``runs`` (one row per run: role, design, behaviour, check, replicate,
    the runner's summary), ``intervals``, ``paper_best`` (names),
    ``verdicts`` and ``survivors`` ({name: LegDesign})."""
    n = objective.profile.replicates if replicates is None else int(replicates)
    if n < 2:
        raise ValueError(f"validating a front needs at least 2 replicates per design, got {n}")
    tasks = validation_tasks(front, objective, n)
    res = run_grid(tasks, cache_dir, workers=workers, progress=progress, desc="front validation")
    runs = res.summary
    if res.n_failed:
        bad = runs[runs["status"] == FAILED]
        raise RuntimeError(f"{len(bad)} validation run(s) failed: {'; '.join(bad['error'].astype(str).unique()[:3])}")
    iv = intervals(runs, objective, seed=seed)
    ver = verdicts(runs, iv)
    keep = set(ver.loc[ver["survives"], "design"]) if len(ver) else set()
    return {
        "runs": runs,
        "intervals": iv,
        "paper_best": paper_best(iv),
        "verdicts": ver,
        "survivors": {k: v for k, v in front.items() if k in keep},
    }


def beats_paper(validation: dict, seed: int = 0) -> pd.DataFrame:
    """Every surviving design against each of the paper's best: the
    percent change of each objective's replicate mean with its bootstrap
    interval, and ``beats on both`` (both intervals wholly below 0).
    Also whether the design is a gradient (its segments differ)."""
    runs, front = validation["runs"], validation["survivors"]
    reps = runs[(runs["check"] == REPLICATE) & (runs["status"] == OK)]
    means = reps.groupby(["role", "design", "replicate"])[[f"mean_{o}" for o in OBJECTIVES]].mean()
    rows = []
    for name, design in front.items():
        for best in validation["paper_best"]:
            row = {
                "design": name,
                "gradient": len(set(zip(design.densities_g_cm3, design.moduli_gpa))) > 1,
                "against": best,
            }
            both = True
            for obj in OBJECTIVES:
                a = means.loc[("front", name)][f"mean_{obj}"].to_numpy(float)
                b = means.loc[("paper", best)][f"mean_{obj}"].to_numpy(float)
                pct, lo, hi = bootstrap_pct_change(a, b, n_boot=N_BOOT, confidence=CONFIDENCE, seed=seed)
                short = obj.rsplit("_", 1)[0]
                row.update({f"{short} change (%)": pct, f"{short} ci_low (%)": lo, f"{short} ci_high (%)": hi})
                both = both and bool(np.isfinite(hi) and hi < 0)
            row["beats on both"] = both
            rows.append(row)
    return pd.DataFrame(rows)


def answer(validation: dict, table: pd.DataFrame) -> str:
    """The chapter's plain answer, with the numbers of `table`
    (:func:`beats_paper`)."""
    n_front, n_surv = len(validation["verdicts"]), len(validation["survivors"])
    best = ", ".join(validation["paper_best"]) or "none"
    head = f"{n_surv} of {n_front} front designs survive validation; the paper's best designs are {best}."
    wins = table[table["beats on both"] & table["gradient"]] if len(table) else table
    if len(wins) == 0:
        return (
            head
            + " No: no surviving gradient beats any of the paper's best on both objectives with intervals clear of zero."
        )
    parts = []
    for r in wins.to_dict("records"):
        parts.append(
            f"{r['design']} against {r['against']}: tracking {r['tracking_error change (%)']:+.1f} % "
            f"[{r['tracking_error ci_low (%)']:+.1f}, {r['tracking_error ci_high (%)']:+.1f}], power "
            f"{r['power change (%)']:+.1f} % [{r['power ci_low (%)']:+.1f}, {r['power ci_high (%)']:+.1f}]"
        )
    beaten = sorted(set(wins["against"]))
    every = " every one of them" if set(beaten) == set(validation["paper_best"]) else f" {', '.join(beaten)}"
    return head + f" Yes: a gradient beats{every} on both objectives (95 % intervals): " + "; ".join(parts) + "."
