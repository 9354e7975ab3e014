"""`pampipe route`: the shortest path between two nodes of a network, written as a mission file to edit by
hand (docs/commands.md §7).

Each pipe of the path (:func:`pampipe.specs.network.route_sections`) becomes one section of the route, named
by its id (:meth:`pampipe.specs.network.Sections.mission_route`); each pipe whose 3-D direction turns into the
next (:func:`pampipe.io.routes.turn_angles`) gets a ``bend: {angle}`` of the mission's elbow radius. Every key
of the template mission but ``route`` is copied, its PAM paths rewritten to name the same files from the new
file's folder.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass
from pathlib import Path

from pampipe.errors import InputError
from pampipe.io import bundled, yamlwrite
from pampipe.io.epanet import load_network
from pampipe.io.files import check_not_input
from pampipe.io.routes import turn_angles
from pampipe.io.yamlfile import load_mapping
from pampipe.specs.network import Network, Sections, route_sections
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

    def as_document(self) -> dict:
        """The `route --json` document (docs/commands.md §7)."""
        net, sections = self.network, self.sections
        return {"network": net.name, "network_file": str(net.source), "from": self.from_node,
                "to": self.to_node, "pipes": len(sections), "length_m": float(sections.length.sum()),
                "rise_m": self.rise, "friction": self.friction, "template": str(self.template),
                "output": None if self.output is None else str(self.output),
                "incline_clipped": sections.name[sections.clipped].tolist(),
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
        route = sections.mission_route()
        for entry, turn in zip(route, turn_angles(sections).tolist(), strict=True):
            if turn > 0:  # an elbow of the mission's elbow_radius (docs/formats.md §4)
                entry["bend"] = {"angle": f"{math.degrees(turn):.4g} deg"}
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
