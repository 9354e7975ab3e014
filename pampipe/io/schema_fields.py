"""What the file schemas share (docs/formats.md §1-§4): the quantity fields with their SI ranges, made of
the rules of :mod:`.field_rules`.

The PAM (:mod:`.pam_model`), experiment (:mod:`.experiment_schema`) and mission (:mod:`.mission_model`)
schemas read their lengths, pressures, forces and angles through these fields.
"""

from __future__ import annotations

from typing import Annotated

from pydantic import AfterValidator

from pampipe.io import field_rules as rules
from pampipe.specs.schema import quantity_field

Length = quantity_field(rules.LENGTH)
RouteLength = quantity_field(rules.ROUTE_LENGTH)
Pressure = quantity_field(rules.PRESSURE)
PositivePressure = quantity_field(rules.POSITIVE_PRESSURE)
Force = quantity_field(rules.FORCE)
NonNegativeForce = quantity_field(rules.NON_NEGATIVE_FORCE)
Mass = quantity_field(rules.MASS)
Angle = quantity_field(rules.ANGLE)
Incline = quantity_field(rules.INCLINE)
Friction = quantity_field(rules.FRICTION)
Coefficient = Annotated[float, AfterValidator(rules.finite)]
