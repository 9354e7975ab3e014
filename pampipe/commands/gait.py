"""`pampipe gait`: the peristaltic schedule in one pipe section, and the time-optimal gait."""

from __future__ import annotations

import argparse
from pathlib import Path

from pampipe import api
from pampipe.commands.common import add_output_options, add_units_option, emit, say
from pampipe.runtime.progress import note
from pampipe.views.gait_text import result_text

NAME = "gait"
HELP = ("the 7-step peristaltic schedule of a mission section: steps, pressures, positions, valve "
        "timing, speed; --optimal adds the time-optimal gait")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("mission", type=Path, metavar="MISSION.yaml",
                        help="mission file (docs/formats.md §4); its optional gait: block sets the valves")
    parser.add_argument("--section", metavar="NAME", help="route section to walk (default: the first)")
    parser.add_argument("--optimal", action="store_true",
                        help="also solve the minimum-time gait (CasADi/IPOPT) and compare the speeds")
    add_output_options(parser)
    add_units_option(parser)


def run(args: argparse.Namespace) -> int:
    report = api.gait(args.mission, section=args.section, optimal=args.optimal,
                      progress=note)
    emit(args, report.to_dict(), result_text(report))
    if args.plots:
        from pampipe.views.plots.gait import plot_gait

        for result in report.results:
            for path in plot_gait(result, args.plots):
                say(args, f"wrote {path}")
    return 0
