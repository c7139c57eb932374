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
import sys

# Modules that contribute subcommands (each defines register_cli(subparsers)).
COMMAND_MODULES = (
    "mat_hopper.cli.simulate",
    "mat_hopper.cli.reproduce",
    "mat_hopper.cli.optimize",
    "mat_hopper.cli.render",
    "mat_hopper.cli.batch",
    "mat_hopper.cli.modes",
)


def build_parser() -> argparse.ArgumentParser:
    from .. import __version__

    p = argparse.ArgumentParser(
        prog="mat-hopper", description=("Materials Matter, executable: simulate graded robot legs on a MuJoCo hopper.")
    )
    p.add_argument("--version", action="version", version=f"mat-hopper {__version__}")
    sub = p.add_subparsers(dest="command", metavar="COMMAND", required=True)
    for name in COMMAND_MODULES:
        importlib.import_module(name).register_cli(sub)
    return p


class UsageError(ValueError):
    """Bad input found by a command (reported as one line, exit code 2)."""


def main(argv=None) -> int:
    from ..sim import route_mujoco_warnings

    route_mujoco_warnings()
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return int(args.func(args) or 0)
    except (ValueError, FileNotFoundError) as e:
        print(f"mat-hopper {args.command}: error: {e}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return 130
