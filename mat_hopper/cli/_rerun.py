"""Command lines a message may tell the user to run: a design as
``mat-hopper simulate`` reads it, by its name where simulate knows the name,
else by its per-segment ``--density`` and ``--modulus`` lists (a design
from a CSV file, the map or a sweep has a name no command reads)."""

from __future__ import annotations

import shlex


def design_flags(design) -> list[str]:
    """simulate's flags that give `design`: ``--design NAME`` (with
    ``--segments N`` for a single material at another number) where
    :func:`mat_hopper.core.materials.parse_design` reads its name back as
    the same segments, else ``--density`` (g/cm^3) and ``--modulus`` (GPa,
    ``rigid`` for a rigid segment) with each value's shortest exact
    spelling (``repr``), which always has a decimal point (never read as a
    decimal comma)."""
    from ..core.materials import parse_design

    def reads_back(**kw) -> bool:
        try:
            return parse_design(design.name, **kw).segments == design.segments
        except (ValueError, TypeError):
            return False

    if reads_back():
        return ["--design", design.name]
    if reads_back(n_segments=design.n_segments):  # a single material at another number of segments
        return ["--design", design.name, "--segments", str(design.n_segments)]
    densities = ",".join(repr(float(m.density_g_cm3)) for m in design.segments)
    moduli = ",".join("rigid" if m.modulus_gpa is None else repr(float(m.modulus_gpa)) for m in design.segments)
    return ["--density", densities, "--modulus", moduli]


def simulate_command(design, **options) -> str:
    """``mat-hopper simulate`` with `design`'s flags (:func:`design_flags`)
    and then `options`, simulate's options by their names
    (``timestep="auto"``: ``--timestep auto``; ``segment_mass``:
    ``--segment-mass``); one whose value is None is left out. Each word is
    shell-quoted where it needs to be (a map point's name ``rho=1.4
    E=340`` has a space), so the line runs as printed."""
    flags = [f for name, value in options.items() if value is not None for f in (_flag(name), str(value))]
    return shlex.join(["mat-hopper", "simulate", *design_flags(design), *flags])  # pasted into a shell as printed


def _flag(name: str) -> str:
    return "--" + name.replace("_", "-")
