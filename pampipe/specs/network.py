"""Routes through pipe networks (docs/commands.md §7): the network graph as columnar arrays, SI.

:class:`Network` is a network's nodes and pipes (read from EPANET files by
:func:`pampipe.io.epanet.load_network`). :func:`route_sections` gives the pipes of the shortest path by
length through the pipes the robot can pass, :func:`whole_network` every pipe, and :func:`coverage` sums
what a plan serves. Only pipes are ever passed: pumps and valves are not.

Conventions:

* a node's elevation is the junction's or tank's elevation (a tank's bottom) or the reservoir's head [m];
* ``incline = asin(Δz / length)`` along travel. Where a model's length is shorter than the elevation
  difference (|Δz| > length, data that no straight pipe can have), the incline is taken as ±90° and the
  pipe is flagged in ``Sections.clipped``;
* bends are plan-view deflections at the joints between consecutive pipes (0 = straight on), from the
  node coordinates and pipe vertices; NaN where the network has no coordinates. ``deflection`` keeps their
  sign (+ to the left), from which :mod:`pampipe.specs.turns` says which way each elbow turns.
"""

from __future__ import annotations

import difflib
import math
from collections import Counter
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from pampipe.errors import InfeasibleError, InputError

#: |Δz| / length above 1 by more than this counts as impossible data (ft -> m rounding stays below).
_CLIP_SLACK = 1e-9


@dataclass(frozen=True, eq=False)
class Network:
    """A pipe network as columnar arrays, SI; nodes and pipes are numbered in the file's order."""

    name: str
    source: Path
    node_ids: np.ndarray  # (N,) str
    elevation: np.ndarray  # (N,) [m] junction or tank elevation, reservoir head
    xy: np.ndarray  # (N, 2) plan coordinates in the file's units; NaN where the file gives none
    pipe_ids: np.ndarray  # (P,) str
    start: np.ndarray  # (P,) int, start node as stored
    end: np.ndarray  # (P,) int, end node as stored
    length: np.ndarray  # (P,) [m]
    diameter: np.ndarray  # (P,) inner diameter [m]
    after_start: np.ndarray  # (P, 2) the next plan point from the start: first vertex, else the end node
    before_end: np.ndarray  # (P, 2) the last plan point before the end: last vertex, else the start node
    other_links: int  # pumps and valves, which the robot never passes

    def node_index(self, node: str, *, role: str = "") -> int:
        """Index of node ``node``; an unknown id is an :class:`InputError` naming the nearest ids."""
        hits = np.flatnonzero(self.node_ids == str(node))
        if hits.size:
            return int(hits[0])
        near = difflib.get_close_matches(str(node), self.node_ids.tolist(), n=5, cutoff=0.5)
        hint = (f"did you mean {', '.join(near)}?" if near else
                f"its {len(self.node_ids)} node ids look like {', '.join(self.node_ids[:5])}, ...")
        what = f"{role} node" if role else "node"
        raise InputError(f"{what} {node!r}: no such node in network {self.name}; {hint}")


@dataclass(frozen=True, eq=False)
class Sections:
    """Pipes as route sections, columnar and SI: one entry per pipe (in travel order for a route)."""

    network: str
    name: np.ndarray  # (n,) pipe ids
    from_node: np.ndarray  # (n,) node ids, entry of travel (as stored in whole_network)
    to_node: np.ndarray  # (n,) node ids, exit of travel
    length: np.ndarray  # (n,) [m]
    diameter: np.ndarray  # (n,) inner diameter [m]
    incline: np.ndarray  # (n,) [rad] above horizontal along travel; |incline| in whole_network
    friction: np.ndarray  # (n,) braid-wall Coulomb coefficient
    bend: np.ndarray  # (n,) [rad] plan-view deflection from the previous pipe; NaN for the first or unknown
    clipped: np.ndarray  # (n,) bool: |Δz| > length, incline set to ±90°
    deflection: np.ndarray | None = None  # (n,) [rad] ``bend`` signed: + to the left (counter-clockwise)

    def __len__(self) -> int:
        return len(self.name)

    def mission_route(self) -> list[dict]:
        """The sections as a mission file's ``route:`` list (docs/formats.md §4), with unit strings."""
        return [{"name": str(n), "length": f"{length:.12g} m", "inner_diameter": f"{d * 1e3:.12g} mm",
                 "incline": f"{math.degrees(a):.12g} deg", "friction": float(mu)}
                for n, length, d, a, mu in zip(self.name, self.length, self.diameter, self.incline,
                                               self.friction, strict=True)]

    def as_document(self) -> list[dict]:
        """One JSON entry per section, SI with unit suffixes (bends in degrees, null where unknown)."""
        return [{"name": str(n), "pipe": str(n), "from": str(a), "to": str(b), "length_m": float(length),
                 "inner_diameter_m": float(d), "incline_deg": math.degrees(i), "friction": float(mu),
                 "bend_deg": None if math.isnan(t) else math.degrees(t), "incline_clipped": bool(c)}
                for n, a, b, length, d, i, mu, t, c in zip(
                    self.name, self.from_node, self.to_node, self.length, self.diameter, self.incline,
                    self.friction, self.bend, self.clipped, strict=True)]


@dataclass(frozen=True)
class Coverage:
    """What a whole-network plan serves: pipes and length, and why the others fail."""

    pipes_total: int
    length_total: float  # [m]
    pipes_feasible: int
    length_feasible: float  # [m]
    reasons: dict[str, int]  # reason -> number of infeasible pipes

    def as_document(self) -> dict:
        return {"pipes_total": self.pipes_total, "pipes_feasible": self.pipes_feasible,
                "length_total_m": self.length_total, "length_feasible_m": self.length_feasible,
                "reasons": dict(self.reasons)}


def route_sections(net: Network, from_node: str, to_node: str, *, friction: float,
                   passable: Callable[[float], bool] | None = None) -> Sections:
    """The pipes of the shortest path by length from ``from_node`` to ``to_node``, in travel order.

    Only pipes whose inner diameter [m] satisfies ``passable`` (default: all) are used. An unknown node is
    an :class:`InputError`; no path an :class:`InfeasibleError`.
    """
    a = net.node_index(from_node, role="from")
    b = net.node_index(to_node, role="to")
    if a == b:
        raise InputError(f"from and to are the same node {from_node!r}; a route needs two different nodes.")
    usable = _passable_mask(net.diameter, passable)
    pipes, forward = _shortest_path(net, usable, a, b)
    if pipes is None:
        excluded = int((~usable).sum())
        raise InfeasibleError(
            f"no route from {from_node} to {to_node} in network {net.name} through the "
            f"{len(usable) - excluded} pipes the robot can pass ({excluded} excluded by their diameter; "
            f"the {net.other_links} pumps and valves are never passed).")
    entry = np.where(forward, net.start[pipes], net.end[pipes])
    exit_ = np.where(forward, net.end[pipes], net.start[pipes])
    incline, clipped = _incline(net.elevation[exit_] - net.elevation[entry], net.length[pipes])
    # plan points just before and just after each joint, along travel
    before_exit = np.where(forward[:, None], net.before_end[pipes], net.after_start[pipes])
    after_entry = np.where(forward[:, None], net.after_start[pipes], net.before_end[pipes])
    deflection = np.full(len(pipes), math.nan)
    deflection[1:] = _deflection(net.xy[entry[1:]] - before_exit[:-1], after_entry[1:] - net.xy[entry[1:]])
    return Sections(net.name, net.pipe_ids[pipes], net.node_ids[entry], net.node_ids[exit_],
                    net.length[pipes], net.diameter[pipes], incline, np.full(len(pipes), float(friction)),
                    np.abs(deflection), clipped, deflection)


def whole_network(net: Network, *, friction: float) -> Sections:
    """Every pipe as a section, in file order and direction as stored.

    The direction of travel is unknown, so ``incline`` is |asin(Δz / length)|: climbing and descending
    the same pipe need different pressures, and the planner must treat both signs. Bends are NaN.
    """
    incline, clipped = _incline(net.elevation[net.end] - net.elevation[net.start], net.length)
    n = len(net.pipe_ids)
    return Sections(net.name, net.pipe_ids, net.node_ids[net.start], net.node_ids[net.end], net.length,
                    net.diameter, np.abs(incline), np.full(n, float(friction)), np.full(n, math.nan),
                    clipped)


def coverage(sections: Sections, *, feasible: Sequence[bool] | np.ndarray,
             reasons: Sequence[str | None] | None = None) -> Coverage:
    """Pipes and length served, given a per-pipe ``feasible`` mask and each infeasible pipe's reason."""
    ok = np.asarray(feasible, dtype=bool)
    if ok.shape != (len(sections),):
        raise ValueError(f"feasible has shape {ok.shape}; expected ({len(sections)},), one per pipe")
    if reasons is not None and len(reasons) != len(sections):
        raise ValueError(f"reasons has {len(reasons)} entries; expected {len(sections)}, one per pipe")
    counts = Counter(str(r) for r, good in zip(reasons or [None] * len(ok), ok, strict=True) if not good)
    return Coverage(len(sections), float(sections.length.sum()), int(ok.sum()),
                    float(sections.length[ok].sum()), dict(counts.most_common()))


def _passable_mask(diameter: np.ndarray, passable: Callable[[float], bool] | None) -> np.ndarray:
    """``passable`` on each pipe diameter, called once per distinct diameter."""
    if passable is None:
        return np.ones(len(diameter), dtype=bool)
    values, inverse = np.unique(diameter, return_inverse=True)
    return np.array([bool(passable(float(d))) for d in values], dtype=bool)[inverse]


def _shortest_path(net: Network, usable: np.ndarray, a: int, b: int):
    """(pipe indices, travelled as stored?) of the shortest path from node a to b, or (None, None)."""
    from scipy.sparse import csr_matrix
    from scipy.sparse.csgraph import dijkstra

    pipes = np.flatnonzero(usable & (net.start != net.end))
    lo = np.minimum(net.start[pipes], net.end[pipes])
    hi = np.maximum(net.start[pipes], net.end[pipes])
    order = np.lexsort((net.length[pipes], hi, lo))  # by node pair, the shortest parallel pipe first
    pipes, lo, hi = pipes[order], lo[order], hi[order]
    first = np.ones(len(pipes), dtype=bool)
    first[1:] = (lo[1:] != lo[:-1]) | (hi[1:] != hi[:-1])
    pipes, lo, hi = pipes[first], lo[first], hi[first]
    n = len(net.node_ids)
    graph = csr_matrix((net.length[pipes], (lo, hi)), shape=(n, n))
    _, predecessor = dijkstra(graph, directed=False, indices=a, return_predecessors=True)
    if predecessor[b] < 0:
        return None, None
    nodes = [b]
    while nodes[-1] != a:
        nodes.append(int(predecessor[nodes[-1]]))
    nodes = np.array(nodes[::-1], dtype=np.int64)
    pair = np.minimum(nodes[:-1], nodes[1:]) * n + np.maximum(nodes[:-1], nodes[1:])
    chosen = pipes[np.searchsorted(lo * n + hi, pair)]  # (lo, hi) keys are sorted by the lexsort
    return chosen, net.start[chosen] == nodes[:-1]


def _incline(rise: np.ndarray, length: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """asin(rise / length) [rad], clipped to ±90°, and where the clip applied."""
    ratio = rise / length
    return np.arcsin(np.clip(ratio, -1.0, 1.0)), np.abs(ratio) > 1 + _CLIP_SLACK


def _deflection(incoming: np.ndarray, outgoing: np.ndarray) -> np.ndarray:
    """Signed angle [rad] from the incoming to the outgoing plan direction (rows), 0 = straight on, + to the
    left (counter-clockwise, x east and y north); NaN for unknown or zero vectors."""
    cross = incoming[:, 0] * outgoing[:, 1] - incoming[:, 1] * outgoing[:, 0]
    dot = np.einsum("ij,ij->i", incoming, outgoing)
    angle = np.arctan2(cross, dot)
    degenerate = (np.hypot(*incoming.T) == 0) | (np.hypot(*outgoing.T) == 0)
    return np.where(degenerate, math.nan, angle)
