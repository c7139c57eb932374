"""``mat-hopper reproduce``: the command line of
:func:`mat_hopper.experiments.reproduce.reproduce`."""

from __future__ import annotations

import os
import sys

from ..core.materials import CONVENTIONS
from ..experiments.cache import CACHE_ENV, DEFAULT_CACHE_DIR
from ..experiments.paper import EXPERIMENT_SPELLINGS, experiment_name, experiment_spellings
from ..experiments.profiles import PROFILES
from ..experiments.reproduce import default_out_dir, reproduce
from ..util.limits import check_total_steps, check_workers
from ._checks import (
    cache_folder,
    check_distinct_paths,
    check_name_list,
    check_no_outputs_in,
    check_output_dir,
    is_inside,
    nothing_left_behind,
)
from ._options import add_force, add_no_progress, add_profile, profile_of, suggesting

# The exit rule, as simulate's and compare's: a run that diverged is a result
# the tables and claims record, and still exits 1; the map's tries do not count.
EXIT_STATUS = (
    "Exit status: 0 when every task ran and no run diverged; 1 when a task failed or any run of experiments 1-3, "
    "the controls or robustness diverged (as simulate and compare: the tables, figures and claims are still "
    "written; the claims leave those runs out and name them; the stability map's tries diverge by design and do "
    "not count); 2 for bad input."
)

# What a reproduction writes into --out (experiments.reproduce): its tables,
# the claims and the figures folder; any of them there is an earlier run's.
REPRODUCTION_FILES = ("*.csv", "claims.md", os.path.join("figures", "*"))


def _connect(address: str):
    """A Dask client of the scheduler at `address`, before anything is
    written (ValueError, one line, if it cannot be reached)."""
    if not str(address).strip():
        raise ValueError("--scheduler address is empty (e.g. tcp://127.0.0.1:8786)")
    try:
        from distributed import Client
    except ImportError:
        raise ValueError("--scheduler needs Dask distributed (pip install 'mat-hopper[cluster]')") from None
    try:
        return Client(address, timeout="20s")
    except (OSError, TimeoutError, ValueError) as e:
        cause = str(e).strip().splitlines()[0] if str(e).strip() else type(e).__name__
        raise ValueError(f"cannot reach the Dask scheduler at {address!r}: {cause}") from None


def _check_size(profile, args) -> None:
    """The whole reproduction's physics steps, before any work (mat_hopper.util.limits)."""
    from ..experiments.paper import parse_experiments
    from ..experiments.profiles import check_replicates
    from ..experiments.reproduce import check_conventions, planned_steps

    try:
        replicates = profile.replicates if args.replicates is None else check_replicates(args.replicates)
    except ValueError:
        raise ValueError(f"--replicates must be an integer >= 0, got {args.replicates!r}") from None
    names = parse_experiments(args.experiments)
    steps = planned_steps(profile, names, check_conventions(args.conventions), replicates)
    what = f"--replicates {replicates}" if args.replicates is not None else f"--experiments {args.experiments}"
    check_total_steps(steps, what, "lower --replicates, or run fewer --experiments or --conventions")


def _warn_stable_step(profile, args) -> None:
    """Before any work: one line on stderr naming the designs whose step
    lies above their analytic stable step
    (:func:`mat_hopper.core.timestep.check_stable_step`); their runs may
    diverge, and the tables record it (the protocol keeps its step). The
    stability map is left out: its ladder goes above the bounds on purpose."""
    from ..core.timestep import check_stable_step
    from ..experiments.paper import get_experiment, parse_experiments
    from ..experiments.reproduce import check_conventions

    over, seen, first = [], set(), None
    conventions = check_conventions(args.conventions)
    for name in parse_experiments(args.experiments):
        if name == "stability":
            continue
        exp = get_experiment(name)
        profiles = [profile] if name == "robustness" else [profile.for_convention(c) for c in conventions]
        for task in (t for p in profiles for t in exp.tasks(p, 0)):
            design, settings = getattr(task, "design", None), getattr(task, "settings", None)
            key = (design, settings and (settings.timestep_s, settings.substeps, settings.convention))
            if design is None or settings is None or key in seen:
                continue
            seen.add(key)
            if check_stable_step(design, settings):
                over.append(f"{name} {design.name}")
                first = first or (design, settings.convention)
    if over:
        names = ", ".join(over[:6]) + (f" and {len(over) - 6} more" if len(over) > 6 else "")
        print(
            f"mat-hopper reproduce: warning: {len(over)} designs run above their analytic stable step ({names}): "
            "they may diverge, and the tables record it (the protocol keeps its step; "
            f"`{_auto_command(*first)}` runs {first[0].name} at the automatic step)",
            file=sys.stderr,
            flush=True,
        )


def _auto_command(design, convention: str) -> str:
    """simulate at the automatic step of `design` (by name where simulate
    knows it, else by its --density and --modulus)."""
    from ._rerun import simulate_command

    return simulate_command(design, timestep="auto", convention=None if convention == "paper" else convention)


# The experiments each option acts on (experiments/reproduce.py's _tasks and
# experiments/paper.py): the stability map takes no replicates, no push and
# no conventions; robustness takes replicates (and their push) but runs its
# own conventions; the controls run at least 2 replicates (so a push) always.
_TAKE_CONVENTIONS = ("exp1", "exp2", "exp3", "exp2-gibson-ashby", "controls")
_TAKE_REPLICATES = ("exp1", "exp2", "exp3", "exp2-gibson-ashby", "robustness", "controls")
_ALWAYS_REPLICATED = ("controls",)


def _check_all_alone(text) -> None:
    """--experiments "all" names every experiment: with others it is a mistake."""
    items = [p.strip().lower() for p in str(text).split(",")] if text is not None else []
    if "all" in items and len(items) > 1:
        raise ValueError(
            f"--experiments: 'all' cannot be combined with other experiments, got {text!r}; "
            "give all alone or list the experiments"
        )


def _check_used(profile, args) -> None:
    """--conventions, --replicates and --push-scale only where a selected
    experiment uses them (ValueError naming both options)."""
    from ..experiments.paper import parse_experiments

    names = parse_experiments(args.experiments)
    chosen = f"--experiments {args.experiments}"
    if args.conventions is not None and not set(names) & set(_TAKE_CONVENTIONS):
        raise ValueError(
            f"--conventions has no effect on {chosen}: it sets experiments 1, 2, 3, 2-gibson-ashby and controls"
        )
    if args.replicates is not None and not set(names) & set(_TAKE_REPLICATES):
        raise ValueError(f"--replicates has no effect on {chosen}: the stability map runs no replicates")
    if args.push_scale is None:
        return
    replicates = profile.replicates if args.replicates is None else args.replicates
    if not set(names) & set(_TAKE_REPLICATES):
        raise ValueError(f"--push-scale has no effect on {chosen}: the push acts on replicates only")
    if replicates == 0 and not set(names) & set(_ALWAYS_REPLICATED):
        raise ValueError(
            f"--push-scale has no effect with --replicates 0 on {chosen}: the push acts on replicates only"
        )


def cmd_reproduce(args) -> int:
    profile = profile_of(args.profile)
    _check_all_alone(args.experiments)
    if args.push_scale is not None:
        from dataclasses import replace

        from ..core.perturbations import check_push_scale

        profile = replace(profile, push_scale=check_push_scale(args.push_scale, "--push-scale"))
    every = args.experiments is not None and args.experiments.strip().lower() == "all"
    spellings = [sp for sps in EXPERIMENT_SPELLINGS.values() for sp in sps]
    canonical = None if every else suggesting(experiment_name, spellings)
    check_name_list(args.experiments, "--experiments", canonical)  # "4,stability": twice; "robustnes": did you mean
    check_name_list(args.conventions, "--conventions")
    _check_used(profile, args)
    if args.conventions is None:
        args.conventions = "paper"
    if args.workers is not None and args.scheduler:
        raise ValueError("give either --workers (local processes) or --scheduler (Dask), not both")
    check_workers(args.workers)
    out = check_output_dir(args.out or default_out_dir(profile.name), "--out")
    check_no_outputs_in(out, REPRODUCTION_FILES, "--out", force=args.force)  # an earlier run's tables and figures
    cache, cache_flag = cache_folder(args.cache)  # an empty or bad $MAT_HOPPER_CACHE is named, not --cache
    # tables and cached runs in one folder cannot be told apart; results inside the
    # cache folder go when the cache is cleared
    check_distinct_paths({"--out": out, cache_flag: cache})
    if is_inside(out, cache):
        raise ValueError(f"--out {out} is inside {cache_flag} {cache}; give the results a folder of their own")
    _check_size(profile, args)
    # a failed run leaves no empty --out or cache folder behind
    with nothing_left_behind(out, cache):
        client = _connect(args.scheduler) if args.scheduler else None
        try:
            _warn_stable_step(profile, args)  # after every check: a refusal stays one line
            rep = reproduce(
                profile,
                args.experiments,
                out,
                workers=args.workers,
                scheduler=client,
                replicates=args.replicates,
                cache_dir=cache,
                progress=not args.no_progress,
                figures=not args.no_figures,
                conventions=args.conventions,
            )
        finally:
            if client is not None:
                client.close()
    total = sum(rep.wall_s.values())
    print(
        f"wrote {len(rep.files)} files to {rep.out_dir} in {total:.1f} s wall "
        f"({', '.join(f'{k} {v:.1f} s' for k, v in rep.wall_s.items())})"
    )
    _controls_note(rep)
    _earlier_outputs_note(rep)
    n_failed = sum(rep.failed.values())
    if n_failed:
        print(f"{n_failed} tasks failed (see the status and error columns); rerun to retry them", file=sys.stderr)
    n_diverged = sum(rep.diverged.values())
    if n_diverged:
        where = ", ".join(f"{k} {v}" for k, v in rep.diverged.items() if v)
        print(
            f"{n_diverged} run{'s' if n_diverged != 1 else ''} diverged ({where}): exit status 1, as every command "
            "whose run diverges; the tables record them"
            + ("" if args.no_figures else ", and the claims leave them out and name them")
        )
    return 1 if n_failed or n_diverged else 0  # EXIT_STATUS


def _earlier_outputs_note(rep) -> None:
    """One line naming the files of an earlier run that this one did not
    replace (an earlier run's claims beside a --no-figures run's tables,
    or another experiment's tables): --force replaces what the run writes,
    and removes nothing, so the folder now mixes two runs."""
    import glob

    written = {os.path.realpath(f) for f in rep.files}
    earlier = sorted(
        f
        for pattern in REPRODUCTION_FILES
        for f in glob.glob(os.path.join(rep.out_dir, pattern))
        if os.path.isfile(f) and os.path.realpath(f) not in written
    )
    if earlier:
        names = ", ".join(os.path.relpath(f, rep.out_dir) for f in earlier[:5])
        more = f" and {len(earlier) - 5} more" if len(earlier) > 5 else ""
        print(
            f"note: {len(earlier)} files in {rep.out_dir} are an earlier run's, not this one's ({names}{more}); "
            "remove them or give a new --out"
        )


def _controls_note(rep) -> None:
    """Where the controls' results are and what they feed: the claims'
    beyond-mass columns, which stay "not run" without the experiments whose
    claims they control (a run of the controls alone judges no claim)."""
    if "controls" not in rep.wall_s:
        return
    where = os.path.join(rep.out_dir, "controls_hops.csv")
    claims_run = [k for k in rep.wall_s if k in ("exp1", "exp2", "exp3")]
    line = f"controls: {where} and controls_runs.csv beside it; they feed claims.csv's beyond-mass columns"
    line += " (vs_rigid_twin, vs_mass_matched, beyond_mass)"
    if not claims_run:
        line += ", judged beside experiments 1-3: rerun with --experiments 1,2,3,controls (runs already made come from the cache)"
    print(line)


def register_cli(sub) -> None:
    p = sub.add_parser(
        "reproduce",
        help="run the paper's experiments, write tables, figures and claims",
        description=(
            "Run the paper's experiments under one profile (cached, resumable, "
            "in parallel), write their tables as CSV into --out, then the figures "
            "and the claims table (claims.md, claims.csv). " + EXIT_STATUS
        ),
    )
    add_profile(p)
    p.add_argument(
        "--experiments",
        default="1,2,3,stability,robustness",
        help=f"comma-separated, any case, other spellings in parentheses: {experiment_spellings()}, or all; "
        "2-gibson-ashby is experiment 2 with porosity that softens (default 1,2,3,stability,robustness)",
    )
    p.add_argument("--workers", type=int, default=None, help="local processes (default: all cores)")
    p.add_argument("--scheduler", default=None, help="Dask scheduler address, e.g. tcp://host:8786")
    p.add_argument(
        "--out",
        default=None,
        help="output folder (default results/<profile>/); one holding an earlier run's tables, claims or "
        "figures is refused unless --force",
    )
    p.add_argument(
        "--replicates",
        type=int,
        default=None,
        help="perturbed replicate runs per design and behaviour, seeds 0..N-1 (default: the profile's, "
        + ", ".join(f"{p.replicates} {name}" for name, p in PROFILES.items())
        + "; the claims' inferential basis)",
    )
    p.add_argument(
        "--push-scale",
        type=float,
        default=None,
        help="the replicates' push, x 5 N for 0.1 s inside the scored window, in [0, 100] (default 1; 0: no push)",
    )
    p.add_argument(
        "--conventions",
        default=None,
        help=f"stiffness conventions of experiments 1-3 (and controls), comma-separated: {', '.join(CONVENTIONS)}, "
        "e.g. paper,axial (axial runs with auto physics substeps under the 1e-4 s controller; the bending "
        "conventions with auto substeps set by the hinges' modes; default paper)",
    )
    p.add_argument(
        "--cache", default=None, help=f"result cache folder (default ${CACHE_ENV}, else {DEFAULT_CACHE_DIR})"
    )
    p.add_argument(
        "--no-figures",
        action="store_true",
        help="the run and hop tables only: no figures and no claims table (claims.csv, claims.md)",
    )
    add_force(p)
    add_no_progress(p)
    p.set_defaults(func=cmd_reproduce)
