"""The mission file's ``tether:`` block (docs/formats.md §4, ``tether:``): the tether dragged behind the
robot, the supply hose inside it and the compressor, checked strictly and built into
:class:`pampipe.specs.tether.Tether`.

    tether:
      weight: 0.8 N/m          # or a mass per length, 80 g/m (times g)
      friction: 0.35           # or {value: 0.35, sd: 0.05}
      back_tension: 5 N
      length: 400 m            # on the reel
      hose: {inner_diameter: 6 mm, roughness: 1.5 um}
      compressor: {free_air_delivery: 300 L/min}
"""

from __future__ import annotations

from typing import Annotated

from pydantic import AfterValidator, BeforeValidator

from pampipe.errors import InputError
from pampipe.model.no_slip import STANDARD_GRAVITY
from pampipe.specs.schema import QuantityJson, Strict, quantity
from pampipe.specs.tether import Compressor, Hose, Tether
from pampipe.units.quantities import show, to_si

#: Largest accepted weight per length [N/m]: a steel wire rope of 100 mm weighs about 400 N/m.
LARGEST_WEIGHT = 1e4


def _weight(value) -> float:
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


def _weight_range(value: float) -> float:
    if not 0 <= value <= LARGEST_WEIGHT:
        raise ValueError(f"{value:.6g} N/m must be within 0 … {LARGEST_WEIGHT:g} N/m")
    return value


Weight = Annotated[float, BeforeValidator(_weight), AfterValidator(_weight_range),
                   QuantityJson("force per length", "N/m")]
TetherFriction = quantity("dimensionless", ge=0, le=10)


class UncertainTetherFriction(Strict):
    value: TetherFriction
    sd: quantity("dimensionless", ge=0, le=10) = 0.0


class HoseSchema(Strict):
    """``hose: {inner_diameter, roughness}``: the supply line inside the tether."""

    inner_diameter: quantity("length", gt=0, le=1.0, unit="m")
    roughness: quantity("length", ge=0, le=0.01, unit="m") = 1.5e-6  # drawn plastic tubing


class CompressorSchema(Strict):
    """``compressor: {free_air_delivery}``: normal (ISO 8778) volume flow."""

    free_air_delivery: quantity("volume flow", gt=0, le=100.0, unit="m³/s")


class TetherSchema(Strict):
    weight: Weight
    friction: TetherFriction | UncertainTetherFriction
    back_tension: quantity("force", ge=0, le=1e7, unit="N") = 0.0
    length: quantity("length", ge=0, le=1e7, unit="m")
    hose: HoseSchema | None = None
    compressor: CompressorSchema | None = None


def build_tether(schema: TetherSchema | None) -> Tether | None:
    """The SI :class:`Tether` of a validated ``tether:`` block (None stays None)."""
    if schema is None:
        return None
    friction, sd = ((schema.friction.value, schema.friction.sd)
                    if isinstance(schema.friction, UncertainTetherFriction) else (schema.friction, 0.0))
    hose = None if schema.hose is None else Hose(schema.hose.inner_diameter, schema.hose.roughness)
    compressor = None if schema.compressor is None else Compressor(schema.compressor.free_air_delivery)
    return Tether(schema.weight, friction, schema.back_tension, schema.length, sd, hose, compressor)
