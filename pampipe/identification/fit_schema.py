"""The strict schema of the ``fit:`` block (:mod:`.options` holds its meaning and the validated
:class:`~.options.FitOptions`); imported only when a block is validated, since it loads pydantic."""

from __future__ import annotations

import math
from typing import Literal

from pydantic import Field, model_validator

from pampipe.specs.schema import Strict, quantity

Stress = quantity("pressure", ge=-1e10, le=1e10, unit="Pa")
Length = quantity("length", gt=0, le=10.0, unit="m")
Angle = quantity("angle", gt=0, lt=math.pi / 2, unit="rad")


class GridSchema(Strict):
    pressures: int = Field(6, ge=2, le=100)
    lengths: int = Field(15, ge=2, le=400)


class BoundsSchema(Strict):
    model_config = Strict.model_config | {"strict": False}  # YAML lists become (low, high) tuples
    constant: tuple[Stress, Stress] = (0.0, 50e6)
    other: tuple[Stress, Stress] = (-50e6, 50e6)
    contact: tuple[Stress, Stress] = (-50e6, 50e6)

    @model_validator(mode="after")
    def _ordered(self):
        for name in ("constant", "other", "contact"):
            low, high = getattr(self, name)
            if not low < high:
                raise ValueError(f"bounds.{name}: the lower bound {low:g} Pa must be below the upper "
                                 f"bound {high:g} Pa")
        return self


class CoefficientPrior(Strict):
    """``{value: 4.4 MPa, sd: 0.5 MPa}``: a Gaussian prior on one moduli coefficient."""

    value: Stress
    sd: quantity("pressure", ge=1e3, le=1e10, unit="Pa")


class PriorSchema(Strict):
    """A ridge ``{sd, toward}``; or a Gaussian prior: ``coefficients: {hoop.a0: {value, sd}}``, or
    ``pam: FILE`` (its moduli and ``uncertainty:`` covariance, read by the experiment loader into
    ``mean`` [Pa] and ``covariance`` [Pa²])."""

    sd: quantity("pressure", ge=1e3, le=1e10, unit="Pa") | None = None  # below 1 kPa it fixes the coefficient
    toward: Literal["input", "axial", "zero"] = "input"
    coefficients: dict[str, CoefficientPrior] | None = Field(None, min_length=1, max_length=32)
    pam: str | None = Field(None, min_length=1)
    mean: list[float] | None = Field(None, min_length=1, max_length=32)
    covariance: list[list[float]] | None = None

    @model_validator(mode="after")
    def _one_kind(self):
        given = [name for name in ("sd", "coefficients", "pam") if getattr(self, name) is not None]
        if self.mean is not None and self.pam is None:
            given.append("mean")
        if len(given) != 1:
            raise ValueError("give exactly one of sd (a ridge: {sd: 2 MPa, toward: input}), coefficients "
                             "({hoop.a0: {value: 4.4 MPa, sd: 0.5 MPa}}) or pam (a PAM file with moduli: "
                             f"and uncertainty:); {', '.join(given) or 'none'} given")
        if (self.mean is None) != (self.covariance is None):
            raise ValueError("mean and covariance go together")
        if self.pam is not None and self.mean is None:
            raise ValueError(f"pam: {self.pam!r} is read by the experiment loader; give the prior in an "
                             "experiment file")
        return self


class CalibrationBoundsSchema(Strict):
    model_config = Strict.model_config | {"strict": False}  # YAML lists become (low, high) tuples
    braid_angle: tuple[Angle, Angle] | None = None
    initial_length: tuple[Length, Length] | None = None
    bladder_thickness: tuple[Length, Length] | None = None

    @model_validator(mode="after")
    def _ordered(self):
        for name in type(self).model_fields:  # the calibratable geometry, in options.CALIBRATABLE order
            bounds = getattr(self, name)
            if bounds is not None and not bounds[0] < bounds[1]:
                raise ValueError(f"calibration_bounds.{name}: the lower bound must be below the upper bound")
        return self


class FitSchema(Strict):
    degree: int = Field(3, ge=0, le=7)
    mode: Literal["shared", "per_pipe", "contact_increment"] = "shared"
    objective: Literal["least_squares", "sum_rmse"] = "least_squares"
    average_legs: bool = False
    average_bins: int = Field(30, ge=2, le=10_000)
    drucker: Literal["tangent", "sum", "none"] = "tangent"
    drucker_grid: GridSchema = GridSchema()
    bounds: BoundsSchema = BoundsSchema()
    contact_terms: Literal["constant", "full"] = "constant"
    prior: PriorSchema | None = None
    contact_smoothing: quantity("force", ge=1e-6, le=1e6, unit="N") = 1.0  # narrower: exp overflows
    rmse_smoothing: float = Field(1e-4, gt=0, le=1e6)
    max_iterations: int = Field(1000, ge=1, le=100_000)
    tolerance: float = Field(1e-10, gt=0, le=1e-2)
    slack: Literal["unilateral", "exclude"] = "unilateral"
    calibrate: list[Literal["braid_angle", "initial_length", "bladder_thickness"]] = Field(
        default_factory=list, max_length=3)
    calibration_bounds: CalibrationBoundsSchema = CalibrationBoundsSchema()
    pipe_diameters: list[Length] = Field(default_factory=list, max_length=50)


class FitBlock(Strict):
    """The ``fit:`` block by its key, so that errors name ``fit.<key>``."""

    fit: FitSchema
