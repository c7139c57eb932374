"""``mat-hopper batch``: many designs, one behaviour, one row per design.

    mat-hopper batch --designs SS,rho-inc,PVC-Ti-SS --behaviour forward --backend warp --csv out.csv
    mat-hopper batch --designs-csv designs.csv --backend mujoco --csv out.csv

``--backend mujoco`` (default) runs one CPU rollout per design, the
reference; ``--backend warp`` runs the designs as MuJoCo Warp batches (one
per topology) on ``--device`` (needs the ``gpu`` extra).
"""

from __future__ import annotations

import argparse
import dataclasses
import math
import sys

from ..core import reference as ref
from ..core.behaviours import DEFAULT_BEHAVIOUR
from ..core.materials import SEGMENT_MASSES
from ..experiments.profiles import PROFILES
from ._checks import SENSOR_TIMING_HELP, sensor_timing_type
from ._options import (
    AUTO_TIMESTEP_HELP,
    BEHAVIOUR_HELP,
    DURATION_HELP,
    SEGMENT_MASS_HELP,
    TRANSIENT_HELP,
    add_behaviour,
    add_convention,
    add_force,
    add_no_progress,
    add_profile,
    check_force_used,
    no_hops_line,
    profile_of,
    timestep_arg,
)

CSV_HELP = (
    "CSV of designs: columns density_1..density_N (g/cm^3) and modulus_1..modulus_N "
    "(GPa, or 'rigid' for a rigid segment; a leg shorter than the table leaves both cells of each segment past its "
    "last empty), optional 'design' column of names"
)


def add_parser(subparsers) -> argparse.ArgumentParser:
    p = subparsers.add_parser(
        "batch",
        help="evaluate many designs on one behaviour (CPU rollouts or a MuJoCo Warp batch)",
        description="Evaluate many leg designs on one behaviour; one row per design: design, n_hops, "
        "hop_height_m, tracking_error_m, power_w, stable (the CSV adds when a run diverged, diverged_at_s, and when the "
        "hopper fell, fell_at_s: the base tilted past 60 deg, and when its numbers became suspect, suspect_at_s; "
        "--backend mujoco only). A design that fell, diverged or is numerically suspect "
        "is named below the table with when. Designs whose time step lies above their analytic "
        "stable step are warned of before any run (try --timestep auto). Exit status: 0 when every run ended "
        "without numerical divergence; 1 when any diverged or is numerically suspect (a hop apex far above the "
        "target: corrupted numbers without a blow-up; the table is still printed and written); 2 for bad "
        "input. --stability exits 0: its tries diverge by design, and a design stable at no step is a result.",
    )
    src = p.add_mutually_exclusive_group(required=True)
    src.add_argument("--designs", help="comma-separated designs, e.g. SS,rho-inc,PVC-Ti-SS")
    src.add_argument("--designs-csv", metavar="FILE", help=CSV_HELP)
    src.add_argument(
        "--map",
        type=int,
        metavar="N",
        help="the stable-time-step map's N x N mono-material designs (density x modulus, "
        "docs/reference-hopper.md; the paper's N is 20)",
    )
    # None: the default below, and a way to tell that --stability was given run settings it has no use for
    add_behaviour(p, None, BEHAVIOUR_HELP)
    p.add_argument("--duration", type=float, help=DURATION_HELP)
    p.add_argument("--transient", type=float, help=TRANSIENT_HELP)
    p.add_argument(
        "--timestep",
        help=f"physics time step, s (the profile's, {ref.TIMESTEP_S:g}): the controller runs every physics step; "
        f"or {AUTO_TIMESTEP_HELP}, for each design as simulate --timestep auto does (--backend mujoco)",
    )
    add_profile(p)
    add_convention(p)
    p.add_argument("--sensor-timing", default="authors", type=sensor_timing_type(), help=SENSOR_TIMING_HELP)
    p.add_argument("--segment-mass", default="leg", choices=SEGMENT_MASSES, help=SEGMENT_MASS_HELP)
    p.add_argument(
        "--backend",
        choices=("mujoco", "warp"),
        default="mujoco",
        help="mujoco: CPU rollouts, the reference (default); warp: MuJoCo Warp batches",
    )
    p.add_argument(
        "--device",
        default=None,
        help="Warp device for --backend warp: cpu or cuda (default: cuda where Warp sees a GPU)",
    )
    p.add_argument("--workers", type=int, default=None, help="processes for --backend mujoco (all cores)")
    p.add_argument("--max-batch", type=int, default=None, help="most worlds in one warp batch (all)")
    p.add_argument(
        "--stability",
        action="store_true",
        help="instead of one behaviour: the reference stable-time-step scan (static hopping for "
        "--stability-duration s at 20 steps from 1e-3 down to 1e-5 s, one batch per step); one row per "
        "design with spec_timestep_s, the first step at which it ends upright",
    )
    p.add_argument(
        "--stability-duration",
        type=float,
        default=None,
        help=f"static hopping per try of --stability, s ({ref.STABILITY_TEST_DURATION_S:g})",
    )
    p.add_argument("--csv", help="write the table (one row per design) here (- for standard output)")
    add_force(p)
    add_no_progress(p, "--quiet")
    p.set_defaults(func=run_batch)
    return p


register_cli = add_parser  # the name mat_hopper.cli looks for


def _auto(args) -> bool:
    """Whether --timestep is 'auto' (each design its own physics substeps)."""
    from ..core.timestep import AUTO

    return timestep_arg(args.timestep) == AUTO


# Settings the CSV carries beside each row (every table says what made it).
SETTING_COLUMNS = (
    "behaviour",
    "convention",
    "sensor_timing",
    "segment_mass",
    "duration_s",
    "transient_s",
    "timestep_s",
    "substeps",
    "backend",
)
# When each run diverged, when its hopper fell and when its numbers became
# suspect (core.rollout.Rollout.suspect_apex) (s; empty if never), after the settings.
EVENT_COLUMNS = ("diverged_at_s", "fell_at_s", "suspect_at_s")


def run_batch(args) -> int:
    from ..batch import RESULT_COLUMNS, design_settings, designs_from_csv, evaluate, parse_design_list
    from ..core.behaviours import behaviour
    from ._checks import (
        check_distinct_paths,
        check_input_file,
        check_output_file,
        named_by_flags,
        sensor_timing_arg,
        warp_device,
    )

    check_force_used(args, {"--csv": args.csv})
    check_distinct_paths({"--csv": args.csv}, {"--designs-csv": args.designs_csv})  # never over the input table
    check_output_file(args.csv, "--csv", stdout=True, force=args.force)  # before any work
    check_input_file(args.designs_csv, "--designs-csv")
    profile = profile_of(args.profile)  # ValueError for a bad --profile or $MAT_HOPPER_PROFILE
    timing = sensor_timing_arg(args.sensor_timing)
    _check_applicable(args)
    if args.map is not None:
        designs = _map_designs(args.map)
    elif args.designs_csv is not None:
        designs = designs_from_csv(args.designs_csv)
    else:
        designs = parse_design_list(args.designs)
    beh = behaviour(DEFAULT_BEHAVIOUR if args.behaviour is None else args.behaviour)
    auto = _auto(args)
    with named_by_flags():
        settings = _batch_settings(args, profile, timing)
        per_design = [design_settings(d, settings, auto) for d in designs]  # each its own substeps under auto
    device = warp_device(args.device) if args.backend == "warp" else None  # name, gpu extra, CUDA seen
    _check_size(args, designs, settings, per_design)
    if not args.stability:  # the scan's ladder goes above the bounds on purpose
        _warn_stable_step(designs, per_design)
    run = dict(backend=args.backend, device=device, workers=args.workers, max_batch=args.max_batch)
    progress = (
        not args.no_progress
    )  # a bar on a terminal, a line per stage in logs and pipes (mat_hopper.util.progress)
    if progress and args.backend == "warp":  # model building and kernel compilation come before any bar
        print(
            f"warp: building {_count(len(designs), 'world')} on {device} and compiling its kernels "
            f"(minutes on the first use{', and slower than one core on cpu' if device == 'cpu' else ''})",
            file=sys.stderr,
            flush=True,
        )
    if args.stability:
        return _run_stability(args, designs, settings, run, progress)
    table = evaluate(designs, beh, settings, progress=progress, auto_timestep=auto, **run)
    out = (
        table[list(RESULT_COLUMNS)]
        .assign(behaviour=beh.name, **settings.columns("convention", "sensor_timing", "segment_mass"))
        .assign(**settings.columns("duration_s", "transient_s"))
        .assign(timestep_s=[s.timestep_s for s in per_design], substeps=[s.substeps for s in per_design])
        .assign(backend=args.backend)
        .assign(**{c: table[c].to_numpy() for c in EVENT_COLUMNS})
    )
    out = _with_properties(out, designs, settings.segment_mass)
    where = f" on {device}" if device else ""
    print(
        f"{_count(len(out), 'design')} on {beh.name}: {settings.duration_s:g} s at {_step_text(per_design)}, "
        f"transient {settings.transient_s:g} s, convention {settings.convention}, sensor timing "
        f"{settings.sensor_timing}{_segment_mass_text(settings)}, backend {args.backend}{where}"
    )
    shown = _blank_diverged(out[list(RESULT_COLUMNS)])
    suspect = table["suspect_at_s"].astype(float).notna().to_numpy()
    if suspect.any():  # stable, but corrupted: the table says so beside "stable"
        shown = shown.assign(suspect=suspect)
    rerun = {d.name: _rerun_command(d, beh, settings, auto) for d in designs}
    note = _diverged_note(table, auto, designs, per_design, args.backend, rerun)
    odd = _suspect_note(table, auto)
    hopless = table["stable"].astype(bool) & (table["n_hops"] == 0) & table["upright"].astype(bool)
    empty = f"{int(hopless.sum())} of {_count(len(table), 'design')}: {no_hops_line(settings.transient_s, settings.duration_s)}"
    notes = (note, odd, _fallen_note(table, designs, per_design), empty if hopless.any() else "")
    _report(out, args.csv, "\n".join(n for n in notes if n), shown=shown)
    return 1 if note or odd else 0  # any run diverged or suspect: exit 1 (the rule of every command); a fall: 0


def _blank_diverged(shown):
    """The printed table with a diverged design's metrics shown as "-": its
    hop cycles before the divergence are not results (the CSV keeps them,
    beside stable False and diverged_at_s). Metric columns become text,
    4 significant digits as the rest of the table."""
    bad = ~shown["stable"].astype(bool)
    if not bad.any():
        return shown
    out = shown.copy()
    for c in shown.columns:
        if c in ("design", "stable"):
            continue
        text = [f"{v:.4g}" if isinstance(v, float) else str(v) for v in shown[c]]
        out[c] = ["-" if b else t for t, b in zip(text, bad)]
    return out


def _segment_mass_text(settings) -> str:
    """``, segment mass capsule`` where the batch does not run the default (leg)."""
    return "" if settings.segment_mass == "leg" else f", segment mass {settings.segment_mass}"


def _step_text(per_design) -> str:
    """The batch's physics step: one, or under --timestep auto the range of the designs' own."""
    steps = sorted({(s.timestep_s, s.substeps) for s in per_design})
    if len(steps) == 1 and steps[0][1] == 1:
        return f"dt={steps[0][0]:g} s"
    (lo, _), (hi, _) = steps[0], steps[-1]
    ks = sorted({k for _, k in steps})
    dt = f"{lo:.3g} s" if lo == hi else f"{lo:.3g} to {hi:.3g} s"
    k = f"{ks[0]}" if len(ks) == 1 else f"{ks[0]} to {ks[-1]}"
    return f"--timestep auto (dt={dt}, {k} physics substeps per control period)"


def _warn_stable_step(designs, per_design) -> None:
    """Before any run: one line on stderr for the designs whose step lies
    above their analytic stable step (:func:`mat_hopper.core.timestep.check_stable_step`)."""
    from ..core.timestep import CLI_AUTO_HINT, check_stable_step

    notes = [(d.name, check_stable_step(d, s, auto_hint=CLI_AUTO_HINT)) for d, s in zip(designs, per_design)]
    over = [(name, note) for name, note in notes if note]
    if len(over) == 1:
        line = f"{over[0][0]}: {over[0][1]}"
    elif over:
        names = ", ".join(name for name, _ in over[:5]) + (f" and {len(over) - 5} more" if len(over) > 5 else "")
        line = (
            f"{len(over)} of {_count(len(designs), 'design')} run above their analytic stable step ({names}): "
            f"they may diverge; try {CLI_AUTO_HINT} (each design its own physics substeps)"
        )
    else:
        return
    print(f"mat-hopper batch: warning: {line}", file=sys.stderr, flush=True)


def _diverged_note(table, auto: bool, designs=(), per_design=(), backend: str = "mujoco", rerun=None) -> str:
    """The line on the designs that diverged (when, after a fall where one
    fell first, and what to try), or "". --timestep auto is advised only
    where it would change a diverged design's step
    (:func:`mat_hopper.core.timestep.auto_suggestion`; a leg that falls
    before it diverges may already run at its automatic step) and only for
    the backend that takes it (mujoco). `rerun` (design name to a
    ``mat-hopper simulate`` command line that runs it, :func:`_rerun_command`)
    names the command that says why; without it the line says
    ``simulate`` with the design's --density and --modulus."""
    from ..core.timestep import CLI_AUTO_HINT, CLI_CONTACT_HINT, auto_suggestion, soft_contact_note

    bad = table[~table["stable"]]
    if not len(bad):
        return ""
    at = ", ".join(_when(r) for r in bad.head(5).itertuples())
    more = f" and {len(bad) - 5} more" if len(bad) > 5 else ""
    first = str(bad["design"].iloc[0])
    command = (rerun or {}).get(first)
    why = f"`{command}` says why ({first})" if command else "`mat-hopper simulate` of the design says why"
    by_name = {d.name: (d, st) for d, st in zip(designs, per_design)}
    helps = any(auto_suggestion(*by_name[n], CLI_AUTO_HINT) for n in bad["design"] if n in by_name)
    if auto:
        fix = f"already at --timestep auto; {why}"
    elif backend != "mujoco":
        fix = f"--timestep auto is for --backend mujoco (each design its own physics substeps); {why}"
    elif helps or not by_name:
        fix = f"try --timestep auto (each design its own physics substeps); {why}"
    else:
        fix = f"--timestep auto would not change their step; {why}"
    soft = next(
        (n for n in (soft_contact_note(*by_name[d], CLI_CONTACT_HINT) for d in bad["design"] if d in by_name) if n),
        None,
    )
    soft = f"{soft}; " if soft else ""
    return (
        f"{len(bad)} of {_count(len(table), 'design')} diverged ({at}{more}); their metrics are shown as -; {soft}{fix}"
    )


def _when(row) -> str:
    """A diverged design's name and time, after its fall where it fell first."""
    fell = getattr(row, "fell_at_s", math.nan)
    fell = math.nan if fell is None else float(fell)
    if math.isfinite(fell) and fell < row.diverged_at_s:
        return f"{row.design} fell at t = {fell:.3f} s, then diverged at t = {row.diverged_at_s:.4f} s"
    return f"{row.design} at t = {row.diverged_at_s:.4f} s"


def _suspect_note(table, auto: bool) -> str:
    """The line on the designs whose run did not diverge but whose numbers
    are corrupted (a scored hop apex far above the target:
    :attr:`mat_hopper.core.rollout.Rollout.suspect`), or "": their rows are
    the integrator's, not the leg's."""
    from ..core.rollout import SUSPECT_APEX_MARGIN_M

    at = table["suspect_at_s"].astype(float) if "suspect_at_s" in table.columns else None
    if at is None or not at.notna().any():
        return ""
    rows = table[at.notna()]
    names = ", ".join(f"{r.design} at t = {r.suspect_at_s:.3f} s" for r in rows.head(5).itertuples())
    more = f" and {len(rows) - 5} more" if len(rows) > 5 else ""
    fix = "already at --timestep auto: try a smaller --timestep" if auto else "try --timestep auto"
    return (
        f"{len(rows)} of {_count(len(table), 'design')} numerically suspect ({names}{more}: a hop apex more than "
        f"{SUSPECT_APEX_MARGIN_M:g} m above the target, energy the integrator made up near the stable step; "
        f"their numbers are corrupted); {fix}"
    )


def _fallen_note(table, designs=(), per_design=()) -> str:
    """The line on the designs that fell over without diverging (base
    tilted past FELL_TILT_DEG, or below the upright height at the end), or
    "": their hop cycles after the fall are not scored; a fall alone does
    not change the exit status (as simulate). With the batch's `designs`
    and their settings `per_design`, a bending leg on the default soft
    contact gets why and what to try
    (:func:`mat_hopper.core.timestep.soft_contact_note`)."""
    from ..core.rollout import FELL_TILT_DEG
    from ..core.timestep import CLI_CONTACT_HINT, soft_contact_note

    fell = table["fell_at_s"].astype(float) if "fell_at_s" in table.columns else None
    down = table["stable"] & (~table["upright"] | (fell.notna() if fell is not None else False))
    if not down.any():
        return ""
    rows = table[down]
    by_name = {d.name: (d, st) for d, st in zip(designs, per_design)}
    soft = next(
        (n for n in (soft_contact_note(*by_name[d], CLI_CONTACT_HINT) for d in rows["design"] if d in by_name) if n),
        None,
    )
    at = ", ".join(
        f"{r.design} at t = {r.fell_at_s:.3f} s"
        if math.isfinite(float(r.fell_at_s))
        else f"{r.design} (when: not tracked)"
        for r in rows.head(5).itertuples()
    )
    more = f" and {len(rows) - 5} more" if len(rows) > 5 else ""
    return (
        f"{len(rows)} of {_count(len(table), 'design')} fell over ({at}{more}; base tilted past {FELL_TILT_DEG:g} deg "
        "or below the upright height at the end): hop cycles after a fall are not scored"
        + (f"; {soft}" if soft else "")
    )


def _rerun_command(design, beh, settings, auto: bool) -> str:
    """A ``mat-hopper simulate`` command line that runs `design` as this
    batch did (:func:`mat_hopper.cli._rerun.simulate_command`: by name
    where simulate knows it, else by --density and --modulus), with the
    batch's behaviour, duration, transient, step and the settings that
    differ from simulate's defaults."""
    from ._rerun import simulate_command

    return simulate_command(
        design,
        behaviour=beh.name,
        duration=f"{settings.duration_s:g}",
        transient=f"{settings.transient_s:g}",
        timestep="auto" if auto else f"{settings.timestep_s:g}",
        convention=None if settings.convention == "paper" else settings.convention,
        sensor_timing=None if settings.sensor_timing.name == "authors" else settings.sensor_timing.name,
        segment_mass=None if settings.segment_mass == "leg" else settings.segment_mass,
    )


def _batch_settings(args, profile, timing):
    from ..batch import BatchSettings

    step = None if _auto(args) else timestep_arg(args.timestep)  # auto: each design its own (design_settings)
    return BatchSettings(
        duration_s=profile.duration_s if args.duration is None else args.duration,
        timestep_s=profile.timestep_s if step is None else step,
        transient_s=profile.transient_s if args.transient is None else args.transient,
        convention=args.convention,
        sensor_timing=timing,
        segment_mass=args.segment_mass,
    )


def _with_properties(table, designs, segment_mass: str):
    """The table (one row per design, in order) with each design's
    densities, moduli and leg mass after its name: rows that differ only
    in their properties can be told apart."""
    import pandas as pd

    from ..batch import design_columns

    n_max = max(d.n_segments for d in designs)
    props = pd.DataFrame([design_columns(d, n_max, segment_mass) for d in designs], index=table.index)
    props = props.drop(columns=[c for c in props.columns if c in table.columns])
    at = list(table.columns).index("design") + 1
    return pd.concat([table.iloc[:, :at], props, table.iloc[:, at:]], axis=1)


def _count(n: int, noun: str) -> str:
    return f"{n} {noun}" + ("" if n == 1 else "s")


def _check_applicable(args) -> None:
    """Options given that the chosen mode or backend has no use for: one line, before any work."""
    run_options = {"--behaviour": args.behaviour, "--duration": args.duration, "--transient": args.transient}
    run_options["--timestep"] = args.timestep
    given = [flag for flag, value in run_options.items() if value is not None]
    if args.segment_mass != "leg":
        given.append(f"--segment-mass {args.segment_mass}")
    if args.stability and given:
        raise ValueError(f"{', '.join(given)}: not used by --stability (static hopping at its ladder of time steps)")
    if not args.stability and args.stability_duration is not None:
        raise ValueError("--stability-duration is for --stability")
    _check_stability_duration(args.stability_duration)
    if args.backend != "warp":
        for flag, value in (("--device", args.device), ("--max-batch", args.max_batch)):
            if value is not None:
                raise ValueError(f"{flag} is for --backend warp")
    elif args.workers is not None:
        raise ValueError("--workers is for --backend mujoco (a warp batch is one process)")
    elif _auto(args):
        raise ValueError(
            "--timestep auto is for --backend mujoco (a warp batch runs every world at one physics step, the "
            "controller every step); give --timestep a number"
        )
    from ..util.limits import MAX_WORLDS, check_count, check_workers

    check_workers(args.workers)
    check_count(args.max_batch, "--max-batch", 1, MAX_WORLDS, "worlds")


def _check_stability_duration(duration) -> None:
    """--stability-duration (None: the reference's) is > 0 and at least the
    ladder's largest time step: a shorter try takes no step at that rung and
    would read as a design that never ends upright."""
    if duration is None:
        return
    if not (math.isfinite(duration) and duration > 0):
        raise ValueError(f"--stability-duration must be > 0 s, got {duration:g}")
    first = ref.STABILITY_TIMESTEP_RANGE[0]  # the ladder's largest step (mat_hopper.physics.stability.spec_ladder)
    if duration < first:
        raise ValueError(
            f"--stability-duration must be at least the scan's largest time step, {first:g} s (a shorter try "
            f"takes no step), got {duration:g} s"
        )


def _check_size(args, designs, settings, per_design) -> None:
    """designs x physics steps, before any work (mat_hopper.util.limits)."""
    from ..physics.stability import spec_ladder
    from ..util.limits import check_total_steps

    source = "--map" if args.map is not None else "--designs-csv" if args.designs_csv is not None else "--designs"
    if args.stability:
        duration = ref.STABILITY_TEST_DURATION_S if args.stability_duration is None else args.stability_duration
        per_design, what = sum(duration / dt for dt in spec_ladder()), "--stability-duration"
    else:
        per_design, what = sum(s.n_steps for s in per_design) / len(designs), "--duration / --timestep"
    check_total_steps(
        len(designs) * per_design,
        f"{source}: {_count(len(designs), 'design')} x {per_design:.3g} steps",
        f"fewer designs or a shorter {what}",
    )


def _map_designs(n: int) -> list:
    """The stable-time-step map's designs (experiment 4), n x n."""
    from ..experiments.paper import StabilityMap

    if n < 1 or n > 100:
        raise ValueError(f"--map must be in [1, 100] designs per axis, got {n}")
    profile = dataclasses.replace(PROFILES["paper"], stability_grid_size=n)
    return [task.design for task in StabilityMap().tasks(profile)]


def _run_stability(args, designs, settings, run: dict, progress: bool) -> int:
    from ..batch import spec_scan_batch

    duration = ref.STABILITY_TEST_DURATION_S if args.stability_duration is None else args.stability_duration
    summary, tries = spec_scan_batch(
        designs,
        duration_s=duration,
        convention=args.convention,
        sensor_timing=settings.sensor_timing,
        progress=progress,
        **run,
    )
    summary = summary.assign(**settings.columns("convention", "sensor_timing"), stability_duration_s=duration)
    summary = _with_properties(summary, designs, settings.segment_mass)
    where = f" on {run['device']}" if run["device"] else ""
    print(
        f"{_count(len(summary), 'design')}, stable-time-step scan: static hopping for {duration:g} s per try, "
        f"sensor timing {settings.sensor_timing}, {len(tries)} tries, backend {args.backend}{where}"
    )
    n_none = int(summary["spec_timestep_s"].isna().sum())
    note = f"{n_none} of {_count(len(summary), 'design')} ended upright at no step of the ladder" if n_none else ""
    return _report(summary, args.csv, note)


def _report(table, csv: str | None, note: str, shown=None) -> int:
    """Print the table (or its columns `shown`) and a note, write the whole
    table to `csv` if given; returns 0 (the callers set the exit code)."""
    from ._checks import write_table

    print((table if shown is None else shown).to_string(index=False, float_format=lambda v: f"{v:.4g}"))
    if note:
        print(note)
    if csv:
        where = write_table(table, csv)
        print(f"wrote {_count(len(table), 'row')} to {where}")
    return 0
