"""`pampipe rehearse`: the whole route in time (docs/commands.md §13, docs/physics.md §16)."""

from __future__ import annotations

import argparse
from pathlib import Path

from pampipe.commands.common import (
    add_confidence_options,
    add_output_options,
    add_report_option,
    add_units_option,
    emit,
    say,
    warn,
    write_html_report,
)
from pampipe.errors import InfeasibleError, InputError
from pampipe.io.files import check_output

NAME = "rehearse"
HELP = ("the whole route in time: per section the gait's cycles, time and free air, the tether's tension, "
        "the supply hose and compressor, the reach; --confidence the chance of completing it")

EPILOG = """\
Each section is walked with the sequential gait of `pampipe gait` (--optimal: scaled by the time-optimal
gait, solved once per bore) at the plan's pressures: cycles = length/stride, time = cycles x cycle time, plus
the steering steps at bends; the free air is counted in normal litres (ISO 8778). A tether (tether: in the
mission) adds its tension to every anchor's load and may stop the robot (the reach); its supply hose
(tether.hose) slows every fill the further the robot goes, and a compressor (tether.compressor) that delivers
less air than a cycle needs makes the fills wait. With --confidence C the robot walks at the pressures of
`plan --confidence C`, and the same draws give the chance of completing the route, where it first slips and
the time and air at quantile C (docs/physics.md section 16).

examples:
  pampipe rehearse problems/missions/tethered-climb.yaml
  pampipe rehearse problems/missions/tethered-climb.yaml --confidence 0.95 --samples 2000 --json
  pampipe rehearse MISSION.yaml --optimal --plots plots/ --report rehearsal.html

exit codes: 0 the robot walks the whole route; 2 bad input; 3 it stops before the end (the reach says where
and why; the report is printed first)."""


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.epilog = EPILOG
    parser.formatter_class = argparse.RawDescriptionHelpFormatter
    parser.add_argument("mission", type=Path, metavar="MISSION.yaml",
                        help="mission file (docs/formats.md §4), with an optional tether: block")
    parser.add_argument("--optimal", action="store_true",
                        help="walk with the time-optimal gait (CasADi/IPOPT, once per bore) instead of the "
                             "sequential one")
    add_confidence_options(parser, confidence="walk at the pressures of `plan --confidence C` and give the "
                           "probability of completing the route, where it first slips, and the time and air "
                           "at quantile C", samples="draws for --confidence (default 4000)",
                           seed="seed of the draws (default 22)")
    parser.add_argument("--all-sections", action="store_true",
                        help="list every section even on routes of more than 60 sections")
    add_output_options(parser)
    add_units_option(parser)
    add_report_option(parser)


def run(args: argparse.Namespace) -> int:
    from pampipe import api
    from pampipe.runtime.progress import note
    from pampipe.units.display import current
    from pampipe.views.rehearse_text import rehearse_text

    mission = api.load_mission(args.mission)
    if args.confidence is None and (args.samples is not None or args.seed is not None):
        raise InputError("--samples and --seed only apply with --confidence C.")
    if args.report is not None:
        check_output(args.report, mission.input_files, option="--report")
    result = api.rehearse(mission, optimal=args.optimal, confidence=args.confidence, samples=args.samples,
                          seed=args.seed, progress=note)
    warn(result.plan.warnings)
    text = rehearse_text(result, all_sections=args.all_sections)
    document = result.to_dict()
    emit(args, document, text)
    unit = current().pressure
    if args.plots:
        from pampipe.views.plots.rehearse import plot_rehearsal

        for path in plot_rehearsal(result, args.plots, unit=unit):
            say(args, f"wrote {path}")
    if args.report is not None:
        from pampipe.views.plots.rehearse import plot_rehearsal

        write_html_report(args, "rehearse", inputs=[mission.source, *mission.input_files], text=text,
                          document=document, draw=lambda: plot_rehearsal(result, None, unit=unit),
                          warnings=result.plan.warnings, reasons=result.plan.reasons)
    if not result.completed:
        reach = result.tether.reach.sentence(tether=mission.tether is not None)
        raise InfeasibleError(f"the robot stops {result.walk.walked.sum():.6g} m from the entry, before the "
                              f"route's end; {reach}.")
    return 0
