"""The text report of `pampipe route`: the pipes of the path with their bores, inclines and bends, and where
the mission file went (docs/commands.md §7)."""

from __future__ import annotations

import math

from pampipe.specs.turns import turn_name
from pampipe.units.display import counted
from pampipe.views.tables import table


def route_text(found) -> str:
    """The route of ``found`` (a :class:`pampipe.io.network_mission.NetworkMission`) as `route` prints it."""
    net, sections = found.network, found.sections
    elbows = {i: f"{math.degrees(angle):.3g} {turn_name(direction)}" for i, angle, direction in found.elbows}
    rows = [(name, a, b, length, d * 1e3, d / 0.0254, math.degrees(incline) if not clip else "±90 (clip)",
             "-" if math.isnan(bend) else math.degrees(bend), elbows.get(i, "-"))
            for i, (name, a, b, length, d, incline, bend, clip) in enumerate(zip(
                sections.name, sections.from_node, sections.to_node, sections.length, sections.diameter,
                sections.incline, sections.bend, sections.clipped, strict=True))]
    parts = [f"route through {net.name} ({net.source}) from {found.from_node} to {found.to_node}: "
             f"{counted(len(sections), 'pipe')}, {sections.length.sum():.6g} m, "
             f"friction {sections.friction[0]:g}",
             table(["pipe", "from", "to", "length [m]", "bore [mm]", "bore [in]", "incline [deg]",
                    "bend [deg]", "elbow after [deg]"], rows),
             "incline: along travel, from the node elevations; bend: plan-view deflection at the joint "
             "with the previous pipe. The file gives each pipe whose 3-D direction turns by 0.5 deg or more "
             "into the next a bend: {angle, direction} (elbow after: the 3-D angle and which way it turns "
             "along travel), of the mission's elbow_radius (assumed: the network gives no radius), which "
             "plan checks."]
    if sections.clipped.any():
        parts.append(f"note: {', '.join(sections.name[sections.clipped])}: the model's length is shorter "
                     "than the elevation difference; taken as vertical (±90 deg). Check these pipes.")
    if found.output is not None:
        parts.append(f"wrote {found.output} (every key but route from {found.template}); "
                     f"edit it by hand, then: pampipe plan {found.output}")
    return "\n".join(parts)
