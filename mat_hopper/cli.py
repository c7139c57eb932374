"""The ``mat-hopper`` command line.

Each feature module adds its own subcommand through ``register_cli``;
this module only gathers them and turns bad input into a one-line error
with exit code 2.
"""

from __future__ import annotations

import argparse
import importlib
import sys

# Modules that contribute subcommands (each defines register_cli(subparsers)).
COMMAND_MODULES = (
    "mat_hopper.cli_simulate",
    "mat_hopper.cli_reproduce",
    "mat_hopper.optimize",
    "mat_hopper.render",
    "mat_hopper.cli_batch",
)


def build_parser() -> argparse.ArgumentParser:
    from . import __version__
    p = argparse.ArgumentParser(prog="mat-hopper", description=(
        "Materials Matter, executable: simulate graded robot legs on a MuJoCo hopper."))
    p.add_argument("--version", action="version", version=f"mat-hopper {__version__}")
    sub = p.add_subparsers(dest="command", metavar="COMMAND", required=True)
    for name in COMMAND_MODULES:
        importlib.import_module(name).register_cli(sub)
    return p


class UsageError(ValueError):
    """Bad input found by a command (reported as one line, exit code 2)."""


def main(argv=None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    from .sim import route_mujoco_warnings
    route_mujoco_warnings()
    try:
        return int(args.func(args) or 0)
    except (ValueError, FileNotFoundError) as e:
        print(f"mat-hopper {args.command}: error: {e}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(main())
