"""A mission's ``route:`` as columns (:class:`pampipe.mission.Route`), listed or a network (formats.md §4).

* A list of sections: each ``inner_diameter`` is read by :func:`pampipe.pipes.bore` (a length, ``{value}``,
  ``{nps, schedule}`` or ``{dn, sdr}``, with ``tolerance`` and ``sd``), once per distinct value.
* ``{network, from, to, friction}``: the shortest path by length through the pipes the robot can pass
  (:func:`pampipe.network.route_sections`); without ``from``/``to`` every pipe of the network
  (:func:`pampipe.network.whole_network`). ``tolerance`` and ``sd`` apply to every pipe's bore.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from pampipe.errors import InfeasibleError, InputError
from pampipe.mission import NetworkRoute, Route
from pampipe.pipes import BoreSpec, bore


def listed_route(path: Path, sections, measured=None) -> Route:
    """The columns of a validated list of sections (``SectionSchema`` objects).

    ``measured(where)`` → (μ, σ_μ) of the robot's PAM files, for sections whose friction is
    ``from_pam`` or absent.
    """
    names = [s.name for s in sections]
    if len(set(names)) != len(names):
        raise InputError(f"{path}: route: section names must be unique.")
    cache: dict = {}
    bores = [_bore(path, s.inner_diameter, f"route[{i}].inner_diameter", cache)
             for i, s in enumerate(sections)]
    friction = [_friction(s.friction, measured, f"route[{i}].friction") for i, s in enumerate(sections)]

    def column(values) -> np.ndarray:
        return np.fromiter(values, dtype=float, count=len(sections))

    return Route(np.array(names, dtype=str), column(s.length for s in sections),
                 column(b.nominal for b in bores), column(s.incline for s in sections),
                 column(f[0] for f in friction),
                 column(f[1] for f in friction), column(b.low for b in bores), column(b.high for b in bores),
                 column(b.sd for b in bores), label=np.array([b.label for b in bores], dtype=str))


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
    if isinstance(value, bool):
        return None
    if isinstance(value, str | int | float):
        return type(value), value
    if isinstance(value, dict) and all(isinstance(v, str | int | float) for v in value.values()):
        return tuple(sorted((str(k), type(v), v) for k, v in value.items()))
    return None


def network_route(path: Path, spec, segments, measured=None) -> Route:
    """The route of ``{network, from, to, friction, tolerance, sd}`` (a ``NetworkRouteSchema``) for a robot
    of ``segments``: only pipes whose whole bore range lies inside the muscles' range are passed.
    """
    from pampipe.network import load_network, route_sections, whole_network

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
    return Route(sections.name, sections.length, sections.diameter, sections.incline, sections.friction,
                 np.full(n, float(mu_sd)), np.array([b.low for b in per_pipe]),
                 np.array([b.high for b in per_pipe]), np.array([b.sd for b in per_pipe]), label=labels,
                 origin=origin)


def _network_bores(path: Path, spec, diameters: np.ndarray) -> list[BoreSpec]:
    """The bore range of each distinct pipe diameter of the network, with the route's tolerance and sd."""
    extra = {key: value for key, value in (("tolerance", spec.tolerance), ("sd", spec.sd))
             if value is not None}
    out = []
    for d in np.unique(diameters).tolist():
        try:
            out.append(bore({"value": d, **extra}, where="route"))
        except InputError as exc:
            raise InputError(f"{path}: {exc}") from None
    return out
