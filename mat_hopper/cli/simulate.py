"""``mat-hopper simulate``: one design, one behaviour, a per-hop summary."""

from __future__ import annotations

import argparse
import math
import sys

from ..core import reference as ref
from ..core.behaviours import DEFAULT_BEHAVIOUR, behaviour
from ..core.contact import CONTACTS, DEFAULT_CONTACT
from ..core.control_legs import CONTROLS, control, mass_properties
from ..core.damping import DAMPINGS, DEFAULT_DAMPING
from ..core.materials import (
    DENSITY_RANGE_G_CM3,
    MODULUS_RANGE_GPA,
    SEGMENT_MASSES,
    LegDesign,
    check_n_segments,
    parse_design,
)
from ..core.rollout import FELL_TILT_DEG
from ..core.timestep import CLI_AUTO_HINT, check_stable_step, is_auto
from ..experiments.profiles import PROFILE_ENV
from ..physics.metrics import METRICS, hop_table, run_summary
from ._checks import (
    SENSOR_TIMING_HELP,
    check_distinct_paths,
    check_input_file,
    check_output_file,
    named_by_flags,
    parse_list,
    sensor_timing_arg,
    sensor_timing_type,
    write_table,
)
from ._options import (
    BEHAVIOUR_HELP,
    DENSITY_HELP,
    DURATION_HELP,
    MODULUS_HELP,
    SEGMENT_MASS_HELP,
    SEGMENTS_HELP,
    TRANSIENT_HELP,
    add_behaviour,
    add_convention,
    add_force,
    add_no_progress,
    add_profile,
    add_timestep,
    check_force_used,
    decimal_comma_of,
    no_hops_line,
    profile_of,
    timestep_arg,
)

DEFAULT_DESIGN = "SS"
PROGRESS_CHUNK_S = 1.0  # simulated seconds per progress-bar update


def design_from_args(args) -> LegDesign:
    """--design NAME, --design-csv FILE, or --density/--modulus lists
    (g/cm^3, GPa); never two of them, and --segments only with a
    single-material --design (a file, a gradient such as PVC-Ti-SS, a
    named design such as rho-inc or a custom(...) name sets its own: the
    pair is refused, naming both, rather than --segments ignored) or, with
    lists, as their count confirmed (DECIMAL_COMMA_RULE: "2,7" with
    "1,5" may be decimal commas, and is refused without it)."""
    segments = ref.REFERENCE_SEGMENTS if args.segments is None else args.segments
    with named_by_flags():
        n = check_n_segments(segments)  # an integer in [1, 64] whatever the design form
    if getattr(args, "design_csv", None) is not None:
        given = [
            flag
            for flag, v in (
                ("--design", args.design),
                ("--density", args.density),
                ("--modulus", args.modulus),
                ("--segments", args.segments),
            )
            if v is not None
        ]
        if given:
            raise ValueError(f"--design-csv gives the design: leave out {', '.join(given)}")
        return _design_from_csv(check_input_file(args.design_csv, "--design-csv"))
    if args.density is not None or args.modulus is not None:
        given = "--density" if args.density is not None else "--modulus"
        if args.design is not None:
            raise ValueError("give either --design or --density with --modulus, not both")
        if args.density is None or args.modulus is None:
            raise ValueError("--density and --modulus go together (one value per segment)")
        dens = parse_list(args.density, "--density", unit="g/cm^3")
        mods = parse_list(args.modulus, "--modulus", rigid=True, unit="GPa")
        _check_list_count(args, len(dens), len(mods), given)
        for flag, vals, (lo, hi), unit in (
            ("--density", dens, DENSITY_RANGE_G_CM3, "g/cm^3"),
            ("--modulus", mods, MODULUS_RANGE_GPA, "GPa"),
        ):
            bad = [v for v in vals if v is not None and v <= 0]
            if bad:
                raise ValueError(f"{flag} must be > 0 {unit} (accepted {lo:g} to {hi:g}), got {bad[0]:g}")
        return LegDesign.from_properties(dens, mods)
    name = DEFAULT_DESIGN if args.design is None else args.design
    design = parse_design(name, n_segments=n)
    if args.segments is not None and parse_design(name, n_segments=1 if n != 1 else 2).n_segments == design.n_segments:
        # a gradient, a named design (rho-inc) or custom(...) has its own segments: --segments would be ignored
        raise ValueError(
            f"--segments is for a single-material --design; --design {name.strip()} has its own "
            f"{design.n_segments} segments (leave out --segments)"
        )
    return design


def _comma_hint(flag: str, text: str, decimal: str, n_dens: int, n_mods: int) -> str:
    """ "for 2.7 write a point" where writing the point would make the two
    counts equal; else what it would leave (a hint that does not fix the
    input is not one)."""
    dens, mods = (1, n_mods) if flag == "--density" else (n_dens, 1)
    if dens == mods:
        return f"; {flag} {text} is two values: for {decimal} write a point"
    unit = ("density", "densities"), ("modulus", "moduli")
    left = f"{dens} {unit[0][dens != 1]} and {mods} {unit[1][mods != 1]}"
    return f"; {flag} {text} is two values ({decimal} with a point would still leave {left})"


def _check_list_count(args, n_dens: int, n_mods: int, given: str) -> None:
    """--density and --modulus have one value per segment, as many as
    --segments where it is given; two lists that may be decimal commas
    ("2,7" and "1,5": one segment of 2.7 g/cm^3 and 1.5 GPa, or two) are
    refused unless --segments confirms the count (DECIMAL_COMMA_RULE)."""
    commas = {f: d for f, t in (("--density", args.density), ("--modulus", args.modulus)) if (d := decimal_comma_of(t))}
    if n_dens != n_mods:  # no lone value spread over the segments (the help says one per segment)
        hint = "".join(_comma_hint(f, getattr(args, f[2:]), d, n_dens, n_mods) for f, d in commas.items())
        raise ValueError(f"--density and --modulus need one value per segment (got {n_dens} and {n_mods}){hint}")
    if args.segments is not None and args.segments != n_dens:
        raise ValueError(f"--segments {args.segments}: {given} gives {n_dens} values, one per segment")
    if args.segments is None and len(commas) == 2:
        shown = " and ".join(f"{f} {getattr(args, f[2:])}" for f in commas)
        raise ValueError(
            f"{shown}: two segments, or decimal commas ({' and '.join(commas.values())})? write "
            f"{' and '.join(commas.values())} with a decimal point for one segment, or give --segments 2"
        )


def _design_from_csv(path) -> LegDesign:
    """The one design of a designs CSV (``mat-hopper optimize --export``,
    :func:`mat_hopper.batch.designs_from_csv`'s columns)."""
    from ..batch import designs_from_csv

    designs = designs_from_csv(path)
    if len(designs) != 1:
        raise ValueError(
            f"--design-csv: {path} holds {len(designs)} designs; simulate runs one (batch --designs-csv runs many)"
        )
    return designs[0]


def add_sim_arguments(p: argparse.ArgumentParser) -> None:
    """Design and run options shared by commands that simulate one design."""
    p.add_argument(
        "--design",
        default=None,
        help=f"material (MD, PVC, Al, Ti, SS, ...), gradient like PVC-Ti-SS, rho-inc or rho-dec (default "
        f"{DEFAULT_DESIGN}); or --density and --modulus",
    )
    p.add_argument(
        "--design-csv",
        metavar="FILE",
        help="the one design of a designs CSV (density_i, modulus_i columns; e.g. optimize --export's)",
    )
    p.add_argument("--density", help=DENSITY_HELP)
    p.add_argument("--modulus", help=MODULUS_HELP)
    p.add_argument("--segments", type=int, default=None, help=SEGMENTS_HELP)
    add_behaviour(p, DEFAULT_BEHAVIOUR, BEHAVIOUR_HELP)
    add_timestep(p, f"default: the profile's (1e-4; ${PROFILE_ENV})")
    add_convention(p)
    p.add_argument("--sensor-timing", default="authors", type=sensor_timing_type(), help=SENSOR_TIMING_HELP)
    p.add_argument("--segment-mass", default="leg", choices=SEGMENT_MASSES, help=SEGMENT_MASS_HELP)
    p.add_argument(
        "--damping",
        default=DEFAULT_DAMPING,
        choices=DAMPINGS,
        help="material springs' damping: authors (default, 1 N s/m) or loss-factor (per material class)",
    )
    p.add_argument(
        "--contact",
        default=DEFAULT_CONTACT,
        choices=tuple(CONTACTS),
        help="foot-terrain contact: authors (default: MuJoCo's soft default, time constant 0.02 s) or stiff (1 ms)",
    )


def sim_settings_from_args(
    args, design: LegDesign, duration_s: float, transient_s: float, duration_flag: str = "--duration", **extra
):
    """SimSettings of the run options, checked (run-size limits included)
    before any work; --timestep auto resolved for this design. Errors name
    the options (duration_flag: what sets the run's length).

    Args:
        args: the parsed command line (--timestep, --convention,
            --sensor-timing, --segment-mass, --damping, --contact, --profile).
        design: the leg (for --timestep auto).
        duration_s: the run's length, s.
        transient_s: hop cycles starting before it are not scored, s.
        duration_flag: the option(s) named for the run's length in errors.
        **extra: further :class:`~mat_hopper.core.sim.SimSettings` fields.

    Returns:
        The :class:`~mat_hopper.core.sim.SimSettings`.

    Raises:
        ValueError: a bad setting (a run shorter than one control period
            included), or a run above the limit of physics steps
            (:func:`mat_hopper.util.limits.check_total_steps`, $MAT_HOPPER_MAX_STEPS),
            naming the options.
    """
    from ..util.limits import check_total_steps

    with named_by_flags(duration_s=duration_flag, duration=duration_flag):
        settings = _sim_settings(args, design, duration_s, transient_s, **extra)
    check_total_steps(  # the one limit of every command's work, as batch, optimize and reproduce
        settings.n_steps,
        f"{duration_flag} {settings.duration_s:g} s at {settings.timestep_s:g} s a physics step",
        f"a shorter {duration_flag} or a larger --timestep",
    )
    return settings


def _sim_settings(args, design: LegDesign, duration_s: float, transient_s: float, **extra):
    from ..core.sim import sim_settings

    dt = timestep_arg(args.timestep)
    return sim_settings(
        design,
        duration_s=duration_s,
        timestep_s=profile_of(getattr(args, "profile", None)).timestep_s if dt is None else dt,
        transient_s=transient_s,
        convention=args.convention,
        sensor_timing=sensor_timing_arg(args.sensor_timing),
        segment_mass=args.segment_mass,
        damping=getattr(args, "damping", DEFAULT_DAMPING),
        contact=getattr(args, "contact", DEFAULT_CONTACT),
        **extra,
    )


def describe_settings(settings, auto: bool = False) -> str:
    step = f"dt={settings.timestep_s:g} s"
    if auto or settings.substeps > 1:
        step += f" ({settings.substeps} physics substeps per {settings.control_period_s:g} s control period)"
    return (
        f"{step}, convention={settings.convention}, sensor timing={settings.sensor_timing}, "
        f"segment mass={settings.segment_mass}, damping={settings.damping}, contact={settings.contact}"
    )


def run_with_progress(design, beh, settings, *, progress: bool, record_qpos: bool = False):
    """The rollout, advanced in chunks of PROGRESS_CHUNK_S simulated seconds
    with progress on stderr (:mod:`mat_hopper.util.progress`: a bar on a
    terminal, a line per stage otherwise; none when progress is false).
    Chunked and single-call rollouts are bit-identical."""
    from ..core.sim import RolloutRunner
    from ..util.progress import StageLines, progress_bar

    runner = RolloutRunner(design, beh, settings, record_qpos=record_qpos)
    chunk = max(1, int(round(PROGRESS_CHUNK_S / settings.timestep_s)))
    with progress_bar(
        total=round(settings.duration_s, 6),
        unit="sim s",
        desc=design.name,
        file=sys.stderr,
        enabled=progress,
        dynamic_ncols=True,
        leave=False,
        bar_format="{l_bar}{bar}| {n:.0f}/{total:.0f} simulated s [{elapsed}<{remaining}]",
    ) as bar:
        while not runner.done:
            runner.advance(chunk)
            bar.update(min(runner.step * settings.timestep_s, settings.duration_s) - bar.n)
        result = runner.result()
        if result.diverged:  # cut short: "stopped" at the divergence, not "done" nor a chunk's end
            bar.update(result.diverged_at_s - bar.n)
            if isinstance(bar, StageLines):
                bar.close(stopped=True)
    return result


def stable_step_warning(command: str, design, settings) -> str | None:
    """Before any run: :func:`mat_hopper.core.timestep.check_stable_step`'s
    line, if the run's step lies above the leg's analytic bound, printed on
    stderr as ``mat-hopper <command>: warning: ...`` (naming --timestep
    auto); returned too (None when within the bounds)."""
    note = check_stable_step(design, settings, auto_hint=CLI_AUTO_HINT)
    if note:
        print(f"mat-hopper {command}: warning: {note}", file=sys.stderr, flush=True)
    return note


def unstable_line(rollout) -> str:
    """Why a run ended early, in one line: when, which check, the step
    above the analytic bound if it is, the soft contact's cause for a leg
    that bends, what to try
    (:meth:`mat_hopper.core.rollout.Rollout.divergence_message`); a fall
    (the base tilted past FELL_TILT_DEG before the numbers blew up) says so
    first."""
    message = rollout.divergence_message(CLI_AUTO_HINT)
    fell = rollout.fell_at_s
    if fell is None or fell >= rollout.diverged_at_s:
        return f"UNSTABLE: {message}"
    return f"UNSTABLE: the hopper fell (base tilted past {FELL_TILT_DEG:g} deg at t = {fell:.3f} s), then {message}"


def fall_line(rollout) -> str | None:
    """A stable run whose hopper fell, in one line: when
    (:meth:`~mat_hopper.core.rollout.Rollout.fall_message`), and for a leg
    that bends on the default soft contact why and what to try
    (:func:`mat_hopper.core.timestep.soft_contact_note`); None for a run
    that did not fall or diverged (:func:`unstable_line` says it)."""
    from ..core.timestep import CLI_CONTACT_HINT, soft_contact_note

    fell = rollout.fall_message()
    if fell is None:
        return None
    note = soft_contact_note(rollout.design, rollout.settings, CLI_CONTACT_HINT)
    return f"FELL: {fell}" + (f"; {note}" if note else "")


EXIT_STATUS = (
    "Exit status: 0 when every run ended without numerical divergence; 1 when any diverged or is numerically "
    "suspect (a hop apex far above the target: corrupted numbers without a blow-up; the output says when, why "
    "and what to try; tables are still printed and written); 2 for bad input."
)


def cmd_simulate(args) -> int:
    profile = profile_of(args.profile)  # ValueError for an unknown $MAT_HOPPER_PROFILE (e.g. turbo)
    check_force_used(args, {"--csv": args.csv})
    check_distinct_paths({"--csv": args.csv}, {"--design-csv": args.design_csv})  # never over the input table
    check_output_file(args.csv, "--csv", stdout=True, force=args.force)
    design = design_from_args(args)
    if args.control is not None:
        if str(args.control).lower() == "rigid" and all(seg.rigid for seg in design.segments):
            raise ValueError(
                f"--control rigid: design {design.name} has no springs (every segment is rigid), so it is its "
                "own rigid twin; leave out --control rigid or give a design with springs"
            )
        design = control(design, args.control, args.segment_mass)
    beh = behaviour(args.behaviour)
    duration = profile.duration_s if args.duration is None else args.duration
    transient = profile.transient_s if args.transient is None else args.transient
    settings = sim_settings_from_args(args, design, duration, transient)  # a bad value is named first
    if args.profile is not None and None not in (args.duration, args.transient, args.timestep):
        raise ValueError(
            "--profile sets only the defaults of --duration, --transient and --timestep, and all three are given: "
            "leave out --profile (or one of the three)"
        )
    stable_step_warning("simulate", design, settings)
    rollout = run_with_progress(design, beh, settings, progress=not args.no_progress)
    hops = hop_table(rollout, warn=False)  # the UNSTABLE line below says it
    s = run_summary(rollout)
    print(
        f"{design.name} on {beh.name}: {settings.duration_s:g} s ({profile.name} profile) at "
        f"{describe_settings(settings, is_auto(args.timestep))}, mass {rollout.total_mass_kg:.2f} kg"
    )
    mp = mass_properties(design, settings.segment_mass)
    print(
        f"leg: mass {mp.leg_mass_kg:.3f} kg, centre of mass {mp.leg_com_m:.4f} m below the hip, "
        f"hip inertia {mp.hip_inertia_kg_m2:.4f} kg m^2"
    )
    if not rollout.stable:
        print(unstable_line(rollout))
    elif rollout.suspect:
        print(f"SUSPECT: {rollout.suspect_message(CLI_AUTO_HINT)}")
    if fall_line(rollout):
        print(fall_line(rollout))
    before = "" if rollout.stable else f", before the divergence at t = {rollout.diverged_at_s:.4f} s: not results"
    print(f"{len(hops)} hop cycles scored after {settings.transient_s:g} s{before}")
    if not len(hops) and rollout.stable and rollout.fell_at_s is None:  # a short window, not a failure: say so
        print(f"note: {no_hops_line(settings.transient_s, settings.duration_s)}")
    if len(hops):
        desc = hops[list(METRICS)].describe().loc[["mean", "std", "min", "max"]]
        print(desc.to_string(float_format=lambda v: f"{v:.4g}"))
        cot = s["cost_of_transport"]
        cot = f"{cot:.3g}" if math.isfinite(cot) else "none (no distance travelled)"
        print(
            f"power_w: hip actuators only (mean mechanical power); work of all three actuators (hips and leg "
            f"slide) {s['work_abs_j']:.1f} J ({s['thrust_work_fraction']:.0%} by the thrust), "
            f"{s['energy_per_hop_j']:.2f} J per hop, path {s['path_length_m']:.2f} m, cost of transport {cot}"
        )
        if s["peak_stress_pa"] == s["peak_stress_pa"]:  # a leg with modelled stress
            flag = "  ** PEAK STRESS OVER YIELD **" if s["yield_exceeded"] else ""
            from ..physics.fatigue import strength_basis

            # a leg given by its properties is judged by its class's curve, not a catalogue entry's: say whose
            curves = ", ".join(dict.fromkeys(strength_basis(m) for m in design.segments if not m.rigid))
            print(
                f"peak stress {s['peak_stress_pa'] / 1e6:.3g} MPa ({s['yield_ratio']:.2g} x yield), damage per hop "
                f"{s['damage_per_hop']:.3g}, hops to failure {s['hops_to_failure']:.3g} (S-N curve: {curves}){flag}"
            )
    if args.csv:
        at = list(hops.columns).index("segment_mass") + 1
        hops.insert(at, "timestep_s", settings.timestep_s)
        hops.insert(at + 1, "substeps", settings.substeps)
        # how the run ended, in every row (as batch's CSV): a diverged, fallen or suspect run's rows are not results
        ended = {"diverged_at_s": rollout.diverged_at_s, "fell_at_s": rollout.fell_at_s, "suspect_at_s": None}
        if rollout.suspect:
            ended["suspect_at_s"] = rollout.suspect_apex[0]
        for k, (col, when_s) in enumerate(ended.items()):
            hops.insert(at + 2 + k, col, math.nan if when_s is None else float(when_s))
        from ..batch import design_columns  # the design's properties in every row: rows of two runs differ

        props = {k: v for k, v in design_columns(design, segment_mass=settings.segment_mass).items() if k not in hops}
        at = list(hops.columns).index("substeps") + 1  # after the run settings
        for k, (col, value) in enumerate(props.items()):
            hops.insert(at + k, col, value)
        print(f"wrote {len(hops)} rows to {write_table(hops, args.csv)}")
    return 0 if rollout.stable and not rollout.suspect else 1


def register_cli(sub) -> None:
    p = sub.add_parser(
        "simulate",
        help="simulate one design on one behaviour, print a per-hop summary",
        description="Simulate one leg design on one behaviour and summarize its hop cycles. Run sizes are "
        "capped (2e9 physics steps, 5e6 recorded samples, 64 segments) and checked before any work; a time "
        f"step above the design's analytic stable step is warned of (try --timestep auto). {EXIT_STATUS}",
    )
    add_sim_arguments(p)
    p.add_argument(
        "--control",
        choices=CONTROLS,
        default=None,
        help="simulate a control of the design instead: rigid (same densities, no springs), mass (homogeneous "
        "leg of the same leg mass), inertia (same leg mass and hip inertia; mat_hopper.core.control_legs)",
    )
    add_profile(p)
    p.add_argument("--duration", type=float, default=None, help=DURATION_HELP)
    p.add_argument("--transient", type=float, default=None, help=TRANSIENT_HELP)
    p.add_argument("--csv", help="write the per-hop table (one row per scored hop cycle) here (- for standard output)")
    add_force(p)
    add_no_progress(p)
    p.set_defaults(func=cmd_simulate)
