"""The PAM file's strict pydantic schema (docs/formats.md §2): what :func:`pampipe.io.pam_schema.load_pam`
validates a file with when its quick check (:data:`pampipe.io.quick_schemas.PAM`, the same keys and rules)
does not plainly accept it, so that the message names the key, the value and what is allowed.
"""

from __future__ import annotations

from typing import Any, Literal

from pydantic import Field, model_validator

from pampipe.io import field_rules as rules
from pampipe.io.quick_schemas import consistent_moduli, one_angle, same_length
from pampipe.io.schema_fields import (
    Angle,
    Coefficient,
    Friction,
    Length,
    NonNegativeForce,
    PositivePressure,
)
from pampipe.specs.schema import Strict, quantity_field


class UncertainLength(Strict):
    """``{value: 57.15 mm, sd: 0.2 mm}``: a length with its standard deviation (a tolerance)."""

    value: Length
    sd: quantity_field(rules.LENGTH_SD)


class UncertainAngle(Strict):
    """``{value: 24 deg, sd: 1 deg}``: an angle with its standard deviation."""

    value: Angle
    sd: quantity_field(rules.ANGLE_SD)


class GeometrySchema(Strict):
    initial_length: Length | UncertainLength
    initial_diameter: Length | UncertainLength
    braid_angle_from_transverse: Angle | UncertainAngle | None = None
    braid_angle_from_axis: Angle | UncertainAngle | None = None
    bladder_thickness: Length | UncertainLength
    wall: Literal["thick", "thin"] = "thick"
    fitting_length: quantity_field(rules.LENGTH_SD) = 0.0  # rigid end fittings, both ends

    @model_validator(mode="after")
    def _one_angle(self):
        one_angle(self)
        return self


class LawSchema(Strict):
    a: list[Coefficient] = Field(min_length=1, max_length=8)
    b: list[Coefficient] = Field(min_length=1, max_length=8)

    @model_validator(mode="after")
    def _same_length(self):
        same_length(self)
        return self


class ContactSchema(Strict):
    axial: LawSchema
    hoop: LawSchema


class ModuliSchema(Strict):
    unit: str = "MPa"
    reference_pressure: quantity_field(rules.REFERENCE_PRESSURE) = 1e6  # P_ref: 1 kPa .. 100 MPa
    axial: LawSchema
    hoop: LawSchema
    contact: ContactSchema | None = None

    @model_validator(mode="after")
    def _consistent(self):
        consistent_moduli(self)
        return self


class UndeterminedSchema(Strict):
    """One direction the data do not determine (docs/formats.md §2 ``uncertainty.undetermined``)."""

    direction: dict[str, Coefficient] = Field(min_length=1)  # parameter name -> weight, scaled coordinates
    scale: quantity_field(rules.DIRECTION_SCALE) = 1.0  # the width left open [scaled units]
    moves: dict[str, Coefficient] = Field(default_factory=dict)  # prediction -> change per scale
    test: str = ""  # the test that would determine it


class UncertaintySchema(Strict):
    """Joint covariance of ``parameters`` (moduli rows in ``unit``, geometry rows in m or rad)."""

    unit: str = "MPa"
    parameters: list[str] | None = Field(None, min_length=1, max_length=64)
    covariance: list[list[Coefficient]]
    model_error: NonNegativeForce = 0.0
    model_error_dof: int | None = Field(None, ge=1)  # degrees of freedom of model_error² (identify's blocks)
    undetermined: list[UndeterminedSchema] = Field(default_factory=list, max_length=64)
    prior_determined: list[UndeterminedSchema] = Field(default_factory=list, max_length=64)


class MeasuredValue(Strict):
    value: Friction
    sd: Friction = 0.0


class GripSchema(Strict):
    """The top-level ``contact:`` block: wall friction and load coupling from slip tests (formats.md §2)."""

    friction: MeasuredValue
    load_coupling: MeasuredValue | None = None
    pipe_material: str | None = Field(None, min_length=1, max_length=100)
    tested_pipe_diameters: list[Length] | None = Field(None, max_length=100)


class PamSchema(Strict):
    name: str = Field(min_length=1)
    geometry: GeometrySchema
    moduli: ModuliSchema | None = None
    uncertainty: UncertaintySchema | None = None
    effects: dict[str, dict[str, Any]] | None = None  # docs/physics.md §9; checked by build_effects
    contact: GripSchema | None = None  # measured wall friction (moduli.contact: stiffening increments)
    max_pressure: PositivePressure | None = None  # the maker's rated (gauge) pressure
    max_contraction: quantity_field(rules.CONTRACTION) | None = None  # largest 1 - L/L0 allowed
