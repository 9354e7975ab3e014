"""`pampipe next-test`: the test of a lab's menu that lowers the mission's plan most per unit cost
(docs/commands.md §14)."""

from __future__ import annotations

import argparse
from pathlib import Path

from pampipe.commands.common import (
    add_confidence_options,
    add_output_options,
    add_parallel_options,
    add_report_option,
    add_units_option,
    emit,
    integer_type,
    say,
    write_html_report,
)
from pampipe.io.files import check_not_input, check_output

NAME = "next-test"
HELP = ("rank the tests a lab can run (a MENU file with their costs) by how much each lowers the mission's "
        "planned pressure at confidence C, per unit cost; the D-optimal pick beside it")

EPILOG = """\
For each test of the menu, its Fisher information about the fitted muscle (exact CasADi Jacobians of the
test's predictions, the protocol's force noise and the PAM's model error) is added to what the PAM's
uncertainty: block knows (covariance, and its undetermined directions over their open width); the mission is
planned again at C (plan's own sampled quantile, the same seeded draws for every test) and the tests are
ranked by the predicted drop of the largest planned pressure (--objective air: the air-weighted mean) per
unit cost. Each row says which undetermined directions the test closes and whether plan's exit 3 would go
away. The D-optimal pick (largest log det of the information gain per unit cost) is shown beside it.
The top --check N tests (default 3) are then checked: truths drawn from the fit, the test's data synthesised,
refitted with identify and planned again (the mean over --truths K, on --workers/--scheduler).

examples:
  pampipe next-test problems/pams/paper-radial-pam-uncertain.yaml \\
      problems/missions/riser-uncertain-friction.yaml --menu problems/menus/radial-menu.yaml
  pampipe next-test PAM.yaml MISSION.yaml --menu MENU.yaml --confidence 0.99 --pairs --json
  pampipe next-test PAM.yaml MISSION.yaml --menu MENU.yaml --check 3 --workers 2 -o next/

exit codes: 0 ranked; 2 bad input."""


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.epilog = EPILOG
    parser.formatter_class = argparse.RawDescriptionHelpFormatter
    parser.add_argument("pam", type=Path, metavar="PAM.yaml",
                        help="the PAM file identify wrote (with its uncertainty: block)")
    parser.add_argument("mission", type=Path, metavar="MISSION.yaml",
                        help="a mission whose segments carry that PAM file")
    parser.add_argument("--menu", type=Path, required=True, metavar="MENU.yaml",
                        help="the tests the lab can run, each with its cost (docs/commands.md §14.1)")
    add_confidence_options(parser, confidence="plan at confidence C as `plan --confidence C` (default 0.95)",
                           default_confidence=0.95, samples="draws of each plan (default 10000)",
                           seed="seed of the draws (default 22)")
    parser.add_argument("--objective", choices=("pressure", "air"), default="pressure",
                        help="what a test should lower: the largest planned pressure (default) or the "
                             "air-weighted mean")
    parser.add_argument("--pairs", action="store_true", help="rank every pair of tests too")
    parser.add_argument("-o", "--output", type=Path, metavar="DIR",
                        help="write the best test as an experiment skeleton into DIR: the PAM, the "
                             "experiment file (the old fit as prior) and a CSV of the rows to measure, for "
                             "identify")
    parser.add_argument("--check", type=integer_type("--check", ge=0), default=3, metavar="N",
                        help="the preposterior check of the top N tests: truths drawn from the fit, the "
                             "test's data synthesised, refitted and planned again (default 3; 0: none)")
    parser.add_argument("--truths", type=integer_type("--truths", ge=2), default=None, metavar="K",
                        help="truths per checked test (default 8)")
    add_parallel_options(parser, "the preposterior check")
    add_output_options(parser)
    add_units_option(parser)
    add_report_option(parser)


def run(args: argparse.Namespace) -> int:
    from pampipe import api
    from pampipe.views.nexttest_text import result_text

    inputs = [args.pam, args.mission, args.menu]
    if args.report is not None:
        check_output(args.report, inputs, option="--report")
    if args.output is not None:
        for name in ("pam.yaml", "next-test.yaml"):
            check_not_input(args.output / name, inputs, option="-o")
    result = api.next_test(args.pam, args.mission, menu=args.menu, confidence=args.confidence,
                           objective=args.objective, pairs=args.pairs, samples=args.samples, seed=args.seed,
                           check=args.check, truths=args.truths, workers=args.workers,
                           scheduler=args.scheduler)
    text = result_text(result)
    document = result.to_dict()
    emit(args, document, text)
    if args.output is not None:
        from pampipe.io.skeleton import write_skeleton
        from pampipe.model.muscle import Muscle

        pam = api.load_pam(args.pam)
        for test in result.best.tests:
            folder = args.output if len(result.best.tests) == 1 else args.output / f"test-{test.entry}"
            note = f"The test `pampipe next-test` ranked first: {test.describe()}."
            for path in write_skeleton(folder, pam, test, Muscle.from_pam(pam), comments=[note]):
                say(args, f"wrote {path}")
    if args.plots:
        from pampipe.views.plots.nexttest import plot_next_test

        for path in plot_next_test(result, args.plots):
            say(args, f"wrote {path}")
    if args.report is not None:
        from pampipe.views.plots.nexttest import plot_next_test

        write_html_report(args, "next-test", inputs=[args.pam, args.mission, args.menu], text=text,
                          document=document, draw=lambda: plot_next_test(result, None))
    return 0
