"""`pampipe plan`: minimum anchoring pressure per route section and segment (docs/physics.md §8)."""

from __future__ import annotations

import argparse
import math
from pathlib import Path

from pampipe.commands.common import add_output_options, emit, quantity_type, say, write_json
from pampipe.errors import InfeasibleError, InputError
from pampipe.io.files import check_output
from pampipe.report import table
from pampipe.units import to_si

NAME = "plan"
HELP = "minimum anchoring pressure per route section and segment, with reasons where none exists"


EPILOG = """\
Every segment is the only anchor in some gait step, so in each section each segment must hold the whole
load W = g(M|sin(incline)| + friction cos(incline)(M - m_segment)) + tether_drag alone, with
friction*pi*F_r >= safety_factor*W (docs/physics.md section 8). The plan is the least such pressure, never
below the pressure at which the loaded muscle touches the wall.

examples:
  pampipe plan problems/missions/vertical-climb-3in.yaml
  pampipe plan MISSION.yaml --max-payload --json -o plan.json --plots plots/
  pampipe plan problems/missions/riser-uncertain-friction.yaml --confidence 0.95

exit codes: 0 every section planned; 2 bad input; 3 some section infeasible (one reason per section)."""


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
    add_output_options(parser)


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

    mission = api.load_mission(args.mission)
    if args.output is not None:
        check_output(args.output, mission.input_files, option="-o")
    plan = api.plan(mission, payload=args.payload, confidence=args.confidence, solver=args.solver,
                    max_payload=args.max_payload)
    document = plan.to_dict()
    emit(args, document, _text(plan))
    if args.output is not None:
        write_json(args.output, document, args)
        say(args, f"wrote {args.output}")
    if args.plots:
        from pampipe.plots.plan import plot_plan

        for path in plot_plan(plan, args.plots):
            say(args, f"wrote {path}")
    if not plan.feasible:
        bad = [s.name for s in plan.sections if not s.feasible]
        raise InfeasibleError(f"{len(bad)} of {len(plan.sections)} sections cannot be planned "
                              f"({', '.join(bad)}); the reasons are listed above.")
    return 0


def _text(plan) -> str:
    head = (f"plan for {plan.mission}: supply {plan.supply_pressure / 1e3:.4g} kPa, payload "
            f"{plan.payload:.4g} kg, safety factor {plan.safety_factor:g}, load path {plan.load_path}"
            + (f", confidence {plan.confidence:.3g}" if plan.confidence is not None else ""))
    uncertain = plan.confidence is not None
    headers = ["section", "segment", "P [kPa]", *(["P_nominal [kPa]"] if uncertain else []),
               "P_anchor [kPa]", "hold W [N]", "capacity [N]", "margin", "ok"]
    rows = []
    for sec in plan.sections:
        if not sec.segments:
            rows.append((sec.name, *["-"] * (len(headers) - 2), "NO"))
            continue
        for seg in sec.segments:
            nominal = [seg.nominal_pressure / 1e3] if uncertain else []
            rows.append((sec.name, seg.name, seg.pressure / 1e3, *nominal, seg.anchoring_pressure / 1e3,
                         seg.required_hold, seg.holding_capacity,
                         seg.margin if math.isfinite(seg.margin) else "inf",
                         "yes" if seg.feasible else "NO"))
    parts = [head, table(headers, rows)]
    parts.append("margin = capacity / W (the safety factor where no slip sets the pressure); P_anchor: "
                 "the pressure at which the unloaded muscle touches the wall.")
    if plan.max_payload is not None:
        limit = plan.max_payload
        if limit.payload is None:
            parts.append(f"max payload: none; the robot cannot get through section {limit.section!r} at "
                         f"{limit.supply_pressure / 1e3:.4g} kPa.")
        else:
            parts.append(f"max payload at {limit.supply_pressure / 1e3:.4g} kPa: {limit.payload:.4g} kg, "
                         f"limited by {limit.segment} in section {limit.section!r}.")
    if plan.feasible:
        parts.append("feasible: every segment holds in every section within the supply.")
    else:
        parts.append("INFEASIBLE:\n  " + "\n  ".join(plan.reasons))
    return "\n".join(parts)
