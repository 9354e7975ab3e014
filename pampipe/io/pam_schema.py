"""The PAM file (docs/formats.md §2): :func:`load_pam`, and the SI :class:`~pampipe.model.pam.Pam` built from
its validated content.

A well-formed file is read by its quick check (:data:`pampipe.io.quick_schemas.PAM`); any other is
validated by its strict pydantic schema (:mod:`.pam_model`, imported only then), so that a problem raises
:class:`InputError` naming the file, the key, the value and what is allowed.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from pampipe.errors import InputError
from pampipe.io.field_rules import relative
from pampipe.io.file_units import read_units
from pampipe.io.quick_check import Fallback, Record
from pampipe.io.quick_schemas import PAM
from pampipe.model.domain import check_geometry, check_spread
from pampipe.model.effects import LIBRARY
from pampipe.model.pam import TIES, Geometry, Grip, Moduli, Pam
from pampipe.model.uncertainty import (
    GEOMETRY_NAMES,
    ParameterUncertainty,
    UndeterminedDirection,
    moduli_names,
)
from pampipe.units.quantities import to_si

if TYPE_CHECKING:
    from pampipe.io.pam_model import (
        GripSchema,
        ModuliSchema,
        PamSchema,
        UncertaintySchema,
        UndeterminedSchema,
    )


def _value_sd(entry) -> tuple[float, float | None]:
    """(value, sd) of a plain or ``{value, sd}`` geometry entry (sd None when plain)."""
    if hasattr(entry, "sd"):
        return entry.value, entry.sd
    return entry, None


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


def resolve_pam(owner: Path, ref: str | PamSchema | Record, key: str) -> Pam:
    """The PAM the file ``owner`` names at ``key``: a PAM file's path (beside ``owner``) or an inline
    block (validated)."""
    if not isinstance(ref, str):
        return _build(owner, ref, prefix=key)
    target = relative(owner, ref)
    try:
        return load_pam(target)
    except InputError as exc:
        raise InputError(f"{owner}: {key}: {exc}") from None


def validated_pam(path: Path, raw) -> PamSchema | Record:
    """The PAM file ``path``'s content ``raw`` validated: by the quick check if it plainly accepts it, else
    by the schema (whose message names the problem)."""
    try:
        return PAM(raw)
    except Fallback:
        from pampipe.io.pam_model import PamSchema
        from pampipe.specs.schema import validate

        return validate(path, PamSchema, raw)


def _build(path: Path, raw, prefix: str = "") -> Pam:
    schema = raw if hasattr(raw, "geometry") else validated_pam(path, raw)  # a mapping has no attributes
    try:
        return build_pam(schema)
    except (InputError, ValueError) as exc:
        raise InputError(f"{path}: {prefix + ': ' if prefix else ''}{exc}") from None
