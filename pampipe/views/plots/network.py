"""Plots of a plan along a route and over a pipe network (docs/commands.md §7).

* ``route_profile.png``: the elevation along the route above, the planned pressure of each section
  below (largest over the segments, with the contact pressure of the largest bore and the supply),
  the section that needs most pressure marked, and the bends (green: passed, red: not; their angles);
* ``network_pressure.png``: every pipe of the network in plan view (node coordinates), the planned ones
  coloured by their pressure, those that cannot be planned in red, the others in grey.

Everything drawn comes from the plan: its pressures, and its route's lengths, elevations and network
geometry (:meth:`pampipe.specs.mission.Route.elevation_profile`, :class:`pampipe.specs.network.Network`).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from pampipe.views.tables import new_figure, save_figure

MIN_SPAN = 0.05  # the colour bar spans at least this fraction of the supply pressure

def route_profile(plan, folder: Path, unit: str, scale: float) -> Path:
    """Elevation and planned pressure against distance along the route."""
    a = plan.arrays
    distance, elevation = a.route.elevation_profile()
    pressure = plan.section_pressure / scale
    touch = np.where(a.complete, np.max(a.largest_bore_anchoring, axis=1), np.nan) / scale
    fig, (top, bottom) = new_figure(2, 1, figsize=(9, 6), sharex=True, height_ratios=(1, 1.4))
    top.plot(distance, elevation, color="C2", lw=1.5)
    top.fill_between(distance, elevation, elevation.min(), color="C2", alpha=0.12)
    top.set(ylabel="elevation [m]", title="route profile: elevation and planned pressure along the route")
    top.grid(alpha=0.3)
    bottom.stairs(pressure, distance, baseline=None, color="C0", lw=2,
                  label="planned pressure (largest segment)")
    bottom.stairs(touch, distance, baseline=None, color="grey", ls=":", lw=1.5,
                  label="first touches the largest bore (no load)")
    supply = plan.supply_pressure / scale
    both = np.concatenate([pressure, touch])
    finite = both[np.isfinite(both)]
    low, high = (finite.min(), finite.max()) if finite.size else (0.0, supply)
    if high < supply / 1.5:  # zoom on the pressures, so that their variation shows; the supply is named
        pad = max(0.1 * (high - low), 0.01 * high)
        bottom.set_ylim(low - pad, high + 3 * pad)
        bottom.annotate(f"supply pressure {supply:.4g} {unit}: above this axis", (0.99, 0.97),
                        xycoords="axes fraction", ha="right", va="top", fontsize=8, color="C3")
    else:
        bottom.set_ylim(0, 1.08 * max(supply, high))
        bottom.axhline(supply, color="C3", ls="--", lw=1.2, label="supply pressure")
    for n, s in enumerate(sorted(a.reasons)):
        for ax in (top, bottom):
            ax.axvspan(distance[s], distance[s + 1], color="C3", alpha=0.12, lw=0,
                       label="infeasible section" if n == 0 and ax is bottom else None)
    if np.isfinite(pressure).any():
        s = int(np.nanargmax(np.where(np.isfinite(pressure), pressure, np.nan)))
        middle = 0.5 * (distance[s] + distance[s + 1])
        bottom.annotate(f"most pressure: {a.route.name[s]}\n{pressure[s]:.4g} {unit}", (middle, pressure[s]),
                        xytext=(0, 18), textcoords="offset points", ha="center", fontsize=8,
                        arrowprops={"arrowstyle": "->", "lw": 0.8})
        bottom.axvspan(distance[s], distance[s + 1], color="C1", alpha=0.2, lw=0,
                       label="section of most pressure")
    labelled = set()  # one legend entry per kind of bend, on its first drawn line
    for k, bend in enumerate(plan.bends):  # at the end of the section each bend follows
        at = distance[bend.index + 1]
        colour = "C2" if bend.passable else "C3"
        label = "bend the robot passes" if bend.passable else "bend it cannot pass"
        top.axvline(at, color=colour, lw=0.9, ls="-." if bend.passable else "-", alpha=0.8)
        bottom.axvline(at, color=colour, lw=0.9, ls="-." if bend.passable else "-", alpha=0.8,
                       label=None if label in labelled else label)
        labelled.add(label)
        top.annotate(f"{math.degrees(bend.angle):.0f}°", (at, 1.0), xycoords=("data", "axes fraction"),
                     xytext=(2, -10 - 8 * (k % 2)), textcoords="offset points", fontsize=7, color=colour)
    bottom.set(xlabel="distance along the route [m]", ylabel=f"gauge pressure [{unit}]")
    bottom.grid(alpha=0.3)
    bottom.legend(fontsize=8, loc="best")
    return save_figure(fig, folder, "route_profile.png")


def network_pressure(plan, folder: Path, unit: str, scale: float) -> Path | None:
    """The network in plan view, planned pipes coloured by pressure; None where it has no coordinates."""
    from matplotlib.collections import LineCollection

    route = plan.arrays.route
    origin = route.origin
    net = origin.network
    if not np.isfinite(net.xy).any():
        return None
    fig, ax = new_figure(figsize=(8, 7))
    ax.add_collection(LineCollection(_polylines(net, np.arange(len(net.pipe_ids))), colors="0.8", lw=0.6,
                                     label="pipe not planned (off the route)"))
    pipes = _pipe_index(net, route.name)
    pressure = plan.section_pressure / scale
    planned = np.isfinite(pressure) & plan.arrays.feasible.all(axis=1)
    width = 1.6 if origin.whole else 2.6
    lines = LineCollection(_polylines(net, pipes[planned]), array=pressure[planned], cmap="viridis", lw=width)
    if planned.any():  # a span of a fraction of a kPa would paint rounding noise as a pattern
        low, high = float(np.min(pressure[planned])), float(np.max(pressure[planned]))
        half = max(0.5 * (high - low), MIN_SPAN * plan.supply_pressure / scale / 2)
        lines.set_clim(0.5 * (low + high) - half, 0.5 * (low + high) + half)
    ax.add_collection(lines)
    failed = ~planned
    if failed.any():
        ax.add_collection(LineCollection(_polylines(net, pipes[failed]), colors="C3", lw=width * 0.7,
                                         label="cannot be planned"))
    if not origin.whole:
        for node, marker, name in ((origin.from_node, "o", "from"), (origin.to_node, "s", "to")):
            x, y = net.xy[net.node_index(node)]
            ax.plot(x, y, marker, color="k", ms=7, label=f"{name} {node}")
    fig.colorbar(lines, ax=ax, label=f"planned pressure [{unit}] (largest segment)", shrink=0.8)
    ax.autoscale()
    ax.set_aspect("equal", adjustable="datalim")
    what = "every pipe" if origin.whole else f"route {origin.from_node} → {origin.to_node}"
    ax.set(title=f"network {net.name}: {what}, coloured by planned pressure\n(grey: not planned; red: cannot "
                 "be planned)", xlabel="x (network units)", ylabel="y (network units)")
    ax.ticklabel_format(axis="both", style="plain", useOffset=False)  # coordinates as written, no 1e6 offset
    ax.legend(fontsize=8, loc="best")
    return save_figure(fig, folder, "network_pressure.png")


def _pipe_index(net, names: np.ndarray) -> np.ndarray:
    """Index in the network of each named pipe."""
    order = np.argsort(net.pipe_ids)
    return order[np.searchsorted(net.pipe_ids, names, sorter=order)]


def _polylines(net, pipes: np.ndarray) -> np.ndarray:
    """(pipes, 4, 2) plan points of each pipe: start node, first vertex, last vertex, end node."""
    return np.stack([net.xy[net.start[pipes]], net.after_start[pipes], net.before_end[pipes],
                     net.xy[net.end[pipes]]], axis=1)
