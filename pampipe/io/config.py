"""Strict pydantic schemas for the PAM, experiment and mission files (docs/formats.md §1-§4).

Each ``load_*`` function reads a YAML file, validates it (unknown keys, units, ranges) and returns
frozen SI objects. Any problem raises :class:`InputError` naming the file, the key, the value and
what is allowed.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any, Literal

import numpy as np
from pydantic import AfterValidator, Field, field_validator, model_validator

from pampipe.errors import InputError
from pampipe.io.routes import elbow_radius, listed_route, network_route
from pampipe.io.tether_schema import TetherSchema, build_tether
from pampipe.io.yamlfile import load_mapping
from pampipe.model.domain import check_geometry, check_kind
from pampipe.model.effects import LIBRARY
from pampipe.model.pam import Geometry, Grip, Moduli, Pam
from pampipe.model.uncertainty import (
    GEOMETRY_NAMES,
    ParameterUncertainty,
    UndeterminedDirection,
    moduli_names,
)
from pampipe.runtime.collector import paused
from pampipe.specs.mission import Mission, Segment, Steering
from pampipe.specs.schema import Strict, quantity
from pampipe.specs.schema import validate as _validate
from pampipe.units.quantities import to_si

if TYPE_CHECKING:
    from pampipe.specs.experiment import Experiment

__all__ = ["Strict", "_validate", "load_experiment", "load_mission", "load_pam", "quantity"]

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


# ---------------------------------------------------------------------------------------------- PAM
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
    pam = Pam(schema.name, geometry, moduli, None, build_effects(schema.effects), _grip(schema.contact),
              geometry_sd=sd, max_pressure=schema.max_pressure, max_contraction=schema.max_contraction,
              fitting_length=g.fitting_length)
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
                                    on_prior)
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


# ------------------------------------------------------------------------------------- experiment
class DirectionSchema(Strict):
    """``direction: {column: state, loading: 1, unloading: 2}``: the codes of a direction column."""

    column: Literal["direction", "state"]
    loading: float = Field(allow_inf_nan=False)
    unloading: float = Field(allow_inf_nan=False)
    held: float | None = Field(None, allow_inf_nan=False)

    @model_validator(mode="after")
    def _distinct(self):
        codes = [c for c in (self.loading, self.unloading, self.held) if c is not None]
        if len(set(codes)) != len(codes):
            raise ValueError(f"direction: loading, unloading and held need distinct codes, got {codes}")
        return self


class TestSchema(Strict):
    name: str = Field(min_length=1)
    kind: Literal["axial", "radial", "slip"]
    data: str = Field(min_length=1)
    pipe_diameter: Length | None = None
    axial_load: Force = 0.0
    set_pressures: list[Pressure] | None = Field(None, min_length=1, max_length=1000)
    protocol: Literal["isobaric", "isometric", "mixed"] | None = None
    pipe_material: str | None = Field(None, min_length=1, max_length=100)
    direction: DirectionSchema | None = None

    @model_validator(mode="after")
    def _radial_needs_pipe(self):
        if self.kind in ("radial", "slip") and self.pipe_diameter is None:
            raise ValueError(f"a {self.kind} test needs pipe_diameter (e.g. '3 in')")
        if self.kind == "slip":
            given = [k for k in ("axial_load", "set_pressures", "protocol") if k in self.model_fields_set]
            if given:
                raise ValueError(f"a slip test takes no {', '.join(given)}: its CSV records the pressure "
                                 "and the rising axial load (keys: name, kind, data, pipe_diameter, "
                                 "pipe_material)")
        elif self.pipe_material is not None:
            raise ValueError("pipe_material belongs to slip tests (kind: slip), where it names the wall the "
                             "measured friction holds for")
        if self.kind == "axial" and self.pipe_diameter is not None:
            raise ValueError("an axial test has no pipe_diameter; use kind: radial for a pipe test")
        if self.kind == "radial" and self.protocol is not None:
            raise ValueError("protocol applies to axial tests (isobaric, isometric or mixed); a radial "
                             "test has none")
        return self


class ExperimentSchema(Strict):
    pam: str | PamSchema
    tests: list[TestSchema] = Field(min_length=1)
    fit: dict[str, Any] | None = None  # options of `identify`; validated there


# ---------------------------------------------------------------------------------------- mission
class SegmentSchema(Strict):
    name: str = Field(min_length=1)
    pam: str | PamSchema
    mass: Mass


def _three_segments(segments: list) -> list:
    if len(segments) != 3:
        raise ValueError(f"needs exactly 3 segments (rear to front), got {len(segments)}")
    return segments


class SteeringSchema(Strict):
    """``robot.steering``: extensile PAMs in parallel at ``radius`` from the axis (docs/physics.md §14.4)."""

    pam: str | PamSchema
    count: Literal[3] = 3
    radius: Length


class RobotSchema(Strict):
    segments: Annotated[list[SegmentSchema], AfterValidator(_three_segments)]
    payload: Mass = 0.0
    steering: SteeringSchema | None = None
    joint_angle: quantity("angle", gt=0, le=math.pi, unit="rad") | None = None  # largest joint deflection


class BendSchema(Strict):
    """``bend: {angle, radius, direction}`` at the end of a section (docs/formats.md §4)."""

    angle: quantity("angle")
    radius: str | float | int | None = None  # a length or a multiple of the bore, "1.5 D"; None: elbow_radius
    direction: quantity("angle", ge=-2 * math.pi, le=2 * math.pi, unit="rad") = math.pi

    @field_validator("angle")
    @classmethod
    def _turn(cls, value: float) -> float:
        if not 0 <= value <= math.pi:
            raise ValueError(f"{math.degrees(value):.6g} deg: a bend turns the route by 0 to 180 deg (the "
                             "angle between the pipes' directions; which way it turns is 'direction')")
        return value


class UncertainFriction(Strict):
    value: Friction
    sd: quantity("dimensionless", ge=0, le=10) = 0.0


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
    safety_factor: quantity("dimensionless", ge=1, le=100) | None = None
    load_path: Literal["through_anchor", "distributed", "none"] | None = None  # None: the PAMs' κ or through
    tether_drag: NonNegativeForce = 0.0
    route: Annotated[list[SectionSchema], Field(min_length=1)] | NetworkRouteSchema
    gait: dict[str, Any] | None = None  # options of `gait`; validated there
    elbow_radius: str | float | int = "1.5 D"  # default centreline radius of a bend: a length or "k D"
    bend_model: Literal["rigid", "flexible"] = "rigid"
    tether: TetherSchema | None = None  # the tether, hose and compressor (pampipe.io.tether_schema)


#: The safety factor of a mission that gives none, and what the commands say about it.
DEFAULT_SAFETY_FACTOR = 1.0
NO_SAFETY_FACTOR = ("the mission gives no safety_factor, so 1 is used: the plan holds exactly the load, with "
                    "no margin for friction, load or model error; write e.g. 'safety_factor: 1.5'.")


# ---------------------------------------------------------------------------------------- loaders
def load_pam(path: str | Path, *, raw: dict | None = None) -> Pam:
    """Read and validate a PAM file (``raw``: its content as a mapping instead; ``path`` names it)."""
    path = Path(path)
    return _build(path, PamSchema, load_mapping(path, what="PAM file") if raw is None else raw, build_pam)


def load_experiment(path: str | Path, *, raw: dict | None = None) -> Experiment:
    """Read and validate an experiment file; CSV paths are resolved but not read here.

    ``raw``: the file's content as a mapping instead; relative paths resolve beside ``path``.
    """
    from pampipe.specs.experiment import (  # not needed on plan's start-up path
        DirectionCoding,
        Experiment,
        TestSpec,
    )

    path = Path(path)
    schema = _validate(path, ExperimentSchema,
                       load_mapping(path, what="experiment file") if raw is None else raw)
    pam = _resolve_pam(path, schema.pam, "pam")
    try:
        check_kind(pam.geometry, extensile=False, where="pam", role="identify and diagnose (radial and axial "
                   "tests of an anchoring muscle)")
    except InputError as exc:
        raise InputError(f"{path}: {exc}") from None
    tests = []
    names = set()
    for i, t in enumerate(schema.tests):
        if t.name in names:
            raise InputError(f"{path}: tests[{i}].name: duplicate test name {t.name!r}.")
        names.add(t.name)
        tests.append(TestSpec(t.name, t.kind, _relative(path, t.data), t.pipe_diameter, t.axial_load,
                              None if t.set_pressures is None else tuple(t.set_pressures), t.protocol,
                              t.pipe_material, None if t.direction is None else DirectionCoding(
                                  t.direction.column, t.direction.loading, t.direction.unloading,
                                  t.direction.held)))
    pam_file = _relative(path, schema.pam) if isinstance(schema.pam, str) else None
    fit = dict(schema.fit or {})
    return Experiment(path, pam, tuple(tests), _prior_from_pam(path, fit), pam_file, _prior_file(path, fit))


def _prior_file(path: Path, fit: dict) -> Path | None:
    """The PAM file named by ``fit.prior.pam`` (see :func:`_prior_from_pam`), or None."""
    prior = fit.get("prior")
    return _relative(path, prior["pam"]) if isinstance(prior, dict) and isinstance(prior.get("pam"), str) \
        else None


def _prior_from_pam(path: Path, fit: dict) -> dict:
    """``fit`` with ``prior: {pam: FILE}`` read: the file's moduli as ``mean`` [Pa] and the moduli block of
    its ``uncertainty:`` as ``covariance`` [Pa²] (docs/formats.md §3, fit.prior)."""
    target = _prior_file(path, fit)
    if target is None:
        return fit
    prior = fit["prior"]
    try:
        pam = load_pam(target)
    except InputError as exc:
        raise InputError(f"{path}: fit.prior.pam: {exc}") from None
    if pam.moduli is None or pam.covariance is None:
        raise InputError(f"{path}: fit.prior.pam: {target} needs a moduli: and an uncertainty: block to be a "
                         "prior (the moduli are its mean, the covariance its spread).")
    k = pam.moduli.degree + 1  # the fit's b coefficients are per 1 MPa: rescale the file's P_ref
    scale = np.ones(4 * k)
    scale[k:2 * k] = scale[3 * k:] = 1e6 / pam.moduli.reference_pressure
    covariance = np.asarray(pam.covariance) * np.outer(scale, scale)
    return fit | {"prior": prior | {"mean": (scale * pam.moduli.as_vector()).tolist(),
                                    "covariance": covariance.tolist()}}


def load_mission(path: str | Path, *, raw: dict | None = None) -> Mission:
    """Read and validate a mission file and the PAM files it names.

    ``raw``: the file's content as a mapping instead; relative paths resolve beside ``path``.
    """
    with paused():  # a long route is millions of acyclic objects (pampipe.runtime.collector)
        return _load_mission(Path(path), raw)


def _load_mission(path: Path, raw: dict | None) -> Mission:
    schema = _validate(path, MissionSchema, load_mapping(path, what="mission file") if raw is None else raw)
    segments = tuple(Segment(s.name, _resolve_pam(path, s.pam, f"robot.segments[{i}].pam"), s.mass,
                             _relative(path, s.pam) if isinstance(s.pam, str) else None)
                     for i, s in enumerate(schema.robot.segments))
    if len({s.name for s in segments}) != len(segments):
        raise InputError(f"{path}: robot.segments: segment names must be unique, got "
                         f"{[s.name for s in segments]}.")
    warnings = ()
    safety_factor = schema.safety_factor
    if safety_factor is None:
        safety_factor, warnings = DEFAULT_SAFETY_FACTOR, (f"{path}: {NO_SAFETY_FACTOR}",)
    for i, seg in enumerate(segments):
        try:
            check_kind(seg.pam.geometry, extensile=False, where=f"robot.segments[{i}].pam",
                       role="an anchoring segment")
        except InputError as exc:
            raise InputError(f"{path}: {exc}") from None
    steering = _steering(path, schema.robot.steering)
    elbow = elbow_radius(path, schema.elbow_radius, "elbow_radius")
    grip = MeasuredGrip(path, segments)
    if isinstance(schema.route, NetworkRouteSchema):
        route = network_route(path, schema.route, segments, grip.friction, elbow=elbow)
        sections = [("route", schema.route.friction, schema.route.pipe_material)]
    else:
        route = listed_route(path, schema.route, grip.friction, elbow=elbow)
        sections = [(f"route[{i}] ({s.name})", s.friction, s.pipe_material)
                    for i, s in enumerate(schema.route)]
    warnings += grip.material_warnings(sections) + grip.effective_warning(schema.load_path is not None)
    load_path, kappa, kappa_sd = schema.load_path or "through_anchor", None, 0.0
    if schema.load_path is None and grip.coupling() is not None:
        load_path, (kappa, kappa_sd) = "from_pam", grip.coupling()
    return Mission(path, segments, schema.robot.payload, schema.supply_pressure, safety_factor,
                   load_path, schema.tether_drag, route, dict(schema.gait or {}), warnings,
                   kappa_sd=kappa_sd, load_coupling=kappa, steering=steering, bend_model=schema.bend_model,
                   joint_angle=schema.robot.joint_angle, tether=build_tether(schema.tether))


def _steering(path: Path, schema: SteeringSchema | None) -> Steering | None:
    """The steering module of ``robot.steering``: its PAM must be extensile."""
    if schema is None:
        return None
    pam = _resolve_pam(path, schema.pam, "robot.steering.pam")
    try:
        check_kind(pam.geometry, extensile=True, where="robot.steering.pam", role="a steering PAM")
    except InputError as exc:
        raise InputError(f"{path}: {exc}") from None
    return Steering(pam, schema.count, schema.radius,
                    _relative(path, schema.pam) if isinstance(schema.pam, str) else None)


class MeasuredGrip:
    """The robot's measured wall contact (the PAM files' ``contact:`` blocks), checked to agree when used."""

    def __init__(self, path: Path, segments):
        self.path, self.segments, self.used = path, segments, False

    def _common(self, what: str, where: str, value):
        values = {seg.name: value(seg.pam.grip) if seg.pam.grip is not None else None
                  for seg in self.segments}
        missing = [name for name, v in values.items() if v is None]
        if missing and what == "friction":
            raise InputError(f"{self.path}: {where}: the friction is taken from the PAM files (from_pam "
                             f"or absent), and the PAM of segment(s) {', '.join(missing)} has no contact: "
                             "block; run `pampipe identify` on a slip test (kind: slip) with -o, or give the "
                             "friction, e.g. 'friction: 0.3'.")
        if missing:
            return None
        if len(set(values.values())) > 1:
            shown = ", ".join(f"{name}: {v}" for name, v in values.items())
            raise InputError(f"{self.path}: {where}: the segments' PAM files measured different {what} "
                             f"({shown}); one section has one {what}: give it in the mission, or use PAM "
                             "files that agree.")
        return next(iter(values.values()))

    def friction(self, where: str) -> tuple[float, float]:
        """(μ, σ_μ) of every segment's PAM (they must agree)."""
        self.used = True
        return self._common("friction", where, lambda g: (g.friction, g.friction_sd))

    def effective_warning(self, kappa_given: bool) -> tuple[str, ...]:
        """What a measured friction means when its slip tests did not determine κ (one bore)."""
        grip = self.segments[0].pam.grip
        if not self.used or grip is None or grip.load_coupling is not None:
            return ()
        bores = ", ".join(f"{d * 1e3:.4g} mm" for d in grip.tested_diameters) or "the tested bore"
        path = "the load path" if kappa_given else "load_path through_anchor (kappa = 1, the default)"
        return (f"{self.path}: the PAM's friction {grip.friction:.4g} is the effective friction mu/(1 + "
                f"kappa*mu*pi*A) of slip tests at {bores} only (kappa not determined); with {path} the "
                "plan is conservative for any kappa in [0, 1] (docs/physics.md §13.3); slip tests at a "
                "second bore would give mu and kappa.",)

    def coupling(self) -> tuple[float, float] | None:
        """(κ, σ_κ) when every segment's PAM measured the same κ, else None."""
        if any(seg.pam.grip is None or seg.pam.grip.load_coupling is None for seg in self.segments):
            return None
        return self._common("load_coupling", "load_path", lambda g: (g.load_coupling, g.load_coupling_sd))

    def material_warnings(self, sections) -> tuple[str, ...]:
        """A warning for each section using the measured friction on another pipe material than tested."""
        out = []
        for where, friction, material in sections:
            if friction not in (None, "from_pam") or material is None:
                continue
            tested = {seg.pam.grip.pipe_material for seg in self.segments if seg.pam.grip is not None}
            if tested != {material}:
                shown = ", ".join(sorted(t or "an unnamed material" for t in tested))
                out.append(f"{self.path}: {where}: the friction comes from slip tests on {shown}, and this "
                           f"section's pipe is {material}: friction differs between materials; test a "
                           f"{material} pipe or give the friction.")
        return tuple(out)


def _resolve_pam(owner: Path, ref: str | PamSchema, key: str) -> Pam:
    if isinstance(ref, PamSchema):
        return _build(owner, PamSchema, ref, build_pam, prefix=key)
    target = _relative(owner, ref)
    try:
        return load_pam(target)
    except InputError as exc:
        raise InputError(f"{owner}: {key}: {exc}") from None


def _relative(owner: Path, ref: str) -> Path:
    target = Path(ref).expanduser()
    return target if target.is_absolute() else owner.parent / target


def _build(path: Path, schema_cls, raw, builder, prefix: str = ""):
    schema = raw if isinstance(raw, schema_cls) else _validate(path, schema_cls, raw)
    try:
        return builder(schema)
    except (InputError, ValueError) as exc:
        raise InputError(f"{path}: {prefix + ': ' if prefix else ''}{exc}") from None
