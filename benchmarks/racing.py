"""Does a noise-aware racing study find a front that holds up? Side by side with single draws.

Two studies per sampler seed, on the same budget of simulated seconds:

``racing``
    the robust study: every full-fidelity trial scored on K replicates
    (default 4) on common random numbers (seeds 1000..), screened first on
    one replicate and promoted by successive halving
    (:func:`mat_hopper.optimize.run_racing`, :func:`~mat_hopper.optimize.default_racing`:
    brackets of 9, 1 in 3 promoted). It runs the whole brackets
    ``--budget-s`` buys (a bracket of the quick profile, K = 4: 9 x 12 s +
    3 x 4 x 12 s = 252 s); its spend is its rung records' simulated seconds
    (:func:`mat_hopper.optimize.simulated_seconds`);
``single``
    the single-draw study (``replicates=0``: one unperturbed run per
    trial, :func:`mat_hopper.optimize.run_study`), given as many trials as
    the racing study's actual spend buys (it stops within one trial's
    simulated seconds of it).

Both: the same objective (``--objectives``, default tracking error and hip
power; ``--behaviour``, default ramp; ``--profile``, default quick), the same
space (continuous density and modulus, 3 segments), the paper's designs
enqueued first, TPE seeded with the same seed. Each study's front
(Optuna's ``best_trials``: feasible and non-dominated; for racing only
complete, i.e. full-fidelity, trials) is then validated on fresh seeds
(:func:`mat_hopper.optimize.validate.validate_front`, seeds 0..9 by default, ``--validation-seeds``; never the
search's: 10 replicates, the fewest at which survival is testable; every
check, the paper's nine and each design's mass-matched leg and rigid twin,
Holm). Per study and seed the table gives the front's size, its surviving
fraction and the hypervolume of the validated front: the survivors'
replicate means (over the fresh seeds, each a mean over the behaviours),
against one reference point for every study and seed (the worst of those
means over every survivor of every study and seed, on each objective, times
1.1: a front design that failed validation, with a mean of thousands of W,
would otherwise stretch the box until tracking error no longer counts), computed
by :func:`mat_hopper.optimize.hypervolume` (ours, exact in any number of
objectives; Optuna's own computation is private and no hypervolume package
is installed). A front with no survivor has hypervolume 0. Then the
medians over seeds per study.

Survival is judged under validation's default domination rule, ``margin``
(a paper design dominates a front design when it is significantly better on
one objective, worse on none, and non-inferior within ±10 % on the other),
and, beside it on the same runs, under the ``significance`` rule
(``surviving_fraction_significance``: the margin's non-inferiority
dropped, so that a trade-off short of Holm's threshold counted as
domination), and the fraction of the front that survives *shown* not
dominated (``shown_not_dominated_fraction``: against every paper design,
the design's own advantage on some objective shown by its interval, or
every interval inside ±10 %;
:func:`mat_hopper.optimize.validate.survival_state`), the rest of the
survivors being unresolved.

The full run (5 seeds, 3 brackets each, quick profile, ramp; its results
and run times are in docs/optimizer.md)::

    python benchmarks/racing.py --seeds 5 --budget-s 756 --workers 2 --studies-dir studies-racing --csv racing.csv

``--validate-only`` with the same arguments re-judges the studies stored in
``--studies-dir`` without searching (from the cache). Smaller runs:
``--seeds 3 --budget-s 756``; ``--seeds 2 --budget-s 252`` (one bracket:
8 of its 9 screened trials are the paper's enqueued designs).

All runs go through the result runner's cache (``--cache``; default
``$MAT_HOPPER_CACHE``, else results/cache): the paper's validation runs are
shared by every study and seed, and a rerun costs nothing.
"""

from __future__ import annotations

import argparse
import dataclasses
import math
import os
import sys
import tempfile
import time

import numpy as np
import optuna
import pandas as pd

from mat_hopper.analysis.paired import reachable
from mat_hopper.core.materials import paper_designs
from mat_hopper.experiments.profiles import get_profile
from mat_hopper.optimize import (
    Objective,
    PoolEvaluator,
    RunOptions,
    SearchSpace,
    StudyConfig,
    default_racing,
    hypervolume,
    load_existing,
    open_storage,
    parse_objectives,
    run_racing,
    run_study,
    simulated_seconds,
)
from mat_hopper.optimize._scoring import DEFAULT_REPLICATES
from mat_hopper.optimize.validate import replicate_means, validate_front, verdicts
from mat_hopper.util.atomic import write_csv

VALIDATION_SEEDS = (
    10  # the default of --validation-seeds; fewer and survival is 'untestable' (validate.py's module doc)
)
HV_FACTOR = 1.1  # the reference point: the worst validated value of each objective times this
COLUMNS = [
    "study",
    "seed",
    "complete_trials",
    "simulated_s",
    "front",
    "survivors",
    "surviving_fraction",
    "surviving_fraction_significance",
    "shown_not_dominated_fraction",
    "hv_validated",
    "hv_significance",
    "search_wall_s",
    "validation_wall_s",
]


def objective_of(args, replicates: int) -> Objective:
    """The studies' objective.

    Args:
        args: the parsed command line (profile, run length, behaviours, objectives).
        replicates: K (0: one unperturbed run per trial).

    Returns:
        An Objective.

    Raises:
        ValueError: a bad profile, behaviour or objective.
    """
    profile = get_profile(args.profile)
    if args.duration_s is not None or args.transient_s is not None:
        duration = profile.duration_s if args.duration_s is None else args.duration_s
        transient = min(profile.transient_s, duration / 3) if args.transient_s is None else args.transient_s
        profile = dataclasses.replace(profile, name=f"{profile.name}-{duration:g}s", duration_s=duration,
                                      transient_s=transient)  # fmt: skip
    return Objective(
        behaviours=args.behaviour, profile=profile, replicates=replicates, objectives=parse_objectives(args.objectives)
    )


def bracket_s(config: StudyConfig, racing) -> float:
    """Simulated seconds of one bracket when no run ends early.

    Args:
        config: the racing study.
        racing: its Racing (rungs, eta, screen).

    Returns:
        s: over the rungs, trials x behaviours x replicates x run length.
    """
    n, total = racing.screen, 0.0
    for r in range(len(racing.rungs)):
        ob = racing.objective_at(config.objective, r)
        total += n * len(ob.behaviours) * max(1, ob.replicates) * ob.profile.duration_s
        n = racing.kept(n)
    return total


def race(config: StudyConfig, url: str, seed: int, budget_s: float, args) -> tuple[optuna.Study, float]:
    """The racing study: the whole brackets the budget buys (at least one).

    Args:
        config: the study (K replicates).
        url: its storage.
        seed: the sampler's seed.
        budget_s: simulated seconds.
        args: the command line (workers, cache).

    Returns:
        (study, simulated s spent, from its rung records: a screen run that
        the full rung repeats is charged twice, though the cache runs it once).
    """
    racing = default_racing(config.objective)
    brackets = max(1, round(budget_s / bracket_s(config, racing)))
    with PoolEvaluator(args.cache, workers=args.workers) as evaluator:
        study = run_racing(config, open_storage(url), brackets=brackets, racing=racing, seed=seed, evaluator=evaluator)
    return study, simulated_seconds(study, racing)["simulated_s"]


def single(config: StudyConfig, url: str, seed: int, budget_s: float, args) -> tuple[optuna.Study, float]:
    """The single-draw study, grown until one more trial's simulated
    seconds would pass the budget.

    Args:
        config: the study (replicates 0).
        url: its storage.
        seed: the sampler's seed.
        budget_s: simulated seconds (the racing study's spend).
        args: the command line (workers, cache).

    Returns:
        (study, simulated s spent: its finished trials' runs).
    """
    ob = config.objective
    per_trial = ob.profile.duration_s * len(ob.behaviours)  # a run that falls early costs less
    trials, spent = max(1, int(budget_s // per_trial)), 0.0
    while True:
        opts = RunOptions(trials=trials, workers=args.workers, seed=seed, storage=url, progress=False,
                          cache_dir=args.cache)  # fmt: skip
        run_study(config, opts)
        study = optuna.load_study(study_name=config.name, storage=url)
        spent = sum(
            (t.user_attrs.get("result") or {}).get("simulated_s", 0.0)
            for t in study.get_trials(deepcopy=False)
            if t.state.is_finished()
        )
        more = int((budget_s - spent) // per_trial)
        if more < 1:
            return study, spent
        trials += more


def stored(config: StudyConfig, url: str, seed: int, budget_s: float, args) -> tuple[optuna.Study, float]:
    """A study an earlier run of this benchmark stored (``--validate-only``):
    loaded, not searched further.

    Args:
        config: the study (K replicates: racing; 0: single draws).
        url: its storage.
        seed, budget_s: unused (the signature of :func:`race` and :func:`single`).
        args: the command line (unused).

    Returns:
        (study, simulated s it spent, counted as :func:`race` or :func:`single` counts).

    Raises:
        SystemExit: no such file or study (a one-line message).
    """
    try:  # load_existing refuses a missing file (opening it would create one) and a missing study
        study = load_existing(config.name, url)
    except ValueError as e:
        raise SystemExit(f"racing.py: --validate-only: {e}") from None
    if config.objective.replicates:
        return study, simulated_seconds(study, default_racing(config.objective))["simulated_s"]
    finished = [t for t in study.get_trials(deepcopy=False) if t.state.is_finished()]
    return study, sum((t.user_attrs.get("result") or {}).get("simulated_s", 0.0) for t in finished)


def front_of(study: optuna.Study, config: StudyConfig, label: str) -> dict:
    """The study's front.

    Args:
        study: an optuna.Study of ours.
        config: its StudyConfig (the space builds the designs).
        label: the designs' name prefix (``label#trial``).

    Returns:
        {name: LegDesign} of ``best_trials`` (complete, feasible,
        non-dominated), a design listed twice kept once.
    """
    out, seen = {}, set()
    for t in sorted(study.best_trials, key=lambda t: t.number):
        key = tuple(sorted(t.params.items()))
        if key not in seen:
            seen.add(key)
            out[f"{label}#{t.number}"] = config.space.design(t.params, name=f"{label}#{t.number}")
    return out


def one_seed(seed: int, args, folder: str) -> list[dict]:
    """Both studies of one sampler seed, their fronts validated.

    Args:
        seed: the sampler seed.
        args: the command line.
        folder: where the studies' SQLite files go.

    Returns:
        A row per study (COLUMNS but the hypervolume, whose reference point
        needs every study) carrying the validated designs' replicate means
        (``points``, ``survived``).
    """
    rows, budget = [], args.budget_s
    for study_kind in ("racing", "single"):
        reps = args.replicates if study_kind == "racing" else 0
        config = StudyConfig(f"{study_kind}-s{seed}", SearchSpace(), objective_of(args, reps))
        url = f"sqlite:///{os.path.join(folder, config.name)}.db"
        t0 = time.perf_counter()
        search = stored if args.validate_only else race if study_kind == "racing" else single
        study, spent = search(config, url, seed, budget, args)
        if study_kind == "racing":
            budget = spent  # the single-draw study gets what racing spent
        t1 = time.perf_counter()
        front = front_of(study, config, config.name)
        row = {"study": study_kind, "seed": seed, "simulated_s": spent, "front": len(front)}
        row["complete_trials"] = len(study.get_trials(deepcopy=False, states=(optuna.trial.TrialState.COMPLETE,)))
        row.update(validated(front, objective_of(args, reps), args))
        row.update(search_wall_s=t1 - t0, validation_wall_s=time.perf_counter() - t1)
        rows.append(row)
        print(f"seed {seed} {study_kind}: {row['complete_trials']} complete trials, {spent:.0f} simulated s, "
              f"front {len(front)}, survivors {row['survivors']} ({row['surviving_fraction']:.2f}; "
              f"{row['surviving_fraction_significance']:.2f} under the significance rule); "
              f"{row['search_wall_s']:.0f} + {row['validation_wall_s']:.0f} s", flush=True)  # fmt: skip
    return rows


def validated(front: dict, objective: Objective, args) -> dict:
    """Validate a front on ``args.validation_seeds`` fresh seeds.

    Args:
        front: {name: LegDesign}.
        objective: the studies' objective (profile, behaviours, objectives).
        args: the command line (workers, cache, validation_seeds).

    Returns:
        dict: survivors (count), surviving_fraction (NaN: untestable or no
        front), points (each front design's replicate means averaged over
        the seeds, in the objective's order) and survived (booleans).
    """
    if not front:
        return {"survivors": 0, "surviving_fraction": math.nan, "shown_not_dominated_fraction": math.nan,
                "surviving_fraction_significance": math.nan, "points": np.empty((0, 2)), "names": [],
                "survived": [], "survived_significance": []}  # fmt: skip
    res = validate_front(front, objective, replicates=args.validation_seeds, cache_dir=args.cache, workers=args.workers)
    ver = res["verdicts"]
    # the significance rule, judged on the same runs and table: its fraction beside the margin rule's
    before = verdicts(res["runs"], res["paired"], rule="significance")
    kept_before = set(before.loc[before["survives"].astype(str) == "True", "design"])
    # survivors shown not dominated, not merely not shown dominated (validate.survival_state)
    shown = (ver["survives"].astype(str) == "True") & (ver["against the paper's designs"] == "not dominated")
    testable = not math.isnan(res["surviving_fraction"])
    means = replicate_means(res["runs"], objective)
    names = [n for n in front if ("front", n) in means.index.droplevel("replicate")]
    points = np.array([means.loc[("front", n)].mean().to_numpy(float) for n in names]).reshape(len(names), -1)
    return {
        "survivors": len(res["survivors"]),
        "surviving_fraction": res["surviving_fraction"],
        "shown_not_dominated_fraction": shown.sum() / len(ver) if testable else math.nan,
        "surviving_fraction_significance": len(kept_before) / len(before) if testable else math.nan,
        "points": points,
        "names": names,
        "survived": [n in res["survivors"] for n in names],
        "survived_significance": [n in kept_before for n in names],
    }


def with_hypervolumes(rows: list[dict]) -> tuple[pd.DataFrame, np.ndarray]:
    """Each study's validated hypervolume, against one reference point.

    Args:
        rows: :func:`one_seed`'s rows of every seed.

    Returns:
        (the table, COLUMNS; the reference point: the worst replicate mean
        of any surviving design, of any study and seed, on each objective,
        times HV_FACTOR, the objectives being positive).
    """
    for r in rows:
        survived = np.asarray(r["survived"], bool)
        r["kept"] = r["points"][survived] if len(r["points"]) else r["points"]
    pts = [r["kept"] for r in rows if len(r["kept"])]
    reference = HV_FACTOR * np.nanmax(np.vstack(pts), axis=0) if pts else np.array([])
    for r in rows:
        r["hv_validated"] = hypervolume(r["kept"], reference) if len(r["kept"]) else 0.0
        sig = np.asarray(r.get("survived_significance", []), bool)  # the significance rule, same reference point
        r["hv_significance"] = hypervolume(r["points"][sig], reference) if sig.any() else 0.0
    return pd.DataFrame(rows)[COLUMNS], reference


def parse_args(argv=None) -> argparse.Namespace:
    """The command line (module doc).

    Args:
        argv: the arguments (None: sys.argv).

    Returns:
        The namespace, with ``seed_list``.
    """
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--seeds", default="5", help="sampler seeds: a count N (0..N-1) or a comma list (5)")
    ap.add_argument("--budget-s", type=float, default=252.0,
                    help="simulated seconds per study (252: one racing bracket on the quick profile)")  # fmt: skip
    ap.add_argument("--profile", default="quick", help="run profile (quick)")
    ap.add_argument("--duration-s", type=float, help="run length, s (default the profile's)")
    ap.add_argument(
        "--transient-s", type=float, help="transient, s (default the profile's, at most a third of the run)"
    )
    ap.add_argument("--behaviour", default="ramp", help="behaviour(s), comma-separated (ramp)")
    ap.add_argument("--objectives", default="tracking_error_m,power_w", help="two or three metrics (the default's)")
    ap.add_argument("--replicates", type=int, default=DEFAULT_REPLICATES, help="K of the racing study's full fidelity")
    ap.add_argument("--validation-seeds", type=int, default=VALIDATION_SEEDS,
                    help=f"fresh seeds of the validation ({VALIDATION_SEEDS}; survival is testable from 10 for 2 "
                    "objectives (18 comparisons with the paper's designs), from 11 for 3: fewer warn at once)")  # fmt: skip
    ap.add_argument("--workers", type=int, default=2, help="processes that simulate (2)")
    ap.add_argument("--cache", help="result cache (default $MAT_HOPPER_CACHE, else results/cache)")
    ap.add_argument("--studies-dir", help="where the studies' SQLite files go (default a temporary folder)")
    ap.add_argument("--csv", help="write the table here")
    ap.add_argument("--validate-only", action="store_true",
                    help="re-validate the studies stored in --studies-dir by an earlier run; search nothing")  # fmt: skip
    args = ap.parse_args(argv)
    text = args.seeds.strip()
    try:
        args.seed_list = list(range(int(text))) if text.isdigit() else [int(s) for s in text.split(",") if s.strip()]
    except ValueError:
        ap.error(f"--seeds must be a count N or a comma list of seeds >= 0, got {args.seeds!r}")
    if not args.seed_list or min(args.seed_list) < 0 or not (math.isfinite(args.budget_s) and args.budget_s > 0):
        ap.error("give --seeds >= 1 (seeds >= 0) and a finite --budget-s > 0")
    if args.workers < 1 or args.replicates < 1:
        ap.error(f"--workers and --replicates must be >= 1, got {args.workers} and {args.replicates}")
    if not 2 <= args.validation_seeds <= 1000:
        ap.error(f"--validation-seeds must be in [2, 1000] (paired comparisons), got {args.validation_seeds}")
    if args.validate_only and not (args.studies_dir and os.path.isdir(args.studies_dir)):
        ap.error("--validate-only needs --studies-dir, an existing folder of an earlier run's studies")
    try:  # bad settings fail here, before any run
        objective = objective_of(args, args.replicates)
    except ValueError as e:
        ap.error(str(e))
    family = len(paper_designs()) * len(objective.objectives)  # survival's Holm family
    n = args.validation_seeds
    if not reachable(n, family):  # said now, not after the search (a CI-sized run does this on purpose)
        print(f"racing.py: warning: --validation-seeds {n} cannot make survival testable for {family} comparisons "
              "with the paper's designs (an exact sign-flip test's smallest p is 2 / 2^n): every fraction will be NaN",
              file=sys.stderr, flush=True)  # fmt: skip
    return args


def main(argv=None) -> pd.DataFrame:
    """Run the benchmark (module doc).

    Args:
        argv: the arguments (None: sys.argv).

    Returns:
        The table (COLUMNS), one row per study and seed.
    """
    args = parse_args(argv)
    folder = args.studies_dir or tempfile.mkdtemp(prefix="mat-hopper-racing-")
    os.makedirs(folder, exist_ok=True)
    optuna.logging.set_verbosity(optuna.logging.WARNING)
    t0 = time.perf_counter()
    rows = [r for seed in args.seed_list for r in one_seed(seed, args, folder)]
    table, reference = with_hypervolumes(rows)
    ob = objective_of(args, args.replicates)
    print(
        f"\n{','.join(ob.behaviours)}, {ob.profile.name} profile ({ob.profile.duration_s:g} s runs), budget "
        f"{args.budget_s:g} simulated s, racing K = {args.replicates}, validation on {args.validation_seeds} fresh seeds; "
        f"hypervolume reference ({', '.join(f'{v:.4g}' for v in reference)}) in {', '.join(ob.objectives)}"
    )
    print(table.to_string(index=False, float_format=lambda v: f"{v:.4g}"))
    cols = ["front", "surviving_fraction", "shown_not_dominated_fraction", "surviving_fraction_significance"]
    cols += ["hv_validated", "hv_significance"]
    medians = table.groupby("study", sort=False)[cols].median()
    print("\nmedians over seeds:")
    print(medians.to_string(float_format=lambda v: f"{v:.4g}"))
    print(f"wall {time.perf_counter() - t0:.0f} s")
    if args.csv:
        write_csv(table, args.csv)
        print(f"wrote {args.csv}")
    return table


if __name__ == "__main__":
    main()
