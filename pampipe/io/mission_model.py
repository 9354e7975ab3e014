"""The mission file's strict pydantic schema (docs/formats.md §4): what
:func:`pampipe.io.mission_schema.load_mission` validates a file with when its quick check
(:data:`pampipe.io.quick_schemas.MISSION`, the same keys and rules) does not plainly accept it, so that the
message names the key, the value and what is allowed.
"""

from __future__ import annotations

import math
from typing import Annotated, Any, Literal

from pydantic import AfterValidator, Field

from pampipe.io import field_rules as rules
from pampipe.io.pam_model import PamSchema
from pampipe.io.quick_schemas import three_segments
from pampipe.io.schema_fields import (
    Friction,
    Incline,
    Length,
    Mass,
    NonNegativeForce,
    PositivePressure,
    RouteLength,
)
from pampipe.io.tether_schema import TetherSchema
from pampipe.specs.schema import Strict, quantity_field


class SegmentSchema(Strict):
    name: str = Field(min_length=1)
    pam: str | PamSchema
    mass: Mass
    unit: Literal["tested", "lot"] = "lot"  # which muscle it carries (docs/physics.md §15)


class SteeringSchema(Strict):
    """``robot.steering``: extensile PAMs in parallel at ``radius`` from the axis (docs/physics.md §14.4)."""

    pam: str | PamSchema
    count: Literal[3] = 3
    radius: Length


class RobotSchema(Strict):
    segments: Annotated[list[SegmentSchema], AfterValidator(three_segments)]
    payload: Mass = 0.0
    steering: SteeringSchema | None = None
    joint_angle: quantity_field(rules.JOINT_ANGLE) | None = None  # largest joint deflection


class BendSchema(Strict):
    """``bend: {angle, radius, direction}`` at the end of a section (docs/formats.md §4)."""

    angle: quantity_field(rules.BEND_ANGLE)
    radius: str | float | int | None = None  # a length or a multiple of the bore, "1.5 D"; None: elbow_radius
    direction: quantity_field(rules.BEND_DIRECTION) = math.pi


class UncertainFriction(Strict):
    value: Friction
    sd: Friction = 0.0


#: A section's friction: a number, {value, sd}, or from_pam / absent: the PAM files' measured contact block.
SectionFriction = Literal["from_pam"] | Friction | UncertainFriction | None


class SectionSchema(Strict):
    name: str = Field(min_length=1)
    length: RouteLength
    inner_diameter: Any  # a length or a standard size with a tolerance: read by pampipe.specs.pipes.bore
    incline: Incline = 0.0
    friction: SectionFriction = None
    pipe_material: str | None = Field(None, min_length=1, max_length=100)
    bend: BendSchema | None = None


class NetworkRouteSchema(Strict):
    """``route: {network, from, to, friction}``: a path through a pipe network (docs/commands.md §7)."""

    network: str = Field(min_length=1)
    from_node: str | int | None = Field(default=None, alias="from")
    to_node: str | int | None = Field(default=None, alias="to")
    friction: SectionFriction = None
    tolerance: str | float | int | None = None  # of every pipe's bore: a length or a percentage
    sd: str | float | int | None = None  # standard deviation of every pipe's bore
    pipe_material: str | None = Field(None, min_length=1, max_length=100)


class MissionSchema(Strict):
    robot: RobotSchema
    supply_pressure: PositivePressure
    safety_factor: quantity_field(rules.SAFETY_FACTOR) | None = None
    load_path: Literal["through_anchor", "distributed", "none"] | None = None  # None: the PAMs' κ or through
    tether_drag: NonNegativeForce = 0.0
    route: Annotated[list[SectionSchema], Field(min_length=1)] | NetworkRouteSchema
    gait: dict[str, Any] | None = None  # options of `gait`; validated there
    elbow_radius: str | float | int = "1.5 D"  # default centreline radius of a bend: a length or "k D"
    bend_model: Literal["rigid", "flexible"] = "rigid"
    tether: TetherSchema | None = None  # the tether, hose and compressor (pampipe.io.tether_schema)
