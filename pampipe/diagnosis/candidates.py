"""The candidate explanations of `diagnose`: the library effects and a mis-stated geometry.

A *geometry candidate* says that the PAM file states one geometry entry wrongly. It is refitted,
scored and selected exactly like a library effect (same NLP, BIC, cross-validation and search):

* ``geometry:braid_angle``: α₀ = α₀,stated + δα, δα ∈ [−10°, +10°] (the calibration range of
  `identify`);
* ``geometry:initial_length``: L₀ = L₀,stated·(1 + δL), δL ∈ [−5 %, +5 %];
* ``geometry:bladder_thickness``: t₀ = t₀,stated·(1 + δt), δt ∈ [−75 %, +300 %] (t₀ × [1/4, 4]);
* ``geometry:wall``: the other wall model (thin instead of thick, or thick instead of thin), no
  parameter.

Names are ordered as in :data:`CANDIDATES` (library first): the key of every build and report.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from pampipe.model.effects import LIBRARY, Effect, Parameter, get_effect
from pampipe.model.pam import Geometry

PREFIX = "geometry:"


@dataclass(frozen=True)
class GeometryParameter(Parameter):
    """A geometry correction; ``suffix`` is its JSON unit suffix ("rad" or "" for a ratio)."""

    suffix: str = ""

    @property
    def si_suffix(self) -> str:
        return self.suffix


@dataclass(frozen=True)
class GeometryCandidate:
    """One mis-stated geometry entry: entry ``index`` of :meth:`Geometry.as_vector` corrected by the
    candidate's parameter (added when ``relative`` is False, as a factor 1 + δ when True)."""

    name: str
    summary: str
    index: int | None  # None: the wall model
    relative: bool
    parameters: tuple[Parameter, ...]
    signature: str = ""
    tests: frozenset = frozenset({"axial", "radial"})

    @property
    def null_values(self) -> dict[str, float]:
        return {p.name: p.null for p in self.parameters}

    def corrected(self, vector, value):
        """The geometry vector [L₀, D₀, α₀, t₀] with this entry corrected by ``value`` (SI; numbers or
        CasADi symbols)."""
        if self.index is None:
            return vector
        entries = [vector[i] for i in range(4)]
        old = entries[self.index]
        entries[self.index] = old * (1 + value) if self.relative else old + value
        return entries


GEOMETRY: dict[str, GeometryCandidate] = {c.name: c for c in (
    GeometryCandidate(f"{PREFIX}braid_angle", "the braid angle α₀ is stated wrongly", 2, False,
                      (GeometryParameter("change", "deg", "dimensionless", math.pi / 180, math.radians(-10.0),
                                         math.radians(10.0), 0.0, "α₀ − α₀,stated", suffix="rad"),)),
    GeometryCandidate(f"{PREFIX}initial_length", "the rest length L₀ is stated wrongly", 0, True,
                      (GeometryParameter("relative_change", "%", "dimensionless", 0.01, -0.05, 0.05, 0.0,
                                         "L₀/L₀,stated − 1"),)),
    GeometryCandidate(f"{PREFIX}bladder_thickness", "the bladder thickness t₀ is stated wrongly", 3, True,
                      (GeometryParameter("relative_change", "%", "dimensionless", 0.01, -0.75, 3.0, 0.0,
                                         "t₀/t₀,stated − 1"),)),
    GeometryCandidate(f"{PREFIX}wall", "the other wall model (thin instead of thick or the reverse)", None,
                      False, ()),
)}

#: Cross-validation folds across pressure levels (`diagnose --folds`'s default).
FOLDS = 5
#: Every candidate, in the order of every build and report.
CANDIDATES: tuple[str, ...] = (*LIBRARY, *GEOMETRY)
#: The candidates `diagnose` tries by default. The bladder thickness is asked for by name only
#: (``--effect geometry:bladder_thickness``): over t₀ × [1/4, 4] it trades with the moduli, and as a
#: first step it led the search astray on pairs of library effects (and slowed it 5-fold).
DEFAULT: tuple[str, ...] = tuple(n for n in CANDIDATES if n != f"{PREFIX}bladder_thickness")


def candidate(name: str) -> Effect | GeometryCandidate:
    """The library effect or geometry candidate called ``name``; KeyError lists the known names."""
    if name in GEOMETRY:
        return GEOMETRY[name]
    try:
        return get_effect(name)
    except KeyError:
        raise KeyError(f"unknown effect {name!r}; known: {', '.join(CANDIDATES)}") from None


def library_part(names) -> tuple[str, ...]:
    return tuple(n for n in names if n in LIBRARY)


def geometry_part(names) -> tuple[str, ...]:
    return tuple(n for n in names if n in GEOMETRY)


def wall_of(stated: str, names) -> str:
    """The wall model of a candidate set (the other one with ``geometry:wall``)."""
    if f"{PREFIX}wall" in names:
        return "thin" if stated == "thick" else "thick"
    return stated


def corrected_vector(vector, names, values: dict[str, dict[str, float]]):
    """[L₀, D₀, α₀, t₀] with every geometry candidate of ``names`` applied (SI ``values``)."""
    out = [vector[i] for i in range(4)]
    for name in geometry_part(names):
        c = GEOMETRY[name]
        if c.parameters:
            out = c.corrected(out, values[name][c.parameters[0].name])
    return out


def corrected_geometry(geometry: Geometry, names, values: dict[str, dict[str, float]]) -> Geometry:
    """The stated geometry with the geometry candidates of ``names`` applied."""
    vector = corrected_vector(geometry.as_vector(), names, values)
    return Geometry(*(float(v) for v in vector), wall_of(geometry.wall, names))


def describe(name: str, values: dict[str, float], geometry: Geometry) -> str:
    """The corrected entry in words, e.g. "α₀ = 27.6° instead of the stated 23.6°"."""
    fixed = corrected_geometry(geometry, (name,), {name: values})
    if name == f"{PREFIX}braid_angle":
        return (f"braid angle {math.degrees(fixed.braid_angle):.2f} deg instead of the stated "
                f"{math.degrees(geometry.braid_angle):.2f} deg")
    if name == f"{PREFIX}initial_length":
        return (f"rest length {fixed.initial_length * 1e3:.2f} mm instead of the stated "
                f"{geometry.initial_length * 1e3:.2f} mm")
    if name == f"{PREFIX}bladder_thickness":
        return (f"bladder thickness {fixed.bladder_thickness * 1e3:.3g} mm instead of the stated "
                f"{geometry.bladder_thickness * 1e3:.3g} mm")
    return f"the {fixed.wall}-wall model instead of the stated {geometry.wall}-wall one"
