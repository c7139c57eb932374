"""``mat-hopper optimize`` on a stored study: its report (``--report``),
one trial replayed (``--replay``, ``--render``) and exported
(``--export``); the study run itself is :mod:`mat_hopper.cli.optimize`."""

from __future__ import annotations

import os
import shlex

from optuna.trial import TrialState

from ..core.materials import LegDesign
from ..optimize import (
    CONFIG_ATTR,
    METRICS,
    OBJECTIVES,
    RunOptions,
    StudyConfig,
    check_objectives_vary,
    check_study_name,
    describe,
    dispose,
    diverged_run_message,
    fall_reason,
    front_table,
    load_existing,
    open_storage,
    redact,
    replay,
    scored_by_hops,
    storage_file,
    study_exists,
    write_report,
)
from ..optimize.report import feasible_complete, missing_baselines
from ..viz.render import choose_backend, render_files
from ._checks import check_no_outputs_in, check_output_dir
from ._study_hints import command_text, study_flags

# The study's time step and exit status, in optimize's --help.
STEP_HELP = (
    "A study's runs take --timestep (default the profile's 1e-4 s under --convention paper; 'auto' gives each "
    "design its own physics substeps), under axial and bending the automatic step; a queued design above its "
    "analytic stable step is warned of before any run, and a study whose trials diverged ends with how many and "
    "what to try (--timestep auto, fewer --segments, or --convention axial)."
)
EXIT_STATUS = (
    "Exit status: 0 when the study reached its target, diverged trials included (a search is expected to meet "
    "designs that diverge: they are infeasible trials, counted at the end); 1 when it is short of its target, "
    "or when --replay's runs diverged or differ from the stored values; 2 for bad input."
)

# The files of --report in its folder (mat_hopper.optimize.report.write_report).
REPORT_FILES = (
    "trials.csv",
    "pareto.csv",
    "pareto.png",
    "hypervolume.csv",
    "hypervolume.png",
    "importances.csv",
    "importances.png",
)


def export_files_of(name: str, trial: int) -> tuple[str, ...]:
    """The files --export TRIAL writes (mat_hopper.optimize.export_trial),
    as glob patterns in its folder: the CSV and one MJCF per behaviour."""
    return (f"{name}-trial{trial}.csv", f"{name}-trial{trial}-*.xml")


def render_files_of(name: str, trial: int) -> tuple[str, ...]:
    """The files --replay TRIAL --render writes (:func:`_render`), as glob
    patterns in its folder: gait tiles and a video per behaviour."""
    return (f"{name}-trial{trial}-*-tiles.png", f"{name}-trial{trial}-*.mp4")


def options_from_args(args, trials: int = 1) -> RunOptions:
    """The RunOptions the command line asks for (`trials`: the study's size)."""
    return RunOptions(
        trials=trials,
        workers=args.workers,
        sampler=args.sampler,
        seed=args.seed,
        storage=args.storage,
        studies_dir=args.studies_dir,
        progress=not args.no_progress,
        batch_size=getattr(args, "batch_size", None),
        cache_dir=getattr(args, "cache", None),
    )


def open_existing(name: str, args, *, read_only: bool = False):
    """Storage holding an existing study `name` (ValueError if none);
    read_only for reports (a SQLite file opened read-only: never waits for
    a writer, never removes its -wal/-shm files)."""
    check_study_name(name)
    if not args.storage:
        check_output_dir(args.studies_dir, "--studies-dir")
    options = options_from_args(args)
    if not args.storage:
        path = os.path.join(args.studies_dir, f"{name}.db")
        if not os.path.exists(path):
            raise ValueError(f"no study {name!r}: {path} does not exist (give --storage URL for a shared study)")
    else:
        path = storage_file(args.storage)
        if path and not os.path.exists(path):
            raise ValueError(f"no study {name!r}: {path} does not exist")
    url = options.storage_url(name)
    storage = open_storage(url, read_only=read_only)
    if not study_exists(name, storage):
        raise ValueError(f"no study {name!r} in {redact(options.storage_url(name))}")
    return storage


def _needs_baselines(name: str, storage) -> bool:
    """Whether the report must run (and store) a paper baseline the study
    lacks: its space cannot express SS or rho-inc (the report then writes
    to the study, so it needs a writable storage)."""
    return bool(missing_baselines(load_existing(name, storage)))


def cmd_report(name: str, args, out: str) -> int:
    storage = open_existing(name, args, read_only=True)
    try:
        return _report(name, storage, args, out)
    finally:
        dispose(storage)  # a read-only use leaves no -wal/-shm files beside the study


def _report(name: str, storage, args, out: str) -> int:
    key = storage.get_study_user_attrs(storage.get_study_id_from_name(name)).get(CONFIG_ATTR)
    if key:
        try:
            check_objectives_vary(StudyConfig.from_key(name, key).objective)
        except ValueError:
            behs = ",".join(key["objective"].get("behaviours", []))
            raise ValueError(
                f"study {name!r} optimizes {behs} alone: tracking error and hip power are zero by symmetry "
                "for every design (round-off only); no Pareto front, hypervolume or importances to report"
            ) from None
    if _needs_baselines(name, storage):
        writer = open_existing(name, args)  # writes the baselines it runs into the study
        try:
            rep = write_report(name, writer, out)
        finally:
            dispose(writer)
    else:
        rep = write_report(name, storage, out)
    frame, front = rep["trials"], rep["pareto"]
    states = frame["state"].value_counts().to_dict() if len(frame) else {}
    n_ok = len(feasible_complete(frame))
    print(f"study {name}: {len(frame)} trials {states}, {n_ok} feasible, {len(front)} on the Pareto front")
    print(rep["feasibility"].text())  # why the others are not
    objectives = StudyConfig.from_key(name, key).objective.objectives if key else OBJECTIVES
    for b, values in rep["baselines"].items():
        print(f"  {b}: " + ", ".join(_value_text(o, v) for o, v in zip(objectives, values)))
    for b, why in rep.get("baselines_left_out", {}).items():  # no percent change against a run that fell
        print(f"  {b} left out as a baseline: {why}")
    if len(front):  # the designs, not only their trial numbers: densities, moduli, leg mass
        table = front_table(front, objectives).drop(columns=["hop height (m)"])
        table.insert(1, "design", front["design"].to_numpy())
        print(table.to_string(index=False, float_format=lambda v: f"{v:.4g}"))
        line = command_text("mat-hopper", "optimize", "--study", name, "--export", "TRIAL", *study_flags(args))
        print(f"export a design: {line}")
    for p in rep["paths"].values():
        print(f"wrote {p}")
    return 0


def cmd_replay(name: str, storage, args) -> int:
    t, design, ev, config = replay(name, storage, args.replay)
    print(f"trial {t.number} ({t.state.name}) of {name}: {describe(design.segments)}")
    for i, m in enumerate(design.segments, 1):
        print(f"  segment {i}: {m.density_g_cm3:.6g} g/cm^3, {m.modulus_gpa:.6g} GPa ({m.name})")
    diverged = False
    for r in ev.per_behaviour:
        print(f"  {_run_line(r, config)}")
        if r.get("diverged_at_s") is not None and r["diverged_at_s"] == r["diverged_at_s"]:  # not None, not nan
            diverged = True
            print(f"    UNSTABLE: {diverged_run_message(design, config.objective, r)}")
    se, names = ev.standard_errors, ev.objective_names
    se_text = f" (standard errors {', '.join(_value_text(o, v, 3, False) for o, v in zip(names, se))})"
    se_text = se_text if se and se[0] == se[0] else ""
    cons = ", ".join(f"{n} {c:.4g}" for n, c in zip(ev.constraint_names, ev.constraints))
    values = ", ".join(_value_text(o, v, 6, False) for o, v in zip(names, ev.values))
    values = (
        "none (a run diverged: the values the study holds are whole-run means of runs cut short, for the sampler)"
        if diverged
        else f"{values}{se_text}"
    )
    print(
        f"objectives {values}; "
        f"{'feasible' if ev.feasible else 'infeasible'} (constraints {cons}); leg mass {ev.leg_mass_kg:.4g} kg"
    )
    same = t.state == TrialState.COMPLETE and tuple(t.values) == tuple(ev.values)
    if t.state == TrialState.COMPLETE:
        print(
            "replay matches the stored values exactly"
            if same
            else f"replay differs from the stored values {tuple(t.values)}"
        )
    if diverged:
        print(f"exit status 1: a run of trial {t.number} diverged (as every command whose run diverges)")
    if args.render:
        code = _render(name, design, config, args)
        return 1 if diverged else code
    return 1 if diverged or (t.state == TrialState.COMPLETE and not same) else 0


def _run_line(r: dict, config: StudyConfig) -> str:
    """One replayed run: its metrics where it scored hop cycles and ended
    upright, else why it has none (a run cut short has no hop to score)."""
    where = r["behaviour"] + (f" (replicate seed {r['replicate']})" if r.get("replicate", -1) >= 0 else "")
    if scored_by_hops(int(r["n_hops"]), bool(r["upright"])):
        metrics = ", ".join(_value_text(o, r[o], 6) for o in config.objective.objectives)
        return f"{where}: {metrics}, hop height {r['hop_height_m']:.4g} m over {r['n_hops']} hops, upright"
    why = fall_reason([r]) or "no hop cycle scored after the transient"
    return f"{where}: no metric: {r['n_hops']} hop cycles scored, {why}"


def _value_text(name: str, value: float, digits: int = 4, label: bool = True) -> str:
    """``hip power 0.123 W``: a metric's value with its unit (and its label)."""
    m = METRICS[name]
    unit = "" if m.unit == "1" else f" {m.unit}"
    return (f"{m.label} " if label else "") + f"{value:.{digits}g}{unit}"


def _render(name: str, design: LegDesign, config: StudyConfig, args) -> int:
    """Gait tiles and a 10 s video of the replayed design on each behaviour,
    in --out or the studies folder: <study>-trial<N>-<behaviour>-*."""
    folder = args.out or args.studies_dir
    backend = choose_backend()
    for b in config.objective.behaviours:
        stem = os.path.join(folder, f"{name}-trial{args.replay}-{b}")
        for path in render_files(
            design,
            b,
            tiles=f"{stem}-tiles.png",
            video=f"{stem}.mp4",
            convention=config.objective.convention,
            backend=backend,
        ):
            print(f"wrote {path}")
    return 0


def cmd_export(args) -> int:
    """--export TRIAL: the trial's design as CSV and MJCF (mat_hopper.optimize._export)."""
    from ..optimize import export_trial

    name = args.report or args.study
    if not name:
        raise ValueError("--export TRIAL needs --study NAME (or --report NAME)")
    out = check_output_dir(args.out or args.studies_dir, "--out")
    check_no_outputs_in(out, export_files_of(name, args.export), "--out", force=args.force)
    storage = open_existing(name, args, read_only=True)
    try:
        res = export_trial(name, storage, args.export, out)
    finally:
        dispose(storage)  # a read-only use leaves no -wal/-shm files beside the study
    print(f"trial {args.export} of {name}: {describe(res['design'].segments)}")
    if res["why"]:  # a diverged, fallen or otherwise infeasible trial says so, as its CSV row does
        what = f"trial {args.export} {res['runs']}" if res["runs"] else f"trial {args.export}"
        blank = (
            "; its objective columns are empty: its runs were cut short" if res["why"].startswith("diverged") else ""
        )
        print(f"{what}: not feasible (the CSV's not_feasible_because: {res['why']}{blank})")
    print(f"wrote {res['csv']}")
    for path in res["mjcf"].values():
        print(f"wrote {path}")
    ob = res["config"].objective
    print(f"simulate it: {simulate_command(res['csv'], ob)}")
    return 0


def _option_text(value) -> str:
    """A run setting as simulate's option reads it: a sensor timing by its name, a number as repr gives it."""
    named = getattr(value, "key_value", None)
    return str(named() if callable(named) else value)


def simulate_command(csv: str, objective) -> str:
    """The ``mat-hopper simulate`` command that runs an exported trial's
    design unperturbed under every setting of the study's objective: its
    behaviour, profile (by name where it is one of the named profiles and
    sets one of the run's length, transient and step), each run setting
    the study holds apart from that profile's (run length, transient, time
    step, sensor timing), its convention and segment mass; with a note
    where the study's replicates or record rate are not what the command
    runs."""
    from ..experiments.profiles import PROFILES

    # simulate's option for each run setting a study may hold apart from its named profile's
    options = {"duration_s": "--duration", "transient_s": "--transient", "timestep_s": "--timestep",
               "sensor_timing": "--sensor-timing"}  # fmt: skip
    prof = objective.profile
    named = PROFILES.get(prof.name)
    words = ["mat-hopper", "simulate", "--design-csv", csv, "--behaviour", objective.behaviours[0]]
    apart = [f for f in options if named is None or _option_text(prof.run[f]) != _option_text(named.run[f])]
    if named is not None and not {"duration_s", "transient_s", "timestep_s"} <= set(apart):
        words += ["--profile", prof.name]  # simulate refuses a profile whose three settings are all given
    for field in apart:
        words += [options[field], _option_text(prof.run[field])]
    words += ["--convention", objective.convention, "--segment-mass", objective.segment_mass]
    notes = []
    if objective.replicates:
        notes.append(f"the study scores {objective.replicates} perturbed replicates; simulate runs the unperturbed one")
    default_rate = (named or PROFILES["paper"]).run["record_rate_hz"]
    if prof.run["record_rate_hz"] != default_rate:
        notes.append(f"the study records at {prof.run['record_rate_hz']:g} Hz, simulate at {default_rate:g} Hz")
    return shlex.join(words) + (f" ({'; '.join(notes)})" if notes else "")


def done_text(res, trials: int) -> str:
    """How many trials the study holds against its target, in the words of
    the feasibility line below it: under racing the target counts screened
    trials (--trials rounded up to whole brackets), of which those finished
    at full fidelity and those stopped on a screening rung."""
    if res.evaluator != "racing" or res.feasibility is None:
        running = f", {res.running} still running elsewhere" if res.running else ""
        return f"{res.done}/{res.target} trials finished{running}"
    f = res.feasibility
    rounded = f", --trials {trials} rounded up to whole brackets" if res.target != trials else ""
    return (
        f"{res.done}/{res.target} trials screened by racing{rounded}: {f.finished} finished at full fidelity, "
        f"{f.pruned} stopped on a screening rung"
    )
