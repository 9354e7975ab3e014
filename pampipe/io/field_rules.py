"""The quantity rules of the file schemas (docs/formats.md §2-§4), without the schema library: each
:class:`~pampipe.specs.quantity_rule.QuantityRule` reads a value to SI and checks its range.

The pydantic fields (:mod:`.schema_fields` and the schema classes) and the quick check of a well-formed
file (:mod:`.quick_schemas`) are made of the same rules, so both read a value the same way.
"""

from __future__ import annotations

import math
from pathlib import Path

from pampipe.errors import InputError
from pampipe.model.no_slip import STANDARD_GRAVITY
from pampipe.specs.quantity_rule import QuantityRule
from pampipe.units.quantities import show, to_si

LENGTH = QuantityRule("length", gt=0, le=10.0, unit="m")  # a PAM dimension or a pipe diameter
LENGTH_SD = QuantityRule("length", ge=0, le=10.0, unit="m")  # a length's sd; an end fitting's length
ROUTE_LENGTH = QuantityRule("length", gt=0, le=1e7, unit="m")
PRESSURE = QuantityRule("pressure", ge=0, le=1e8, unit="Pa")
POSITIVE_PRESSURE = QuantityRule("pressure", gt=0, le=1e8, unit="Pa")
REFERENCE_PRESSURE = QuantityRule("pressure", ge=1e3, le=1e8, unit="Pa")  # P_ref: 1 kPa .. 100 MPa
FORCE = QuantityRule("force", ge=-1e7, le=1e7, unit="N")
NON_NEGATIVE_FORCE = QuantityRule("force", ge=0, le=1e7, unit="N")
MASS = QuantityRule("mass", ge=0, le=1e5, unit="kg")
ANGLE = QuantityRule("angle", gt=0, lt=math.pi / 2, unit="rad")  # a braid angle
ANGLE_SD = QuantityRule("angle", ge=0, lt=math.pi / 2, unit="rad")
INCLINE = QuantityRule("angle", ge=-math.pi / 2, le=math.pi / 2, unit="rad")
JOINT_ANGLE = QuantityRule("angle", gt=0, le=math.pi, unit="rad")  # the largest joint deflection
BEND_ANGLE = QuantityRule("angle", ge=0, le=math.pi, unit="rad",
                          hint="a bend turns the route by 0 to 180 deg (the angle between the pipes' "
                               "directions; which way it turns is 'direction')")
BEND_DIRECTION = QuantityRule("angle", ge=-2 * math.pi, le=2 * math.pi, unit="rad")
FRICTION = QuantityRule("dimensionless", ge=0, le=10)  # a friction or load coupling, or its sd
SAFETY_FACTOR = QuantityRule("dimensionless", ge=1, le=100)
DIRECTION_SCALE = QuantityRule("dimensionless", gt=0, le=1e12)  # an undetermined direction's width
CONTRACTION = QuantityRule("dimensionless", gt=0, lt=1)  # the largest 1 - L/L0
HOSE_BORE = QuantityRule("length", gt=0, le=1.0, unit="m")
ROUGHNESS = QuantityRule("length", ge=0, le=0.01, unit="m")
FREE_AIR_DELIVERY = QuantityRule("volume flow", gt=0, le=100.0, unit="m³/s")
TETHER_LENGTH = QuantityRule("length", ge=0, le=1e7, unit="m")

#: Largest accepted tether weight per length [N/m]: a steel wire rope of 100 mm weighs about 400 N/m.
LARGEST_WEIGHT = 1e4


def weight(value) -> float:
    """w [N/m] from a weight per length ('0.8 N/m', a bare number in N/m) or a mass per length ('80 g/m',
    times g)."""
    try:
        return to_si(value, "force per length")
    except InputError as weight:
        try:
            return to_si(value, "mass per length") * STANDARD_GRAVITY
        except InputError:
            if not isinstance(value, str):  # a bare number in a file without units: SI
                raise ValueError(str(weight)) from None
            raise ValueError(f"{show(value)} is neither a weight per length (e.g. '0.8 N/m') nor a mass per "
                             "length (e.g. '80 g/m')") from None


def weight_range(value: float) -> float:
    """``value`` [N/m] if within 0 … :data:`LARGEST_WEIGHT`, else ValueError."""
    if not 0 <= value <= LARGEST_WEIGHT:
        raise ValueError(f"{value:.6g} N/m must be within 0 … {LARGEST_WEIGHT:g} N/m")
    return value


def finite(value: float) -> float:
    """``value`` if finite, else ValueError."""
    if not math.isfinite(value):
        raise ValueError(f"{value!r} is not a finite number")
    return value


def relative(owner: Path, ref: str) -> Path:
    """The path ``ref`` written in the file ``owner``: absolute as given (``~`` expanded), else beside it."""
    target = Path(ref).expanduser()
    return target if target.is_absolute() else owner.parent / target
