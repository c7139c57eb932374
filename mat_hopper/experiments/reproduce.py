"""The reproduction pipeline: the paper's four experiments, end to end
(``mat-hopper reproduce`` is its command line, :mod:`mat_hopper.cli.reproduce`).

Runs the chosen experiments under one profile (cached, resumable, in
parallel; see :mod:`mat_hopper.experiments.runner`), writes their tables as CSV into
the output folder (default ``results/<profile>/``), then the figures and
the claims table through :mod:`mat_hopper.viz.figures` and
:mod:`mat_hopper.analysis.claims`. Tables (see :func:`reproduce`):

- ``exp{1,2,3}_hops.csv``: one row per scored hop cycle of every run;
- ``exp{1,2,3}_runs.csv``: one row per run (outcome, means, energy);
- ``stability.csv``: one row per design of the map; ``stability_tries.csv``:
  every try; ``stability_agreement.csv``: analytic estimate vs measured;
- ``robustness_hops.csv``, ``robustness_runs.csv``: the robustness study's
  runs; ``robustness.csv``: each quantity per variant, classified;
  ``robustness_summary.csv``: per quantity, how many variants keep, move
  or flip it (:mod:`mat_hopper.analysis.robustness`);
- ``controls_hops.csv``, ``controls_runs.csv``: the claims' designs beside
  their rigid twins and mass- and inertia-matched legs on shared seeds
  (:mod:`mat_hopper.experiments.controls`), read by the claims table's
  beyond-mass columns.

By default every hopping experiment also runs the profile's perturbed
replicates (``Profile.replicates``), the claims' inferential basis.
"""

from __future__ import annotations

import os
import time
from dataclasses import dataclass, field

import pandas as pd

from ..core.materials import CONVENTIONS, check_convention
from ..util.atomic import write_csv
from ..util.limits import check_total_steps, task_steps
from .paper import get_experiment, parse_experiments
from .profiles import FIGURE_REPLICATES, check_replicates, get_profile, resolve_profile
from .runner import Runner, check_workers


@dataclass
class Reproduction:
    """What :func:`reproduce` made: tables by name (the CSV file names
    without .csv), files written, wall seconds per experiment (for the
    log and benchmarks; never part of a table), failed task counts and,
    per experiment, its runs that diverged (:func:`diverged_runs`)."""

    profile: str
    out_dir: str
    tables: dict = field(default_factory=dict)
    files: list = field(default_factory=list)
    wall_s: dict = field(default_factory=dict)
    failed: dict = field(default_factory=dict)
    computed: dict = field(default_factory=dict)
    diverged: dict = field(default_factory=dict)
    conventions: tuple = ("paper",)  # those asked for: the claims table has rows for these only


def default_out_dir(profile_name: str) -> str:
    """The default output folder of a reproduction.

    Args:
        profile_name: the profile's name (e.g. ``"paper"``).

    Returns:
        ``results/<profile_name>``, relative to the working folder.
    """
    return os.path.join("results", profile_name)


def reproduce(
    profile=None,
    experiments=None,
    out_dir: str | None = None,
    *,
    workers: int | None = None,
    scheduler=None,
    replicates: int | None = None,
    cache_dir: str | None = None,
    progress: bool = True,
    figures: bool = True,
    conventions=("paper",),
    log=print,
) -> Reproduction:
    """Run experiments (names or '1,2,3,stability'; default all) under a
    profile (name or Profile; default $MAT_HOPPER_PROFILE or paper), write
    their tables into out_dir, then figures and claims. Every input is
    checked before any work starts.

    Args:
        profile: a Profile or its name (None: $MAT_HOPPER_PROFILE, else ``paper``).
        experiments: comma-separated names or aliases (``"1,2,3,stability"``),
            a list of them, or None (or ``"all"``) for every experiment
            (:func:`~mat_hopper.experiments.paper.parse_experiments`).
        out_dir: the folder for the CSV tables, figures and claims (created if
            missing); None: :func:`default_out_dir`.
        workers: local worker processes (an integer >= 1; default: every core);
            not with `scheduler`.
        scheduler: a Dask scheduler address (``tcp://host:8786``) or a
            ``distributed.Client``; None runs local processes.
        replicates: perturbed replicates per design and behaviour (an integer
            >= 0); None: the profile's ``replicates``.
        cache_dir: the result cache folder (default: $MAT_HOPPER_CACHE, else
            ``results/cache``).
        progress: show a progress bar per experiment.
        figures: also write the figures and the claims table.
        conventions: stiffness conventions of the hopping experiments (1-3),
            e.g. ("paper", "axial"), or one comma-separated string; axial runs use
            the profile's axial_timestep_s. The stability map uses the profile's own
            convention. The claims table has rows for the conventions asked for (a
            claim whose runs are missing among them reads "not run").
        log: called with one line of text per step (the profile, each
            experiment's counts and failed tasks, the stability agreement, the
            figures).

    Returns:
        The :class:`Reproduction`: its tables by name (those of the module
        doc, plus ``claims`` with figures), the files written, wall seconds
        per experiment (and ``figures``), and failed and computed task counts
        per experiment. Failed tasks are counted and logged, not raised.

    Raises:
        ValueError: an unknown profile, experiment or convention, no
            convention, invalid `replicates` or `workers`, an `out_dir` that
            exists and is not a folder, a plan above the physics-step limit
            (:func:`mat_hopper.util.limits.check_total_steps`), `workers` together
            with `scheduler`, an invalid or unreachable scheduler, or
            $MAT_HOPPER_PROFILE or $MAT_HOPPER_CACHE set but empty; all
            of them before `out_dir` is made.
    """
    prof = resolve_profile(profile)
    conventions = check_conventions(conventions)
    names = parse_experiments(
        experiments if experiments is None or isinstance(experiments, str) else ",".join(experiments)
    )
    replicates = prof.replicates if replicates is None else check_replicates(replicates)
    check_workers(workers)
    out_dir = out_dir or default_out_dir(prof.name)
    if os.path.exists(out_dir) and not os.path.isdir(out_dir):
        raise ValueError(f"--out {out_dir!r} exists and is not a folder")
    check_total_steps(planned_steps(prof, names, conventions, replicates), f"replicates={replicates}")
    tasks = experiment_tasks(prof, names, conventions, replicates)
    # the runner checks workers against scheduler, the scheduler and the cache
    # folder; a scheduler is reached now: all before the results folder is made
    with Runner(cache_dir, workers=workers, scheduler=scheduler, progress=progress) as runner:
        if scheduler is not None:
            runner._get_client()
        os.makedirs(out_dir, exist_ok=True)
        rep = Reproduction(prof.name, out_dir, conventions=conventions)
        log(
            f"profile {prof.name}: {prof.duration_s:g} s runs, transient {prof.transient_s:g} s, "
            f"dt {prof.timestep_s:g} s; stability grid {prof.stability_grid_size}x{prof.stability_grid_size}; "
            f"replicates {replicates}; conventions {', '.join(conventions)}; out {out_dir}"
        )
        for name in names:
            _run_experiment(runner, name, tasks[name], rep, log)
    if "stability_agreement" in rep.tables:
        _log_agreement(rep.tables["stability_agreement"], log)
    if figures:
        t0 = time.perf_counter()
        rep.files += _figures_and_claims(rep, log)
        rep.wall_s["figures"] = time.perf_counter() - t0
    return rep


def _run_experiment(runner, name: str, tasks, rep: Reproduction, log) -> None:
    """Run one experiment's tasks, write its tables into ``rep.out_dir`` and
    record them, its wall time and its counts in `rep` (reproduce's steps)."""
    t0 = time.perf_counter()
    res = runner.run(tasks, desc=name)
    wall = time.perf_counter() - t0
    rep.wall_s[name] = wall
    rep.failed[name] = res.n_failed
    rep.diverged[name] = diverged_runs(name, res.summary)
    rep.computed[name] = res.n_computed
    for tname, frame in _tables_of(name, res).items():
        path = os.path.join(rep.out_dir, f"{tname}.csv")
        write_csv(frame, path)
        rep.tables[tname] = frame
        rep.files.append(path)
    log(
        f"{name}: {res.n_tasks} tasks ({res.n_unique} unique): {res.n_cached} cached, "
        f"{res.n_computed - res.n_failed} computed, {res.n_failed} failed in {wall:.1f} s wall"
    )
    if res.n_failed:
        bad = res.summary[res.summary["status"] == "failed"]
        for row in bad.head(5).itertuples():
            log(f"  failed: {row.design} {getattr(row, 'behaviour', '')}: {row.error}")
    _log_unusable(name, res.summary, log)


def diverged_runs(name: str, summary) -> int:
    """How many of an experiment's runs diverged numerically (after a fall
    or not; :func:`mat_hopper.analysis.stats.unusable_runs`): the count
    that sets ``mat-hopper reproduce``'s exit status. The stability map's
    tries diverge by design (its ladder goes above the stable steps on
    purpose) and count 0.

    Args:
        name: the experiment's canonical name (``exp1``, ``stability``, ...).
        summary: its run-summary table (one row per run), or None.

    Returns:
        The number of its runs that diverged.
    """
    from ..analysis.stats import unusable_runs

    if name == "stability" or summary is None or not len(summary):
        return 0
    bad = unusable_runs(summary)
    return int(bad["why"].astype(str).str.contains("unstable").sum()) if len(bad) else 0


def _log_unusable(name: str, summary, log) -> None:
    """One line counting the experiment's runs that diverged or fell (they
    are results of the study, not failures: the claims leave them out and
    name them), and up to 5 of them with why."""
    from ..analysis.stats import unusable_runs

    bad = unusable_runs(summary)
    bad = bad[bad["why"] != "failed"] if len(bad) else bad
    if not len(bad):
        return
    log(f"  {len(bad)} runs diverged or fell (left out of every claim and named in claims.md), e.g.:")
    for row in bad.head(5).itertuples():
        log(f"    {row.design} {row.behaviour}: {row.why}")


def experiment_tasks(profile, names, conventions=("paper",), replicates: int | None = None) -> dict:
    """The tasks :func:`reproduce` runs, per experiment, without running any
    (its own task list; :mod:`mat_hopper.experiments.plan` counts them).

    Args:
        profile: a Profile or its name.
        names: canonical experiment names, as
            :func:`~mat_hopper.experiments.paper.parse_experiments` returns them.
        conventions: stiffness conventions of the hopping experiments (1-3).
        replicates: perturbed replicates per design and behaviour (>= 0);
            None: the profile's.

    Returns:
        dict {experiment name: list of runner tasks}, in the order of `names`;
        the hopping experiments under every convention given.

    Raises:
        ValueError: an unknown profile or experiment, or invalid `replicates`.
    """
    prof = get_profile(profile)
    replicates = prof.replicates if replicates is None else check_replicates(replicates)
    return _tasks(prof, names, conventions, replicates)


def _tasks(prof, names, conventions, replicates) -> dict:
    """{experiment: its tasks}; the hopping experiments under every convention asked for."""
    plan = {n: get_experiment(n) for n in names}
    return {
        n: (
            e.tasks(prof, replicates)
            if n in ("stability", "robustness")
            else [t for c in conventions for t in e.tasks(prof.for_convention(c), replicates)]
        )
        for n, e in plan.items()
    }


def _tables_of(name: str, res) -> dict:
    """{table name: table} one experiment's run makes (module doc)."""
    if name == "stability":
        from ..physics.stability import agreement

        return {
            "stability": res.summary,
            "stability_tries": res.tables,
            "stability_agreement": agreement(res.summary),
        }
    if name == "robustness":
        from ..analysis import robustness

        values = robustness.quantity_values(res.tables, res.summary)
        table = robustness.robustness_table(values)
        return {
            "robustness_hops": res.tables,
            "robustness_runs": res.summary,
            "robustness": table,
            "robustness_summary": robustness.summary(table),
        }
    return {f"{name}_hops": res.tables, f"{name}_runs": res.summary}


def _log_agreement(a: pd.DataFrame, log) -> None:
    """One log line per estimate: how well it predicts the measured stable steps."""
    for est in ("spring", "combined"):
        q = dict(zip(a.loc[a["estimate"] == est, "quantity"], a.loc[a["estimate"] == est, "value"]))
        log(
            f"stability, {est} estimate vs measured: "
            + ", ".join(
                f"{k} {q[k]:.3g}"
                for k in ("median_ratio_measured_to_estimate", "loglog_pearson_r", "fraction_within_factor_2")
                if k in q
            )
        )


def _figures_and_claims(rep: Reproduction, log) -> list:
    """Figures (:func:`mat_hopper.viz.figures.write_figures`) and the claims table
    (:func:`mat_hopper.analysis.claims.claims_table`, ``claims.md`` and ``claims.csv``)
    from the tables of this reproduction."""
    from ..analysis import claims
    from ..viz import figures as plots

    files = [str(p) for p in plots.write_figures(rep.tables, rep.out_dir)]
    hops = _concat([rep.tables.get(f"{e}_hops") for e in ("exp1", "exp2", "exp3")])
    runs = _concat([rep.tables.get(f"{e}_runs") for e in ("exp1", "exp2", "exp3")])
    stab = rep.tables.get("stability")
    from ..analysis.robustness import FINE_LABEL, fine_step_hops

    fine = fine_step_hops(rep.tables.get("robustness_hops"))
    table = claims.claims_table(
        hops,
        runs,
        stab,
        conventions=rep.conventions,
        fine_hops=fine,
        fine_label=FINE_LABEL if fine is not None else "",
        controls=rep.tables.get("controls_hops"),
        control_runs=rep.tables.get("controls_runs"),
    )
    files += [str(p) for p in claims.write_claims(table, rep.out_dir)]
    rep.tables["claims"] = table
    log(f"figures and claims: {len(files)} files in {rep.out_dir}")
    return files


def planned_steps(profile, names, conventions, replicates: int) -> float:
    """Physics steps a reproduction would take at most (every task run,
    nothing cached), without building its whole task list: the tasks grow
    linearly with the replicates from 3 on (the controls run at least 2,
    and the profile's number when given 0; the grids no test reads stop at
    their figure seeds, :data:`~mat_hopper.experiments.profiles.FIGURE_REPLICATES`,
    3), so the plans at 3 and 4 replicates give the rest. Used to refuse,
    before any work, runs beyond :data:`mat_hopper.util.limits.MAX_TOTAL_STEPS`.

    Args:
        profile: a Profile or its name (the command resolves $MAT_HOPPER_PROFILE).
        names: canonical experiment names, as
            :func:`~mat_hopper.experiments.paper.parse_experiments` returns them.
        conventions: stiffness conventions of the hopping experiments.
        replicates: perturbed replicates per design and behaviour (>= 0).

    Returns:
        The physics steps (:func:`mat_hopper.util.limits.task_steps` summed over
        every task): exact for replicates <= 4, extrapolated linearly from 3
        and 4 replicates above.

    Raises:
        ValueError: an unknown profile, experiment or convention, or (for an
            experiment that takes replicates) `replicates` < 0 or not an integer.
    """
    prof = get_profile(profile)

    def exact(r: int) -> float:
        return sum(task_steps(t) for ts in _tasks(prof, names, conventions, r).values() for t in ts)

    if replicates <= FIGURE_REPLICATES + 1:  # 0 means "the profile's" to the controls: count it as it runs
        return exact(replicates)
    at = [exact(FIGURE_REPLICATES), exact(FIGURE_REPLICATES + 1)]
    return at[0] + (replicates - FIGURE_REPLICATES) * (at[1] - at[0])


def check_conventions(conventions) -> tuple:
    """The stiffness conventions of a reproduction, each once, in canonical spelling.

    Args:
        conventions: names (any case) as a sequence or a comma-separated string.

    Returns:
        A tuple of canonical convention names, in the order given, without repeats.

    Raises:
        ValueError: an unknown convention, or none given.
    """
    if isinstance(conventions, str):
        conventions = [c.strip() for c in conventions.split(",") if c.strip()]
    out = tuple(dict.fromkeys(check_convention(c) for c in conventions))
    if not out:
        raise ValueError(f"--conventions needs at least one of {', '.join(CONVENTIONS)}")
    return out


def _concat(frames) -> pd.DataFrame | None:
    frames = [f for f in frames if f is not None and len(f)]
    return pd.concat(frames, ignore_index=True) if frames else None


def run_experiments(
    profile,
    experiments: str,
    *,
    out_dir=None,
    cache_dir=None,
    replicates: int | None = None,
    workers: int | None = None,
    quiet: bool = False,
) -> dict[str, pd.DataFrame]:
    """Run (or load from the cache) experiments ('1', '2', '3',
    'stability', comma-separated) under a profile with :func:`reproduce`
    (tables only, no figures, no log), which also writes their tables to
    `out_dir` (default ``results/<profile>/``). Returns the tables by name
    (``exp1_hops``, ``exp1_runs``, ..., ``stability``,
    ``stability_agreement``). A task that raised (not a diverged run: that
    is a result) raises RuntimeError. Prints one line per experiment (runs
    computed now / loaded from the cache) unless quiet.

    Args:
        profile: a Profile or its name (None: $MAT_HOPPER_PROFILE, else ``paper``).
        experiments: comma-separated names or aliases (None or ``"all"``: every
            experiment).
        out_dir: the folder for the CSV tables; None: ``results/<profile>/``.
        cache_dir: the result cache folder (default: $MAT_HOPPER_CACHE, else
            ``results/cache``).
        replicates: perturbed replicates per design and behaviour; None: the
            profile's.
        workers: local worker processes (default: every core).
        quiet: print nothing.

    Returns:
        dict of DataFrames by table name (:attr:`Reproduction.tables`), under
        the ``paper`` convention only.

    Raises:
        RuntimeError: a task raised (the experiments with failed tasks named).
        ValueError: as :func:`reproduce`.
    """
    prof = resolve_profile(profile)
    out_dir = str(out_dir) if out_dir is not None else None
    cache_dir = str(cache_dir) if cache_dir is not None else None
    rep = reproduce(
        prof,
        experiments,
        out_dir,
        workers=workers,
        replicates=replicates,
        cache_dir=cache_dir,
        progress=False,
        figures=False,
        log=lambda *a, **k: None,
    )
    failed = {k: v for k, v in rep.failed.items() if v}
    if failed:
        raise RuntimeError(f"tasks failed in {failed}; see the error column of the runs tables in {rep.out_dir}")
    if not quiet:
        where = os.path.relpath(cache_dir) if cache_dir else "the cache"
        for name, n in rep.computed.items():
            runs = rep.tables.get(f"{name}_runs", rep.tables.get(name))
            total = len(runs) if runs is not None else n
            print(f"{name} ({prof.name} profile): {total} tasks, {n} computed now, the rest loaded from {where}/")
    return rep.tables
