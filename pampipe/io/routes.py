"""A mission's ``route:`` as columns (:class:`pampipe.specs.mission.Route`), listed or a network (formats.md
§4).

* A list of sections: each ``inner_diameter`` is read by :func:`pampipe.specs.pipes.bore` (a length,
``{value}``,
  ``{nps, schedule}`` or ``{dn, sdr}``, with ``tolerance`` and ``sd``), once per distinct value.
* ``{network, from, to, friction}``: the shortest path by length through the pipes the robot can pass
  (:func:`pampipe.specs.network.route_sections`); without ``from``/``to`` every pipe of the network
  (:func:`pampipe.specs.network.whole_network`). ``tolerance`` and ``sd`` apply to every pipe's bore.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from pampipe.errors import InfeasibleError, InputError
from pampipe.io.distinct_sections import DistinctSections
from pampipe.specs.mission import NetworkRoute, Route
from pampipe.specs.pipes import BoreSpec, bore
from pampipe.specs.turns import turn_directions
from pampipe.units.quantities import bare_numbers, to_si

#: "1.5 D": an elbow radius as a multiple of the bore.
_MULTIPLE = re.compile(r"^\s*([+-]?[0-9]*\.?[0-9]+(?:[eE][+-]?[0-9]+)?)\s*D\s*$")
#: The largest centreline radius of a bend [m]: a wider one is a straight pipe for any robot (a 1 m muscle
#: deflects by 0.1 mm over it); beyond it the bend's geometry leaves the float range (1e300 m overflowed).
LARGEST_RADIUS = 1000.0
#: Joints of a network route that turn by less than this [rad] are not listed as bends (0.5°).
LEAST_NETWORK_BEND = math.radians(0.5)


@dataclass(frozen=True)
class Radius:
    """An elbow's centreline radius: ``value`` [m], or ``value`` times the bore where ``of_bore``."""

    value: float
    of_bore: bool
    text: str

    def at(self, diameter: float, *, path: Path, where: str) -> float:
        """The radius [m] in a pipe of ``diameter``; smaller than half the bore or larger than
        :data:`LARGEST_RADIUS` is an InputError."""
        radius = self.value * diameter if self.of_bore else self.value
        if radius > LARGEST_RADIUS:
            raise InputError(
                f"{path}: {where}: {self.text!r} gives a centreline radius of {radius:.4g} m; a bend's "
                f"radius must be at most {LARGEST_RADIUS:g} m (wider, the pipe is straight for the robot: "
                "leave the bend out).")
        if not radius >= diameter / 2:
            raise InputError(
                f"{path}: {where}: {self.text!r} gives a centreline radius of {radius * 1e3:.4g} mm in a "
                f"{diameter * 1e3:.4g} mm bore; an elbow's radius must be at least half the bore "
                f"({diameter * 500:.4g} mm, '0.5 D'); long-radius elbows are '1.5 D', short-radius '1 D'.")
        return radius


def elbow_radius(path: Path, value, where: str) -> Radius:
    """A :class:`Radius` from a length (``"114 mm"``, a number in m) or a multiple of the bore ("1.5 D")."""
    if isinstance(value, str):
        found = _MULTIPLE.match(value)
        if found and float(found.group(1)) > 0:
            return Radius(float(found.group(1)), True, value)
        if found:
            raise InputError(f"{path}: {where}: {value!r} must be a positive length or a positive multiple "
                             "of the bore ('1.5 D').")
    try:
        radius = to_si(value, "length", where=where)
    except InputError as exc:
        raise InputError(f"{path}: {exc} Give a length ('114 mm') or a multiple of the bore "
                         "('1.5 D').") from None
    if not (math.isfinite(radius) and radius > 0):
        raise InputError(f"{path}: {where}: {value!r} must be a positive length or a multiple of the bore "
                         "('1.5 D').")
    return Radius(radius, False, str(value))


def listed_route(path: Path, sections, measured=None, *, elbow: Radius | None = None,
                 distinct: DistinctSections | None = None) -> Route:
    """The columns of a validated list of sections (``SectionSchema`` objects).

    ``measured(where)`` → (μ, σ_μ) of the robot's PAM files, for sections whose friction is
    ``from_pam`` or absent. A section's ``bend`` without a radius takes ``elbow``; a radius in bores
    (``k D``) is k times the bore the steering segment passes (:func:`_bend_bore`), as in a network route.
    ``distinct``: ``sections`` are the distinct sections of a long route
    (:mod:`pampipe.io.distinct_sections`, which has no bends): each is read once, at its first place, and
    the columns are expanded back to every place.
    """
    names = [s.name for s in sections] if distinct is None else distinct.names
    if len(set(names)) != len(names):
        raise InputError(f"{path}: route: section names must be unique.")
    places = range(len(sections)) if distinct is None else distinct.first
    cache: dict = {}
    bores = [_bore(path, s.inner_diameter, f"route[{i}].inner_diameter", cache)
             for i, s in zip(places, sections, strict=True)]
    friction = [_friction(s.friction, measured, f"route[{i}].friction")
                for i, s in zip(places, sections, strict=True)]
    if distinct is not None:  # every column taken from the distinct sections' at each place
        columns = [column[distinct.index] for column in _columns(sections, bores, friction)]
        labels = np.array([b.label for b in bores], dtype=str)[distinct.index]
        return Route(np.array(names, dtype=str), *columns, label=labels)
    bends = {}
    if any(s.bend is not None for s in sections):
        angle, radius, direction = np.zeros(len(sections)), np.full(len(sections), np.nan), np.full(
            len(sections), math.pi)
        assumed = np.zeros(len(sections), dtype=bool)
        for i, s in enumerate(sections):
            if s.bend is None or s.bend.angle == 0:
                continue
            where = f"route[{i}].bend.radius"
            given = elbow if s.bend.radius is None else elbow_radius(path, s.bend.radius, where)
            if given is None:
                given = elbow_radius(path, "1.5 D", "elbow_radius")
            angle[i], direction[i], assumed[i] = s.bend.angle, s.bend.direction, s.bend.radius is None
            radius[i] = given.at(_bend_bore(bores, i), path=path,
                                 where=where if s.bend.radius is not None else f"elbow_radius (route[{i}])")
        bends = {"bend_angle": angle, "bend_radius": radius, "bend_direction": direction,
                 "bend_radius_assumed": assumed}
    return Route(np.array(names, dtype=str), *_columns(sections, bores, friction),
                 label=np.array([b.label for b in bores], dtype=str), **bends)


def _columns(sections, bores, friction) -> tuple[np.ndarray, ...]:
    """The float columns of :class:`Route` after its names: length, nominal bore, incline, μ, σ_μ, the bore's
    low and high ends and its sd."""
    def column(values) -> np.ndarray:
        return np.fromiter(values, dtype=float, count=len(sections))

    return (column(s.length for s in sections), column(b.nominal for b in bores),
            column(s.incline for s in sections), column(f[0] for f in friction),
            column(f[1] for f in friction), column(b.low for b in bores), column(b.high for b in bores),
            column(b.sd for b in bores))


def _bend_bore(bores, i: int) -> float:
    """D [m] of the bend at the end of section i: the smaller nominal bore of section i and the next (a
    reducer at the elbow), the bore the bend check passes the segments through (pampipe.bends.plan);
    network routes take the same (:func:`_network_bends`)."""
    return min(bores[i].nominal, bores[i + 1].nominal) if i + 1 < len(bores) else bores[i].nominal


def _friction(friction, measured=None, where: str = "route.friction") -> tuple[float, float]:
    """(μ, σ_μ) of a friction given as a number, as ``{value, sd}``, or (``from_pam`` or absent) measured."""
    if friction is None or friction == "from_pam":
        if measured is None:
            raise InputError(f"{where}: give the friction (e.g. 0.3 or {{value: 0.3, sd: 0.05}}).")
        return measured(where)
    return (friction.value, friction.sd) if hasattr(friction, "sd") else (friction, 0.0)


def _bore(path: Path, value, where: str, cache: dict) -> BoreSpec:
    """:func:`bore` of ``value``, computed once per distinct value (a file repeats few bores)."""
    key = _key(value)
    if key is not None and key in cache:
        return cache[key]
    try:
        spec = bore(value, where=where)
    except InputError as exc:
        raise InputError(f"{path}: {exc}") from None
    if key is not None:
        cache[key] = spec
    return spec


def _key(value):
    """A hashable key of a bore value (None if it has none: such values are not cached)."""
    kind = type(value)
    if kind is str or kind is float or kind is int:  # the common cases first
        return kind, value
    if isinstance(value, bool):
        return None
    if isinstance(value, str | int | float):
        return kind, value
    if isinstance(value, dict) and all(isinstance(v, str | int | float) for v in value.values()):
        return tuple(sorted((str(k), type(v), v) for k, v in value.items()))
    return None


def network_route(path: Path, spec, segments, measured=None, *, elbow: Radius | None = None) -> Route:
    """The route of ``{network, from, to, friction, tolerance, sd}`` (a ``NetworkRouteSchema``) for a robot
    of ``segments``: only pipes whose whole bore range lies inside the muscles' range are passed.
    """
    from pampipe.io.epanet import load_network
    from pampipe.specs.network import route_sections, whole_network

    mu, mu_sd = _friction(spec.friction, measured, "route.friction")
    given = [spec.from_node is not None, spec.to_node is not None]
    if any(given) and not all(given):
        raise InputError(f"{path}: route: give both 'from' and 'to' (a route between two nodes) or neither "
                         "(plan every pipe of the network and report the coverage).")
    try:
        net = load_network(spec.network, base=path.parent)
    except InputError as exc:
        raise InputError(f"{path}: route.network: {exc}") from None
    rest = max(seg.pam.geometry.initial_diameter for seg in segments)
    reach = min(seg.pam.geometry.largest_diameter for seg in segments)
    bores = _network_bores(path, spec, net.diameter)
    lookup = {d: b for d, b in zip(np.unique(net.diameter).tolist(), bores, strict=True)}
    whole = not any(given)
    excluded = 0
    if whole:
        sections = whole_network(net, friction=mu)
    else:
        def passable(diameter: float) -> bool:
            return lookup[diameter].low > rest and lookup[diameter].high < reach

        try:
            sections = route_sections(net, str(spec.from_node), str(spec.to_node), friction=mu,
                                      passable=passable)
        except InputError as exc:
            raise InputError(f"{path}: route: {exc}") from None
        except InfeasibleError as exc:
            raise InfeasibleError(f"{path}: route: {exc} The robot passes bores wider than its muscles at "
                                  f"rest ({rest * 1e3:.4g} mm) and anchors in bores narrower than its braids "
                                  f"open to ({reach * 1e3:.4g} mm).") from None
        excluded = int(sum(not passable(d) for d in net.diameter.tolist()))
    index = {node: i for i, node in enumerate(net.node_ids.tolist())}
    entry = np.array([index[n] for n in sections.from_node.tolist()], dtype=np.int64)
    exit_ = np.array([index[n] for n in sections.to_node.tolist()], dtype=np.int64)
    origin = NetworkRoute(net, None if whole else str(spec.from_node), None if whole else str(spec.to_node),
                          entry, exit_, sections.bend, sections.clipped, whole, excluded)
    per_pipe = [lookup[d] for d in sections.diameter.tolist()]
    n = len(sections)
    labels = None
    if spec.tolerance is not None or spec.sd is not None:
        labels = np.array([b.label for b in per_pipe], dtype=str)
    default = elbow or elbow_radius(path, "1.5 D", "elbow_radius")
    bends = {} if whole else _network_bends(path, sections, default)
    return Route(sections.name, sections.length, sections.diameter, sections.incline, sections.friction,
                 np.full(n, float(mu_sd)), np.array([b.low for b in per_pipe]),
                 np.array([b.high for b in per_pipe]), np.array([b.sd for b in per_pipe]), label=labels,
                 origin=origin, **bends)


def turn_angles(sections) -> np.ndarray:
    """(n,) [rad] the turn after each pipe of a network path (0 under 0.5° and after the last): the angle
    between the pipes' 3-D directions, from the plan-view deflection δ and the inclines,
    cos θ = cos i₁ cos i₂ cos δ + sin i₁ sin i₂ (|i₂ − i₁| where the network has no coordinates)."""
    i1, i2 = sections.incline[:-1], sections.incline[1:]
    delta = sections.bend[1:]
    cosine = np.cos(i1) * np.cos(i2) * np.cos(np.nan_to_num(delta)) + np.sin(i1) * np.sin(i2)
    turn = np.where(np.isnan(delta), np.abs(i2 - i1), np.arccos(np.clip(cosine, -1.0, 1.0)))
    angle = np.zeros(len(sections))
    angle[:-1] = np.where(turn >= LEAST_NETWORK_BEND, turn, 0.0)
    return angle


def turn_directions_after(sections) -> np.ndarray:
    """(n,) [rad] which way the route turns after each pipe of a network path, φ_b in the steering
    module's frame (:func:`pampipe.specs.turns.turn_directions`; π after the last pipe)."""
    direction = np.full(len(sections), math.pi)
    deflection = sections.deflection if sections.deflection is not None else sections.bend
    direction[:-1] = turn_directions(sections.incline[:-1], sections.incline[1:], deflection[1:])
    return direction


def _network_bends(path: Path, sections, elbow: Radius) -> dict:
    """The elbow after each pipe of a network path (:func:`turn_angles`), turning as the network's
    coordinates and elevations say (:func:`turn_directions_after`), with the mission's ``elbow_radius`` in
    the smaller of the two bores: a radius the network does not give, so assumed."""
    n = len(sections)
    angle = turn_angles(sections)
    radius = np.full(n, np.nan)
    for i in np.flatnonzero(angle > 0).tolist():
        bore_here = min(float(sections.diameter[i]), float(sections.diameter[i + 1]))
        radius[i] = elbow.at(bore_here, path=path, where=f"elbow_radius (after pipe {sections.name[i]})")
    return {"bend_angle": angle, "bend_radius": radius, "bend_direction": turn_directions_after(sections),
            "bend_radius_assumed": angle > 0}


def _network_bores(path: Path, spec, diameters: np.ndarray) -> list[BoreSpec]:
    """The bore range of each distinct pipe diameter of the network, with the route's tolerance and sd."""
    extra = {key: value for key, value in (("tolerance", spec.tolerance), ("sd", spec.sd))
             if value is not None}
    out = []
    try:
        if extra:  # the user's tolerance and sd, read as the file says (a bare number needs units: SI)
            bore({"value": f"{float(diameters.min())!r} m", **extra}, where="route")
        with bare_numbers(True):  # the network's diameters are SI already
            for d in np.unique(diameters).tolist():
                out.append(bore({"value": d, **extra}, where="route"))
    except InputError as exc:
        raise InputError(f"{path}: {exc}") from None
    return out
