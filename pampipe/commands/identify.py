"""`pampipe identify`: fit the bladder moduli to an experiment and write a PAM file."""

from __future__ import annotations

import argparse
from pathlib import Path

from pampipe.commands.common import (
    add_output_options,
    add_report_option,
    add_units_option,
    emit,
    quantity_type,
    say,
    write_html_report,
)
from pampipe.io.files import check_output
from pampipe.runtime.progress import deferred, note

NAME = "identify"
HELP = ("fit the bladder moduli to axial and radial test data (IPOPT, Drucker-stable, with uncertainty), and "
        "the wall friction and load coupling to slip tests")


#: Command-line flags that override the experiment file's ``fit:`` block, validated by the same schema.
FLAGS = {"mode": "--mode", "objective": "--objective", "degree": "--degree", "average_legs": "--average-legs",
         "drucker": "--drucker", "max_iterations": "--max-iterations", "slack": "--slack"}


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("experiment", type=Path, metavar="EXPERIMENT.yaml",
                        help="experiment file: the PAM, the tests (axial, radial, slip) and their CSV "
                             "data, an optional fit: block")
    parser.add_argument("-o", "--output", type=Path, metavar="PAM_OUT.yaml",
                        help="write the PAM file with the fitted moduli: and uncertainty: blocks, and "
                             "with slip tests the measured contact: {friction, load_coupling, "
                             "pipe_material} block")
    parser.add_argument("--mode", choices=("shared", "per_pipe", "contact_increment"),
                        help="one moduli set for all tests (default), separate radial moduli per pipe, "
                             "or axial moduli plus contact-stiffening increments (overrides fit.mode)")
    parser.add_argument("--objective", choices=("least_squares", "sum_rmse"),
                        help="least squares (default) or the paper's sum of RMSE per pressure")
    parser.add_argument("--degree", type=int, choices=range(0, 8), metavar="{0..7}",
                        help="polynomial degree of the moduli in strain (default 3: 16 coefficients)")
    parser.add_argument("--average-legs", action="store_true", default=None,
                        help="fit the mean of the loading and unloading legs per length bin (the paper)")
    parser.add_argument("--drucker", choices=("tangent", "sum", "none"),
                        help="Drucker stability: each tangent modulus >= 0 (default), their weighted sum, "
                             "or no constraint")
    parser.add_argument("--max-iterations", type=int, metavar="N", help="IPOPT iteration limit")
    parser.add_argument("--calibrate", action="append", metavar="NAME",
                        choices=("braid_angle", "initial_length", "bladder_thickness"),
                        help="fit this geometry with the moduli: braid_angle, initial_length or "
                             "bladder_thickness (repeatable; adds to fit.calibrate)")
    parser.add_argument("--slack", choices=("unilateral", "exclude"),
                        help="rows with force <= 0: the model predicts max(0, F) there (default), or they "
                             "are excluded (overrides fit.slack)")
    parser.add_argument("--pipe-diameter", action="append", metavar="D",
                        type=quantity_type("length"),
                        help="a pipe diameter where the report judges the radial-force prediction, e.g. "
                             "'3 in' (repeatable; adds to fit.pipe_diameters)")
    add_output_options(parser)
    add_units_option(parser)
    add_report_option(parser)


def run(args: argparse.Namespace) -> int:
    from pampipe.identification import identify
    from pampipe.identification.grip import GripResult
    from pampipe.identification.options import fit_options
    from pampipe.io.csvfile import load_experiment_data
    from pampipe.runtime.heap import retain_freed_memory
    from pampipe.views.identify_text import fit_report, grip_report

    experiment, options = validated(args.experiment)
    flags = {key: getattr(args, key) for key in FLAGS}
    if args.calibrate or args.pipe_diameter or any(value is not None for value in flags.values()):
        options = fit_options(experiment.fit, flags, calibrate=args.calibrate or (),
                              pipe_diameters=args.pipe_diameter or (), source=experiment.source,
                              where="command line", names=FLAGS)
    if args.output is not None:
        check_output(args.output, experiment.input_files, option="-o")
    if args.report is not None:
        check_output(args.report, experiment.input_files, option="--report")

    def progress(text: str) -> None:
        note(f"pampipe identify: {text}")

    retain_freed_memory()  # arrays of MBs per test, freed and made again: reuse them (pampipe.runtime.heap)
    data = load_experiment_data(experiment, progress=progress)
    with deferred() as later:  # below 10⁵ rows a step is noted only when it takes more than a second
        result = identify(data, options, progress=progress if data.points >= 100_000 else
                          lambda text: later(f"pampipe identify: {text}"))
    document = result.as_document()
    document["experiment"] = str(experiment.source)
    if args.output is not None:
        from pampipe.io.pamfile import write_pam

        write_pam(args.output, result.fitted_pam(experiment.pam),
                  comments=result.pam_comments(experiment.source))
        document["output"] = str(args.output)
    text = (grip_report if isinstance(result, GripResult) else fit_report)(result, str(experiment.source))
    emit(args, document, text)
    write_html_report(args, "identify", inputs=[experiment.source, *experiment.input_files], text=text,
                      document=document, draw=lambda: _draw(data, result), warnings=result.warnings)
    if args.output is not None:
        say(args, f"wrote {args.output}")
    if args.plots:
        from pampipe.views.plots.identify import plot_identification

        if data.tests:
            for path in plot_identification(data, result, args.plots):
                say(args, f"wrote {path}")
        if result.slip is not None:
            from pampipe.views.plots.slip_tests import plot_slip

            for path in plot_slip(data.slip, result.slip, args.plots):
                say(args, f"wrote {path}")
    return 0


def validated(path: Path):
    """(the experiment, the options of its ``fit:`` block) of an experiment file: kept from a previous run
    while every file its validation read is unchanged (:mod:`pampipe.io.validated`: no YAML parse, no
    schema library), else validated and kept."""
    from pampipe.io.validated import cached, keep

    kept = cached("experiment", path)
    if kept is not None:
        return kept
    from pampipe.identification.options import parse_fit_options
    from pampipe.io.experiment_schema import load_experiment

    experiment = load_experiment(path)
    loaded = experiment, parse_fit_options(experiment.fit, source=experiment.source)
    keep("experiment", path, loaded, experiment.validated_files)
    return loaded


def _draw(data, result) -> None:
    """Every plot of `identify --plots` (into the current figure capture)."""
    from pampipe.views.plots.identify import plot_identification
    from pampipe.views.plots.slip_tests import plot_slip

    if data.tests:
        plot_identification(data, result, None)
    if result.slip is not None:
        plot_slip(data.slip, result.slip, None)
