"""``mat-hopper plan``: every cached run the book's chapters will request,
counted and looked up in the result cache, before any run
(:mod:`mat_hopper.experiments.plan`; chapter 9's optimizer study and
chapter 9c's codesign from :mod:`mat_hopper.optimize.book_plan`)."""

from __future__ import annotations

import os

from ..experiments.cache import CACHE_ENV, DEFAULT_CACHE_DIR
from ..experiments.plan import US_PER_STEP
from ..util.limits import check_workers
from ._checks import check_output_file, write_table
from ._options import add_force, add_no_progress, add_profile, check_force_used, profile_of

HELP = "count the book's runs per chapter before any run: shared, cached, physics steps, core-hours"


def cmd_plan(args) -> int:
    check_force_used(args, {"--csv": args.csv})
    check_output_file(args.csv, "--csv", stdout=True, force=args.force)  # before any work
    if not args.us_per_step > 0:
        raise ValueError(f"--us-per-step must be a number > 0 (microseconds per physics step), got {args.us_per_step}")
    if args.workers is not None and not args.run:
        raise ValueError("--workers is for --run (the plan alone runs nothing)")
    check_workers(args.workers, "--workers")
    profile = profile_of(args.profile)
    from ..experiments.plan import format_plan, plan
    from ..optimize.book_plan import chapters
    from ._checks import cache_folder

    folder, flag = cache_folder(args.cache)  # a file, or an empty $MAT_HOPPER_CACHE, is refused
    table = plan(profile, cache_dir=folder, chapters=chapters())
    print(f"plan of the book's runs, profile {profile.name} (nothing run; cache {folder})")
    if not os.path.isdir(folder):  # a mistyped folder must not read as "nothing cached yet"
        print(f"note: {flag} {folder} does not exist: no run is cached there")
    print(format_plan(table, us_per_step=args.us_per_step))
    if args.csv:
        print(f"wrote {len(table)} rows to {write_table(table, args.csv)}")
    return _run(args, profile, folder, chapters()) if args.run else 0


def _run(args, profile, folder: str, registry) -> int:
    """--run: every planned run known before any run, computed into the
    cache in one pool, longest first (:func:`mat_hopper.experiments.plan.book_tasks`);
    exit 1 when a run failed (raised), 0 otherwise (a run that diverged
    or fell is a result the chapters report)."""
    from ..experiments.plan import book_tasks
    from ..experiments.runner import run_grid

    tasks = book_tasks(profile, registry)
    print(f"computing {len(tasks)} planned runs into {folder}, longest first")
    res = run_grid(tasks, folder, workers=args.workers, progress=not args.no_progress, desc="book runs")
    print(f"{res.n_unique} runs: {res.n_cached} were cached, {res.n_computed} computed, {res.n_failed} failed")
    return 1 if res.n_failed else 0


def register_cli(sub) -> None:
    p = sub.add_parser(
        "plan",
        help=HELP,
        description="The runs of the book (the notebooks of _toc.yml, in order) under a profile, counted before "
        "any run: per chapter and task kind, its runs, those an earlier chapter already requested (one cache key, "
        "computed once), those in the result cache, simulated seconds, physics steps and time steps; then the "
        "total, with core-hours estimated from a cost per physics step. Cells that simulate outside the cache are "
        "named, not counted; the optimizer study's runs are an estimate.",
    )
    add_profile(p)
    p.add_argument(
        "--cache", default=None, help=f"result cache folder (default ${CACHE_ENV}, else {DEFAULT_CACHE_DIR})"
    )
    p.add_argument(
        "--csv", help="write the plan's table here, one row per chapter and task kind (- for standard output)"
    )
    p.add_argument(
        "--us-per-step",
        type=float,
        default=US_PER_STEP,
        help=f"wall time of one physics step on one core, microseconds, for the core-hours (default {US_PER_STEP:g})",
    )
    p.add_argument(
        "--run",
        action="store_true",
        help="then compute every planned run known before any run into the cache, in one pool, longest first "
        "(what `make book` does before the notebooks execute; the optimizer's sampled trials are left to their "
        "chapters); exit 1 when a run failed",
    )
    p.add_argument("--workers", type=int, default=None, help="local worker processes for --run (default: every core)")
    add_no_progress(p)
    add_force(p)
    p.set_defaults(func=cmd_plan)
