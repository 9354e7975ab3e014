"""Command-line entry point: argument parsing and exit codes, no physics.

Exit codes (docs/commands.md §1.3): 0 success, 2 bad input, 3 no solution (infeasible or solver
failure, or an internal error, reported with a "please report" hint), 130 interrupted (143 by
SIGTERM). No error prints a Python traceback unless ``--debug`` is given. Under ``--json`` an error
that comes before the command's document prints ``{"error": {"code": …, "message": …}}`` on stdout instead.
"""

from __future__ import annotations

import argparse
import contextlib
import importlib
import json
import re
import sys
import warnings

from pampipe._version import __version__
from pampipe.errors import InputError, PampipeError, StreamError
from pampipe.io import streams
from pampipe.io.files import check_distinct_outputs, forget_written, written
from pampipe.runtime import interrupts, progress
from pampipe.units import display

#: Command modules under pampipe.commands, in the order --help lists them.
COMMANDS = ("simulate", "identify", "plan", "gait", "diagnose", "route", "synth", "design", "example",
            "export", "rehearse", "next_test", "completion")
#: Exit codes of an interrupted run: 128 + SIGINT, 128 + SIGTERM.
INTERRUPTED = (130, 143)
#: Exit code of an unexpected internal error (a bug).
INTERNAL = 3


class _UsageError(Exception):
    """A command-line mistake found by argparse (exit 2)."""


class _Parser(argparse.ArgumentParser):
    """argparse that raises :class:`_UsageError` (one line, with a did-you-mean) instead of exiting."""

    def error(self, message: str):
        commands = getattr(self, "commands", {})
        prog = next(iter(commands.values())).prog if len(commands) == 1 else self.prog
        raise _UsageError(f"{message}{_suggestion(self, message)} (see '{prog} --help')")


def _suggestion(parser: argparse.ArgumentParser, message: str) -> str:
    """'; did you mean --max-iterations?' for a misspelt option or command, else ''."""
    import difflib

    unknown = re.match(r"unrecognized arguments: (.*)", message)
    if unknown:
        options = [o for p in getattr(parser, "commands", {}).values() for a in p._actions
                   for o in a.option_strings] or [o for a in parser._actions for o in a.option_strings]
        for word in unknown.group(1).split():
            close = difflib.get_close_matches(word.split("=")[0], options, n=1, cutoff=0.6)
            if word.startswith("-") and close:
                return f"; did you mean {close[0]}?"
        return ""
    choice = re.search(r"invalid choice: '([^']*)'", message)
    if choice and "COMMAND" in message:
        close = difflib.get_close_matches(choice.group(1), COMMANDS, n=1)
        return f"; did you mean '{close[0]}'?" if close else ""
    return ""


def build_parser(commands: tuple[str, ...] = COMMANDS, *, arguments: bool = True) -> argparse.ArgumentParser:
    """The argument parser with the given command modules registered (all by default).

    With ``arguments=False`` each command is listed by its name and help only (enough for ``--help``,
    ``--version`` and a misspelt command): its ``add_arguments`` is not called, so nothing it needs for its
    options is imported. A command module's top level imports only light argument-definition code; its
    ``run`` imports the science (CasADi, pydantic, …) when the command runs.
    """
    parser = _Parser(
        prog="pampipe",
        description="Plan the inflation pressures of a pneumatic-muscle pipe-crawling robot.",
        epilog="Exit codes: 0 success, 2 bad input, 3 no solution (infeasible or solver failure), "
               "130 interrupted (143 by SIGTERM).")
    parser.add_argument("--version", action="version", version=f"pampipe {__version__}")
    parser.add_argument("--debug", action="store_true", help="show the traceback of an internal error")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    parser.commands = {}
    for name in commands:
        try:
            module = importlib.import_module(f"pampipe.commands.{name}")
        except ModuleNotFoundError as exc:
            if exc.name != f"pampipe.commands.{name}":
                raise
            continue
        command = sub.add_parser(module.NAME, help=module.HELP, description=module.HELP)
        if arguments:
            module.add_arguments(command)
            command.set_defaults(run=module.run)
            if name == "completion":  # the script is built from the whole parser
                command.set_defaults(parser=parser)
            parser.commands[name] = command
    return parser


def main(argv: list[str] | None = None) -> int:
    """Run one command; return its exit code (run as the program, an interrupted run ends at once)."""
    program = argv is None
    argv = sys.argv[1:] if program else list(argv)
    # numpy's floating-point warnings ("invalid value encountered in sqrt") are for developers: every
    # result is checked for NaN/inf where it matters and a user is told in pampipe's words (tests see them)
    warnings.filterwarnings("ignore", category=RuntimeWarning,
                            message=r"(invalid value|divide by zero|overflow|underflow) encountered")
    forget_written()
    try:
        with streams.guarded(), interrupts.handled():
            code = _flushed(_run(argv))
    except StreamError:  # a stream closed before the run: said on the other one if it was open
        return StreamError.exit_code
    if program and (code in INTERRUPTED or _only_thread()):
        _end_now(code)
    return code


def _only_thread() -> bool:
    """No thread but the main one is alive (a pool's threads are joined by the interpreter's shutdown)."""
    threading = sys.modules.get("threading")
    return threading is None or threading.active_count() == 1


def _end_now(code: int) -> None:
    """End the program now: the streams are flushed and the exit handlers run (multiprocessing's clean-up,
    temporary folders, logging), but not the interpreter's teardown of CasADi, numpy and the rest, which
    frees memory the exit frees anyway: about 0.1 s of a 1.5 s `identify` (CPU), and about 1 s with wntr
    loaded (more on a busy machine), which would break an interrupted run's promise of an exit within 2 s."""
    import atexit
    import os

    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except (OSError, ValueError):
            pass
    atexit._run_exitfuncs()
    os._exit(code)


def _run(argv: list[str]) -> int:
    args = None
    command = "pampipe"
    # import only the chosen command's module: start-up then skips the others' heavy imports
    chosen = next((a for a in argv if not a.startswith("-")), None)
    chosen = None if chosen is None else chosen.replace("-", "_")  # next-test: pampipe/commands/next_test.py
    try:
        try:
            # a command: only its module; --help, --version, a misspelt command: the names only; completion:
            # every command's options (its script is built from the whole parser)
            parser = (build_parser((chosen,)) if chosen in COMMANDS and chosen != "completion"
                      else build_parser(COMMANDS, arguments=chosen == "completion"))
            args = parser.parse_args(argv)
        except SystemExit as exc:  # --help and --version
            return int(exc.code or 0)
        command = f"pampipe {args.command}"
        check_distinct_outputs(args)  # before any work: -o x.html --report x.html would keep one of them
        if getattr(args, "plot_format", None):
            from pampipe.views.tables import set_plot_format

            set_plot_format(args.plot_format)
        with progress.shown(enabled=not (getattr(args, "json", False) or getattr(args, "quiet", False))), \
                display.shown_in(getattr(args, "units", None) or "metric"):
            return args.run(args)
    except _UsageError as exc:
        named = command if chosen not in COMMANDS else f"pampipe {chosen.replace('_', '-')}"
        return _fail(args, argv, named, 2, "error", str(exc))
    except StreamError as exc:  # stdout or stderr cannot be written: the environment's fault
        return _fail(args, argv, command, exc.exit_code, "error", str(exc), broken=exc.stream)
    except KeyboardInterrupt:
        return _interrupted(args, argv, command)
    except PampipeError as exc:
        if interrupts.requested():  # a solver stopped by the signal reports a failure: it was the signal
            return _interrupted(args, argv, command)
        kind = "error" if isinstance(exc, InputError) else "no solution"
        shown = None
        if not isinstance(exc, InputError):  # a reason, in the units of --units (input errors echo the input)
            with display.shown_in(getattr(args, "units", None) or "metric"):
                shown = display.localize(str(exc))
        return _fail(args, argv, command, exc.exit_code, kind, str(exc), shown=shown)
    except Exception as exc:  # the last resort: a bug, never a user mistake
        if "--debug" in argv:
            import traceback

            traceback.print_exc()
        first = str(exc).splitlines()[0][:300] if str(exc) else ""
        return _fail(args, argv, command, INTERNAL, "internal error",
                     f"{type(exc).__name__}{': ' + first if first else ''}. This is a bug in pampipe; "
                     "please report it with the input files and the command line "
                     f"({'traceback above' if '--debug' in argv else 'add --debug for the traceback'}).")


def _flushed(code: int) -> int:
    """``code``, once stdout and stderr have taken all the text; 2 if they cannot (a full disk)."""
    try:
        sys.stdout.flush()
        sys.stderr.flush()
    except StreamError as exc:
        if exc.stream == "stdout":
            with contextlib.suppress(StreamError):
                print(f"pampipe: error: {exc}", file=sys.stderr, flush=True)
        return exc.exit_code
    return code


def _interrupted(args, argv, command: str) -> int:
    files = written()
    if files:
        done = ", ".join(str(f) for f in files)
        message = f"interrupted after writing {done}; no partial output was written."
    else:
        message = "interrupted; no partial output was written."
    return _fail(args, argv, command, interrupts.exit_code(), None, message)


def _fail(args, argv, command: str, code: int, kind: str | None, message: str, *,
          broken: str | None = None, shown: str | None = None) -> int:
    """Print the one-paragraph message (``shown``, the message in the display units, if given) and the JSON
    error document under --json (``message``, SI-metric); return ``code``.

    ``broken`` names a stream that already failed: nothing more is written to it. A stream that
    fails here makes the exit 2 (:class:`StreamError`), whatever the first error was.
    """
    try:
        if broken != "stderr":
            print(f"{command}: {kind + ': ' if kind else ''}{shown or message}", file=sys.stderr, flush=True)
        json_mode = getattr(args, "json", None) if args is not None else _json_flag(argv)
        if json_mode and broken != "stdout" and not getattr(args, "document_printed", False):
            sys.stdout.write(json.dumps({"error": {"code": code, "kind": kind or "interrupted",
                                                   "message": message}}, indent=2) + "\n")
            sys.stdout.flush()
    except StreamError as exc:
        if exc.stream == "stdout" and broken is None:
            with contextlib.suppress(StreamError):
                print(f"{command}: error: {exc}", file=sys.stderr, flush=True)
        return StreamError.exit_code
    return code


def _json_flag(argv: list[str]) -> bool:
    """--json (or an abbreviation argparse would accept) among arguments that did not parse."""
    return any(len(a) >= 4 and "--json".startswith(a) for a in argv)


if __name__ == "__main__":
    sys.exit(main())
