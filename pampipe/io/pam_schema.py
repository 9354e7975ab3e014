"""The PAM file (docs/formats.md §2): its strict pydantic schema, the SI :class:`~pampipe.model.pam.Pam` built
from it, and :func:`load_pam`.

Any problem raises :class:`InputError` naming the file, the key, the value and what is allowed.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any, Literal

import numpy as np
from pydantic import Field, model_validator

from pampipe.errors import InputError
from pampipe.io.file_units import read_units
from pampipe.io.schema_fields import Angle, Coefficient, Length, NonNegativeForce, PositivePressure, relative
from pampipe.model.domain import check_geometry, check_spread
from pampipe.model.effects import LIBRARY
from pampipe.model.pam import TIES, Geometry, Grip, Moduli, Pam
from pampipe.model.uncertainty import (
    GEOMETRY_NAMES,
    ParameterUncertainty,
    UndeterminedDirection,
    moduli_names,
)
from pampipe.specs.schema import Strict, quantity, validate
from pampipe.units.quantities import to_si


class UncertainLength(Strict):
    """``{value: 57.15 mm, sd: 0.2 mm}``: a length with its standard deviation (a tolerance)."""

    value: Length
    sd: quantity("length", ge=0, le=10.0, unit="m")


class UncertainAngle(Strict):
    """``{value: 24 deg, sd: 1 deg}``: an angle with its standard deviation."""

    value: Angle
    sd: quantity("angle", ge=0, lt=math.pi / 2, unit="rad")


class GeometrySchema(Strict):
    initial_length: Length | UncertainLength
    initial_diameter: Length | UncertainLength
    braid_angle_from_transverse: Angle | UncertainAngle | None = None
    braid_angle_from_axis: Angle | UncertainAngle | None = None
    bladder_thickness: Length | UncertainLength
    wall: Literal["thick", "thin"] = "thick"
    fitting_length: quantity("length", ge=0, le=10.0, unit="m") = 0.0  # rigid end fittings, both ends

    @model_validator(mode="after")
    def _one_angle(self):
        given = [self.braid_angle_from_transverse is not None, self.braid_angle_from_axis is not None]
        if sum(given) != 1:
            raise ValueError("give exactly one of braid_angle_from_transverse (the paper's convention, "
                             "e.g. '65.92 deg') or braid_angle_from_axis (e.g. '24.08 deg'); "
                             f"{'both were' if all(given) else 'neither was'} given")
        return self


def _value_sd(entry) -> tuple[float, float | None]:
    """(value, sd) of a plain or ``{value, sd}`` geometry entry (sd None when plain)."""
    if isinstance(entry, UncertainLength | UncertainAngle):
        return entry.value, entry.sd
    return entry, None


class LawSchema(Strict):
    a: list[Coefficient] = Field(min_length=1, max_length=8)
    b: list[Coefficient] = Field(min_length=1, max_length=8)

    @model_validator(mode="after")
    def _same_length(self):
        if len(self.a) != len(self.b):
            raise ValueError(f"'a' has {len(self.a)} coefficients and 'b' has {len(self.b)}; "
                             "they must have the same length (degree + 1)")
        return self


class ContactSchema(Strict):
    axial: LawSchema
    hoop: LawSchema


class ModuliSchema(Strict):
    unit: str = "MPa"
    reference_pressure: quantity("pressure", ge=1e3, le=1e8, unit="Pa") = 1e6  # P_ref: 1 kPa .. 100 MPa
    axial: LawSchema
    hoop: LawSchema
    contact: ContactSchema | None = None

    @model_validator(mode="after")
    def _consistent(self):
        to_si(f"1 {self.unit}", "pressure", where=f"unit {self.unit!r}")
        sizes = {len(self.axial.a), len(self.hoop.a)}
        if self.contact is not None:
            sizes |= {len(self.contact.axial.a), len(self.contact.hoop.a)}
        if len(sizes) != 1:
            raise ValueError("axial, hoop (and contact) laws must have the same number of coefficients")
        return self


class UndeterminedSchema(Strict):
    """One direction the data do not determine (docs/formats.md §2 ``uncertainty.undetermined``)."""

    direction: dict[str, Coefficient] = Field(min_length=1)  # parameter name -> weight, scaled coordinates
    scale: quantity("dimensionless", gt=0, le=1e12) = 1.0  # the width left open [scaled units]
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
    value: quantity("dimensionless", ge=0, le=10)
    sd: quantity("dimensionless", ge=0, le=10) = 0.0


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
    max_contraction: quantity("dimensionless", gt=0, lt=1) | None = None  # largest 1 - L/L0 allowed


def build_effects(raw: dict[str, dict[str, Any]] | None) -> dict[str, dict[str, float]] | None:
    """SI effect parameters from an ``effects:`` block, e.g. ``{braid_friction: {f0: "12 N"}}``.

    Unknown effects or parameters, wrong units and values outside the parameter's bounds raise
    ValueError naming ``effects.<name>.<parameter>``, the value and what is allowed.
    """
    if not raw:
        return None
    out = {}
    for name, given in raw.items():
        if name not in LIBRARY:
            raise ValueError(f"effects: unknown effect {name!r}; known effects: {', '.join(LIBRARY)}")
        params = {p.name: p for p in LIBRARY[name].parameters}
        values = {}
        for key, value in (given or {}).items():
            if key not in params:
                raise ValueError(f"effects.{name}: unknown parameter {key!r}; allowed: {', '.join(params)}")
            p = params[key]
            si = to_si(value, p.dimension, where=f"effects.{name}.{key}")
            if not p.lower <= si <= p.upper:
                raise ValueError(f"effects.{name}.{key}: {value!r} is outside the allowed range "
                                 f"[{p.lower / p.scale:g}, {p.upper / p.scale:g}] {p.unit}")
            values[key] = si
        out[name] = values
    return out


def build_pam(schema: PamSchema) -> Pam:
    """SI :class:`Pam` from a validated schema (the geometry's domain is checked too)."""
    g = schema.geometry
    values, sd = {}, {}
    for key, name in (("initial_length", "initial_length"), ("initial_diameter", "initial_diameter"),
                      ("braid_angle_from_axis", "braid_angle"),
                      ("braid_angle_from_transverse", "braid_angle"),
                      ("bladder_thickness", "bladder_thickness")):
        entry = getattr(g, key)
        if entry is None:
            continue
        values[name], spread = _value_sd(entry)
        if key == "braid_angle_from_transverse":
            values[name] = math.pi / 2 - values[name]  # α₀ = 90° − β₀; the sd is the same angle
        if spread is not None:
            sd[name] = spread
    geometry = Geometry(values["initial_length"], values["initial_diameter"], values["braid_angle"],
                        values["bladder_thickness"], g.wall)
    check_geometry(geometry)
    for key, name in (("initial_length", "initial_length"), ("initial_diameter", "initial_diameter"),
                      ("braid_angle_from_axis", "braid_angle"),
                      ("braid_angle_from_transverse", "braid_angle"),
                      ("bladder_thickness", "bladder_thickness")):
        if getattr(g, key) is not None and name in sd:
            check_spread(geometry, name, sd[name], where=f"geometry.{key}",
                         transverse=key == "braid_angle_from_transverse")
    moduli = uncertainty = None
    if schema.moduli is not None:
        m = schema.moduli
        scale = to_si(f"1 {m.unit}", "pressure", where="moduli.unit")
        _check_moduli_magnitude(m, scale)
        contact = None
        if m.contact is not None:
            contact = scale * np.concatenate([m.contact.axial.a, m.contact.axial.b,
                                              m.contact.hoop.a, m.contact.hoop.b])
        moduli = Moduli.from_vector(scale * np.concatenate([m.axial.a, m.axial.b, m.hoop.a, m.hoop.b]),
                                    reference_pressure=m.reference_pressure, contact=contact)
    if schema.uncertainty is not None:
        if moduli is None:
            raise ValueError("uncertainty: is the uncertainty of the moduli and needs a moduli: block")
        uncertainty = build_uncertainty(schema.uncertainty, moduli.degree)
    effects = dict(schema.effects or {})
    ties = effects.pop(TIES, None)
    if ties is not None and not all(isinstance(v, str) for v in ties.values()):
        raise ValueError(f"effects.{TIES}: each group of tied effects maps to a sentence (the test that "
                         "would separate them), e.g. {'prestrain or sensor_offset': 'an axial test ...'}")
    pam = Pam(schema.name, geometry, moduli, None, build_effects(effects), _grip(schema.contact),
              geometry_sd=sd, max_pressure=schema.max_pressure, max_contraction=schema.max_contraction,
              fitting_length=g.fitting_length, ties=ties or None)
    return pam.with_uncertainty(uncertainty)


def _grip(schema: GripSchema | None) -> Grip | None:
    if schema is None:
        return None
    kappa = schema.load_coupling
    return Grip(schema.friction.value, schema.friction.sd, None if kappa is None else kappa.value,
                0.0 if kappa is None else kappa.sd, schema.pipe_material,
                tuple(schema.tested_pipe_diameters or ()))


def build_uncertainty(u: UncertaintySchema, degree: int) -> ParameterUncertainty:
    """SI :class:`ParameterUncertainty` from an ``uncertainty:`` block of a PAM with moduli of ``degree``."""
    moduli = moduli_names(degree)
    names = tuple(u.parameters) if u.parameters is not None else moduli
    if names[:len(moduli)] != moduli or any(n not in GEOMETRY_NAMES for n in names[len(moduli):]) \
            or len(set(names)) != len(names):
        raise ValueError(f"uncertainty.parameters: {list(names)} is not allowed: it must list the "
                         f"{len(moduli)} moduli in order ({moduli[0]} … {moduli[-1]}), then any of "
                         f"{', '.join(GEOMETRY_NAMES)} once each")
    cov = np.asarray(u.covariance, dtype=float)
    n = len(names)
    if cov.ndim != 2 or cov.shape != (n, n):
        rows = {len(row) for row in u.covariance}
        raise ValueError(f"uncertainty.covariance must be {n}x{n} (one row and column per parameter), got "
                         f"{len(u.covariance)} rows of {'/'.join(str(r) for r in sorted(rows)) or 0}")
    unit = to_si(f"1 {u.unit}", "pressure", where="uncertainty.unit")
    row_scale = np.array([unit if name in moduli else 1.0 for name in names])
    directions = tuple(_direction(d, names, f"undetermined[{i}]") for i, d in enumerate(u.undetermined))
    on_prior = tuple(_direction(d, names, f"prior_determined[{i}]") for i, d in enumerate(u.prior_determined))
    try:
        return ParameterUncertainty(names, cov * np.outer(row_scale, row_scale), u.model_error, directions,
                                    on_prior, u.model_error_dof)
    except ValueError as exc:
        raise ValueError(f"uncertainty: {exc}") from None


def _direction(d: UndeterminedSchema, names: tuple[str, ...], key: str) -> UndeterminedDirection:
    unknown = [name for name in d.direction if name not in names]
    if unknown:
        raise ValueError(f"uncertainty.{key}.direction: unknown parameter(s) {unknown}; "
                         f"allowed: the uncertainty's parameters ({', '.join(names)})")
    vector = np.array([d.direction.get(name, 0.0) for name in names])
    norm = float(np.linalg.norm(vector))
    if norm == 0:
        raise ValueError(f"uncertainty.{key}.direction: all weights are zero")
    scale = d.scale
    if abs(norm - 1) > 1e-9:  # a hand-written direction: make it a unit vector, keep the step
        vector, scale = vector / norm, scale * norm
    return UndeterminedDirection(vector, scale, dict(d.moves), d.test)


#: Largest moduli coefficient accepted [Pa]: 1 TPa, far above any elastomer (latex ≈ 1 MPa) or fibre.
MODULI_LIMIT = 1e12


def _check_moduli_magnitude(m: ModuliSchema, scale: float) -> None:
    laws = {"axial": m.axial, "hoop": m.hoop}
    if m.contact is not None:
        laws |= {"contact.axial": m.contact.axial, "contact.hoop": m.contact.hoop}
    for name, law in laws.items():
        for part in ("a", "b"):
            for j, value in enumerate(getattr(law, part)):
                if abs(value) * scale > MODULI_LIMIT:
                    raise ValueError(f"moduli.{name}.{part}[{j}]: {value:g} {m.unit} is not a plausible "
                                     f"modulus; coefficients must be within ±{MODULI_LIMIT:g} Pa")


def load_pam(path: str | Path, *, raw: dict | None = None) -> Pam:
    """Read and validate a PAM file (``raw``: its content as a mapping instead; ``path`` names it)."""
    path = Path(path)
    with read_units(path, raw, what="PAM file") as content:
        return _build(path, content)


def resolve_pam(owner: Path, ref: str | PamSchema, key: str) -> Pam:
    """The PAM the file ``owner`` names at ``key``: a PAM file's path (beside ``owner``) or an inline
    block."""
    if isinstance(ref, PamSchema):
        return _build(owner, ref, prefix=key)
    target = relative(owner, ref)
    try:
        return load_pam(target)
    except InputError as exc:
        raise InputError(f"{owner}: {key}: {exc}") from None


def _build(path: Path, raw, prefix: str = "") -> Pam:
    schema = raw if isinstance(raw, PamSchema) else validate(path, PamSchema, raw)
    try:
        return build_pam(schema)
    except (InputError, ValueError) as exc:
        raise InputError(f"{path}: {prefix + ': ' if prefix else ''}{exc}") from None
