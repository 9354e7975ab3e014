"""What the file schemas share (docs/formats.md §1-§4): the quantity fields with their SI ranges, and where a
path written in a file points.

The PAM (:mod:`.pam_schema`), experiment (:mod:`.experiment_schema`) and mission (:mod:`.mission_schema`)
schemas read their lengths, pressures, forces and angles through these fields.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Annotated

from pydantic import AfterValidator

from pampipe.specs.schema import quantity

Length = quantity("length", gt=0, le=10.0, unit="m")  # a PAM dimension or a pipe diameter
RouteLength = quantity("length", gt=0, le=1e7, unit="m")
Pressure = quantity("pressure", ge=0, le=1e8, unit="Pa")
PositivePressure = quantity("pressure", gt=0, le=1e8, unit="Pa")
Force = quantity("force", ge=-1e7, le=1e7, unit="N")
NonNegativeForce = quantity("force", ge=0, le=1e7, unit="N")
Mass = quantity("mass", ge=0, le=1e5, unit="kg")
Angle = quantity("angle", gt=0, lt=math.pi / 2, unit="rad")
Incline = quantity("angle", ge=-math.pi / 2, le=math.pi / 2, unit="rad")
Friction = quantity("dimensionless", ge=0, le=10)
Coefficient = Annotated[float, AfterValidator(lambda v: _finite(v))]


def _finite(value: float) -> float:
    if not math.isfinite(value):
        raise ValueError(f"{value!r} is not a finite number")
    return value


def relative(owner: Path, ref: str) -> Path:
    """The path ``ref`` written in the file ``owner``: absolute as given (``~`` expanded), else beside it."""
    target = Path(ref).expanduser()
    return target if target.is_absolute() else owner.parent / target
