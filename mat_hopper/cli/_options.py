"""The options several commands share, each defined once: the same flag
does the same thing, with the same default, choices and help, in every
command that has it (tests/cli/test_option_vocabulary.py checks them on
every subcommand's parser).

- ``--no-progress``: no progress display on stderr (batch keeps
  ``--quiet`` as another name of it);
- ``--profile``: the run profile, ``paper`` or ``quick``;
- ``--convention``: the stiffness convention, default ``paper`` (the
  authors') in every command;
- ``--force``: replace output files that exist. Without it a command
  refuses, before any work, to write over a file that is there: an output
  file (``--csv``, ``--tiles``, ``--video``, ``--still``) or a file it would
  write into an output folder (``reproduce --out``, ``optimize --report``,
  ``--export``, ``--replay --render``).

Per-segment lists (``--density``, ``--modulus``) are written with decimal
points; two lists that may be decimal commas are refused
(:data:`DECIMAL_COMMA_RULE`).

Names are read through :func:`mat_hopper.util.parsing.parse_name` (any
case; an unknown one answered with "did you mean ...?"): ``--behaviour``
and ``--convention`` when the command line is, ``--profile`` when the
command starts (:func:`profile_of`: a name may come from
``$MAT_HOPPER_PROFILE``).
"""

from __future__ import annotations

import argparse
import re

from ..core.behaviours import BEHAVIOUR_NAMES, DEFAULT_BEHAVIOUR
from ..core.materials import CONVENTIONS, DEFAULT_CONVENTION, MAX_SEGMENTS
from ..core.reference import REFERENCE_SEGMENTS
from ..experiments.profiles import PROFILE_ENV, PROFILES
from ..util.parsing import close_names, did_you_mean, is_decimal, parse_name, parse_number

NO_PROGRESS_HELP = "no progress display on stderr (else a bar on a terminal, a line per stage in a pipe or a log)"

PROFILE_HELP = (
    f"run profile: {' or '.join(PROFILES)} (default ${PROFILE_ENV}, else paper); it sets each run's length, "
    "transient and time step where the command's own options leave them out ("
    + "; ".join(
        f"{name}: {p.duration_s:g} s runs, {p.transient_s:g} s transient, {p.timestep_s:g} s step"
        for name, p in PROFILES.items()
    )
    + ")"
)

CONVENTION_HELP = (
    f"stiffness convention, modulus to spring (docs/conventions.md): {', '.join(CONVENTIONS)}, any case "
    f"(default {DEFAULT_CONVENTION}); paper is the authors'"
)

DURATION_HELP = (
    "simulated seconds of each run (default: the profile's, "
    + ", ".join(f"{name} {p.duration_s:g}" for name, p in PROFILES.items())
    + ")"
)
TRANSIENT_HELP = (
    "seconds before the first scored hop cycle (default: the profile's, "
    + ", ".join(f"{name} {p.transient_s:g}" for name, p in PROFILES.items())
    + ")"
)
BEHAVIOUR_HELP = f"one of {', '.join(BEHAVIOUR_NAMES)}, any case (default {DEFAULT_BEHAVIOUR})"

FORCE_HELP = (
    "replace output files that exist; without it the command refuses, before any work, to write over a file "
    "that is there"
)


def name_type(what: str, choices):
    """The argparse type of an option naming one of `choices` (any case):
    the name as spelled in `choices`; an unknown one is refused with the
    accepted names and "did you mean ...?" (parse_name)."""
    choices = tuple(choices)

    def read(text):
        if not str(text).strip():  # as every option's (harden_parser)
            raise argparse.ArgumentTypeError("empty value; give one or leave the option out")
        try:
            return parse_name(text, choices, what)
        except ValueError as e:  # argparse puts "argument FLAG: " in front
            raise argparse.ArgumentTypeError(str(e)) from None

    read.__name__ = what
    return read


def suggesting(read, choices):
    """`read` (a name to its canonical one, ValueError for an unknown name)
    with "did you mean ...?" added to its error where one of `choices` is
    close (of two spellings of one name, the first): for the library's
    readers of names that have no :func:`~mat_hopper.util.parsing.parse_name`
    of their own (experiments, materials)."""
    choices = tuple(choices)

    def read_suggesting(text):
        try:
            return read(text)
        except ValueError as e:
            if "did you mean" in str(e):
                raise
            found: dict = {}
            for c in close_names(text, choices):
                found.setdefault(read(c), c)  # one spelling per name, the nearest
            if not found:
                raise
            raise ValueError(f"{e}; did you mean {' or '.join(found.values())}?") from None

    return read_suggesting


def add_no_progress(p, *aliases: str) -> None:
    """``--no-progress`` (and `aliases`, e.g. ``--quiet``): dest
    ``no_progress``, False by default."""
    p.add_argument("--no-progress", *aliases, dest="no_progress", action="store_true", help=NO_PROGRESS_HELP)


def add_profile(p) -> None:
    """``--profile NAME`` (None when left out), read by :func:`profile_of`
    when the command starts: an unknown name, or one from the environment,
    is then named as such."""
    p.add_argument("--profile", default=None, help=PROFILE_HELP)


def profile_of(name):
    """The run profile of ``--profile`` `name` (None: ``$MAT_HOPPER_PROFILE``,
    else paper; :func:`mat_hopper.experiments.profiles.resolve_profile`),
    an unknown name answered with "did you mean ...?"."""
    from ..experiments.profiles import resolve_profile

    return suggesting(resolve_profile, PROFILES)(name)


def add_convention(p, default: str | None = DEFAULT_CONVENTION) -> None:
    """``--convention NAME``. `default` None is for a command that must
    tell a convention given from one left out (render's still refuses run
    settings; optimize resumes a study with its stored one): it applies
    :data:`~mat_hopper.core.materials.DEFAULT_CONVENTION` itself."""
    p.add_argument(
        "--convention",
        default=default,
        choices=CONVENTIONS,
        type=name_type("stiffness convention", CONVENTIONS),
        help=CONVENTION_HELP,
    )


def add_behaviour(p, default: str | None, help: str) -> None:
    """``--behaviour`` (``--behavior``) of one behaviour, read by name."""
    p.add_argument(
        "--behaviour",
        "--behavior",
        dest="behaviour",
        default=default,
        type=name_type("behaviour", BEHAVIOUR_NAMES),
        help=help,
    )


def add_force(p) -> None:
    """``--force``: replace output files that exist."""
    p.add_argument("--force", action="store_true", help=FORCE_HELP)


def check_force_used(args, outputs: dict) -> None:
    """--force without any of the command's outputs (`outputs`, FLAG:
    value) given would be ignored in silence: refused, naming them."""
    if getattr(args, "force", False) and not any(v is not None and v is not False for v in outputs.values()):
        raise ValueError(f"--force is for {' or '.join(outputs)} (it replaces output files that exist)")


# Two whole numbers and one comma, no blank: "2,7" is the decimal 2.7
# written with a decimal comma as much as two values (2 and 7).
DECIMAL_COMMA = re.compile(r"[0-9]+,[0-9]+", re.ASCII)
DECIMAL_COMMA_RULE = (
    "--density and --modulus of two whole numbers each and no blank (2,7 and 1,5) may be decimal commas, "
    "one segment of 2.7 and 1.5: they are refused unless --segments 2 confirms two segments"
)


def decimal_comma_of(text) -> str | None:
    """The decimal `text` may mean with a decimal comma (``"2,7"``:
    ``"2.7"``), or None: a per-segment list is ambiguous when it is exactly
    two whole numbers joined by one comma, no sign, blank, point or
    exponent (:data:`DECIMAL_COMMA_RULE`). ``1.39,4.43,8``, ``8,8,8``,
    ``2.0,7``, ``"2, 7"`` and ``70,rigid`` are lists.

    >>> decimal_comma_of("2,7"), decimal_comma_of("1.39,4.43,8")
    ('2.7', None)
    """
    s = "" if text is None else str(text).strip()
    return s.replace(",", ".") if DECIMAL_COMMA.fullmatch(s) else None


DENSITY_HELP = (
    "per-segment densities, g/cm^3 (0.001-30), comma-separated, with a decimal point: e.g. 1.39,4.43,8; "
    + DECIMAL_COMMA_RULE
)
MODULUS_HELP = (
    "per-segment moduli, GPa (1e-6-2000, or 'rigid'), comma-separated, e.g. 70,70,70 (decimal commas: see --density)"
)
# --timestep auto in every command's help: what it chooses, the control period included.
AUTO_TIMESTEP_HELP = (
    "'auto': the fewest physics substeps of the control period that keep the design's springs stable; the "
    "control period is the authors' 1e-4 s unless the controller's own limit is smaller (a sensor delay, "
    "--sensor-timing latency-L, shortens it) or, under a bending convention, its hips' flight loop needs a "
    "shorter one"
)


def timestep_arg(text):
    """--timestep, one reader for every command: None (not given), seconds
    (an ASCII decimal, :func:`mat_hopper.util.parsing.parse_number`) or
    ``"auto"`` (any case; physics substeps of the control period chosen
    per design, :func:`mat_hopper.core.timestep.auto_timestep`). Raises
    ValueError naming the option."""
    from ..core.timestep import AUTO, is_auto

    if text is None:
        return None
    if is_auto(str(text)):
        return AUTO
    if not is_decimal(str(text)):  # the one number parser's reading: ASCII decimals only ("١e-4", "1_0", "inf": no)
        raise ValueError(f"--timestep must be a decimal number of seconds (e.g. 1e-4) or 'auto', got {text!r}")
    return parse_number(text, "--timestep", unit="s")


def add_timestep(p, default_help: str) -> None:
    """--timestep (read by :func:`timestep_arg`): seconds or 'auto'; `default_help` says what it is when
    left out."""
    p.add_argument("--timestep", default=None, help=f"physics time step, s, or {AUTO_TIMESTEP_HELP}; {default_help}")


def no_hops_line(transient_s: float, duration_s: float) -> str:
    """Why a run that stood scored no hop cycle: a cycle (about 0.6 s of
    the 1 m hop) counts only when it starts after the transient and ends
    before the run does, so a window of a second or so holds none."""
    return (
        f"no hop cycle was scored between {transient_s:g} and {duration_s:g} s: a cycle lasts about 0.6 s and counts "
        "only if it starts after --transient and ends before --duration; give a longer --duration"
    )


SEGMENTS_HELP = (
    f"segments of a single-material --design (default {REFERENCE_SEGMENTS}, at most {MAX_SEGMENTS}); with "
    "--density and --modulus, their count"
)
SEGMENT_MASS_HELP = (
    "segment mass: leg (default, the leg's mass independent of the number of segments; the authors' model at 3) "
    "or capsule (the authors' per-capsule density at any number)"
)


SENSOR_TIMING_HELP = (
    "when the controller reads the base sensors: authors (default: one physics step old, "
    "as the authors' loop), fresh, latency-L, or an integer latency L in physics steps"
)


def sensor_timing_arg(text, flag: str = "--sensor-timing"):
    """--sensor-timing: a name (authors, fresh; any case), ``latency-L`` or
    an integer L, the latency in physics steps; L through
    :func:`mat_hopper.util.parsing.parse_number` (ASCII digits only: "٣" and "²"
    are refused). A SensorTiming is returned as is. Raises ValueError
    naming `flag`."""
    from ..core.controller import LATENCY_PREFIX, MAX_SENSOR_LATENCY_STEPS, SENSOR_TIMINGS, SensorTiming

    if isinstance(text, SensorTiming):
        return text
    s = "" if text is None else str(text).strip()
    accepted = (
        f"accepted: {', '.join(SENSOR_TIMINGS)}, {LATENCY_PREFIX}L or an integer L of physics steps "
        f"in [0, {MAX_SENSOR_LATENCY_STEPS}]"
    )
    if not s:
        raise ValueError(f"{flag} is empty; {accepted}")
    if s.lower() in SENSOR_TIMINGS:
        return SensorTiming(s.lower())
    steps = s[len(LATENCY_PREFIX) :] if s.lower().startswith(LATENCY_PREFIX) else s
    if not is_decimal(steps):
        hint = did_you_mean(s, SENSOR_TIMINGS)
        raise ValueError(f"{flag}: unknown sensor timing {s!r}; {accepted}{f'; {hint}' if hint else ''}")
    latency = parse_number(steps, flag, integer=True, low=0, high=MAX_SENSOR_LATENCY_STEPS, unit="physics steps")
    return SensorTiming(latency)


def sensor_timing_type(flag: str = "--sensor-timing"):
    """The argparse type of a --sensor-timing option: read when the command
    line is, before any command prints or works."""

    def read(text):
        try:
            return sensor_timing_arg(text, flag)
        except ValueError as e:  # argparse puts "argument FLAG: " in front
            raise argparse.ArgumentTypeError(str(e).removeprefix(f"{flag}: ").removeprefix(f"{flag} ")) from None

    read.__name__ = "sensor timing"
    return read
