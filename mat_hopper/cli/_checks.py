"""Checks every command makes before any work: one parser for comma lists,
output paths that can be written, and folders left behind by a failure.

Every function raises ValueError with one line naming the option and what
was wrong; :func:`mat_hopper.cli.main` prints it and exits with code 2.
"""

from __future__ import annotations

import argparse
import os
import re
import shutil
import tempfile
from contextlib import contextmanager

from ..util.atomic import TEMP_PREFIX
from ..util.parsing import RIGID, did_you_mean, parse_name, parse_number

_SENSOR_TIMING = ("SENSOR_TIMING_HELP", "sensor_timing_arg", "sensor_timing_type")  # in _options, named here too


def __getattr__(name):
    """The --sensor-timing reader, kept here by name and loaded on first
    use (:mod:`mat_hopper.cli._options` imports the library's tables;
    ``mat-hopper --help`` imports this module and must stay light)."""
    if name in _SENSOR_TIMING:
        from . import _options

        return getattr(_options, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


# A value argparse would take for an option: "-1", "-1.5e3", "-1,2,3".
NEGATIVE_LIST = re.compile(r"^-(\d|\.\d|inf|nan)", re.IGNORECASE)


def _number_type(flag: str, integer: bool):
    def read(text):
        try:
            return parse_number(text, flag, integer=integer)
        except ValueError as e:  # argparse puts "argument FLAG: " in front
            raise argparse.ArgumentTypeError(str(e).removeprefix(f"{flag} ")) from None

    read.__name__ = "integer" if integer else "number"
    return read


def _name_type(flag: str, choices):
    def read(text):
        try:
            return parse_name(text, choices, flag)
        except ValueError:  # argparse's own words for a choice, and the nearest choice
            hint = did_you_mean(text, choices)
            raise argparse.ArgumentTypeError(
                f"invalid choice: {text!r} (choose from {', '.join(choices)}; any case){f'; {hint}' if hint else ''}"
            ) from None

    read.__name__ = "name"
    return read


def _text_type(flag: str):
    def read(text):
        if not str(text).strip():
            raise argparse.ArgumentTypeError("empty value; give one or leave the option out")
        return text

    read.__name__ = "text"
    return read


class _StoreOnce(argparse._StoreAction):
    """An option of one value given twice ("--designs SS --designs Ti") is
    refused: argparse would keep the last in silence. A repeat is told by
    the value in the namespace no longer being the option's default object
    (argparse puts the default there before it reads the command line)."""

    def __call__(self, parser, namespace, values, option_string=None):
        if getattr(namespace, self.dest, self.default) is not self.default:
            flag = max(self.option_strings, key=len)
            parser.error(f"argument {flag}: given twice; give it once")
        super().__call__(parser, namespace, values, option_string)


def harden_parser(parser: argparse.ArgumentParser) -> argparse.ArgumentParser:
    """One reading of every option of every subcommand: numbers (type=float
    or int) through :func:`mat_hopper.util.parsing.parse_number` (ASCII decimal,
    finite), names with choices through :func:`~mat_hopper.util.parsing.parse_name`
    (case-insensitive), no empty value for any option that takes one, and
    no option of one value given twice. Errors name the flag as typed.
    Abbreviated options are refused ("--convention" is not reproduce's
    --conventions; :func:`mat_hopper.cli._parse` says "did you mean").
    Returns `parser`."""
    parser.allow_abbrev = False  # argparse reads it when it parses
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for sub in dict.fromkeys(action.choices.values()):
                harden_parser(sub)
            continue
        if not action.option_strings or action.nargs == 0:
            continue
        if type(action) is argparse._StoreAction and action.nargs is None:
            action.__class__ = _StoreOnce
        flag = max(action.option_strings, key=len)
        if action.type in (float, int):
            action.type = _number_type(flag, action.type is int)
        elif action.type is None and action.choices is not None:
            action.type = _name_type(flag, tuple(action.choices))
        elif action.type is None:
            action.type = _text_type(flag)
    return parser


# The words of the library's messages that name a setting, and the option
# that sets it (a command passes its own where they differ: render's run
# length is --start + --seconds).
PARAM_FLAGS = {
    "duration_s": "--duration",
    "duration": "--duration",
    "timestep_s": "--timestep",
    "timestep": "--timestep",
    "transient_s": "--transient",
    "transient": "--transient",
    "n_segments": "--segments",
    "sensor_timing": "--sensor-timing",
    "segment_mass": "--segment-mass",
}


# Settings of the library that no option sets, as the library's advice
# names them, and the advice in the command line's terms.
NO_OPTION_ADVICE = {
    # the run's recorded samples (mat_hopper.core.sim.MAX_SAMPLES) at the fixed 1 kHz the command line records
    re.compile(r"lower record_rate_hz or (?P<length>.+)$"): r"give a shorter \g<length> "
    "(the command line records 1000 samples per simulated second)",
}
# The options of the command being run (set by mat_hopper.cli.main), or
# None: then every word of PARAM_FLAGS is translated.
COMMAND_OPTIONS: list = [None]


@contextmanager
def named_by_flags(**flags):
    """A ValueError raised inside names the options, not the Python
    parameters: each word of PARAM_FLAGS (or of `flags`, which override it)
    in its message becomes the option, where the command has that option
    (:data:`COMMAND_OPTIONS`; a word no option of it sets stays as is),
    and advice about a setting that no option sets (record_rate_hz) is
    given in the options' terms (:data:`NO_OPTION_ADVICE`)."""
    have = COMMAND_OPTIONS[0]
    mapping = {**PARAM_FLAGS, **flags}
    mapping = {k: v for k, v in mapping.items() if have is None or k in flags or v in have}
    pattern = re.compile(r"(?<![-\w])(" + "|".join(sorted(map(re.escape, mapping), key=len, reverse=True)) + r")\b")
    try:
        yield
    except ValueError as e:
        text = pattern.sub(lambda m: mapping[m.group(1)], str(e)) if mapping else str(e)
        for advice, words in NO_OPTION_ADVICE.items():
            text = advice.sub(words, text)
        raise ValueError(suggest_in(text)) from None


# A library's "unknown control 'masss'; accepted: rigid, mass, inertia (or none)".
_UNKNOWN = re.compile(
    r"unknown [\w -]+? '(?P<item>[^']*)'; accepted: (?P<names>[^;()]+?)(?: \(or (?P<more>[\w-]+)\))?(?=$|;)"
)


def suggest_in(text: str) -> str:
    """`text` with "did you mean ...?" added after an "unknown NAME 'x';
    accepted: a, b, c" clause where one of them is close (the library's
    readers of comma lists that have no parse_name of their own), unless
    it has one already."""
    m = None if "did you mean" in text else _UNKNOWN.search(text)
    if m is None:
        return text
    names = [n.strip() for n in m.group("names").split(",")] + ([m.group("more")] if m.group("more") else [])
    hint = did_you_mean(m.group("item"), names)
    return f"{text[: m.end()]}; {hint}{text[m.end() :]}" if hint else text


def check_name_list(text, flag: str, canonical=None) -> None:
    """A comma list of names (--experiments, --conventions, --materials,
    --ashby-classes) holds no empty item ("paper,,axial", "3,") and no two
    items that name the same thing: the same text in any case and blanks
    ("1,1", "SS, ss"), or, with `canonical`, two spellings it reads as one
    ("4,stability"); None passes (the option's default). Raises ValueError
    naming the flag and the repeated items (a repeat is refused, not run
    twice nor dropped in silence). `canonical` maps an item (blanks
    trimmed) to its canonical name, raising ValueError for an unknown one."""
    if text is None:
        return
    items = [p.strip() for p in str(text).split(",")]
    if not all(items):
        raise ValueError(f"{flag} must be comma-separated names, got {text!r} (an empty item)")
    seen: dict[str, str] = {}
    for item in items:
        key = item.lower() if canonical is None else canonical(item)
        if key in seen:
            same = "" if seen[key].lower() == item.lower() else f" ({seen[key]!r} and {item!r} are both {key})"
            raise ValueError(f"{flag}: {text!r} names an item twice{same}; give each once")
        seen[key] = item


def parse_list(text, flag: str, *, rigid: bool = False, unit: str = "") -> list[float | None]:
    """A comma-separated list of finite numbers, the one parser of every
    comma list on the command line (--density, --modulus, --density-bounds,
    --modulus-bounds); each item through :func:`mat_hopper.util.parsing.parse_number`
    (ASCII decimal). Empty items ("1,,2", "1,2,") are refused; with
    `rigid`, the word "rigid" stands for a rigid segment (None). Ranges
    are checked by the library (materials, search space), not here."""
    what = f"{flag} must be comma-separated numbers{f' in {unit}' if unit else ''}"
    if text is None or not str(text).strip():
        raise ValueError(f"{what}, got an empty value")
    out: list[float | None] = []
    for part in str(text).split(","):
        p = part.strip()
        if not p:
            raise ValueError(f"{what}, got {text!r} (an empty item)")
        try:
            out.append(parse_number(p, flag, rigid=rigid))
        except ValueError as e:
            hint = f" (or {RIGID})" if rigid else ""
            why = " (not finite)" if "finite" in str(e) else ""
            why += f"; write {RIGID} for a rigid segment" if rigid and "inf" in p.lower() else ""
            raise ValueError(f"{what}{hint}, got {text!r}{why}") from None
    return out


def parse_pair(text, flag: str, unit: str = "") -> tuple[float, float] | None:
    """MIN,MAX through :func:`parse_list` (None when not given)."""
    if text is None:
        return None
    vals = parse_list(text, flag, unit=unit)
    if len(vals) != 2:
        raise ValueError(f"{flag} must be two numbers MIN,MAX{f' in {unit}' if unit else ''}, got {text!r}")
    return vals[0], vals[1]


def negative_list_argv(argv, options=None) -> list[str]:
    """argv with ``--opt -1,2,3`` (or ``--opt -1e-3``) rewritten to
    ``--opt=-1,2,3`` for the given options, or for every ``--option`` when
    `options` is None: argparse takes a value that starts with '-' for an
    option (it knows plain negative numbers, not "-1e-3" or lists) and
    answers "expected one argument"; the user should hear what is wrong
    with the value instead (e.g. density must be > 0)."""
    argv = list(argv)
    out, i = [], 0
    while i < len(argv):
        a = argv[i]
        named = a.startswith("--") and "=" not in a if options is None else a in options
        if named and i + 1 < len(argv) and NEGATIVE_LIST.match(argv[i + 1]):
            out.append(f"{a}={argv[i + 1]}")
            i += 2
            continue
        out.append(a)
        i += 1
    return out


# --- output paths -------------------------------------------------------------


def _existing_ancestor(path: str) -> str:
    p = os.path.abspath(path)
    while not os.path.exists(p):
        parent = os.path.dirname(p)
        if parent == p:
            break
        p = parent
    return p


def _check_folder_can_hold(folder: str, flag: str, what: str) -> None:
    """`folder` exists and a file can be made in it, or it can be made.

    Writability is tried, not read from the permission bits: a probe file
    is created and removed in the deepest existing folder (root passes
    ``os.access`` on /proc and /sys, where nothing can be created)."""
    anc = _existing_ancestor(folder)
    if not os.path.isdir(anc):
        raise ValueError(f"{flag} {what}: {anc} is a file, not a folder")
    if not os.access(anc, os.W_OK | os.X_OK):
        raise ValueError(f"{flag} {what}: folder {anc} is not writable")
    try:
        fd, probe = tempfile.mkstemp(dir=anc, prefix=TEMP_PREFIX)
    except OSError as e:
        raise ValueError(f"{flag} {what}: nothing can be written in folder {anc} ({e.strerror})") from None
    os.close(fd)
    os.remove(probe)


STDOUT = "-"  # --csv -: the table on standard output (the command's other lines on stderr)


def write_table(table, path: str) -> str:
    """Write `table` as CSV to `path` (atomically), or to standard output for
    "-" (:data:`STDOUT`); returns what to name in "wrote ... to" lines."""
    import sys

    from ..util.atomic import write_csv

    if path == STDOUT:
        table.to_csv(sys.__stdout__ if _TABLE_STREAM[0] is None else _TABLE_STREAM[0], index=False)
        return "standard output"
    write_csv(table, path)
    return path


_TABLE_STREAM: list = [None]  # the real stdout while a command with --csv - prints to stderr


@contextmanager
def table_on_stdout(args):
    """With ``--csv -``: the command's own lines go to stderr and only the
    CSV table to stdout, so that ``mat-hopper ... --csv - | other-tool``
    reads a clean table. Otherwise nothing changes."""
    import sys
    from contextlib import redirect_stdout

    if getattr(args, "csv", None) != STDOUT:
        yield
        return
    _TABLE_STREAM[0] = sys.stdout
    try:
        with redirect_stdout(sys.stderr):
            yield
    finally:
        _TABLE_STREAM[0] = None


def check_output_file(path, flag: str, *, stdout: bool = False, force: bool = False) -> str | None:
    """A file the command will write: not an existing folder, not an
    existing file unless `force` (the command's ``--force``), and its
    folder exists and is writable or can be made (nothing is created
    here); with `stdout`, "-" means standard output."""
    if path is None:
        return None
    path = os.fspath(path)
    if stdout and path == STDOUT:
        return path
    if not path.strip():
        raise ValueError(f"{flag}: empty file name")
    if os.path.isdir(path) or path.endswith(os.sep):
        raise ValueError(f"{flag} {path}: is a folder; give a file name")
    if os.path.exists(path) and not os.path.isfile(path):
        raise ValueError(f"{flag} {path}: not a regular file")
    if os.path.exists(path) and not os.access(path, os.W_OK):
        raise ValueError(f"{flag} {path}: file is not writable")
    if os.path.exists(path) and not force:
        raise ValueError(f"{flag} {path}: file exists; give --force to replace it, or another name")
    # with --force an existing file is replaced (atomically, by a new file in its folder)
    _check_folder_can_hold(os.path.dirname(os.path.abspath(path)), flag, path)
    note_new_folders(os.path.dirname(os.path.abspath(path)), flag)
    return path


def check_no_outputs_in(folder, names, flag: str, *, force: bool = False) -> None:
    """The files a command will write into `folder` (`names`: file names
    or glob patterns, relative to it) do not exist yet, unless `force`
    (the command's ``--force``): ValueError naming `flag`, how many there
    are and the first. Nothing is made or removed here."""
    import glob

    if force or folder is None or not os.path.isdir(folder):
        return
    there = sorted(
        {
            p
            for name in names
            for p in glob.glob(os.path.join(glob.escape(os.fspath(folder)), name))
            if os.path.isfile(p) and not os.path.basename(p).startswith(TEMP_PREFIX)
        }
    )
    if there:
        more = f" and {len(there) - 1} more" if len(there) > 1 else ""
        raise ValueError(
            f"{flag} {os.fspath(folder)}: {there[0]}{more} exist{'s' if not more else ''} already; give --force "
            f"to replace {'it' if not more else 'them'}, or another {flag}"
        )


def path_key(path) -> str:
    """One spelling of a path: absolute, symlinks and ``..`` resolved (two
    keys are equal when the paths name one file or folder)."""
    return os.path.normcase(os.path.realpath(os.fspath(path)))


def check_distinct_paths(outputs: dict, inputs: dict | None = None) -> None:
    """The files and folders a command writes (`outputs`, FLAG: PATH) are
    all different, and none is a file it reads (`inputs`, FLAG: PATH):
    an output on an input's path would overwrite it. Paths are compared
    with symlinks and ``..`` resolved; None entries and "-" (standard
    output) are skipped. Raises ValueError naming both flags."""
    reads = {path_key(p): (flag, p) for flag, p in (inputs or {}).items() if p is not None and os.fspath(p) != STDOUT}
    seen: dict[str, str] = {}
    for flag, path in outputs.items():
        if path is None or os.fspath(path) == STDOUT:
            continue
        key = path_key(path)
        if key in reads:
            src, p = reads[key]
            raise ValueError(
                f"{flag} {os.fspath(path)!r} is the file {src} {os.fspath(p)!r} reads: writing it would overwrite "
                "the input; give the output another name"
            )
        if key in seen:
            raise ValueError(f"{seen[key]} and {flag} name the same path {os.fspath(path)!r}; give each its own")
        seen[key] = flag


def is_inside(inner, outer) -> bool:
    """Whether folder `inner` lies inside folder `outer` (symlinks and ``..`` resolved)."""
    a, b = path_key(inner), path_key(outer)
    return a != b and a.startswith(b.rstrip(os.sep) + os.sep)


def check_input_file(path, flag: str) -> str | None:
    """A file the command reads: it exists, is a regular file and can be
    read (None passes). Raises ValueError naming `flag` and the path."""
    if path is None:
        return None
    path = os.fspath(path)
    if not path.strip():
        raise ValueError(f"{flag}: empty file name")
    if not os.path.exists(path):
        raise ValueError(f"{flag} {path}: no such file")
    if os.path.isdir(path):
        raise ValueError(f"{flag} {path}: is a folder; give a CSV file")
    if not os.path.isfile(path):
        raise ValueError(f"{flag} {path}: not a regular file")
    if not os.access(path, os.R_OK):
        raise ValueError(f"{flag} {path}: file is not readable")
    return path


def check_output_dir(path, flag: str) -> str | None:
    """A folder the command will write into: an existing writable folder,
    or one that can be made (nothing is created here)."""
    if path is None:
        return None
    path = os.fspath(path)
    if not path.strip():
        raise ValueError(f"{flag}: empty folder name")
    if os.path.exists(path):
        if not os.path.isdir(path):
            raise ValueError(f"{flag} {path}: is a file, not a folder")
        if not os.access(path, os.W_OK | os.X_OK):
            raise ValueError(f"{flag} {path}: folder is not writable")
        return path
    _check_folder_can_hold(path, flag, path)
    note_new_folders(path, flag)
    return path


def missing_folders(*paths) -> list[str]:
    """Of each path and its ancestors, those that do not exist yet (deepest
    first): what a command may create and must remove if it fails."""
    out: list[str] = []
    for path in paths:
        if path is None:
            continue
        p = os.path.abspath(os.fspath(path))
        while not os.path.exists(p):
            if p not in out:
                out.append(p)
            parent = os.path.dirname(p)
            if parent == p:
                break
            p = parent
    return sorted(out, key=lambda p: -p.count(os.sep))


COMMAND_NAME: list = [None]  # the command being run (set by mat_hopper.cli.main)
_PENDING: list = []  # (flag, folders missing when checked), told by tell_new_folders


def note_new_folders(folder, flag: str) -> list[str]:
    """The one rule of every output: a folder an output needs that does not
    exist is made by the command, and said, in one line on stderr naming
    the folders (top first) and the option, once the command is done
    (:func:`tell_new_folders`: a refusal makes none and says none).
    Returns the folders missing now (empty when all exist)."""
    new = list(reversed(missing_folders(folder)))
    if new:
        _PENDING.append((flag, new))
    return new


def tell_new_folders(tell: bool = True) -> None:
    """One line per option whose missing folders the command made (they
    exist now), each folder named once; the pending notes are cleared
    (`tell` False: cleared only, after an error or an interrupt)."""
    import sys

    told: set = set()
    for flag, folders in _PENDING if tell else ():
        made = [p for p in folders if os.path.isdir(p) and p not in told]
        told.update(made)
        if made:
            who = f"mat-hopper {COMMAND_NAME[0]}" if COMMAND_NAME[0] else "mat-hopper"
            print(f"{who}: note: {flag}: created folder{'s' if len(made) > 1 else ''} {', '.join(made)}",
                  file=sys.stderr, flush=True)  # fmt: skip
    _PENDING.clear()


@contextmanager
def nothing_left_behind(*folders):
    """On failure (an exception), remove those of `folders` that did not
    exist on entry and hold nothing but empty folders now: a command that
    failed leaves no empty output or cache folder behind. A folder that
    got a file (a finished result, which a rerun reuses) is kept."""
    made = missing_folders(*folders)
    try:
        yield
    except BaseException:
        for p in made:  # deepest first
            if os.path.isdir(p) and not any(files for _, _, files in os.walk(p)):
                shutil.rmtree(p, ignore_errors=True)
        raise


def cache_folder(cache) -> tuple[str, str]:
    """The result cache folder a command will write into, checked before
    any work: ``--cache`` if given, else ``$MAT_HOPPER_CACHE``, else the
    default folder. An empty ``$MAT_HOPPER_CACHE`` is an error naming it,
    and a bad folder is named by where it came from (``$MAT_HOPPER_CACHE``,
    never a ``--cache`` the user did not type).

    Args:
        cache: the ``--cache`` option's value, or None when it was left out.

    Returns:
        (the folder, the name to give it in messages: ``--cache`` or
        ``$MAT_HOPPER_CACHE``).

    Raises:
        ValueError: ``$MAT_HOPPER_CACHE`` set but empty, or a folder that
            cannot be written or made (:func:`check_output_dir`).
    """
    from ..experiments.cache import CACHE_ENV, DEFAULT_CACHE_DIR
    from ..util.parsing import env_value

    env_cache = None if cache else env_value(CACHE_ENV, "a folder")
    flag = f"${CACHE_ENV}" if env_cache else "--cache"
    return check_output_dir(cache or env_cache or DEFAULT_CACHE_DIR, flag), flag


_WARP_DEVICE = re.compile(r"^(cpu|cuda(:\d+)?)$")
WARP_DEVICES_ACCEPTED = "cpu, cuda or cuda:N"


def check_warp_device_name(device, flag: str = "--device") -> None:
    """A Warp device name (cpu, cuda, cuda:N) or None, checked before Warp
    is imported (Warp warns about an unknown device).

    Args:
        device: the option's value, or None when it was left out.
        flag: the option named in the error.

    Raises:
        ValueError: any other name, naming `flag` and the accepted names.
    """
    if device is not None and not _WARP_DEVICE.match(str(device).strip()):
        raise ValueError(f"{flag} {device!r}: unknown device; accepted: {WARP_DEVICES_ACCEPTED}")


def warp_device(device, flag: str = "--device") -> str:
    """The Warp device a ``--backend warp`` command will run on, checked
    before any work or file: the name, mujoco-warp installed, and a CUDA
    device that Warp sees (one line, no Warp warning).

    Args:
        device: the option's value (cpu, cuda, cuda:N), or None: cuda
            where Warp sees a GPU, else cpu.
        flag: the option named in errors.

    Returns:
        The device's name (``"cpu"``, ``"cuda"``, ``"cuda:1"``).

    Raises:
        ValueError: an unknown name, no mujoco-warp (the ``gpu`` extra), or
            a CUDA device Warp does not see.
    """
    from ..batch import WarpUnavailable, require_warp

    check_warp_device_name(device, flag)
    try:
        wp, _ = require_warp()
    except WarpUnavailable as e:  # one line, exit 2
        raise ValueError(str(e)) from None
    n = wp.get_cuda_device_count()
    name = str(device).strip() if device is not None else ("cuda" if n > 0 else "cpu")
    if name.startswith("cuda"):
        index = int(name.split(":")[1]) if ":" in name else 0
        if index >= n:
            raise ValueError(f"{flag} {name}: Warp sees {n} CUDA device(s); accepted: cpu{', cuda' if n else ''}")
    return name
