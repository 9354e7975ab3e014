"""`pampipe route`: the shortest path through a water network, written as a mission file to edit by hand."""

from __future__ import annotations

import argparse
import math
import os
from collections.abc import Callable
from pathlib import Path

from pampipe.commands.common import add_output_options, add_units_option, emit, quantity_type
from pampipe.errors import InputError
from pampipe.io import bundled, yamlwrite
from pampipe.io.files import check_not_input
from pampipe.io.mission_schema import load_mission
from pampipe.io.yamlfile import load_mapping
from pampipe.views.tables import table

NAME = "route"
HELP = "the shortest path between two nodes of an EPANET network, as a mission file (one section per pipe)"
DEFAULT_TEMPLATE = "vertical-climb-3in"  # a bundled mission (pampipe.io.bundled), found in any install

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
    document, render = compute(args)
    emit(args, document, render())
    return 0


def compute(args: argparse.Namespace) -> tuple[dict, Callable[[], str]]:
    """(the JSON document, what writes the text report in the display units) of the command; files are
    written here."""
    from pampipe.io.routes import turn_angles
    from pampipe.specs.network import load_network, route_sections

    template = args.template or bundled.find(DEFAULT_TEMPLATE)
    mission = load_mission(template)
    friction = _friction(args.friction, mission)
    net = load_network(args.network)
    if args.output is not None:
        check_not_input(args.output, [*mission.input_files, net.source], option="-o")
        if args.output.exists() and not args.force:
            raise InputError(f"-o {args.output}: the file exists (it may hold your edits); choose another "
                             "name or add --force to overwrite it.")
    low, high = args.min_bore or 0.0, math.inf if args.max_bore is None else args.max_bore
    if low > high:
        raise InputError(f"--min-bore {low * 1e3:g} mm is above --max-bore {high * 1e3:g} mm; no pipe fits.")
    sections = route_sections(net, args.from_node, args.to_node, friction=friction,
                              passable=lambda diameter: low <= diameter <= high)
    rise = float(net.elevation[net.node_index(args.to_node)] - net.elevation[net.node_index(args.from_node)])
    if args.output is not None:
        header = (f"Route through network {net.name} ({net.source}) from {args.from_node} to {args.to_node}: "
                  f"{len(sections)} pipes, {sections.length.sum():.1f} m, written by pampipe route.\n"
                  f"Every key but route is copied from {template}.\n"
                  f"Edit it by hand, then: pampipe plan {args.output}")
        route = sections.mission_route()
        for entry, turn in zip(route, turn_angles(sections).tolist(), strict=True):
            if turn > 0:  # an elbow of the mission's elbow_radius (docs/formats.md §4)
                entry["bend"] = {"angle": f"{math.degrees(turn):.4g} deg"}
        yamlwrite.write(args.output, _mission(load_mapping(template, what="mission file"), template,
                                              args.output, route), comments=[header])
    document = {"network": net.name, "network_file": str(net.source), "from": args.from_node,
                "to": args.to_node, "pipes": len(sections), "length_m": float(sections.length.sum()),
                "rise_m": rise, "friction": friction, "template": str(template),
                "output": None if args.output is None else str(args.output),
                "incline_clipped": sections.name[sections.clipped].tolist(),
                "sections": sections.as_document()}
    return document, lambda: _text(net, args, sections, template)  # tables in the units shown then


def _friction(given: float | None, mission) -> float:
    """--friction, else the template's one known friction."""
    if given is not None:
        if not 0 <= given <= 10:
            raise InputError(f"--friction: {given:g} is out of range; give a coefficient between 0 and 10.")
        return given
    values = {(s.friction, s.friction_sd) for s in mission.route}
    if len(values) != 1 or next(iter(values))[1] != 0:
        raise InputError(f"{mission.source}: its route sections have different or uncertain frictions; "
                         "give --friction, e.g. --friction 0.3.")
    return next(iter(values))[0]


def _mission(template: dict, template_path: Path, output: Path, route: list[dict]) -> dict:
    """The template's keys but route, PAM paths made relative to ``output``, then the new route."""
    document = {key: value for key, value in template.items() if key != "route"}
    robot = dict(document["robot"])
    robot["segments"] = [_moved(segment, template_path, output) for segment in robot["segments"]]
    document["robot"] = robot
    document["route"] = route
    return document


def _moved(segment: dict, template_path: Path, output: Path) -> dict:
    """A robot segment whose ``pam:`` file path still points at the same file from ``output``'s folder."""
    pam = segment.get("pam")
    if not isinstance(pam, str) or Path(pam).is_absolute():
        return segment
    target = (template_path.parent / pam).resolve()
    folder = output.resolve().parent
    if os.path.commonpath([target, folder]) == target.anchor:  # nothing in common but the root
        return {**segment, "pam": str(target)}
    return {**segment, "pam": os.path.relpath(target, folder)}


def _text(net, args: argparse.Namespace, sections, template: Path) -> str:
    rows = [(name, a, b, length, d * 1e3, d / 0.0254, math.degrees(incline) if not clip else "±90 (clip)",
             "-" if math.isnan(bend) else math.degrees(bend))
            for name, a, b, length, d, incline, bend, clip in zip(
                sections.name, sections.from_node, sections.to_node, sections.length, sections.diameter,
                sections.incline, sections.bend, sections.clipped, strict=True)]
    parts = [f"route through {net.name} ({net.source}) from {args.from_node} to {args.to_node}: "
             f"{len(sections)} pipes, {sections.length.sum():.6g} m, friction {sections.friction[0]:g}",
             table(["pipe", "from", "to", "length [m]", "bore [mm]", "bore [in]", "incline [deg]",
                    "bend [deg]"], rows),
             "incline: along travel, from the node elevations; bend: plan-view deflection at the joint "
             "with the previous pipe. The file gives each pipe whose 3-D direction turns by 0.5 deg or more "
             "into the next a bend: {angle}, of the mission's elbow_radius, which plan checks."]
    if sections.clipped.any():
        parts.append(f"note: {', '.join(sections.name[sections.clipped])}: the model's length is shorter "
                     "than the elevation difference; taken as vertical (±90 deg). Check these pipes.")
    if args.output is not None:
        parts.append(f"wrote {args.output} (every key but route from {template}); "
                     f"edit it by hand, then: pampipe plan {args.output}")
    return "\n".join(parts)
