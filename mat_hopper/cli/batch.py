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

from .. import reference as ref
from ..behaviours import BEHAVIOUR_NAMES
from ..materials import CONVENTIONS
from ._checks import SENSOR_TIMING_HELP

CSV_HELP = (
    "CSV of designs: columns density_1..density_N (g/cm^3) and modulus_1..modulus_N "
    "(GPa, empty or 'rigid' for a rigid segment), optional 'design' column of names"
)


def add_parser(subparsers) -> argparse.ArgumentParser:
    p = subparsers.add_parser(
        "batch",
        help="evaluate many designs on one behaviour (CPU rollouts or a MuJoCo Warp batch)",
        description="Evaluate many leg designs on one behaviour; one row per design: design, n_hops, "
        "hop_height_m, tracking_error_m, power_w, stable.",
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
    p.add_argument("--behaviour", "--behavior", dest="behaviour", help=f"one of {', '.join(BEHAVIOUR_NAMES)} (forward)")
    p.add_argument("--duration", type=float, help=f"simulated seconds ({ref.DURATION_S:g})")
    p.add_argument("--transient", type=float, help=f"seconds before the first scored hop cycle ({ref.TRANSIENT_S:g})")
    p.add_argument("--timestep", type=float, help=f"physics time step, s ({ref.TIMESTEP_S:g})")
    p.add_argument("--convention", default="paper", help=f"stiffness convention: {', '.join(CONVENTIONS)}")
    p.add_argument("--sensor-timing", default="authors", help=SENSOR_TIMING_HELP)
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
        default=ref.STABILITY_TEST_DURATION_S,
        help=f"static hopping per try of --stability, s ({ref.STABILITY_TEST_DURATION_S:g})",
    )
    p.add_argument("--csv", help="write the table (one row per design) here")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.set_defaults(func=run_batch)
    return p


register_cli = add_parser  # the name mat_hopper.cli looks for


def _default_device() -> str:
    from ..batch import require_warp

    wp, _ = require_warp()
    return "cuda" if wp.get_cuda_device_count() > 0 else "cpu"


def run_batch(args) -> int:
    from ..batch import RESULT_COLUMNS, BatchSettings, designs_from_csv, evaluate, parse_design_list
    from ..behaviours import behaviour
    from ..control import sensor_latency_steps
    from ._checks import check_output_file, sensor_timing_arg

    check_output_file(args.csv, "--csv")  # before any work
    latency = sensor_latency_steps(sensor_timing_arg(args.sensor_timing))
    if args.map is not None:
        designs = _map_designs(args.map)
    elif args.designs_csv:
        designs = designs_from_csv(args.designs_csv)
    else:
        designs = parse_design_list(args.designs)
    run_options = {"--behaviour": args.behaviour, "--duration": args.duration, "--transient": args.transient}
    run_options["--timestep"] = args.timestep
    given = [flag for flag, value in run_options.items() if value is not None]
    if args.stability and given:
        raise ValueError(f"{', '.join(given)}: not used by --stability (static hopping at its ladder of time steps)")
    beh = behaviour(args.behaviour or "forward")
    settings = BatchSettings(
        duration_s=ref.DURATION_S if args.duration is None else args.duration,
        timestep_s=ref.TIMESTEP_S if args.timestep is None else args.timestep,
        transient_s=ref.TRANSIENT_S if args.transient is None else args.transient,
        convention=args.convention,
        sensor_latency_steps=latency,
    )
    if args.workers is not None and args.workers < 1:
        raise ValueError(f"--workers must be >= 1, got {args.workers}")
    if args.max_batch is not None and args.max_batch < 1:
        raise ValueError(f"--max-batch must be >= 1, got {args.max_batch}")
    if args.backend == "warp":
        from ..batch import WarpUnavailable, require_warp

        try:
            require_warp()  # before any work: a missing gpu extra is one line
            device = args.device or _default_device()
        except WarpUnavailable as e:
            raise ValueError(str(e)) from None
    elif args.device is not None:
        raise ValueError("--device is for --backend warp")
    else:
        device = None
    run = dict(backend=args.backend, device=device, workers=args.workers, max_batch=args.max_batch)
    if args.stability:
        return _run_stability(args, designs, settings, run)
    table = evaluate(designs, beh, settings, progress=not args.quiet, **run)
    out = table[list(RESULT_COLUMNS)]
    where = f" on {device}" if device else ""
    print(
        f"{len(out)} designs on {beh.name}: {settings.duration_s:g} s at dt={settings.timestep_s:g} s, "
        f"transient {settings.transient_s:g} s, sensor timing {settings.sensor_timing}, backend {args.backend}{where}"
    )
    n_bad = int((~out["stable"]).sum())
    return _report(out, args.csv, f"{n_bad} of {len(out)} designs diverged" if n_bad else "")


def _map_designs(n: int) -> list:
    """The stable-time-step map's designs (experiment 4), n x n."""
    from ..experiments.paper import StabilityMap
    from ..experiments.profiles import PROFILES

    if n < 1 or n > 100:
        raise ValueError(f"--map must be in [1, 100] designs per axis, got {n}")
    profile = dataclasses.replace(PROFILES["paper"], stability_grid_size=n)
    return [task.design for task in StabilityMap().tasks(profile)]


def _run_stability(args, designs, settings, run: dict) -> int:
    from ..batch import spec_scan_batch

    if not (math.isfinite(args.stability_duration) and args.stability_duration > 0):
        raise ValueError(f"--stability-duration must be > 0 s, got {args.stability_duration:g}")
    summary, tries = spec_scan_batch(
        designs,
        duration_s=args.stability_duration,
        convention=args.convention,
        sensor_latency_steps=settings.sensor_latency_steps,
        progress=not args.quiet,
        **run,
    )
    where = f" on {run['device']}" if run["device"] else ""
    print(
        f"{len(summary)} designs, stable-time-step scan: static hopping for {args.stability_duration:g} s per try, "
        f"sensor timing {settings.sensor_timing}, {len(tries)} tries, backend {args.backend}{where}"
    )
    n_none = int(summary["spec_timestep_s"].isna().sum())
    note = f"{n_none} of {len(summary)} designs ended upright at no step of the ladder" if n_none else ""
    return _report(summary, args.csv, note)


def _report(table, csv: str | None, note: str) -> int:
    """Print the table (and a note), write it to `csv` if given; exit code 0."""
    from ..atomic import write_csv

    print(table.to_string(index=False, float_format=lambda v: f"{v:.4g}"))
    if note:
        print(note)
    if csv:
        write_csv(table, csv)
        print(f"wrote {len(table)} rows to {csv}")
    return 0
