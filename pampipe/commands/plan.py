"""`pampipe plan`: minimum anchoring pressure per route section and segment (docs/physics.md §8)."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from pampipe.commands.common import (
    add_output_options,
    add_report_option,
    emit,
    quantity_type,
    say,
    write_html_report,
    write_json,
)
from pampipe.errors import InfeasibleError, InputError
from pampipe.io.files import check_output
from pampipe.units import to_si

NAME = "plan"
HELP = "minimum anchoring pressure per route section and segment, with reasons where none exists"
#: Pressure units of --units, as the quantity parser reads them.
PRESSURE_UNITS = ("kPa", "psi", "bar")
FULL_TABLE = 60  # sections the text report lists in full; longer routes are summarised


EPILOG = """\
Every segment is the only anchor in some gait step, so in each section each segment must hold the whole
load W = g(M|sin(incline)| + friction cos(incline)(M - m_segment)) + tether_drag alone, with
friction*pi*F_r >= safety_factor*W (docs/physics.md section 8). The plan is the least such pressure, never
below the pressure at which the loaded muscle touches the wall. Where a bore has a tolerance the plan
holds over the whole range: each segment is planned in the worst bore. The contact margin is the plan
above the pressure at which the unloaded muscle first touches the largest bore; under 5 % of that
pressure it is warned about. A route may be a path through a pipe network (route: {network: ky4,
from: J-315, to: J-897, friction: 0.3}) or, without from/to, every pipe of it, with the coverage.

examples:
  pampipe plan problems/missions/vertical-climb-3in.yaml
  pampipe plan MISSION.yaml --max-payload --json -o plan.json --plots plots/ --units psi
  pampipe plan problems/missions/riser-uncertain-friction.yaml --confidence 0.95
  pampipe plan problems/missions/ky4-route.yaml --plots plots/

exit codes: 0 every section planned (a whole network: at least one pipe can be served); 2 bad input;
3 some section infeasible (one reason per section), or no pipe of a whole network can be served."""


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.epilog = EPILOG
    parser.formatter_class = argparse.RawDescriptionHelpFormatter
    parser.add_argument("mission", type=Path, metavar="MISSION.yaml",
                        help="mission file (docs/formats.md §4)")
    parser.add_argument("-o", "--output", type=Path, metavar="PLAN.json",
                        help="also write the JSON plan to this file (atomically)")
    parser.add_argument("--payload", type=quantity_type("mass"), metavar="M",
                        help="plan for this payload instead of the mission's, e.g. '5 kg'")
    parser.add_argument("--max-payload", action="store_true",
                        help="also report the largest payload the supply carries through the whole route, "
                             "and the section that limits it")
    parser.add_argument("--confidence", type=_probability, metavar="C",
                        help="plan the pressure that holds with probability C (e.g. 0.95), from the PAM "
                             "covariance ('uncertainty:' block) and the sections' friction sd")
    parser.add_argument("--solver", choices=("kkt", "ipopt"), default="kkt",
                        help="kkt: Newton on the NLP's KKT conditions (default, fast); ipopt: the same "
                             "NLP solved by IPOPT")
    parser.add_argument("--units", choices=PRESSURE_UNITS, default="kPa",
                        help="pressure unit of the tables and plots (default kPa); the JSON stays in Pa")
    parser.add_argument("--all-sections", action="store_true",
                        help=f"list every section even on routes of more than {FULL_TABLE} sections")
    add_output_options(parser)
    add_report_option(parser)


def _probability(text: str) -> float:
    """argparse type: a probability in [0.5, 1), as a number or a percentage ('0.95', '95 %')."""
    try:
        value = to_si(text, "dimensionless")
    except InputError as exc:
        raise argparse.ArgumentTypeError(f"{exc} Give a probability, e.g. 0.95 or '95 %'.") from None
    if not 0.5 <= value < 1:
        raise argparse.ArgumentTypeError(f"{text!r} must be a probability in [0.5, 1), e.g. 0.95")
    return value


def run(args: argparse.Namespace) -> int:
    from pampipe import api
    from pampipe.commands.plan_text import SHOWN, plan_text

    mission = api.load_mission(args.mission)
    if args.output is not None:
        check_output(args.output, mission.input_files, option="-o")
    if args.report is not None:
        check_output(args.report, mission.input_files, option="--report")
    plan = api.plan(mission, payload=args.payload, confidence=args.confidence, solver=args.solver,
                    max_payload=args.max_payload)
    document = plan.to_dict()
    for warning in plan.warnings:
        print(f"warning: {warning}", file=sys.stderr, flush=True)
    text = plan_text(plan, unit=args.units, all_sections=args.all_sections)
    emit(args, document, text)
    if args.output is not None:
        write_json(args.output, document, args)
        say(args, f"wrote {args.output}")
    from pampipe.plots.plan import plot_plan

    reasons = [f"{s['name']}: {s['reason']}" for s in document["sections"] if s.get("reason")]
    write_html_report(args, "plan", inputs=[mission.source, *mission.input_files], text=text,
                      document=document, draw=lambda: plot_plan(plan, None, unit=args.units),
                      warnings=plan.warnings,
                      reasons=reasons + [str(r) for r in document.get("reasons", [])])
    if args.plots:

        for path in plot_plan(plan, args.plots, unit=args.units):
            say(args, f"wrote {path}")
    if plan.coverage is not None and plan.arrays.route.origin.whole:
        if plan.coverage.pipes_feasible == 0:
            name = plan.arrays.route.origin.network.name
            raise InfeasibleError(f"no pipe of network {name} can be served; the coverage above says why.")
        return 0
    if not plan.feasible:
        bad = plan.arrays.route.name[sorted(plan.arrays.reasons)].tolist()
        shown = ", ".join(bad[:SHOWN]) + (f" and {len(bad) - SHOWN} more" if len(bad) > SHOWN else "")
        raise InfeasibleError(f"{len(bad)} of {len(plan.arrays.route)} sections cannot be planned "
                              f"({shown}); the reasons are listed above.")
    return 0
