"""``mat-hopper compare``: one design against baselines and its own controls.

    mat-hopper compare --design rho-inc --baseline SS,Ti --controls rigid,mass,inertia --behaviour forward
    mat-hopper compare --density 1.39,4.43,8 --modulus 70,70,70 --profile quick --timestep auto --csv out.csv

Every leg runs on the same settings, the same time step (under ``auto``
the finest any of them needs) and the same seeds, through the one cache
and pool; the table is the book's paired comparison
(:func:`mat_hopper.experiments.compare.compare_design`).
"""

from __future__ import annotations

import math
import sys

from ..core.timestep import CLI_AUTO_HINT, check_stable_step
from ..experiments.cache import CACHE_ENV, DEFAULT_CACHE_DIR
from ._checks import named_by_flags
from ._options import (
    DURATION_HELP,
    TRANSIENT_HELP,
    add_force,
    add_no_progress,
    add_profile,
    check_force_used,
    no_hops_line,
    timestep_arg,
)
from .simulate import EXIT_STATUS, add_sim_arguments, design_from_args

HELP = "compare a design with baselines and its own controls, paired on shared seeds at one time step"
# The API's argument names and the options that set them, for its messages.
FLAGS = {"baselines": "--baseline", "controls": "--controls", "replicates": "--replicates"}


def _signed(v: float, unit: str = "%") -> str:
    return "nan" if not math.isfinite(v) else f"{v:+.3g}{unit}"


def _shown(table, metrics) -> object:
    """The printed table: one line per comparator and metric."""
    import pandas as pd

    from ..experiments.compare import METRIC_LABELS

    rows = []
    for r in table.to_dict("records"):
        for m in metrics:
            lo, hi = r[f"{m}_ci_low"], r[f"{m}_ci_high"]
            rows.append(
                {
                    "comparator": r["comparator"],
                    "role": r["role"],
                    "metric": METRIC_LABELS.get(m, m),
                    "design": f"{r[f'{m}_mean']:.4g}",
                    "comparator mean": f"{r[f'{m}_mean_comparator']:.4g}",
                    "change": _signed(r[f"{m}_pct_change"]),
                    "95% interval": f"[{_signed(lo, '')}, {_signed(hi, '')}]%",
                    "p (Holm)": f"{r[f'{m}_p_holm']:.3g}",
                    "verdict": r[f"{m}_verdict"],
                }
            )
    return pd.DataFrame(rows)


def _header(plan, auto: bool) -> str:
    s = plan.settings[0]
    step = f"dt={s.timestep_s:g} s"
    if auto or s.substeps > 1:
        step += f" ({s.substeps} physics substeps per {s.control_period_s:g} s control period"
        step += f"; the finest automatic step, {plan.finest}'s)" if plan.finest else ")"
    n = plan.replicates
    return (
        f"{plan.design.name} on {plan.behaviour.name} ({plan.profile.name} profile, {s.duration_s:g} s runs, "
        f"{s.transient_s:g} s transient): {n} paired seeds (0-{n - 1}) per leg, every leg at {step}, convention "
        f"{s.convention}, sensor timing {s.sensor_timing}, segment mass {s.segment_mass}, damping {s.damping}, "
        f"contact {s.contact}; replicate protocol {s.replicate_protocol}"
        + (
            f", each seed's push drawn in {p.push_window_s[0]:g}-{p.push_window_s[1]:g} s"
            if (p := s.perturbation)
            else ""
        )
    )


def _left_out_lines(left_out) -> list[str]:
    lines = []
    for e in left_out:
        seeds = f", seed{'s' if len(e['seeds']) > 1 else ''} {' '.join(map(str, e['seeds']))}" if e["seeds"] else ""
        lines.append(f"left out: {e['leg']} ({e['role']}{seeds}): {e['why']}")
    return lines


def _few_seeds_note(table) -> str | None:
    """A line where the seeds are too few for a difference to be significant
    in this family: what the verdicts then rest on."""
    from ..analysis.paired import reachable, wilcoxon_smallest_p
    from ..experiments.compare import min_replicates

    n = int(table["n_pairs"].min())
    if reachable(n, len(table)):
        return None
    return (
        f"with n = {n} seeds no difference can be significant here (exact sign-flip p >= {wilcoxon_smallest_p(n):.2g}, "
        f"Holm over {len(table)} comparator{'s' if len(table) != 1 else ''}); a 'no difference' rests on the t interval alone; for a test give "
        f"--replicates {min_replicates(len(table))} or more"
    )


def _auto_would_change(plan, left_out) -> bool:
    """Whether --timestep auto would change the step of a leg that diverged
    or is numerically suspect (a leg whose automatic step is the one it ran at, e.g. one that fell
    first, gets no such advice)."""
    from ..core.timestep import auto_suggestion

    legs = {leg.name: leg.design for leg in (plan.design, *plan.comparators)}
    numeric = ("unstable", "numerically suspect")  # diverged, or corrupted without diverging
    diverged = [legs[e["leg"]] for e in left_out if any(w in e["why"] for w in numeric) and e["leg"] in legs]
    return any(auto_suggestion(d, plan.settings[0], CLI_AUTO_HINT) for d in diverged)


def _soft_contact_line(plan, left_out) -> str | None:
    """Why a bending leg left out (diverged or fell) on the default soft
    contact went down, and what to try
    (:func:`mat_hopper.core.timestep.soft_contact_note`), or None."""
    from ..core.timestep import CLI_CONTACT_HINT, soft_contact_note

    legs = {leg.name: leg.design for leg in (plan.design, *plan.comparators)}
    down = [legs[e["leg"]] for e in left_out if ("unstable" in e["why"] or "fell" in e["why"]) and e["leg"] in legs]
    note = next((n for n in (soft_contact_note(d, plan.settings[0], CLI_CONTACT_HINT) for d in down) if n), None)
    return f"({note})" if note else None


def _plan(args):
    """The checked plan (every input, before any work)."""
    from ..core.control_legs import CONTROLS
    from ..experiments.compare import plan_compare
    from ..experiments.controls import BASELINES
    from ._checks import sensor_timing_arg

    design = design_from_args(args)
    with named_by_flags(**FLAGS):
        return plan_compare(
            design,
            baselines=",".join(BASELINES) if args.baseline is None else args.baseline,
            controls=",".join(CONTROLS) if args.controls is None else args.controls,
            behaviour=args.behaviour,
            profile=args.profile,
            replicates=args.replicates,
            timestep_s=timestep_arg(args.timestep),
            convention=args.convention,
            sensor_timing=sensor_timing_arg(args.sensor_timing),
            segment_mass=args.segment_mass,
            damping=args.damping,
            contact=args.contact,
            duration_s=args.duration,
            transient_s=args.transient,
        )


def cmd_compare(args) -> int:
    from ..experiments.compare import COMPARE_METRICS, run_plan
    from ..util.limits import check_workers
    from ._checks import cache_folder, check_distinct_paths, check_output_file, nothing_left_behind, write_table

    check_force_used(args, {"--csv": args.csv})
    check_output_file(args.csv, "--csv", stdout=True, force=args.force)  # before any work
    check_distinct_paths({"--csv": args.csv}, {"--design-csv": args.design_csv})
    check_workers(args.workers)
    cache, _ = cache_folder(args.cache)
    plan = _plan(args)
    print(_header(plan, auto=plan.finest is not None))
    for leg in (plan.design, *plan.comparators):  # before any run, as every command, naming the leg
        note = check_stable_step(leg.design, plan.settings[0], auto_hint=CLI_AUTO_HINT)
        if note:
            print(f"mat-hopper compare: warning: {leg.name} ({leg.role}): {note}", file=sys.stderr, flush=True)
    with nothing_left_behind(cache):
        table = run_plan(plan, cache_dir=cache, workers=args.workers, progress=not args.no_progress)
    runs = f"{len(plan.tasks)} runs ({table.attrs['n_cached']} from the cache, {table.attrs['n_computed']} computed)"
    if len(table):
        print(
            f"{runs}; paired % difference of {plan.design.name} against each comparator: log ratio of run means per "
            "seed, 95% t interval, p the larger of the paired t and the exact sign-flip test, Holm over the "
            "comparators of each metric, no difference where the interval lies inside +-10%"
        )
        print(_shown(table, COMPARE_METRICS).to_string(index=False))
        hopless = int(table["n_pairs"].max()) == 0  # every run stood, none scored a cycle: the window, not the seeds
        window = plan.settings[0]
        note = f"note: {no_hops_line(window.transient_s, window.duration_s)}" if hopless else _few_seeds_note(table)
        if note:
            print(note)
    else:
        print(f"{runs}; nothing to compare: no comparator has a usable run at a seed where the design has one")
    for line in _left_out_lines(table.attrs["left_out"]):
        print(line)
    soft = _soft_contact_line(plan, table.attrs["left_out"])
    if soft:
        print(soft)
    if plan.finest is None and _auto_would_change(plan, table.attrs["left_out"]):
        print(
            "(a leg diverged or is numerically suspect at a fixed step: try --timestep auto, the finest automatic "
            "step, for every leg)"
        )
    if args.csv:
        print(f"wrote {len(table)} rows to {write_table(table, args.csv)}")
    numeric = ("unstable", "numerically suspect")  # diverged, or corrupted without diverging
    diverged = [e["leg"] for e in table.attrs["left_out"] if any(w in e["why"] for w in numeric)]
    scored = len(table) and int(table["n_pairs"].max()) > 0
    return 0 if scored and not diverged else 1  # EXIT_STATUS: any run diverged or is suspect, or nothing was scored


def register_cli(sub) -> None:
    p = sub.add_parser(
        "compare",
        help=HELP,
        description="Run a design, baseline legs and the design's controls (rigid twin, mass-matched, "
        "inertia-matched) on one behaviour, at one time step and on the same seeds, and print the paired % "
        "difference of the design against each, with interval and verdict (the book's paired rules). Runs are "
        "cached: a second call is instant. A leg whose step is above its analytic stable step is warned of "
        f"before any run. {EXIT_STATUS} A diverged leg is left out of the table and named.",
    )
    add_sim_arguments(p)
    p.add_argument(
        "--baseline",
        default=None,
        help="comma-separated baseline designs (any design name, e.g. SS,Ti; a material gets the design's "
        "segments), or none (default MD,SS)",
    )
    p.add_argument(
        "--controls",
        default=None,
        help="comma-separated controls of the design: rigid (same densities, no springs), mass (homogeneous leg "
        "of the same leg mass), inertia (same leg mass and hip inertia), or none (default rigid,mass,inertia)",
    )
    add_profile(p)
    p.add_argument("--replicates", type=int, default=None, help="paired seeds per leg, >= 2 (the profile's: paper 10)")
    p.add_argument("--duration", type=float, default=None, help=DURATION_HELP)
    p.add_argument("--transient", type=float, default=None, help=TRANSIENT_HELP)
    p.add_argument("--csv", help="write the table (one row per comparator, every column) here (- for standard output)")
    p.add_argument("--workers", type=int, default=None, help="local processes (default: all cores)")
    p.add_argument(
        "--cache", default=None, help=f"result cache folder (default ${CACHE_ENV}, else {DEFAULT_CACHE_DIR})"
    )
    add_force(p)
    add_no_progress(p)
    p.set_defaults(func=cmd_compare)
