"""Plots of `rehearse`: the timeline (distance against time) and, with a tether, the tension and pressure
profile of the plan it walks (:mod:`pampipe.views.plots.tether`). Everything drawn is the result's."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from pampipe.views.tables import new_figure, save_figure


def plot_rehearsal(result, folder: Path, *, unit: str = "kPa") -> list[Path]:
    """Write timeline.png and, with a tether, tether_profile.png into ``folder``."""
    paths = [_timeline(result, folder)]
    if result.plan.tether is not None:
        from pampipe.units.quantities import to_si
        from pampipe.views.plots.tether import tether_profile

        paths.append(tether_profile(result.plan, folder, unit, to_si(f"1 {unit}", "pressure")))
    return paths


def _timeline(result, folder: Path) -> Path:
    """Distance from the entry against time, section ends marked, the reach and the route's end."""
    w = result.walk
    hours = np.concatenate([[0.0], np.cumsum(w.time)]) / 3600
    distance = np.concatenate([[0.0], w.entry + w.walked])
    fig, ax = new_figure(figsize=(8, 4.5))
    ax.plot(hours, distance, color="C0", lw=1.8, marker="o" if len(w.time) <= 40 else None, ms=3,
            label="the robot (section ends marked)")
    ax.axhline(float(result.route.length.sum()), color="k", ls="--", lw=1, label="the route's end")
    reach = result.tether.reach
    if not reach.reachable:
        ax.axhline(reach.distance, color="C3", ls=":", lw=1.2,
                   label=f"reach {reach.distance:.4g} m ({reach.limit or reach.reason})")
    ax.set(xlabel="time [h]", ylabel="distance from the entry [m]",
           title=f"rehearsal: {result.time / 3600:.4g} h, {result.free_air:.4g} m³ of free air")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="best")
    return save_figure(fig, folder, "timeline.png")
