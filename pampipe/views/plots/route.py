"""The main figures of ``pampipe route`` and ``pampipe export`` results (issue 42, item 6), drawn from their
JSON documents only.

* ``route_profile.png``: the route's elevation (the rise of each pipe, length × sin(incline)) and its bore
  against the distance along it, each pipe's name at its start;
* ``export_gait.png``: the gait table the exported C holds: per section the cycle time and the stride.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from pampipe.views.tables import new_figure, save_figure


def plot_route(result, folder: Path | None) -> list[Path]:
    """Elevation [m] and bore [mm] against the distance along the route [m]."""
    sections = result.to_dict()["sections"]
    lengths = np.array([s["length_m"] for s in sections])
    entries = np.concatenate([[0.0], np.cumsum(lengths)])
    rise = lengths * np.sin(np.radians([s["incline_deg"] for s in sections]))
    fig, (top, bottom) = new_figure(2, 1, figsize=(9, 6), sharex=True)
    top.plot(entries, np.concatenate([[0.0], np.cumsum(rise)]), color="C0", lw=1.8, marker=".")
    top.set(ylabel="elevation above the start [m]",
            title=f"route through {result.to_dict()['network']}: {len(sections)} pipes, {entries[-1]:.4g} m")
    bottom.stairs([s["inner_diameter_m"] * 1e3 for s in sections], entries, baseline=None, color="C2", lw=2)
    bottom.set(xlabel="distance along the route [m]", ylabel="inner diameter [mm]")
    for ax in (top, bottom):
        ax.grid(alpha=0.3)
    if len(sections) <= 12:
        for start, section in zip(entries[:-1], sections, strict=True):
            bottom.annotate(section["name"], (start, section["inner_diameter_m"] * 1e3), fontsize=7,
                            xytext=(2, 3), textcoords="offset points")
    return [p for p in [save_figure(fig, folder, "route_profile.png")] if p is not None]


def plot_export(result, folder: Path | None) -> list[Path]:
    """Cycle time [s] and stride [mm] of each exported section (sections whose gait failed left out)."""
    sections = [s for s in result.to_dict()["sections"] if s.get("cycle_time_s") is not None
                and math.isfinite(s["cycle_time_s"])]
    names = [s["name"] for s in sections]
    fig, (left, right) = new_figure(1, 2, figsize=(10, 4))
    left.bar(names, [s["cycle_time_s"] for s in sections], color="C0")
    left.set(ylabel="gait cycle [s]", title="exported gait: cycle time per section")
    right.bar(names, [s["stride_m"] * 1e3 for s in sections], color="C1")
    right.set(ylabel="stride [mm]", title="stride per section")
    for ax in (left, right):
        ax.grid(alpha=0.3, axis="y")
        ax.tick_params(axis="x", labelrotation=30 if len(names) > 4 else 0)
    return [p for p in [save_figure(fig, folder, "export_gait.png")] if p is not None]


def plot_command(result, folder: Path | None) -> list[Path]:
    """The main figure of a file-writing command's result: the route's profile; synth and example have none
    (``plot()`` then says there is nothing to plot)."""
    return plot_route(result, folder) if result.command == "route" else []
