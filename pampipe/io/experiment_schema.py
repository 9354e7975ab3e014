"""The experiment file (docs/formats.md §3): its strict pydantic schema and :func:`load_experiment`.

The tests' CSV paths are resolved beside the file but not read here (:mod:`.csvfile` reads them). Any problem
raises :class:`InputError` naming the file, the key, the value and what is allowed.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal

import numpy as np
from pydantic import Field, model_validator

from pampipe.errors import InputError
from pampipe.io.field_rules import relative
from pampipe.io.file_units import read_units
from pampipe.io.pam_model import PamSchema
from pampipe.io.pam_schema import load_pam, resolve_pam
from pampipe.io.schema_fields import Force, Length, Pressure
from pampipe.model.domain import check_kind
from pampipe.specs.schema import Strict, validate

if TYPE_CHECKING:
    from pampipe.specs.experiment import Experiment


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


def load_experiment(path: str | Path, *, raw: dict | None = None) -> Experiment:
    """Read and validate an experiment file; CSV paths are resolved but not read here.

    ``raw``: the file's content as a mapping instead; relative paths resolve beside ``path``.
    """
    path = Path(path)
    with read_units(path, raw, what="experiment file") as content:
        return _load_experiment(path, content)


def _load_experiment(path: Path, content: dict) -> Experiment:
    from pampipe.specs.experiment import (  # not needed on plan's start-up path
        DirectionCoding,
        Experiment,
        TestSpec,
    )

    schema = validate(path, ExperimentSchema, content)
    pam = resolve_pam(path, schema.pam, "pam")
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
        tests.append(TestSpec(t.name, t.kind, relative(path, t.data), t.pipe_diameter, t.axial_load,
                              None if t.set_pressures is None else tuple(t.set_pressures), t.protocol,
                              t.pipe_material, None if t.direction is None else DirectionCoding(
                                  t.direction.column, t.direction.loading, t.direction.unloading,
                                  t.direction.held)))
    pam_file = relative(path, schema.pam) if isinstance(schema.pam, str) else None
    fit = dict(schema.fit or {})
    return Experiment(path, pam, tuple(tests), _prior_from_pam(path, fit), pam_file, _prior_file(path, fit))


def _prior_file(path: Path, fit: dict) -> Path | None:
    """The PAM file named by ``fit.prior.pam`` (see :func:`_prior_from_pam`), or None."""
    prior = fit.get("prior")
    return relative(path, prior["pam"]) if isinstance(prior, dict) and isinstance(prior.get("pam"), str) \
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
