"""The ``mat-hopper`` command line (also ``python -m mat_hopper``).

All argparse code lives in this package: one module per subcommand
(:mod:`~mat_hopper.cli.simulate`, :mod:`~mat_hopper.cli.reproduce`,
:mod:`~mat_hopper.cli.optimize`, :mod:`~mat_hopper.cli.render`), each with
``register_cli(subparsers)``, over the library's public calls. Nothing
outside ``cli`` imports it. This module gathers the subcommands, routes
MuJoCo's warnings to logging, and turns bad input into a one-line error
with exit code 2.
"""

from __future__ import annotations

import argparse
import importlib
import os
import sys

from ._checks import negative_list_argv

# Modules that contribute subcommands (each defines register_cli(subparsers)).
COMMAND_MODULES = (
    "mat_hopper.cli.simulate",
    "mat_hopper.cli.reproduce",
    "mat_hopper.cli.optimize",
    "mat_hopper.cli.render",
    "mat_hopper.cli.batch",
    "mat_hopper.cli.modes",
    "mat_hopper.cli.compare",
    "mat_hopper.cli.plan",
    "mat_hopper.cli.records",
)
# Each command's line in `mat-hopper --help` (tests/cli check it is the
# module's own): the top-level help lists the commands without importing
# them, so that it answers in a fraction of a second (MuJoCo, numba,
# pandas, Optuna and matplotlib load with the command that needs them).
COMMAND_HELP = {
    "simulate": "simulate one design on one behaviour, print a per-hop summary",
    "reproduce": "run the paper's experiments, write tables, figures and claims",
    "optimize": "search leg designs with Optuna (multi-objective, resumable, parallel)",
    "render": "render gait tiles, a video or a still of a design, off-screen",
    "batch": "evaluate many designs on one behaviour (CPU rollouts or a MuJoCo Warp batch)",
    "modes": "a leg's axial natural frequencies (lumped chain vs continuum rod) and its stable time step",
    "compare": "compare a design with baselines and its own controls, paired on shared seeds at one time step",
    "plan": "count the book's runs per chapter before any run: shared, cached, physics steps, core-hours",
    "records": "rebuild book/records (the paper-profile results the quick book shows) from one finished book build",
}


class _Parser(argparse.ArgumentParser):
    """argparse with one-line errors: "mat-hopper CMD: error: ...", exit 2
    (argparse's default prints the whole usage first)."""

    def error(self, message):
        self.exit(2, f"{self.prog}: error: {message} (see {self.prog} --help)\n")


def command_of(argv) -> str | None:
    """The subcommand named in argv (its first word that is not an option), or None."""
    return next((a for a in argv if not a.startswith("-")), None)


def build_parser(command: str | None = None) -> argparse.ArgumentParser:
    """The parser; with `command`, only that subcommand is built in full
    (its module imported) and the others are listed by name and help line;
    command="" builds none (for ``mat-hopper --help``)."""
    from .. import __version__
    from ._checks import harden_parser

    p = _Parser(
        prog="mat-hopper", description=("Materials Matter, executable: simulate graded robot legs on a MuJoCo hopper.")
    )
    p.add_argument("--version", action="version", version=f"mat-hopper {__version__}")
    sub = p.add_subparsers(dest="command", metavar="COMMAND", required=True, parser_class=_Parser)
    for name in COMMAND_MODULES:
        short = name.rsplit(".", 1)[-1]
        if command is None or command == short:
            importlib.import_module(name).register_cli(sub)
        else:
            sub.add_parser(short, help=COMMAND_HELP[short])
    return harden_parser(p)


# Options whose value may be a list starting with a minus sign ("-1,2,3"):
# rewritten to --opt=VALUE before argparse sees them (see _checks).
def describe_error(e: BaseException) -> str:
    """One line naming what went wrong: the error's own text for bad input;
    for file-system, SQLite and database errors the deepest cause (SQLAlchemy
    and Optuna wrap the driver's message, e.g. "database is locked", in
    pages of context), with the file it concerns."""
    seen, chain, cur = set(), [], e
    while cur is not None and id(cur) not in seen:
        seen.add(id(cur))
        chain.append(cur)
        cur = getattr(cur, "orig", None) or cur.__cause__ or cur.__context__
    root = chain[-1]
    if isinstance(root, OSError) and not isinstance(e, ValueError):
        what = root.strerror or str(root)
        files = [f for f in (root.filename, root.filename2) if f]
        return f"{what}: {' -> '.join(map(str, files))}" if files else what
    if isinstance(e, ValueError):
        return str(e).strip().splitlines()[0] if str(e).strip() else type(e).__name__
    text = str(root).strip().splitlines()
    return f"{text[0]}" if text else type(root).__name__


def _storage_errors() -> tuple:
    """Database errors turned into one line (imported only when present)."""
    import sqlite3

    out = [sqlite3.Error]
    for mod, name in (("sqlalchemy.exc", "SQLAlchemyError"), ("optuna.exceptions", "StorageInternalError")):
        module = sys.modules.get(mod)
        if module is not None:
            out.append(getattr(module, name))
    return tuple(out)


def subcommand_parser(parser: argparse.ArgumentParser, command: str) -> argparse.ArgumentParser:
    """The parser of subcommand `command` in `parser` (:func:`build_parser`'s)."""
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    return sub.choices[command]


def _parse(parser: argparse.ArgumentParser, argv) -> argparse.Namespace:
    """The command line read, an unknown option refused by its command's
    parser ("mat-hopper batch: error: unrecognized arguments: --no-progres;
    did you mean --no-progress?"), not by the top one, which would name no
    command."""
    from ..util.parsing import close_names

    args, extra = parser.parse_known_args(argv)
    if extra:
        sub = subcommand_parser(parser, args.command)
        flags = [s for a in sub._actions for s in a.option_strings]
        near = [m for a in extra if a.startswith("--") for m in close_names(a.split("=", 1)[0], flags, n=1)]
        hint = f"; did you mean {' or '.join(dict.fromkeys(near))}?" if near else ""
        sub.error(f"unrecognized arguments: {' '.join(extra)}{hint}")
    return args


def main(argv=None) -> int:
    """Run the command of `argv` (None: the process's); its exit code. An
    interrupt at any point, the start-up's imports included, is one line
    ("interrupted") and exit 128 + the signal's number, 130 for Ctrl-C."""
    try:
        return _main(argv)
    except KeyboardInterrupt as e:
        return _interrupted(e)


def _interrupted(e: KeyboardInterrupt) -> int:
    sig = getattr(e, "signal_name", None)
    print(f"interrupted{f' by {sig}' if sig else ''}", file=sys.stderr)
    return 128 + int(getattr(e, "signal_number", 2))


def _main(argv) -> int:
    argv = negative_list_argv(sys.argv[1:] if argv is None else list(argv))  # every --option may take a negative
    command = command_of(argv)
    parser = build_parser(command if command in COMMAND_HELP else "")
    if command is not None and command not in COMMAND_HELP:  # argparse's own words name no near command
        from ..util.parsing import did_you_mean

        hint = did_you_mean(command, COMMAND_HELP)
        parser.error(
            f"unknown command {command!r} (choose from {', '.join(COMMAND_HELP)}){f'; {hint}' if hint else ''}"
        )
    args = _parse(parser, argv)
    from ..core.sim import route_mujoco_warnings

    route_mujoco_warnings()
    from ..optimize import stop_signals
    from ..util.atomic import remove_stale_mp_dirs
    from ._checks import COMMAND_NAME, COMMAND_OPTIONS, table_on_stdout, tell_new_folders

    COMMAND_NAME[0] = args.command  # named in the notes of folders an output makes

    remove_stale_mp_dirs()  # what killed runs left in the temp folder
    COMMAND_OPTIONS[0] = frozenset(
        s for a in subcommand_parser(parser, args.command)._actions for s in a.option_strings
    )
    try:
        with stop_signals(), table_on_stdout(args):  # SIGTERM, SIGHUP: like Ctrl-C (nothing half-written)
            code = int(args.func(args) or 0)
            tell_new_folders()  # the output folders the command made, named
            sys.stdout.flush()  # a closed pipe shows here, not in the interpreter's final flush
            return code
    except BrokenPipeError:
        # the reader went away (`mat-hopper ... | head`): stop quietly, as a
        # shell tool killed by SIGPIPE does; stdout is pointed at /dev/null so
        # that the interpreter's final flush does not fail again
        try:
            devnull = os.open(os.devnull, os.O_WRONLY)
            os.dup2(devnull, sys.stdout.fileno())
        except (OSError, ValueError):
            pass
        return 141
    except KeyboardInterrupt as e:
        return _interrupted(e)
    except (ValueError, OSError, *_storage_errors()) as e:
        print(f"mat-hopper {args.command}: error: {describe_error(e)}", file=sys.stderr)
        return 2
    finally:
        tell_new_folders(tell=False)  # after an error or an interrupt: the line above says what happened
        COMMAND_OPTIONS[0] = None
