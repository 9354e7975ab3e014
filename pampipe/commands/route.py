"""`pampipe route`: the shortest path through a water network, written as a mission file to edit by hand."""

from __future__ import annotations

import argparse
from pathlib import Path

from pampipe.commands.common import add_output_options, add_units_option, emit, quantity_type

NAME = "route"
HELP = "the shortest path between two nodes of an EPANET network, as a mission file (one section per pipe)"

EPILOG = """\
NETWORK is a network shipped with wntr (Net1, Net2, Net3, Net6, ky4, ky10) or an EPANET .inp file.
The route is the shortest path by length through the network's pipes (pumps and valves are never
passed). Each pipe becomes one section, named by its id, with incline = asin(dz/length) along travel
from the node elevations (a reservoir's head); a pipe shorter than its rise is taken as vertical and
listed. Each turning joint is written as the pipe's bend: {angle} (plan checks it). Every key of the
template but route (robot, supply_pressure, safety_factor, load_path, ...) is copied, its PAM paths
rewritten for the new file.

examples:
  pampipe route ky4 --from J-315 --to J-897 -o ky4-route.yaml
  pampipe route my-town.inp --from J-1 --to T-2 --friction 0.25 --template MISSION.yaml -o route.yaml

exit codes: 0 done; 2 bad input (unknown network or node, bad template); 3 no path between the nodes."""


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.epilog = EPILOG
    parser.formatter_class = argparse.RawDescriptionHelpFormatter
    parser.add_argument("network", metavar="NETWORK", help="wntr network name (e.g. ky4) or EPANET .inp file")
    parser.add_argument("--from", dest="from_node", required=True, metavar="NODE", help="start node id")
    parser.add_argument("--to", dest="to_node", required=True, metavar="NODE", help="end node id")
    parser.add_argument("-o", "--output", type=Path, metavar="MISSION.yaml",
                        help="write the route as a mission file (atomically)")
    parser.add_argument("--friction", type=quantity_type("dimensionless"), metavar="MU",
                        help="braid-wall friction coefficient of every section (default: the template's, "
                             "when all its sections share one known value)")
    parser.add_argument("--template", type=Path, metavar="MISSION.yaml",
                        help="mission whose robot, supply, safety factor and load path are copied "
                             "(default: the bundled vertical-climb-3in.yaml)")
    parser.add_argument("--min-bore", type=quantity_type("length"), metavar="D",
                        help="use only pipes with at least this inner diameter, e.g. '3 in'")
    parser.add_argument("--max-bore", type=quantity_type("length"), metavar="D",
                        help="use only pipes with at most this inner diameter, e.g. '4 in'")
    parser.add_argument("--force", action="store_true", help="overwrite an existing -o file")
    add_output_options(parser, plots=False)
    add_units_option(parser)


def run(args: argparse.Namespace) -> int:
    from pampipe import api

    result = api.route(args.network, from_node=args.from_node, to_node=args.to_node, friction=args.friction,
                       template=args.template, min_bore=args.min_bore, max_bore=args.max_bore,
                       output=args.output, force=args.force)
    emit(args, result.document, result.render())
    return 0
