"""``mat-hopper optimize``: the command line of :mod:`mat_hopper.optimize`
(run or resume a study, write its report, replay one trial)."""

from __future__ import annotations

import os
import sys
from dataclasses import replace

from ..experiments.cache import CACHE_ENV, DEFAULT_CACHE_DIR
from ..optimize import (
    DEFAULT_BATCH,
    DEFAULT_BATCH_SIZE,
    DEFAULT_CVAR_ALPHA,
    DEFAULT_REPLICATES,
    DEFAULT_WORKERS,
    HOPS_TO_FAILURE_RANGE,
    KINDS,
    LEG_MASS_SCOPE,
    MAX_LEG_MASS_KG,
    MAX_SEGMENTS,
    MAX_YIELD_FRACTION,
    METRICS,
    PAPER_SEEDS,
    SAMPLERS,
    Objective,
    RunOptions,
    SearchSpace,
    StudyConfig,
    check_objectives_vary,
    check_sampler,
    check_study_name,
    check_warp,
    dispose,
    divergence_advice,
    left_out_text,
    parse_objectives,
    queued_seeds,
    queued_step_warnings,
    run_study,
    storage_errors,
    stored_config,
)
from ..util.limits import MAX_WORLDS, check_count, check_workers
from ._checks import (
    cache_folder,
    check_name_list,
    check_no_outputs_in,
    check_output_dir,
    named_by_flags,
    nothing_left_behind,
    parse_pair,
    warp_device,
)
from ._optimize_outputs import (
    EXIT_STATUS,
    REPORT_FILES,
    STEP_HELP,
    cmd_export,
    cmd_replay,
    cmd_report,
    done_text,
    open_existing,
    options_from_args,
    render_files_of,
)
from ._options import (
    SEGMENT_MASS_HELP,
    add_convention,
    add_force,
    add_no_progress,
    add_profile,
    add_timestep,
    profile_of,
    suggesting,
    timestep_arg,
)
from ._study_hints import command_text, mismatch_text, study_flags

# The search space's and objective's fields, as their options (for messages).
OPTION_OF_FIELD = {
    "density_g_cm3": "--density-bounds",
    "modulus_gpa": "--modulus-bounds",
    "n_segments": "--segments",
    "behaviours": "--behaviour",
    "materials": "--materials",
    "ashby_classes": "--ashby-classes",
    "kinds": "--space",
    "replicates": "--replicates",
    "risk": "--risk",
    "cvar_alpha": "--cvar-alpha",
    "leg_mass_tolerance_kg": "--leg-mass-tolerance",
    "leg_mass": "--leg-mass",
    "max_yield_fraction": "--max-yield-fraction",
    "min_hops_to_failure": "--min-hops-to-failure",
}

# The options of each kind of work; one given to another kind is refused
# naming the pair (it would be silently ignored). --report, --replay and
# --export read the study's stored settings and run nothing.
STUDY_OPTIONS = (
    "behaviour",
    "segments",
    "space",
    "density_bounds",
    "modulus_bounds",
    "materials",
    "ashby_classes",
    "segment_mass",
    "profile",
    "timestep",
    "convention",
    "replicates",
    "risk",
    "cvar_alpha",
    "leg_mass",
    "leg_mass_tolerance",
    "max_yield_fraction",
    "min_hops_to_failure",
)
RUN_OPTIONS = ("trials", "workers", "sampler", "seed", "backend", "device", "batch_size", "race", "no_progress")
# Defaults of options left None by the parser (None: not given, so that a
# given one can be told from the default).
DEFAULTS = {"trials": 200, "workers": DEFAULT_WORKERS, "sampler": "tpe", "seed": 0, "backend": "mujoco"}
DEFAULT_STUDIES_DIR = "studies"
# What each kind of work on a stored study does (the refusal of a study run's option says it).
MODE_WORK = {
    "--export": "--export runs nothing (it reads the stored study; --no-progress is accepted)",
    "--report": "--report runs no trials (it reads the stored study; --no-progress is accepted)",
    "--replay": "--replay re-simulates one trial at the study's stored settings (--no-progress is accepted)",
}


def _flag(dest: str) -> str:
    return "--" + dest.replace("_", "-")


def _given(args, dest: str) -> bool:
    value = getattr(args, dest, None)
    return value is not None and value is not False


def check_options(args) -> None:
    """Every option given acts in the work asked for (a study run, --report,
    --replay or --export), or the conflicting pair is refused (ValueError,
    one line naming both); then the defaults of options left out."""
    if args.export is not None and args.replay is not None:
        raise ValueError("--export and --replay: give one (--export writes a trial's design; --replay re-simulates it)")
    mode = next((f for f in ("--export", "--replay", "--report") if _given(args, f[2:])), None)
    if args.study and args.report and args.study != args.report:
        raise ValueError(f"--study {args.study} and --report {args.report} name two studies; give one")
    if mode is not None:
        for dest in (*STUDY_OPTIONS, *RUN_OPTIONS):
            if _given(args, dest) and dest != "no_progress":  # a shared option: accepted by every kind of work
                raise ValueError(f"{_flag(dest)} is for a study run; {MODE_WORK[mode]}")
    elif args.study and (args.cvar_alpha is not None) and (args.risk or "").strip().lower() != "cvar":
        given = f"--risk {args.risk.strip()}" if args.risk else "no --risk (mean)"
        raise ValueError(f"--cvar-alpha is for --risk cvar, given {given}; give --risk cvar with it")
    if args.render and mode != "--replay":
        raise ValueError(f"--render is for --replay TRIAL{f', not {mode}' if mode else ''}")
    if args.out is not None and (mode is None or (mode == "--replay" and not args.render)):
        what = "a study run writes only its storage" if mode is None else "--replay alone writes nothing"
        raise ValueError(f"--out is for --report, --export or --replay --render ({what})")
    if args.force and not (mode in ("--report", "--export") or (mode == "--replay" and args.render)):
        raise ValueError("--force is for --report, --export or --replay --render (it replaces the files they write)")
    if mode is None and args.backend == "warp" and args.workers is not None:  # as mat-hopper batch
        raise ValueError("--workers is for --backend mujoco (a warp batch is one process; see --batch-size)")
    if args.storage and args.studies_dir is not None:
        writes_there = args.out is None and (mode in ("--report", "--export") or (mode == "--replay" and args.render))
        if not writes_there:
            raise ValueError(
                "--storage and --studies-dir: the study is in --storage, and nothing of this command goes to "
                "--studies-dir (the folder of SQLite studies without --storage, and of outputs without --out)"
            )
    for dest, value in DEFAULTS.items():
        if getattr(args, dest) is None:
            setattr(args, dest, value)
    if args.studies_dir is None:
        args.studies_dir = DEFAULT_STUDIES_DIR


def _check_name_lists(args) -> None:
    """--materials and --ashby-classes name each item once: "SS,ss" or
    "metal, Metal" is refused naming the repeat (the search space would
    drop it in silence); an unknown material or behaviour is answered with
    "did you mean ...?" (the objective reads --behaviour's list itself)."""
    from ..core.behaviours import BEHAVIOUR_NAMES, behaviour
    from ..core.materials import CATALOGUE, material
    from ..optimize import check_classes

    known = [m.name for m in CATALOGUE.values()]
    check_name_list(args.materials, "--materials", suggesting(lambda name: material(name).name, known))
    check_name_list(args.ashby_classes, "--ashby-classes", lambda name: check_classes([name])[0])
    for item in str(args.behaviour or "").split(","):
        if item.strip():
            suggesting(lambda name: behaviour(name).name, BEHAVIOUR_NAMES)(item.strip())


def _check_stress_options(args) -> None:
    """--max-yield-fraction in (0, MAX_YIELD_FRACTION] and
    --min-hops-to-failure in HOPS_TO_FAILURE_RANGE, in the command line's
    words: the option left out is the constraint off (the library says
    None)."""
    from ..util.parsing import check_positive, parse_number

    off = "; leave the option out for no constraint (off)"
    if args.max_yield_fraction is not None:
        try:
            check_positive(args.max_yield_fraction, "--max-yield-fraction", high=MAX_YIELD_FRACTION)
        except ValueError as e:
            raise ValueError(f"{e}{off}") from None
    if args.min_hops_to_failure is not None:
        lo, hi = HOPS_TO_FAILURE_RANGE
        try:
            parse_number(args.min_hops_to_failure, "--min-hops-to-failure", low=lo, high=hi, unit="hops")
        except ValueError as e:
            raise ValueError(f"{e}{off}") from None


def _check_space_options(args, space: SearchSpace) -> None:
    """Bounds are for continuous segments and --materials for catalogue
    ones: each refused, naming --space, when the space has none."""
    where = f"--space {args.space}" if args.space is not None else "the default --space continuous"
    if "continuous" not in space.kinds:
        for dest in ("density_bounds", "modulus_bounds"):
            if _given(args, dest):
                raise ValueError(f"{_flag(dest)} is for continuous segments; {where} has none")
    if "catalogue" not in space.kinds and _given(args, "materials"):
        raise ValueError(f"--materials is for catalogue segments; {where} has none (e.g. --space catalogue)")


def config_from_args(args, stored: StudyConfig | None) -> StudyConfig:
    """Study settings from the command line; options left out take the
    stored study's values (resuming) or the defaults (new study)."""
    base = stored or StudyConfig(args.study)
    sp, ob = base.space, base.objective
    n = args.segments if args.segments is not None else sp.n_segments
    kinds = args.space if args.space is not None else (sp.kinds if n == sp.n_segments else sp.kinds[0])
    if isinstance(kinds, str) and kinds.strip().lower() in ("mix", "mixed"):
        raise ValueError(
            f"--space mix: give one kind per segment, e.g. catalogue,continuous,continuous (kinds: {', '.join(KINDS)})"
        )
    classes = args.ashby_classes if getattr(args, "ashby_classes", None) is not None else sp.ashby_classes
    inherit = not classes  # bounds of an Ashby-restricted space come from its classes' hulls
    space = SearchSpace(
        n_segments=n,
        kinds=kinds,
        density_g_cm3=parse_pair(args.density_bounds, "--density-bounds", "g/cm^3")
        or (sp.density_g_cm3 if inherit else None),
        modulus_gpa=parse_pair(args.modulus_bounds, "--modulus-bounds", "GPa") or (sp.modulus_gpa if inherit else None),
        materials=args.materials if args.materials is not None else sp.materials,
        ashby_classes=classes,
    )
    profile = profile_of(args.profile) if args.profile is not None else ob.profile
    step = timestep_arg(getattr(args, "timestep", None))
    if step is not None and step != profile.timestep_s:  # the study's profile at this step, in its key
        profile = replace(profile, timestep_s=step)
    objective = Objective(
        behaviours=args.behaviour if args.behaviour is not None else ob.behaviours,
        profile=profile,
        convention=args.convention if args.convention is not None else ob.convention,
        hop_height_target_m=ob.hop_height_target_m,
        hop_height_tolerance_m=ob.hop_height_tolerance_m,
        segment_mass=getattr(args, "segment_mass", None) or ob.segment_mass,
        **_noise_and_mass_from_args(args, ob),
        objectives=ob.objectives
        if getattr(args, "objectives", None) is None
        else parse_objectives(args.objectives, "--objectives"),
    )
    return StudyConfig(args.study, space, objective)


def _noise_and_mass_from_args(args, ob: Objective) -> dict:
    """--replicates, --risk, --cvar-alpha, --leg-mass, --leg-mass-tolerance
    (mat_hopper.optimize._scoring) and the stress constraints
    --max-yield-fraction, --min-hops-to-failure, each the stored
    (or default) value when left out; ``--leg-mass none`` lifts the
    constraint."""
    given = lambda name: getattr(args, name, None) is not None  # noqa: E731
    leg_mass = ob.leg_mass
    if given("leg_mass"):
        leg_mass = None if args.leg_mass.strip().lower() == "none" else args.leg_mass
    return {
        "replicates": args.replicates if given("replicates") else ob.replicates,
        "risk": args.risk.strip().lower() if given("risk") else ob.risk,
        "cvar_alpha": args.cvar_alpha if given("cvar_alpha") else ob.cvar_alpha,
        "leg_mass": leg_mass,
        "leg_mass_tolerance_kg": args.leg_mass_tolerance
        if given("leg_mass_tolerance")
        else (ob.leg_mass_tolerance_kg if leg_mass is not None else None),
        "max_yield_fraction": args.max_yield_fraction if given("max_yield_fraction") else ob.max_yield_fraction,
        "min_hops_to_failure": args.min_hops_to_failure if given("min_hops_to_failure") else ob.min_hops_to_failure,
    }


def cmd_optimize(args) -> int:
    check_options(args)  # before any file is opened or made
    url = args.storage or os.path.join(args.studies_dir, f"{args.report or args.study}.db")
    with storage_errors(url):  # a database error: one line naming the storage and the cause
        return _cmd_optimize(args)


def _cmd_optimize(args) -> int:
    for flag, value in (("--replay", args.replay), ("--export", args.export)):
        check_count(value, flag, 0, what="a trial number, from 0")  # before any storage is opened
    if not args.storage or (args.report and not args.out):
        check_output_dir(args.studies_dir, "--studies-dir")
    if getattr(args, "export", None) is not None:
        return cmd_export(args)
    if args.report or args.replay is not None:
        name = args.report or args.study
        if not name:
            raise ValueError("--replay TRIAL needs --study NAME (or --report NAME)")
        if args.replay is not None:
            if args.render:
                folder = check_output_dir(args.out or args.studies_dir, "--out")
                check_no_outputs_in(folder, render_files_of(name, args.replay), "--out", force=args.force)
            storage = open_existing(name, args, read_only=True)  # replay reads the study, never writes it
            try:
                return cmd_replay(name, storage, args)
            finally:
                dispose(storage)  # no -wal/-shm files left beside the study
        out = check_output_dir(args.out or os.path.join(args.studies_dir, f"{name}-report"), "--out")
        check_no_outputs_in(out, REPORT_FILES, "--out", force=args.force)
        with nothing_left_behind(out):
            return cmd_report(name, args, out)
    if not args.study:
        raise ValueError("give --study NAME (or --report NAME)")
    check_count(args.trials, "--trials", 1, what="finished trials to reach")
    check_workers(args.workers)
    check_count(args.batch_size, "--batch-size", 1, MAX_WORLDS, "trials simulated together per round")
    options = options_from_args(args, args.trials)
    check_sampler(options.sampler)
    _check_name_lists(args)
    _check_stress_options(args)
    with named_by_flags(**OPTION_OF_FIELD):
        fresh = config_from_args(args, None)  # bad settings fail here, before any file is made
    _check_space_options(args, fresh.space)
    _check_size(args, fresh)
    check_objectives_vary(fresh.objective)
    if args.backend == "warp":
        check_warp(fresh.objective.objectives)
        for dest in ("max_yield_fraction", "min_hops_to_failure"):  # a stress constraint needs stress
            if getattr(fresh.objective, dest) is not None:
                raise ValueError(f"{OPTION_OF_FIELD[dest]}: the warp backend computes no stress (use --backend mujoco)")
    cache = _check_backend(args)
    check_study_name(args.study)
    studies_dir = None if args.storage else args.studies_dir
    with nothing_left_behind(studies_dir, cache):
        if not args.storage:  # the study's own SQLite file: checked before it is made
            path = os.path.join(args.studies_dir, f"{args.study}.db")
            if os.path.isdir(path):
                raise ValueError(f"sqlite storage {os.path.abspath(path)}: is a folder, not a database file")
        storage = options.open(args.study)
        stored = stored_config(args.study, storage)
        with named_by_flags(**OPTION_OF_FIELD):
            config = config_from_args(args, stored) if stored else fresh
        dispose(storage)  # this look's pooled connection: the run opens its own
        queued, left_out = queued_seeds(config.space, config.objective)
        if left_out and not stored:  # known before any run: not queued, not simulated
            print(left_out_text(left_out, config.objective, config.space.n_segments), flush=True)
        for line in queued_step_warnings(config, queued, args.trials) if not stored else ():  # as simulate's
            print(f"mat-hopper optimize: warning: {line}", file=sys.stderr, flush=True)
        res = _run_backend(config, options, args)
    print(f"study {res.study} ({res.url}): {done_text(res, args.trials)}")
    if res.feasibility is not None:  # how many are feasible, and why the others are not
        print(res.feasibility.text())
    advice = divergence_advice(res.feasibility, config)
    if advice:  # a study still exits 0 (EXIT_STATUS)
        print(advice)
    if res.lost:
        print(f"an evaluation process died: trials failed and re-queued: {res.lost}")
    if res.recovered:
        print(f"trials of an earlier run that died, failed and re-queued: {res.recovered}")
    print(f"report: {command_text('mat-hopper', 'optimize', '--report', res.study, *study_flags(args))}")
    if not res.finished and not res.running:
        print("the study is short of its target: run the same command again to resume", file=sys.stderr)
        return 1
    return 0


def _check_size(args, config: StudyConfig) -> None:
    """--trials x behaviours x replicates x physics steps per run, before
    any work (mat_hopper.util.limits; under auto time steps, at SS's step: the
    stiffest paper material)."""
    from ..core.materials import parse_design
    from ..util.limits import check_total_steps

    ob = config.objective
    steps = ob.sim_settings(design=parse_design("SS", n_segments=config.space.n_segments)).n_steps
    n, k = len(ob.behaviours), max(1, int(getattr(ob, "replicates", 0) or 0))
    check_total_steps(
        args.trials * n * k * steps,
        f"--trials {args.trials} x {n} behaviour(s) x {k} replicate(s) x {steps:.3g} steps",
        "fewer --trials, behaviours or --replicates, or a shorter --profile",
    )


def _check_backend(args) -> str | None:
    """--backend's options, the cache folder ($MAT_HOPPER_CACHE named as
    such) and, for warp, the device and mujoco-warp: one-line errors before
    any file is made (the study's storage included). Returns the CPU
    path's cache folder (None on warp, where args.device is set to the
    device Warp will run on)."""
    race = getattr(args, "race", False)
    if race and args.batch_size is not None:
        raise ValueError("--batch-size is not for --race: racing asks brackets of 9 trials")
    if args.backend != "warp":
        if args.device is not None:
            raise ValueError("--device is for --backend warp")
        return cache_folder(args.cache)[0]
    if race:
        raise ValueError("--race runs on --backend mujoco (the warp backend has no perturbations yet)")
    if args.cache is not None:
        raise ValueError("--cache is for --backend mujoco (the warp backend caches nothing)")
    args.device = warp_device(args.device)  # as mat-hopper batch: the name, the gpu extra, a CUDA device seen
    return None


def _run_backend(config: StudyConfig, options: RunOptions, args):
    """The study on --backend mujoco (CPU processes, the reference) or warp
    (MuJoCo Warp batches), rounds of --batch-size trials either way."""
    from ..optimize import StudyMismatch, race_study, run_batch_study

    try:
        if getattr(args, "race", False):  # on mujoco (_check_backend)
            return race_study(config, options)
        return (
            run_study(config, options)
            if args.backend != "warp"
            else run_batch_study(config, options, device=args.device)
        )
    except StudyMismatch as e:  # in the options' terms
        raise ValueError(mismatch_text(e, OPTION_OF_FIELD)) from None


def _seeds_text() -> str:
    """The help's sentence on the paper designs every study starts from, as
    the default space enqueues them (SearchSpace.seeds)."""
    seeds = [name for name, _ in SearchSpace().seeds()]
    left = [name for name in PAPER_SEEDS if name not in seeds]
    return (
        f"Starts from the paper's designs its space can express, enqueued before the sampler's first trial: "
        f"{len(seeds)} of {len(PAPER_SEEDS)} in the default continuous space ({', '.join(seeds)}"
        + (f"; not {', '.join(left)}, a rigid leg" if left else "")
        + ")."
    )


def register_cli(sub) -> None:
    p = sub.add_parser(
        "optimize",
        help="search leg designs with Optuna (multi-objective, resumable, parallel)",
        description="Search per-segment densities and moduli (or catalogue materials) for low tracking "
        f"error and hip power, hop height 1 +- 0.05 m and stable runs. {_seeds_text()} {STEP_HELP} {EXIT_STATUS}",
    )
    p.add_argument("--study", help="study name (letters, digits, _ . -); resumes if it exists")
    p.add_argument("--trials", type=int, default=None, help="study size: finished trials to reach (200)")
    p.add_argument(
        "--behaviour",
        "--behavior",
        dest="behaviour",
        help="behaviour, or comma-separated behaviours (objectives averaged), default ramp",
    )
    p.add_argument(
        "--segments",
        type=int,
        help=f"segments per leg, 1 to {MAX_SEGMENTS} (default {SearchSpace().n_segments})",
    )
    p.add_argument(
        "--space", help="continuous (default), catalogue, or one kind per segment, e.g. catalogue,continuous,continuous"
    )
    p.add_argument("--density-bounds", help="MIN,MAX g/cm^3 for continuous segments (default 0.9,20)")
    p.add_argument("--modulus-bounds", help="MIN,MAX GPa for continuous segments (default 0.1,1000)")
    p.add_argument("--materials", help="catalogue choices, comma-separated (default: all with a modulus)")
    p.add_argument(
        "--ashby-classes",
        help="restrict every segment to these catalogue classes' hulls (log density-modulus), e.g. metal,polymer",
    )
    p.add_argument("--segment-mass", help=SEGMENT_MASS_HELP)  # read by the study config (the stored one's if left out)
    add_profile(p)
    add_timestep(p, "for every trial's runs; default: the profile's (1e-4 s) or the stored study's (in its key)")
    add_convention(p, None)  # None: the stored study's when resuming, else paper
    p.add_argument(
        "--replicates",
        type=int,
        help=f"perturbed replicates per trial, the same seeds for every trial (default {DEFAULT_REPLICATES}; "
        "0: one unperturbed run)",
    )
    p.add_argument("--risk", help="objective over replicates: mean (default) or cvar (mean of the worst tail)")
    p.add_argument("--cvar-alpha", type=float, help=f"--risk cvar's level in [0, 1) (default {DEFAULT_CVAR_ALPHA})")
    p.add_argument(
        "--leg-mass",
        help=f"constrain the leg's mass ({LEG_MASS_SCOPE}, as simulate reports it) to a paper design's (e.g. SS) "
        f"or to a mass in kg in (0, {MAX_LEG_MASS_KG:g}], e.g. 6.5; none: unconstrained (default)",
    )
    p.add_argument(
        "--leg-mass-tolerance",
        type=float,
        help=f"kg, +- around --leg-mass, in (0, {MAX_LEG_MASS_KG:g}] (default 5 %% of the target); one that holds "
        "every leg of the search space is refused (the constraint would be void). The sampler proposes legs inside "
        "the band; paper designs outside it are not queued",
    )
    p.add_argument(
        "--max-yield-fraction",
        type=float,
        metavar="F",
        help="constraint: every segment's peak stress <= F x its yield strength, the worst behaviour "
        f"(F in (0, {MAX_YIELD_FRACTION:g}], e.g. 0.5; default off; meaningful under a bending convention)",
    )
    p.add_argument(
        "--min-hops-to-failure",
        type=float,
        metavar="N",
        help="constraint: fatigue life (Basquin S-N, Miner) of at least N hops, the worst behaviour "
        f"(N in [{HOPS_TO_FAILURE_RANGE[0]:g}, {HOPS_TO_FAILURE_RANGE[1]:g}], e.g. 1e7; default off; meaningful "
        "under a bending convention)",
    )
    p.add_argument(
        "--objectives",
        metavar="M1,M2[,M3]",
        help="two or three metrics to minimize, comma-separated, any case (default tracking_error_m,power_w): "
        + "; ".join(f"{m.name} ({m.unit}, {m.label})" for m in METRICS.values())
        + ". Stress and damage mean something only under a bending convention (under paper and axial the "
        "stress is axial only); --backend warp computes tracking_error_m, power_w and leg_mass_kg only",
    )
    _add_run_arguments(p)
    p.add_argument("--report", metavar="NAME", help="write the study's report (plots, tables, CSV)")
    p.add_argument(
        "--out",
        help="folder of the files written: --report's (default STUDIES_DIR/NAME-report), --export's and "
        "--replay --render's (default STUDIES_DIR)",
    )
    p.add_argument("--replay", type=int, metavar="TRIAL", help="re-simulate trial TRIAL's design")
    p.add_argument(
        "--render",
        action="store_true",
        help="with --replay: also render it (mat_hopper.viz.render), gait tiles and a video per behaviour in --out "
        "(default STUDIES_DIR)",
    )
    p.add_argument(
        "--export",
        type=int,
        metavar="TRIAL",
        help="write trial TRIAL's design as CSV (for simulate --design-csv, batch --designs-csv) and MJCF, "
        "NAME-trialTRIAL.csv and NAME-trialTRIAL-BEHAVIOUR.xml in --out (default STUDIES_DIR, not the report's folder)",
    )
    add_force(p)
    p.set_defaults(func=cmd_optimize)


def _add_run_arguments(p) -> None:
    """How a study runs: processes, rounds, storage, sampler, backend, racing."""
    p.add_argument(
        "--workers",
        type=int,
        default=None,
        help=f"processes that simulate here ({DEFAULT_WORKERS}); they never change the trials (see --batch-size)",
    )
    p.add_argument(
        "--storage",
        help="Optuna storage URL (default sqlite:///STUDIES_DIR/NAME.db); "
        "postgresql://USER@HOST:PORT/DB or journal:///PATH for shared studies",
    )
    p.add_argument(
        "--studies-dir",
        default=None,
        help=f"folder of the default SQLite files, and of outputs without --out ({DEFAULT_STUDIES_DIR})",
    )
    p.add_argument("--sampler", default=None, help=f"one of {', '.join(SAMPLERS)} (tpe)")
    p.add_argument("--seed", type=int, default=None, help="sampler seed (0)")
    add_no_progress(p)
    p.add_argument(
        "--backend",
        choices=("mujoco", "warp"),
        default=None,
        help="mujoco: CPU rollouts in --workers processes, the reference (default); warp: MuJoCo Warp batches",
    )
    p.add_argument(
        "--cache",
        help=f"--backend mujoco: cache of the trials' runs (default ${CACHE_ENV}, else {DEFAULT_CACHE_DIR}): "
        "a repeated design, a re-queued trial or a rerun costs nothing",
    )
    p.add_argument("--device", help="Warp device for --backend warp: cpu or cuda (default: cuda where Warp sees a GPU)")
    p.add_argument(
        "--batch-size",
        type=int,
        help=f"trials asked, simulated together and told per round ({DEFAULT_BATCH}; --backend warp "
        f"{DEFAULT_BATCH_SIZE}); with --seed it fixes a fresh study's trials",
    )
    p.add_argument(
        "--race",
        action="store_true",
        help="multi-fidelity racing: screen trials on short one-replicate runs and promote 1 in 3 to the study's "
        "full fidelity; --trials counts screened trials, in brackets of 9; give it again to resume",
    )
