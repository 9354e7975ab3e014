"""Command-line entry point: argument parsing and exit codes, no physics.

Exit codes (docs/commands.md §5): 0 success, 2 bad input, 3 no solution (infeasible or solver
failure), 130 interrupted. A user mistake never prints a Python traceback.
"""

from __future__ import annotations

import argparse
import importlib
import signal
import sys

from pampipe import __version__
from pampipe.errors import InputError, PampipeError

#: Command modules under pampipe.commands, in the order --help lists them.
COMMANDS = ("simulate", "identify", "plan", "gait", "diagnose", "route", "synth", "design", "example",
            "export")


class _Parser(argparse.ArgumentParser):
    """argparse with one-line usage errors (exit 2) instead of the full usage block."""

    def error(self, message: str):
        self.exit(2, f"{self.prog}: error: {message} (see '{self.prog} --help')\n")


def build_parser(commands: tuple[str, ...] = COMMANDS) -> argparse.ArgumentParser:
    """The argument parser with the given command modules registered (all by default)."""
    parser = _Parser(
        prog="pampipe",
        description="Plan the inflation pressures of a pneumatic-muscle pipe-crawling robot.",
        epilog="Exit codes: 0 success, 2 bad input, 3 no solution (infeasible or solver failure), "
               "130 interrupted.")
    parser.add_argument("--version", action="version", version=f"pampipe {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    for name in commands:
        try:
            module = importlib.import_module(f"pampipe.commands.{name}")
        except ModuleNotFoundError as exc:
            if exc.name != f"pampipe.commands.{name}":
                raise
            continue
        command = sub.add_parser(module.NAME, help=module.HELP, description=module.HELP)
        module.add_arguments(command)
        command.set_defaults(run=module.run)
    return parser


def _interrupted(signum, frame):
    raise KeyboardInterrupt


def main(argv: list[str] | None = None) -> int:
    """Run one command; return its exit code."""
    signal.signal(signal.SIGTERM, _interrupted)
    command = "pampipe"
    argv = sys.argv[1:] if argv is None else list(argv)
    # import only the chosen command's module: start-up then skips the others' heavy imports
    chosen = next((a for a in argv if not a.startswith("-")), None)
    try:
        parser = build_parser((chosen,) if chosen in COMMANDS else COMMANDS)
        try:
            args = parser.parse_args(argv)
        except SystemExit as exc:  # --help, --version and usage errors
            return int(exc.code or 0)
        command = f"pampipe {args.command}"
        return args.run(args)
    except PampipeError as exc:
        kind = "error" if isinstance(exc, InputError) else "no solution"
        print(f"{command}: {kind}: {exc}", file=sys.stderr)
        return exc.exit_code
    except KeyboardInterrupt:
        print(f"{command}: interrupted; no partial output was written.", file=sys.stderr)
        return 130
    except BrokenPipeError:
        return 0


if __name__ == "__main__":
    sys.exit(main())
