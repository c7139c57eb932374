"""``mat-hopper modes``: a leg's axial natural frequencies, lumped chain
beside the continuum rod, and its analytic stable time step."""

from __future__ import annotations

import pandas as pd

from ..core import reference as ref
from ..core.controller import DEFAULT_SENSOR_TIMING
from ..core.materials import (
    AXIAL_CONVENTIONS,
    BENDING_CONVENTIONS,
    DEFAULT_SEGMENT_MASS,
    MAX_SEGMENTS,
    SEGMENT_MASSES,
)
from ..core.stable_step import AUTO_SAFETY, auto_substeps, controller_timestep, estimate_timestep
from ..physics.modes import axial_modes, bending_modes
from ..util.limits import check_count
from ._checks import SENSOR_TIMING_HELP, check_output_file, sensor_timing_type, write_table
from ._options import (
    DENSITY_HELP,
    MODULUS_HELP,
    SEGMENT_MASS_HELP,
    SEGMENTS_HELP,
    add_convention,
    add_force,
    check_force_used,
)
from .simulate import design_from_args

BOUNDARY_CONDITIONS = (
    "boundary conditions: the rod carries the mass above it (base, hips, stub) at its top end and the foot's "
    "upper capsule at its lower end; the foot below its 8000 N/m spring is left out of both"
)
FORMULA = (
    "rod: (a1 a2 z^2 - 1) sin z = (a1 + a2) z cos z, w = z sqrt(E A L / m) / L, a1 = M_top / m, a2 = M_bot / m "
    "(longitudinal vibration of a bar with end masses; S. S. Rao, Vibration of Continuous Systems, 2nd ed., "
    "Wiley 2019, ch. 9); chain: eigh(K, M) of the compiled model's lumped masses and springs"
)


BENDING_FORMULA = (
    "bending: chain = eigh(K, M) of the compiled model on the hinges about x (base, hips, slides held; foot made "
    "massless); beam = Euler-Bernoulli clamped-free, w = (beta_n L)^2 sqrt(E I / (mu L^4)), beta_n L = 1.8751, "
    "4.6941, 7.8548, ... (S. S. Rao, Vibration of Continuous Systems, 2nd ed., Wiley 2019, ch. 11); the chain keeps "
    "the capsules' rotary inertia, the beam does not"
)
DEFAULT_MODES = 5
PAPER_NOTE = (
    f"convention paper: the chain's springs are the authors' ({ref.PAPER_STIFFNESS_PER_GPA:.5g} N/m per GPa, "
    "whatever the segment's size), not E A N / L: error_pct is their distance from the rod of this modulus; "
    "--convention axial gives the lumping's own error"
)


def is_uniform(design) -> bool:
    """Whether a leg is of one elastic material (every segment the same
    density and modulus, not rigid): the legs whose modes have a uniform
    rod and beam to be compared with.

    Args:
        design: the leg (a LegDesign).

    Returns:
        True for one elastic material; False for a graded or rigid leg.
    """
    mats = {(m.density_g_cm3, m.modulus_gpa) for m in design.segments}
    return len(mats) == 1 and not design.segments[0].rigid


GRADED_NOTE = (
    "no modes table: the rod and beam it is compared with are of one material, and this leg is graded; "
    "its stable time step, from its own spring chain, follows"
)


def _check_graded(args, design) -> None:
    """A graded leg (some segment elastic) gets its stable time step only:
    --modes and --csv, which are of the modes table, are refused naming
    why; a leg with no spring at all is left to the modes' own refusal."""
    if is_uniform(design) or all(m.rigid for m in design.segments):
        return
    for flag, value in (("--modes", args.modes), ("--csv", args.csv)):
        if value is not None:
            raise ValueError(
                f"{flag} is for a leg of one elastic material (the modes table compares it with a uniform rod "
                f"and beam); {design.name} is graded: leave out {flag} for its stable time step"
            )


def _tables(args, design, n_modes: int) -> dict:
    """{kind: table} of the convention's axial and bending modes, every
    count checked (--modes beyond the leg's modes is refused, whichever the
    kind) before anything is printed; none for a graded leg."""
    tables = {}
    if not is_uniform(design) and not all(m.rigid for m in design.segments):
        return tables
    if args.convention in AXIAL_CONVENTIONS:
        tables["axial"] = axial_modes(
            design,
            convention="axial" if args.convention == "axial+bending" else args.convention,
            segment_mass=args.segment_mass,
            n_modes=n_modes,
        )
    if args.convention in BENDING_CONVENTIONS:
        tables["bending"] = bending_modes(
            design, convention=args.convention, segment_mass=args.segment_mass, n_modes=n_modes
        )
    for kind, table in tables.items():
        if args.modes is not None and len(table) < args.modes:  # as many modes as masses (hinges) that move
            chain = "spring chain" if kind == "axial" else "hinge chain"
            raise ValueError(
                f"--modes {args.modes}: this leg's {chain} has {len(table)} {kind} modes; ask for at most that"
            )
    return tables


def _default_step_note(design, args) -> str | None:
    """:func:`mat_hopper.core.timestep.check_stable_step`'s line for a run of
    this leg at the authors' default step (1e-4 s, one physics step per
    control period), or None when it lies within the bounds."""
    from ..core.sim import SimSettings
    from ..core.timestep import CLI_AUTO_HINT, check_stable_step

    settings = SimSettings(convention=args.convention, segment_mass=args.segment_mass, sensor_timing=args.sensor_timing)
    return check_stable_step(design, settings, auto_hint=CLI_AUTO_HINT)


def _controller_note(control: float, auto_period: float) -> str:
    """The line on a controller limit `control` (s) below the authors'
    control period: physics substeps alone cannot help (the torque is held
    over the period), but simulate's --timestep auto shortens the period itself to
    `auto_period` (s); only a period still above the limit is beyond the
    controller."""
    head = f"warning: the controller's limit {control:.3g} s is below its {ref.TIMESTEP_S:g} s control period"
    if auto_period <= control:
        return (
            f"{head}: physics substeps alone cannot help; simulate --timestep auto shortens the control period to "
            f"{auto_period:.3g} s, within it"
        )
    return f"{head}: even simulate --timestep auto's {auto_period:.3g} s period is above it; this leg is beyond the controller"


def cmd_modes(args) -> int:
    check_force_used(args, {"--csv": args.csv})
    check_output_file(args.csv, "--csv", stdout=True, force=args.force)  # before any work
    check_count(args.modes, "--modes", 1, MAX_SEGMENTS, "modes to list")
    design = design_from_args(args)
    _check_graded(args, design)
    n_modes = DEFAULT_MODES if args.modes is None else args.modes
    head = (
        f"{design.name}, {design.n_segments} segments, convention {args.convention}, segment mass {args.segment_mass}"
    )
    # every table and limit is computed (and checked) before the first line is printed
    tables = _tables(args, design, n_modes)
    w, spring = estimate_timestep(design, args.convention, args.segment_mass)
    control = controller_timestep(design, args.convention, sensor_timing=args.sensor_timing)
    k, dt, _ = auto_substeps(design, args.convention, args.segment_mass, sensor_timing=args.sensor_timing)
    fmt = lambda v: f"{v:.6g}"
    if "axial" in tables:
        print(f"{head}: axial modes (Hz)")
        print(tables["axial"].to_string(index=False, float_format=fmt))
        print(BOUNDARY_CONDITIONS)
        print(FORMULA)
        if args.convention == "paper":
            print(PAPER_NOTE)
    if "bending" in tables:
        print(f"{head}: bending modes in one plane (Hz), chain beside the continuum cantilever")
        print(tables["bending"].to_string(index=False, float_format=fmt))
        print(BENDING_FORMULA)
    if not tables:
        print(f"{head}: {GRADED_NOTE}")
    table = pd.concat([t.assign(kind=kind) for kind, t in tables.items()], ignore_index=True) if tables else None
    which = (
        "the spring chain (2 / w_max)"
        if spring < control
        else "the controller's delayed stance damping or, under bending, its hips' flight damping"
    )
    print(
        f"analytic stable time step: {min(spring, control):.3g} s, set by {which}; spring chain 2 / w_max = "
        f"{spring:.3g} s (w_max {w:.4g} rad/s), controller c(L) I / (Kd gear) = {control:.3g} s "
        f"(sensor timing {args.sensor_timing})"
    )
    note = _default_step_note(design, args)
    if note:
        print(f"warning: at the default step, {note}")
    if control < ref.TIMESTEP_S:
        print(_controller_note(control, k * dt))
    print(
        f"simulate --timestep auto: {k} physics substep(s) of {dt:.3g} s per {k * dt:.3g} s control period "
        f"(at most {AUTO_SAFETY:g} x the spring bound"
        + (
            f"; the controller's limit shortens the {ref.TIMESTEP_S:g} s period"
            if k * dt < ref.TIMESTEP_S * 0.999
            else ""
        )
        + ")"
    )
    if args.csv:
        print(f"wrote {len(table)} rows to {write_table(table, args.csv)}")
    return 0


def register_cli(sub) -> None:
    p = sub.add_parser(
        "modes",
        help="a leg's axial natural frequencies (lumped chain vs continuum rod) and its stable time step",
        description="Axial natural frequencies of a one-material leg: the lumped spring chain the model uses "
        "beside the continuum rod of the same mass per length and E A, under the same end masses; and the "
        "analytic stable time step with the limit that sets it. The convention is simulate's, paper by default "
        "(the authors' springs, not E A N / L: the rod shows how far they are from the bar of that modulus); "
        "--convention axial compares the lumping alone; bending and axial+bending add the bending modes. A graded "
        "leg (--density and --modulus of several materials) gets its stable time step only: the rod and beam are of "
        "one material. It runs no simulation, so it has no run profile and no progress display.",
    )
    p.add_argument(
        "--design",
        default=None,
        help="one elastic material (SS, Ti, Al, PVC, ...; default SS); a graded design (PVC-Ti-SS) gets its stable "
        "time step only",
    )
    p.add_argument("--density", help=DENSITY_HELP)
    p.add_argument("--modulus", help=MODULUS_HELP)
    p.add_argument("--segments", type=int, default=None, help=SEGMENTS_HELP)
    add_convention(p)
    p.add_argument("--segment-mass", default=DEFAULT_SEGMENT_MASS, choices=SEGMENT_MASSES, help=SEGMENT_MASS_HELP)
    p.add_argument("--sensor-timing", default=DEFAULT_SENSOR_TIMING, type=sensor_timing_type(), help=SENSOR_TIMING_HELP)
    p.add_argument(
        "--modes",
        type=int,
        default=None,
        help=f"how many modes of each kind, 1 to {MAX_SEGMENTS} (default {DEFAULT_MODES}, or as many as the leg has)",
    )
    p.add_argument("--csv", help="write the table (mode, chain_hz, rod_hz, error_pct) here (- for standard output)")
    add_force(p)
    p.set_defaults(func=cmd_modes)
