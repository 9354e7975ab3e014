"""The planning problem of one mission, as per-element arrays (docs/physics.md §5, §7, §8).

An *element* is one (section s, segment i) pair. The gait of docs/physics.md §8 anchors, in steps
I…VII, the segments {2}, {1,2}, {1}, {1,3}, {3}, {2,3}, {2}: every segment is the only anchor in
some step, so in every section each segment must hold the section's whole load alone.

* Load on the single anchor i in section s (incline φ, wall friction μ, M = segment masses + payload):
  W = g·(M·|sin φ| + μ·cos φ·(M − m_i)) + tether_drag  [N]  (:func:`pampipe.model.no_slip.incline_load`),
  plus the tether's largest tension in the section where the mission has one (docs/physics.md §16).
* No slip: μπF_r(P, D_s, κW) ≥ SF·W, asked of the segment's :class:`~pampipe.model.muscle.Muscle`.
* Contact: P ≥ max(P_a(κW), 0), the pressure at which the loaded muscle presses on the wall.
* A bore range [D_low, D_high] (a tolerance): each element is planned in its worst bore, the D of the
  range where the least holding pressure is largest (:func:`pampipe.planning.bores.worst_bores`), so that the
  plan holds over the whole range; the element's other numbers are those of that bore.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field
from functools import cached_property
from operator import attrgetter

import numpy as np

from pampipe.model.muscle import Muscle
from pampipe.model.no_slip import STANDARD_GRAVITY, incline_load
from pampipe.planning.bores import worst_bores
from pampipe.planning.tension import section_drag
from pampipe.runtime.alike import distinct_rows, per_distinct, taken_back

#: Sections per pass over the element table: a pass's temporaries stay in cache, so memory is the
#: table itself, linear in elements (benchmarks/bench_plan.py).
CHUNK = 1 << 14


def chunks(count: int):
    """Slices of at most :data:`CHUNK` sections covering ``range(count)``."""
    return (slice(start, min(start + CHUNK, count)) for start in range(0, count, CHUNK))


@dataclass(frozen=True)
class Elements:
    """Per-element arrays of shape (sections, segments), SI; invalid elements hold finite placeholders.

    Each array is the transposed view of a (segments, sections) block, so that a segment's column is
    contiguous; arrays equal for every segment (``friction``, ``load_per_payload``, and ``diameter``
    where every element is valid) are broadcast views. What only the report needs (``length``,
    ``volume``, ``free_anchoring``) is computed on first use.
    """

    diameter: np.ndarray  # D_s [m], the range's worst bore (a placeholder in the muscle's range if invalid)
    diameter_high: np.ndarray  # the largest bore of the range [m] (the same placeholder where invalid)
    load: np.ndarray  # W [N], required hold
    load_per_payload: np.ndarray  # ∂W/∂payload = g(|sin φ| + μ cos φ) [N/kg]
    friction: np.ndarray  # μ [-]
    anchoring: np.ndarray  # P_a(κW) [Pa]: the loaded muscle reaches the wall
    least_pressure: np.ndarray  # [Pa] the least pressure that presses and holds (inf: none, or invalid)
    kappa: float  # κ of the load path
    safety_factor: float  # SF
    valid: np.ndarray  # inside the model's domain over the whole range: D₀ < D_low, D_high < D(B/√3), μ > 0
    muscles: tuple = field(repr=False)  # the segments' Muscle objects
    #: (first, index) where the elements were evaluated once per distinct section and taken back
    #: (:func:`build_elements`), else None
    alike: tuple | None = field(default=None, repr=False, compare=False)

    @property
    def lower_bound(self) -> np.ndarray:
        """Contact constraint as a bound: P ≥ max(P_a(κW), 0) [Pa]."""
        return np.maximum(self.anchoring, 0.0)

    @cached_property
    def length(self) -> np.ndarray:
        """Anchored length L_p = L(D_s) [m]."""
        return self._per_segment(lambda m, i: m.anchored_length(self.diameter[:, i]))

    @cached_property
    def volume(self) -> np.ndarray:
        """V(L_p) = πD²L/4 [m³], the air the segment takes per pascal."""
        return self._per_segment(lambda m, i: m.enclosed_volume(self.length[:, i]))

    @cached_property
    def free_anchoring(self) -> np.ndarray:
        """P_a(0) [Pa]: the unloaded muscle reaches the wall (of the worst bore)."""
        return self._per_segment(lambda m, i: m.anchoring_pressure(self.diameter[:, i], 0.0))

    @cached_property
    def largest_bore_anchoring(self) -> np.ndarray:
        """P_a(D_high, 0) [Pa]: the unloaded muscle first touches the wall everywhere in the range."""
        return self._per_segment(lambda m, i: m.anchoring_pressure(self.diameter_high[:, i], 0.0))

    def take(self, index: np.ndarray, *, alike: tuple | None = None) -> Elements:
        """The elements of the sections ``index`` (an index array), in that order: every array, and every
        report array already computed, taken row-wise in the same layout (a segment's column contiguous,
        a broadcast view still broadcast); ``alike``: their :attr:`alike`."""
        taken = {}
        for key, value in self.__dict__.items():
            if not isinstance(value, np.ndarray):
                continue
            if value.strides[1] == 0:  # one column broadcast to every segment
                taken[key] = np.broadcast_to(value[index, :1], (index.size, value.shape[1]))
            else:
                taken[key] = np.ascontiguousarray(value.T[:, index]).T
        kept = {key: taken.pop(key) for key in _REPORT if key in taken}
        elements = dataclasses.replace(self, **taken, alike=alike)
        elements.__dict__.update(kept)  # the cached report arrays, already taken
        return elements

    def per_section(self, function, *columns):
        """``function(*columns)`` of per-section arrays (first axis: the sections) that maps each section's
        values to its outputs alone, evaluated once per distinct section: the alike sections of
        :attr:`alike` where the columns repeat with them, else :func:`~pampipe.runtime.alike.per_distinct`
        of the columns."""
        if self.alike is not None:
            first, index = self.alike
            if all(np.array_equal(c, c[first][index], equal_nan=True) for c in columns):
                return taken_back(function, columns, first, index)
        return per_distinct(function, *columns)

    def _per_segment(self, value) -> np.ndarray:
        out = np.empty(self.load.shape[::-1])
        for i, muscle in enumerate(self.muscles):
            out[i] = value(muscle, i)
        return out.T


#: The report arrays of :class:`Elements`, computed on first use (cached in the instance).
_REPORT = ("length", "volume", "free_anchoring", "largest_bore_anchoring")


def mission_muscles(mission) -> tuple[Muscle, ...]:
    """The muscle of every segment, rear to front (InputError if a PAM has no moduli)."""
    return tuple(Muscle.from_pam(seg.pam, where=f"{mission.source}: robot.segments[{i}].pam")
                 for i, seg in enumerate(mission.segments))


@dataclass(frozen=True)
class RouteColumns:
    """The arrays of a route the planner reads (SI): bore range, incline and friction per section."""

    diameter: np.ndarray  # nominal bore [m]
    low: np.ndarray  # smallest bore [m]
    high: np.ndarray  # largest bore [m]
    incline: np.ndarray  # [rad]
    friction: np.ndarray


def route_columns(route) -> RouteColumns:
    """The columns of a route: a :class:`~pampipe.specs.mission.Route`, a sequence of
    :class:`~pampipe.specs.mission.Section`, or any object with ``diameter``, ``incline`` and ``friction``
    arrays
    (and optionally ``diameter_low``/``diameter_high``; without them the bore is exact).
    """
    keys = ("diameter", "incline", "friction")
    if all(hasattr(route, key) for key in keys):
        get = {key: np.asarray(getattr(route, key), dtype=float) for key in keys}
        for key in ("diameter_low", "diameter_high"):
            get[key] = np.asarray(getattr(route, key, get["diameter"]), dtype=float)
    else:
        get = {key: np.fromiter(map(attrgetter(key), route), dtype=float, count=len(route))
               for key in (*keys, "diameter_low", "diameter_high")}
    return RouteColumns(get["diameter"], get["diameter_low"], get["diameter_high"], get["incline"],
                        get["friction"])


def build_elements(mission, muscles: tuple[Muscle, ...], *, payload: float | None = None,
                   route=None, drag=None) -> Elements:
    """Evaluate the muscles once per element for ``mission`` (payload [kg] overrides the mission's;
    ``route``, columns as :func:`route_columns` reads them, overrides its route; ``drag`` [N], a number or
    one per section, the constant load added to every anchor's, overrides the mission's
    :func:`~pampipe.planning.tension.section_drag`: ``tether_drag``, plus the tether's largest tension).

    A muscle without effects is evaluated once per element (:meth:`Muscle.affine_coefficients`), and
    the loaded anchoring pressure and the least holding pressure (the NLP's KKT point,
    :meth:`Muscle.least_holding_pressure`) follow from its coefficients in the same pass; sin φ and
    cos φ are taken once per section; the work runs over :data:`CHUNK` sections at a time. Sections with
    a bore range are first searched for their worst bore (:func:`~pampipe.planning.bores.worst_bores`).
    A long route whose sections repeat is evaluated once per distinct section
    (:func:`~pampipe.runtime.alike.distinct_rows` of the numbers above: bores, incline, friction, drag),
    with its report arrays, and taken back to every place (:meth:`Elements.take`): the same floats.
    """
    payload = mission.payload if payload is None else float(payload)
    drag = section_drag(mission) if drag is None else drag
    r = route_columns(mission.route if route is None else route)
    alike = distinct_rows([r.diameter, r.low, r.high, r.incline, r.friction,
                           np.broadcast_to(np.asarray(drag, dtype=float), r.diameter.shape)])
    if alike is not None:
        first, index = alike
        distinct = RouteColumns(*(getattr(r, f.name)[first] for f in dataclasses.fields(r)))
        elements = _elements(mission, muscles, payload, distinct, drag[first] if np.ndim(drag) else drag)
        for key in _REPORT:
            getattr(elements, key)  # computed once per distinct section, then taken
        return elements.take(index, alike=alike)
    return _elements(mission, muscles, payload, r, drag)


def _elements(mission, muscles, payload: float, r: RouteColumns, drag) -> Elements:
    """:func:`build_elements` of the route columns ``r`` (every section evaluated)."""
    count, segments = r.diameter.shape[0], len(muscles)
    total_mass = sum(seg.mass for seg in mission.segments) + payload
    valid = np.empty((segments, count), dtype=bool)
    for i, muscle in enumerate(muscles):
        g = muscle.geometry
        np.logical_and(r.low > g.initial_diameter, r.high < g.largest_diameter, out=valid[i])
        valid[i] &= r.friction > 0
    ranged = r.high > r.low
    shared_diameter = bool(valid.all()) and not ranged.any()
    keys = ["load", "anchoring", "least_pressure"]
    keys += [] if shared_diameter else ["diameter", "diameter_high"]
    blocks = {key: np.empty((segments, count)) for key in keys}
    per_kg = np.empty(count)
    kappa, safety = mission.kappa, mission.safety_factor
    for part in chunks(count):
        mu = r.friction[part]
        rise, run = np.abs(np.sin(r.incline[part])), np.cos(r.incline[part])
        per_kg[part] = STANDARD_GRAVITY * (rise + mu * run)
        for i, (seg, muscle) in enumerate(zip(mission.segments, muscles, strict=True)):
            g = muscle.geometry
            load = incline_load(total_mass, seg.mass, rise, run, mu,
                                drag if np.ndim(drag) == 0 else drag[part])
            if shared_diameter:
                safe = high = r.diameter[part]
            else:
                middle = 0.5 * (g.initial_diameter + g.largest_diameter)
                low, high = (np.where(valid[i, part], v[part], middle) for v in (r.low, r.high))
                safe = low if not ranged[part].any() else worst_bores(
                    muscle, low, high, load, kappa=kappa, friction=mu, safety_factor=safety)
            c = None if muscle.has_effects else muscle.affine_coefficients(safe)
            least = muscle.least_holding_pressure(safe, load, kappa=kappa, friction=mu, safety_factor=safety,
                                                  anchored=c)
            values = {"load": load, "diameter": safe, "diameter_high": high,
                      "least_pressure": np.where(valid[i, part], least, np.inf),
                      "anchoring": muscle.anchoring_pressure(safe, kappa * load, anchored=c)}
            for key, block in blocks.items():
                block[i, part] = values[key]
    columns = {key: block.T for key, block in blocks.items()}
    for key, value in (("friction", r.friction), ("load_per_payload", per_kg), ("diameter", r.diameter),
                       ("diameter_high", r.diameter)):
        columns.setdefault(key, np.broadcast_to(value[:, None], (count, segments)))
    return Elements(**columns, kappa=kappa, safety_factor=safety, valid=valid.T, muscles=tuple(muscles))
