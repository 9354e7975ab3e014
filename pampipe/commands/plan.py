"""`pampipe plan`: minimum anchoring pressure per route section and segment (docs/physics.md §8)."""

from __future__ import annotations

import argparse
from functools import partial
from itertools import islice
from pathlib import Path

from pampipe.commands.common import (
    add_confidence_options,
    add_output_options,
    add_parallel_options,
    add_report_option,
    add_units_option,
    emit,
    emit_streamed,
    next_test_command,
    quantity_type,
    say,
    warn,
    write_html_report,
    write_json,
)
from pampipe.errors import InfeasibleError, InputError
from pampipe.io.files import Streamed, check_output
from pampipe.views.tables import FULL_TABLE

NAME = "plan"
HELP = "minimum anchoring pressure per route section and segment, with reasons where none exists"


EPILOG = """\
Every segment is the only anchor in some gait step, so in each section each segment must hold the whole
load W = g(M|sin(incline)| + friction cos(incline)(M - m_segment)) + tether_drag alone, with
friction*pi*F_r >= safety_factor*W (docs/physics.md section 8). The plan is the least such pressure, never
below the pressure at which the loaded muscle touches the wall. Where a bore has a tolerance the plan
holds over the whole range: each segment is planned in the worst bore. The contact margin is the plan
above the pressure at which the unloaded muscle first touches the largest bore; it is warned about
where a bore 1 mm wider or a braid angle 1 deg off would cost more than that margin.
With --confidence C the plan samples every stated uncertainty (the PAM's fit covariance, model error
and geometry sds, the bores', friction and kappa sds) and plans the least pressure that holds in a share
C of the draws, with the holding and contact probabilities, the pressures at 0.9, 0.99 and 0.999 and
the source that dominates, for the muscle each segment's `unit:` says (tested, or another of its lot). A
direction the muscle's test data leave undetermined is covered over its open width; where that moves a
segment's plan by more than a tenth of its margin to the supply, the section is infeasible (exit 3),
naming the test that would fix it.
A route may be a path through a pipe network (route: {network: ky4,
from: J-315, to: J-897, friction: 0.3}) or, without from/to, every pipe of it, with the coverage.

examples:
  pampipe plan problems/missions/vertical-climb-3in.yaml
  pampipe plan MISSION.yaml --max-payload --json -o plan.json --plots plots/ --units psi
  pampipe plan problems/missions/riser-uncertain-friction.yaml --confidence 0.95
  pampipe plan problems/missions/riser-uncertain-friction.yaml --confidence 0.95 --max-payload
  pampipe plan MISSION.yaml --confidence 0.95 --samples 10000 --workers 2
  pampipe plan problems/missions/ky4-route.yaml --plots plots/

A section may end with a bend (bend: {angle: 90 deg, radius: 1.5 D}); network routes take theirs from the
pipes, with the mission's elbow_radius (default 1.5 D). Each segment must pass each bend deflated, as a rigid
cylinder L0 + fitting_length long and D0 wide (bend_model: flexible lets it bend); with robot: {steering:
{pam, count: 3, radius}} the least-pressure triad of extensile PAMs that bends the module to 1/R is planned
per bend (docs/physics.md section 13).
  pampipe plan problems/missions/elbows-3in.yaml

exit codes: 0 every section planned and every bend passed (a whole network: at least one pipe can be served);
2 bad input; 3 some section infeasible or some bend impassable (one reason each), or no pipe of a whole
network can be served."""


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.epilog = EPILOG
    parser.formatter_class = argparse.RawDescriptionHelpFormatter
    parser.add_argument("mission", type=Path, metavar="MISSION.yaml",
                        help="mission file (docs/formats.md §4)")
    parser.add_argument("-o", "--output", type=Path, metavar="PLAN.json",
                        help="also write the JSON plan to this file (atomically); with --json the plan goes "
                             "to the file only and stdout gets the text report (nothing with --quiet)")
    parser.set_defaults(json_output=True)
    parser.add_argument("--payload", type=quantity_type("mass"), metavar="M",
                        help="plan for this payload instead of the mission's, e.g. '5 kg'")
    parser.add_argument("--max-payload", action="store_true",
                        help="also report the largest payload the supply carries through the whole route, "
                             "and the section that limits it")
    add_confidence_options(
        parser, confidence="plan the pressure that holds with probability C (e.g. 0.95), sampling every "
        "stated uncertainty: the PAM's 'uncertainty:' block (moduli, calibrated geometry, model error), its "
        "geometry sds, the bores' and friction sds and kappa's sd; with --max-payload, the payload held with "
        "probability C", samples="draws of the uncertain inputs for --confidence (default 4000; the holding "
        "probability's Monte Carlo error is about sqrt(C(1-C)/N), 0.34 %% at C = 0.95)",
        seed="seed of the draws (default 22): the same seed gives the same plan")
    add_parallel_options(parser, "the --confidence sampling (in chunks of alike sections; the same plan)")
    parser.add_argument("--prior-from", type=Path, default=None, metavar="PAM.yaml",
                        help="with --confidence: a PAM file whose moduli and uncertainty serve as the prior "
                             "along the directions the muscle's own fit leaves undetermined (otherwise "
                             "they are covered over their open width, or exit 3 where that costs more than "
                             "a tenth of the margin); the report says the margin rests on a prior")
    parser.add_argument("--solver", choices=("kkt", "ipopt"), default="kkt",
                        help="kkt: Newton on the NLP's KKT conditions (default, fast); ipopt: the same "
                             "NLP solved by IPOPT")
    parser.add_argument("--all-sections", action="store_true",
                        help=f"list every section even on routes of more than {FULL_TABLE} sections")
    add_output_options(parser)
    add_units_option(parser)
    add_report_option(parser)


#: Above this many sections the JSON document is written on one line (the indented encoder is 3× slower).
COMPACT_SECTIONS = 10_000


def run(args: argparse.Namespace) -> int:
    from pampipe import api
    from pampipe.views.plan_text import infeasible_reason, plan_text

    mission = api.load_mission(args.mission)
    if args.output is not None:
        check_output(args.output, mission.input_files, option="-o")
    if args.confidence is None and (args.prior_from or args.samples or args.seed is not None
                                    or args.workers is not None or args.scheduler is not None):
        raise InputError("--samples, --seed, --prior-from, --workers and --scheduler only apply with "
                         "--confidence C.")
    if args.report is not None:
        check_output(args.report, mission.input_files, option="--report")
    plan = api.plan(mission, payload=args.payload, confidence=args.confidence, solver=args.solver,
                    max_payload=args.max_payload, samples=args.samples, seed=args.seed,
                    prior=args.prior_from, workers=args.workers, scheduler=args.scheduler)
    # the JSON document only when asked for: at 10⁵ sections building it costs more than the plan;
    # above COMPACT_SECTIONS it is streamed (one line, written section by section) unless --report needs it
    large = len(plan.arrays.route) > COMPACT_SECTIONS
    wanted = args.json or args.output is not None or args.report is not None
    document = plan.to_dict() if wanted and not (large and args.report is None) else None
    from pampipe.units.display import current

    unit = current().pressure
    warn(plan.warnings)
    text = plan_text(plan, unit=unit, all_sections=args.all_sections)
    indent = None if large else 2
    if document is None and wanted:
        from pampipe.io.json_columns import streamed_records

        sections = partial(streamed_records, len(plan.arrays.route), plan.section_columns,
                           lambda start, stop: islice(plan.section_documents(), start, stop))
        reducers = partial(streamed_records, len(plan.reducers), plan.reducer_columns,
                           lambda start, stop: (r.as_document() for r in plan.reducers[start:stop]))
        emit_streamed(args, lambda: plan.as_document(  # the big lists encoded column-wise, a chunk at a time
            sections=Streamed(sections()), reducers=Streamed(reducers())), text)
    else:
        emit(args, document, text, indent=indent)
        if args.output is not None:
            write_json(args.output, document, args, indent=indent)
    if args.output is not None:
        say(args, f"wrote {args.output}")
    from pampipe.views.plots.plan import plot_plan

    if args.report is not None:
        reasons = [f"{s['name']}: {s['reason']}" for s in document["sections"] if s.get("reason")]
        write_html_report(args, "plan", inputs=[mission.source, *mission.input_files], text=text,
                          document=document, draw=lambda: plot_plan(plan, None, unit=unit),
                          warnings=plan.warnings,
                          reasons=reasons + [str(r) for r in document.get("reasons", [])])
    if args.plots:
        for path in plot_plan(plan, args.plots, unit=unit):
            say(args, f"wrote {path}")
    if plan.coverage is not None and plan.arrays.route.origin.whole:
        if plan.coverage.pipes_feasible == 0:
            name = plan.arrays.route.origin.network.name
            raise InfeasibleError(f"no pipe of network {name} can be served; the coverage above says why.")
        return 0
    if not plan.feasible:
        raise InfeasibleError(infeasible_reason(plan) + _next_test(plan, mission, args.confidence))
    return 0


def _next_test(plan, mission, confidence) -> str:
    """Where an undetermined direction stops the plan (exit 3): the `next-test` command line that ranks the
    tests a lab can run for it (MENU.yaml: the lab's tests and costs, docs/commands.md §14)."""
    stopped = [] if plan.uncertainty is None else sorted(plan.uncertainty.undetermined.values(),
                                                         key=lambda v: v[0])
    if not stopped:
        return ""
    segment = mission.segments[stopped[0][0]]
    pam = segment.pam_file if segment.pam_file is not None else "PAM.yaml"
    return (" To rank the tests your lab can run by how much each lowers this plan: "
            + next_test_command(pam, mission.source, "MENU.yaml", confidence))

