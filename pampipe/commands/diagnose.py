"""`pampipe diagnose`: where the model and the data disagree, the missing effect, the gap before and after."""

from __future__ import annotations

import argparse
from pathlib import Path

from pampipe.commands.common import (
    add_output_options,
    add_report_option,
    add_units_option,
    emit,
    integer_type,
    say,
    write_html_report,
)
from pampipe.io.files import check_output

NAME = "diagnose"
HELP = "name the effect missing from the model of an experiment, refit with it, show the gap shrink"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    from pampipe.diagnosis.candidates import CANDIDATES, DEFAULT, FOLDS, GEOMETRY
    from pampipe.model.effects import LIBRARY

    parser.add_argument("experiment", type=Path, metavar="EXPERIMENT.yaml",
                        help="experiment file (docs/formats.md §3): a PAM and its axial and radial tests")
    parser.add_argument("-o", "--output", type=Path, metavar="PAM_OUT.yaml",
                        help="write the augmented PAM file (refitted moduli: and the selected effects: "
                             "block), "
                             "which `simulate` and `plan` use")
    parser.add_argument("--effect", action="append", choices=list(CANDIDATES), metavar="NAME",
                        help="test only this effect or mis-stated geometry entry (repeatable; default: "
                             f"all of {', '.join(DEFAULT)})")
    parser.add_argument("--folds", type=integer_type("--folds", ge=2), default=FOLDS, metavar="K",
                        help=f"cross-validation folds across pressure levels (default {FOLDS})")
    add_output_options(parser)
    add_units_option(parser)
    add_report_option(parser)
    parser.epilog = ("Effects (docs/physics.md §9): "
                     + "; ".join(f"{e.name}: {e.summary}" for e in LIBRARY.values())
                     + ". Geometry candidates: "
                     + "; ".join(f"{g.name}: {g.summary}" for g in GEOMETRY.values())
                     + ". Exit codes: 0 success (including 'none'), 2 bad input, 3 solver failure.")


def run(args: argparse.Namespace) -> int:
    from pampipe.diagnosis.workflow import diagnose
    from pampipe.io.csvfile import load_experiment_data
    from pampipe.io.experiment_schema import load_experiment
    from pampipe.io.pamfile import write_pam
    from pampipe.views.diagnose_text import result_text

    experiment = load_experiment(args.experiment)
    if args.output is not None:
        check_output(args.output, experiment.input_files, option="-o")
    if args.report is not None:
        check_output(args.report, experiment.input_files, option="--report")
    data = load_experiment_data(experiment, progress=lambda text: say_err(args, text))
    result = diagnose(data, effects=args.effect, folds=args.folds, progress=lambda text: say_err(args, text))
    text = result_text(result)
    document = result.as_document()
    emit(args, document, text)
    from pampipe.views.plots.diagnose import plot_diagnosis

    write_html_report(args, "diagnose", inputs=[experiment.source, *experiment.input_files], text=text,
                      document=document, draw=lambda: plot_diagnosis(result, None),
                      reasons=[document["reason"]] if document.get("reason") else [])
    if args.output is not None:
        ties = [f"Tie: {group} (the data cannot tell them apart; none is written as the muscle's physics, "
                f"see effects.indistinguishable): {test}." for group, test in result.ties.items()]
        write_pam(args.output, result.augmented_pam(),
                  comments=[f"Written by `pampipe diagnose` from {experiment.source}.",
                            f"Verdict: {result.verdict.verdict}. Moduli refitted in shared mode together "
                            f"with: {' + '.join(result.written.effects) or 'no effect'}.", *ties])
        say(args, f"wrote {args.output}")
    if args.plots:
        for path in plot_diagnosis(result, args.plots):
            say(args, f"wrote {path}")
    return 0


def say_err(args, text: str) -> None:
    """A progress line on stderr (:mod:`pampipe.runtime.progress`: none under --json or --quiet)."""
    from pampipe.runtime import progress

    progress.note(f"diagnose: {text}")
