"""`pampipe route`: the shortest path between two nodes of a network, written as a mission file to edit by
hand (docs/commands.md §7).

Each pipe of the path (:func:`pampipe.specs.network.route_sections`) becomes one section of the route, named
by its id (:meth:`pampipe.specs.network.Sections.mission_route`); each pipe whose 3-D direction turns into the
next (:func:`pampipe.io.routes.turn_angles`) gets a ``bend: {angle, direction}`` (which way it turns:
:func:`pampipe.io.routes.turn_directions_after`) of the mission's elbow radius. Every key of the template
mission but ``route`` is copied, its PAM paths (the segments' and the steering module's) rewritten to name
the same files from the new file's folder.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from pampipe.errors import InputError
from pampipe.io import bundled, yamlwrite
from pampipe.io.epanet import load_network
from pampipe.io.field_rules import relative
from pampipe.io.files import check_not_input
from pampipe.io.routes import turn_angles, turn_directions_after
from pampipe.io.yamlfile import load_mapping
from pampipe.specs.network import Network, Sections, route_sections
from pampipe.specs.turns import turn_name
from pampipe.units.display import counted

#: The bundled mission (:mod:`pampipe.io.bundled`, found in any install) whose keys a route copies by default.
DEFAULT_TEMPLATE = "vertical-climb-3in"


@dataclass(frozen=True)
class NetworkMission:
    """A path through a network as mission sections: what `pampipe route` found and wrote."""

    network: Network
    from_node: str
    to_node: str
    sections: Sections
    friction: float
    template: Path  # the mission whose keys but route were copied
    output: Path | None  # the mission file written (None: nothing written)

    @property
    def rise(self) -> float:
        """Elevation of the end node above the start node [m]."""
        net = self.network
        top, bottom = net.node_index(self.to_node), net.node_index(self.from_node)
        return float(net.elevation[top] - net.elevation[bottom])

    @property
    def elbows(self) -> list[tuple[int, float, float]]:
        """(pipe index, angle θ [rad], direction φ_b [rad]) of each elbow the file gives: where the path
        turns by 0.5° or more after a pipe (:func:`turn_angles`, :func:`turn_directions_after`)."""
        angles, directions = turn_angles(self.sections), turn_directions_after(self.sections)
        return [(i, float(angles[i]), float(directions[i])) for i in np.flatnonzero(angles > 0).tolist()]

    def as_document(self) -> dict:
        """The `route --json` document (docs/commands.md §7)."""
        net, sections = self.network, self.sections
        return {"network": net.name, "network_file": str(net.source), "from": self.from_node,
                "to": self.to_node, "pipes": len(sections), "length_m": float(sections.length.sum()),
                "rise_m": self.rise, "friction": self.friction, "template": str(self.template),
                "output": None if self.output is None else str(self.output),
                "incline_clipped": sections.name[sections.clipped].tolist(),
                "bends": [{"after_section": str(sections.name[i]), "angle_deg": math.degrees(angle),
                           "direction_deg": math.degrees(direction), "turn": turn_name(direction),
                           "radius_assumed": True} for i, angle, direction in self.elbows],
                "sections": sections.as_document()}


def network_mission(network: str, from_node: str, to_node: str, *, friction: float | None = None,
                    template: Path | None = None, min_bore: float | None = None,
                    max_bore: float | None = None, output: Path | None = None,
                    force: bool = False) -> NetworkMission:
    """The shortest path from ``from_node`` to ``to_node`` through the pipes of ``network`` (a name shipped
    with wntr or an .inp file) whose bore [m] lies in [``min_bore``, ``max_bore``], as sections of the
    ``friction`` given (default: the template's one known friction); written to ``output`` when given (an
    existing file only with ``force``)."""
    from pampipe.io.mission_schema import load_mission

    template = template or bundled.find(DEFAULT_TEMPLATE)
    mission = load_mission(template)
    friction = _friction(friction, mission)
    net = load_network(network)
    if output is not None:
        check_not_input(output, [*mission.input_files, net.source], option="-o")
        if output.exists() and not force:
            raise InputError(f"-o {output}: the file exists (it may hold your edits); choose another "
                             "name or add --force to overwrite it.")
    low, high = min_bore or 0.0, math.inf if max_bore is None else max_bore
    if low > high:
        raise InputError(f"--min-bore {low * 1e3:g} mm is above --max-bore {high * 1e3:g} mm; no pipe fits.")
    sections = route_sections(net, from_node, to_node, friction=friction,
                              passable=lambda diameter: low <= diameter <= high)
    found = NetworkMission(net, from_node, to_node, sections, friction, template, output)
    if output is not None:
        header = (f"Route through network {net.name} ({net.source}) from {from_node} to {to_node}: "
                  f"{counted(len(sections), 'pipe')}, {sections.length.sum():.1f} m, written by pampipe "
                  "route.\n"
                  f"Every key but route is copied from {template}.\n"
                  f"Edit it by hand, then: pampipe plan {output}")
        header += ("\nBends turn as the network's coordinates and elevations say (direction: in the "
                   "steering module, 0 up, 90 left, 180 down, -90 right along travel); their radius is "
                   "not in the network: each takes elbow_radius, an assumption.")
        route = sections.mission_route()
        for i, angle, direction in found.elbows:  # elbows of the mission's elbow_radius (formats.md §4)
            route[i]["bend"] = {"angle": f"{math.degrees(angle):.4g} deg",
                                "direction": f"{math.degrees(direction):.4g} deg"}
        document = _mission(load_mapping(template, what="mission file"), template, output, route)
        yamlwrite.write(output, document, comments=[header])
    return found


def _friction(given: float | None, mission) -> float:
    """``given`` (checked), else the template's one known friction."""
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
    """The template's keys but route, every PAM path (``robot.segments[].pam``, ``robot.steering.pam``)
    made relative to ``output``, then the new route."""
    document = {key: value for key, value in template.items() if key != "route"}
    robot = dict(document["robot"])
    robot["segments"] = [_moved(segment, template_path, output) for segment in robot["segments"]]
    if isinstance(robot.get("steering"), dict):
        robot["steering"] = _moved(robot["steering"], template_path, output)
    document["robot"] = robot
    document["route"] = route
    return document


def _moved(block: dict, template_path: Path, output: Path) -> dict:
    """A robot block (a segment, the steering module) whose ``pam:`` file path still points at the same
    file from ``output``'s folder (an inline PAM mapping is kept as it is)."""
    pam = block.get("pam")
    if not isinstance(pam, str) or Path(pam).expanduser().is_absolute():
        return block
    target = relative(template_path, pam).resolve()
    folder = output.resolve().parent
    if os.path.commonpath([target, folder]) == target.anchor:  # nothing in common but the root
        return {**block, "pam": str(target)}
    return {**block, "pam": os.path.relpath(target, folder)}
