"""``mat-hopper batch``: many designs, one behaviour, one row per design.

    mat-hopper batch --designs SS,rho-inc,PVC-Ti-SS --behaviour forward --backend warp --csv out.csv
    mat-hopper batch --designs-csv designs.csv --backend mujoco --csv out.csv

``--backend mujoco`` (default) runs one CPU rollout per design, the
reference; ``--backend warp`` runs the designs as MuJoCo Warp batches (one
per topology) on ``--device`` (needs the ``gpu`` extra).
"""

from __future__ import annotations

import argparse

from .. import reference as ref
from ..behaviours import BEHAVIOUR_NAMES
from ..materials import CONVENTIONS

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
    p.add_argument(
        "--behaviour", "--behavior", dest="behaviour", default="forward", help=f"one of {', '.join(BEHAVIOUR_NAMES)}"
    )
    p.add_argument("--duration", type=float, default=ref.DURATION_S, help="simulated seconds (60)")
    p.add_argument(
        "--transient", type=float, default=ref.TRANSIENT_S, help="seconds before the first scored hop cycle (20)"
    )
    p.add_argument("--timestep", type=float, default=ref.TIMESTEP_S, help="physics time step, s (1e-4)")
    p.add_argument("--convention", default="paper", help=f"stiffness convention: {', '.join(CONVENTIONS)}")
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
    from ..atomic import write_csv
    from ..batch import RESULT_COLUMNS, BatchSettings, designs_from_csv, evaluate, parse_design_list
    from ..behaviours import behaviour
    from ._checks import check_output_file

    check_output_file(args.csv, "--csv")  # before any work
    designs = designs_from_csv(args.designs_csv) if args.designs_csv else parse_design_list(args.designs)
    beh = behaviour(args.behaviour)
    settings = BatchSettings(
        duration_s=args.duration, timestep_s=args.timestep, transient_s=args.transient, convention=args.convention
    )
    if args.workers is not None and args.workers < 1:
        raise ValueError(f"--workers must be >= 1, got {args.workers}")
    if args.max_batch is not None and args.max_batch < 1:
        raise ValueError(f"--max-batch must be >= 1, got {args.max_batch}")
    device = None
    if args.backend == "warp":
        from ..batch import WarpUnavailable

        try:
            device = args.device or _default_device()
            table = evaluate(
                designs, beh, settings, backend="warp", device=device, max_batch=args.max_batch, progress=not args.quiet
            )
        except WarpUnavailable as e:
            raise ValueError(str(e)) from None
    else:
        if args.device is not None:
            raise ValueError("--device is for --backend warp")
        table = evaluate(designs, beh, settings, backend="mujoco", workers=args.workers, progress=not args.quiet)
    out = table[list(RESULT_COLUMNS)]
    where = f" on {device}" if device else ""
    print(
        f"{len(out)} designs on {beh.name}: {settings.duration_s:g} s at dt={settings.timestep_s:g} s, "
        f"transient {settings.transient_s:g} s, backend {args.backend}{where}"
    )
    print(out.to_string(index=False, float_format=lambda v: f"{v:.4g}"))
    n_bad = int((~out["stable"]).sum())
    if n_bad:
        print(f"{n_bad} of {len(out)} designs diverged")
    if args.csv:
        write_csv(out, args.csv)
        print(f"wrote {len(out)} rows to {args.csv}")
    return 0
