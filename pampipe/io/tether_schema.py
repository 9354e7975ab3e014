"""The strict pydantic schema of the mission file's ``tether:`` block (docs/formats.md §4, ``tether:``): the
tether dragged behind the robot, the supply hose inside it and the compressor, built into
:class:`pampipe.specs.tether.Tether` by :func:`pampipe.io.mission_schema.build_tether`.

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

from pampipe.io import field_rules as rules
from pampipe.io.schema_fields import Friction
from pampipe.specs.schema import QuantityJson, Strict, quantity_field

Weight = Annotated[float, BeforeValidator(rules.weight), AfterValidator(rules.weight_range),
                   QuantityJson("force per length", "N/m")]


class UncertainTetherFriction(Strict):
    value: Friction
    sd: Friction = 0.0


class HoseSchema(Strict):
    """``hose: {inner_diameter, roughness}``: the supply line inside the tether."""

    inner_diameter: quantity_field(rules.HOSE_BORE)
    roughness: quantity_field(rules.ROUGHNESS) = 1.5e-6  # drawn plastic tubing


class CompressorSchema(Strict):
    """``compressor: {free_air_delivery}``: normal (ISO 8778) volume flow."""

    free_air_delivery: quantity_field(rules.FREE_AIR_DELIVERY)


class TetherSchema(Strict):
    weight: Weight
    friction: Friction | UncertainTetherFriction
    back_tension: quantity_field(rules.NON_NEGATIVE_FORCE) = 0.0
    length: quantity_field(rules.TETHER_LENGTH)
    hose: HoseSchema | None = None
    compressor: CompressorSchema | None = None
