"""Helpers shared by the command modules: unit-aware option types and output emission."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from pampipe.errors import InputError
from pampipe.io.files import atomic_write, atomic_write_text, json_chunks, to_json
from pampipe.units.quantities import to_si


def quantity_type(dimension: str):
    """argparse type: a quantity such as '3 in' or '400 kPa', converted to SI."""

    def parse(text: str) -> float:
        try:
            return to_si(text, dimension)  # argparse names the option
        except InputError as exc:
            raise argparse.ArgumentTypeError(str(exc)) from None

    parse.__name__ = dimension
    return parse


def probability(text: str) -> float:
    """argparse type: a probability in [0.5, 1), as a number or a percentage ('0.95', '95 %')."""
    try:
        value = to_si(text, "dimensionless")
    except InputError as exc:
        raise argparse.ArgumentTypeError(f"{exc} Give a probability, e.g. 0.95 or '95 %'.") from None
    if not 0.5 <= value < 1:
        raise argparse.ArgumentTypeError(f"{text!r} must be a probability in [0.5, 1), e.g. 0.95")
    return value


def integer_type(option: str, *, ge: int | None = None, le: int | None = None):
    """argparse type: a whole number within [ge, le], with a message naming ``option``."""

    def parse(text: str) -> int:
        try:
            value = int(text.strip())
        except ValueError:
            raise argparse.ArgumentTypeError(f"{option}: {text!r} is not a whole number") from None
        if (ge is not None and value < ge) or (le is not None and value > le):
            bounds = (f"from {ge} to {le}" if ge is not None and le is not None
                      else f"at least {ge}" if ge is not None else f"at most {le}")
            raise argparse.ArgumentTypeError(f"{option}: {value} must be {bounds}")
        return value

    parse.__name__ = "integer"
    return parse


#: The fewest draws of a confidence plan (the planner's N(1 − C) ≥ 10 rule is checked with C, when it runs).
FEWEST_DRAWS = 100


def add_confidence_options(parser: argparse.ArgumentParser, *, confidence: str, samples: str,
                           seed: str | None, default_confidence: float | None = None) -> None:
    """--confidence C, --samples N and --seed S of every command that plans at a confidence (plan,
    rehearse, export, next-test), each with one validator: C a probability in [0.5, 1) (:func:`probability`),
    N a whole number of at least :data:`FEWEST_DRAWS`, S a whole number of at least 0. The help texts are
    each command's (``seed=None``: no --seed)."""
    parser.add_argument("--confidence", type=probability, default=default_confidence, metavar="C",
                        help=confidence)
    parser.add_argument("--samples", type=integer_type("--samples", ge=FEWEST_DRAWS), default=None,
                        metavar="N", help=samples)
    if seed is not None:
        parser.add_argument("--seed", type=integer_type("--seed", ge=0), default=None, metavar="S", help=seed)


def add_output_options(parser: argparse.ArgumentParser, *, plots: bool = True) -> None:
    """--json, --reproducible, --debug and (for commands that draw) --plots DIR."""
    parser.add_argument("--json", action="store_true",
                        help="print exactly one JSON document on stdout; human text goes to stderr")
    parser.add_argument("--quiet", action="store_true",
                        help="no progress lines on stderr (--json is quiet too); results and errors still "
                             "show")
    parser.add_argument("--reproducible", action="store_true",
                        help="write wall-clock timings (keys ending wall_time_s) as 0 in JSON, so that the "
                             "same inputs give byte-identical JSON")
    parser.add_argument("--debug", action="store_true", default=argparse.SUPPRESS,
                        help="show the traceback of an internal error")
    if plots:
        parser.add_argument("--plots", metavar="DIR", type=_plots_folder,
                            help="write the plots into DIR (created if missing)")
        parser.add_argument("--plot-format", choices=("png", "svg", "pdf"), default="png",
                            help="file format of --plots: png (150 dpi), or svg / pdf (vector, for a paper); "
                                 "default png")


def add_units_option(parser: argparse.ArgumentParser) -> None:
    """--units: the units of the text output (:mod:`pampipe.units.display`); JSON stays SI."""
    from pampipe.units.display import CHOICES

    parser.add_argument("--units", choices=CHOICES, default="metric",
                        help="units of the tables, warnings, reasons and plots: si (Pa, m, N), metric (kPa, "
                             "mm, N; default), us (psi, in, lbf), or one pressure unit (kPa, psi, bar, MPa, "
                             "Pa) for pressures only; the JSON stays SI. Options take values in any unit "
                             "('6.6 lb', '4.5 in')")


def add_parallel_options(parser: argparse.ArgumentParser, what: str) -> None:
    """--workers N and --scheduler ADDRESS: where ``what`` runs (:func:`pampipe.runtime.executors.executor`);
    the
    result is the same on each."""
    parser.add_argument("--workers", type=int, metavar="N", help=f"run {what} on N local processes")
    parser.add_argument("--scheduler", metavar="ADDRESS",
                        help=f"run {what} on the Dask cluster at ADDRESS (pip install pampipe[dask])")


def add_report_option(parser: argparse.ArgumentParser) -> None:
    """--report FILE.html or FILE.pdf: the report to send (:mod:`pampipe.views.html`,
    :mod:`pampipe.views.pdf_report`)."""
    parser.add_argument("--report", type=Path, metavar="FILE.html|FILE.pdf",
                        help="also write one self-contained HTML file to send: inputs with their SHA-256, "
                             "tables, warnings, plots (inline SVG) and the model's assumptions; a name "
                             "ending .pdf writes the same report as an A4 PDF")


def write_html_report(args: argparse.Namespace, command: str, *, inputs, text: str, document: dict,
                      draw, warnings=(), reasons=()) -> None:
    """Write ``args.report`` if asked for; ``draw()`` draws the command's plots (captured as SVG)."""
    if getattr(args, "report", None) is None:
        return
    from pampipe.units.display import localize

    source = getattr(args, "mission", None) or getattr(args, "experiment", None)
    parts = {"title": f"pampipe {command} {source}", "inputs": inputs, "text": localize(text),
             "document": document, "warnings": [localize(w) for w in warnings],
             "reasons": [localize(r) for r in reasons]}
    if args.report.suffix.lower() == ".pdf":
        from pampipe.views.pdf_report import write_pdf

        write_pdf(args.report, command, draw=draw, **parts)
    else:
        from pampipe.views.html import svg_figures, write_report

        write_report(args.report, command, figures=svg_figures(draw), **parts)
    say(args, f"wrote {args.report}")


def _plots_folder(text: str) -> Path:
    """argparse type: a folder for the plots, refused at once if it exists as something else."""
    path = Path(text)
    if path.exists() and not path.is_dir():
        raise argparse.ArgumentTypeError(f"{text}: exists and is not a folder; give a folder for the plots")
    return path


def warn(warnings) -> None:
    """Each warning on stderr, one ``warning:`` line each, in the display units."""
    from pampipe.units.display import localize

    for warning in warnings:
        print(f"warning: {localize(warning)}", file=sys.stderr, flush=True)


def text_stream(args: argparse.Namespace):
    """Where human-readable text goes: stderr under --json, stdout otherwise."""
    return sys.stderr if getattr(args, "json", False) else sys.stdout


def say(args: argparse.Namespace, text: str) -> None:
    """Print human-readable text to the right stream."""
    print(text, file=text_stream(args), flush=True)


def _json_in_file(args: argparse.Namespace) -> bool:
    """True under ``--json -o FILE`` of a command whose -o is its JSON document (``plan``): the document goes
    to FILE only, and stdout gets the text report (nothing with --quiet), not a second copy of a document
    that may be megabytes long."""
    return getattr(args, "json", False) and getattr(args, "json_output", False) and args.output is not None


def _report_only(args: argparse.Namespace, text: str) -> None:
    if not getattr(args, "quiet", False):
        print(text, flush=True)


def emit(args: argparse.Namespace, document: dict | None, text: str, *, indent: int | None = 2) -> None:
    """Print the JSON document (under --json) or the text report (``document`` may then be None); the text
    in the display units of --units (:func:`pampipe.units.display.localize`)."""
    from pampipe.units.display import localize

    text = localize(text)
    if _json_in_file(args):
        _report_only(args, text)
    elif getattr(args, "json", False):
        print(text, file=sys.stderr, flush=True)
        sys.stdout.write(to_json(document, timings=not args.reproducible, indent=indent))
        sys.stdout.flush()
        args.document_printed = True  # a later error adds no second JSON document
    else:
        print(text, flush=True)


def emit_streamed(args: argparse.Namespace, document, text: str) -> None:
    """:func:`emit` and :func:`write_json` (``-o``) of a large document written as it is produced
    (:func:`pampipe.io.files.json_chunks`), on one line; ``document()`` gives it with its
    :class:`~pampipe.io.files.Streamed` lists. -o is written first (atomically), then copied to stdout."""
    from pampipe.units.display import localize

    timings = not args.reproducible
    if args.output is not None:
        atomic_write(args.output, lambda tmp: _write_chunks(tmp, json_chunks(document(), timings=timings)))
    if _json_in_file(args):
        _report_only(args, localize(text))
        return
    if not getattr(args, "json", False):
        print(localize(text), flush=True)
        return
    print(localize(text), file=sys.stderr, flush=True)
    args.document_printed = True  # from here on an error adds no second JSON document
    write = getattr(sys.stdout, "write_escaped", sys.stdout.write)  # JSON: ASCII, its controls escaped
    if args.output is not None:
        with open(args.output, encoding="utf-8") as written:
            while chunk := written.read(1 << 20):
                write(chunk)
    else:
        for chunk in json_chunks(document(), timings=timings):
            write(chunk)
    sys.stdout.flush()


def _write_chunks(path: Path, chunks) -> None:
    with open(path, "w", encoding="utf-8") as handle:
        for chunk in chunks:
            handle.write(chunk)


def write_json(path: Path, document: dict, args: argparse.Namespace, *, indent: int | None = 2) -> None:
    """Write the JSON document to ``path`` atomically (honouring --reproducible)."""
    atomic_write_text(path, to_json(document, timings=not args.reproducible, indent=indent))


def next_test_command(pam, mission, menu, confidence: float) -> str:
    """The `pampipe next-test` command line that ranks ``menu``'s tests for ``mission`` (docs/commands.md
    §14)."""
    import shlex

    return (f"pampipe next-test {shlex.quote(str(pam))} {shlex.quote(str(mission))} --menu "
            f"{shlex.quote(str(menu))} --confidence {confidence:g}")
