"""``mat-hopper simulate``: one design, one behaviour, a per-hop summary."""

from __future__ import annotations

import argparse
import math

from .. import reference as ref
from ..atomic import write_csv
from ..behaviours import BEHAVIOUR_NAMES, behaviour
from ..materials import CONVENTIONS, LegDesign, parse_design
from ..metrics import METRICS, hop_table, run_summary


def _floats(text: str, field: str) -> list[float | None]:
    out = []
    for part in text.split(","):
        part = part.strip()
        if part.lower() in ("rigid", "inf"):
            out.append(None)
            continue
        try:
            out.append(float(part))
        except ValueError:
            raise ValueError(f"{field} must be comma-separated numbers, got {text!r}") from None
    return out


def _timing(text: str):
    """--sensor-timing: a name, or digits for a latency in physics steps."""
    text = str(text).strip()
    return int(text) if text.isdigit() else text


def design_from_args(args) -> LegDesign:
    """--design NAME, or --density/--modulus lists (g/cm^3, GPa)."""
    if args.density is not None or args.modulus is not None:
        if args.density is None or args.modulus is None:
            raise ValueError("--density and --modulus go together (one value per segment)")
        dens = _floats(args.density, "--density")
        if any(d is None for d in dens):
            raise ValueError("--density must be numbers in g/cm^3 (> 0)")
        return LegDesign.from_properties(dens, _floats(args.modulus, "--modulus"))
    return parse_design(args.design, n_segments=args.segments)


def add_sim_arguments(p: argparse.ArgumentParser) -> None:
    """Design and run options shared by commands that simulate one design."""
    p.add_argument(
        "--design",
        default="SS",
        help="material (MD, PVC, Al, Ti, SS, ...), gradient like PVC-Ti-SS, rho-inc or rho-dec",
    )
    p.add_argument("--density", help="per-segment densities, g/cm^3, e.g. 1.39,4.43,8")
    p.add_argument("--modulus", help="per-segment moduli, GPa (or 'rigid'), e.g. 70,70,70")
    p.add_argument(
        "--segments", type=int, default=ref.REFERENCE_SEGMENTS, help="segments for a single-material design (default 3)"
    )
    p.add_argument(
        "--behaviour", "--behavior", dest="behaviour", default="forward", help=f"one of {', '.join(BEHAVIOUR_NAMES)}"
    )
    p.add_argument("--timestep", type=float, default=ref.TIMESTEP_S, help="physics time step, s")
    p.add_argument("--convention", default="paper", help=f"stiffness convention: {', '.join(CONVENTIONS)}")
    p.add_argument(
        "--sensor-timing",
        default="authors",
        help="when the controller reads the base sensors: authors (default: one physics step old, "
        "as the authors' loop), fresh, or an integer latency in physics steps",
    )


def cmd_simulate(args) -> int:
    from ..sim import SimSettings, simulate

    design = design_from_args(args)
    beh = behaviour(args.behaviour)
    settings = SimSettings(
        duration_s=args.duration,
        timestep_s=args.timestep,
        transient_s=args.transient,
        convention=args.convention,
        sensor_timing=_timing(args.sensor_timing),
    )
    rollout = simulate(design, beh, settings=settings)
    hops = hop_table(rollout)
    s = run_summary(rollout)
    print(
        f"{design.name} on {beh.name}: {settings.duration_s:g} s at dt={settings.timestep_s:g} s, "
        f"convention={settings.convention}, sensor timing={settings.sensor_timing}, "
        f"mass {rollout.total_mass_kg:.2f} kg"
    )
    if not rollout.stable:
        print(f"UNSTABLE: diverged at t = {rollout.diverged_at_s:.4f} s")
    print(f"{len(hops)} hop cycles scored after {settings.transient_s:g} s")
    if len(hops):
        desc = hops[list(METRICS)].describe().loc[["mean", "std", "min", "max"]]
        print(desc.to_string(float_format=lambda v: f"{v:.4g}"))
        cot = s["cost_of_transport"]
        cot = f"{cot:.3g}" if math.isfinite(cot) else "none (no distance travelled)"
        print(f"energy {s['energy_j']:.1f} J, cost of transport {cot}")
    if args.csv:
        write_csv(hops, args.csv)
        print(f"wrote {len(hops)} rows to {args.csv}")
    return 0 if rollout.stable else 1


def register_cli(sub) -> None:
    p = sub.add_parser(
        "simulate",
        help="simulate one design on one behaviour, print a per-hop summary",
        description="Simulate one leg design on one behaviour and summarize its hop cycles.",
    )
    add_sim_arguments(p)
    p.add_argument("--duration", type=float, default=ref.DURATION_S, help="simulated seconds (60)")
    p.add_argument(
        "--transient", type=float, default=ref.TRANSIENT_S, help="seconds before the first scored hop cycle (20)"
    )
    p.add_argument("--csv", help="write the per-hop table (one row per scored hop cycle) here")
    p.set_defaults(func=cmd_simulate)
