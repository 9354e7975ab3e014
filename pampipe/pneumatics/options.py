"""The mission's ``gait:`` block: valve, gas and optimiser settings (strict schema, SI inside).

Example (every key is optional; the values shown are the defaults)::

    gait:
      valve:
        sonic_conductance: 0.5 dm^3/(s*bar)   # ISO 6358 C of each muscle's valve
        critical_pressure_ratio: 0.3          # ISO 6358 b
        subsonic_index: 0.5                   # ISO 6358 m
      gas:
        temperature: 20 degC
        polytropic_index: 1.0                 # 1 = isothermal (default) ... 1.4 = adiabatic
        atmospheric_pressure: 101.325 kPa
      vented_pressure: 0.5 kPa                # a venting muscle counts as deflated below this
      optimal:
        intervals: 8                          # control intervals per phase
        substeps: 8                           # RK4 steps per interval
        contact_margin: 5 kPa                 # a pre-filled idle muscle stays this far below contact
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

from pydantic import Field

from pampipe.specs.schema import Strict, quantity
from pampipe.specs.schema import validate as _validate

Conductance = quantity("sonic conductance", gt=0, le=1e-5, unit="m³/(s·Pa)")
Ratio = quantity("dimensionless", ge=0, lt=1)
Temperature = quantity("temperature", gt=150, le=500, unit="K")
GaugePressure = quantity("pressure", gt=0, le=1e6, unit="Pa")
SmallPressure = quantity("pressure", ge=0, le=1e6, unit="Pa")
Atmosphere = quantity("pressure", gt=1e4, le=2e5, unit="Pa")


class ValveSchema(Strict):
    sonic_conductance: Conductance = 5e-9  # 0.5 dm³/(s·bar): a small solenoid valve
    critical_pressure_ratio: Ratio = 0.3
    subsonic_index: quantity("dimensionless", gt=0, le=1) = 0.5


class GasSchema(Strict):
    temperature: Temperature = 293.15
    polytropic_index: quantity("dimensionless", ge=1, le=1.4) = 1.0
    atmospheric_pressure: Atmosphere = 101325.0


class OptimalSchema(Strict):
    intervals: int = Field(8, ge=1, le=100)
    substeps: int = Field(8, ge=1, le=50)
    contact_margin: SmallPressure = 5e3


class GaitSchema(Strict):
    valve: ValveSchema = ValveSchema()
    gas: GasSchema = GasSchema()
    vented_pressure: GaugePressure = 500.0
    optimal: OptimalSchema = OptimalSchema()


class _MissionGait(Strict):
    """Wrapper so that error messages name the full key path, ``gait.valve...``."""

    gait: GaitSchema = GaitSchema()


@dataclass(frozen=True)
class Valve:
    """ISO 6358 valve: sonic conductance C [m³/(s·Pa)], critical ratio b, subsonic index m."""

    sonic_conductance: float = 5e-9
    critical_pressure_ratio: float = 0.3
    subsonic_index: float = 0.5


@dataclass(frozen=True)
class Gas:
    """Air at ``temperature`` [K]; ``polytropic_index`` n (1 isothermal); atmosphere [Pa, absolute]."""

    temperature: float = 293.15
    polytropic_index: float = 1.0
    atmospheric_pressure: float = 101325.0


@dataclass(frozen=True)
class GaitOptions:
    """Validated ``gait:`` settings (SI)."""

    valve: Valve = Valve()
    gas: Gas = Gas()
    vented_pressure: float = 500.0  # [Pa] gauge: "deflated" below this
    intervals: int = 8
    substeps: int = 8
    contact_margin: float = 5e3  # [Pa]


def gait_options(raw: dict[str, Any] | None, *, source: Path | str = "mission file") -> GaitOptions:
    """Validate a mission's raw ``gait:`` mapping; errors name the file and the key (exit 2)."""
    schema = _validate(Path(source), _MissionGait, {"gait": dict(raw or {})}).gait
    v, g, o = schema.valve, schema.gas, schema.optimal
    return GaitOptions(Valve(v.sonic_conductance, v.critical_pressure_ratio, v.subsonic_index),
                       Gas(g.temperature, g.polytropic_index, g.atmospheric_pressure),
                       schema.vented_pressure, o.intervals, o.substeps, o.contact_margin)
