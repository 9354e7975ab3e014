"""``tether_profile.png``: the tether's tension and the planned pressures against the distance along the
route, with the reach marked (docs/physics.md §16). Everything drawn is the plan's (its TetherPlan and
arrays)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from pampipe.views.tables import new_figure, save_figure


def tension_line(tether, route) -> tuple[np.ndarray, np.ndarray]:
    """(distance [m], tension [N]) of the tension along the route: T_in to T_out over each section (affine,
    never below 0), the capstan jump at each bend between sections."""
    entries = np.concatenate([[0.0], np.cumsum(route.length)])
    distance = np.repeat(entries, 2)[1:-1]
    tension = np.column_stack([tether.tension_in, tether.tension_out]).ravel()
    return distance, tension


def tether_profile(plan, folder: Path, unit: str, scale: float) -> Path:
    """Tension above, planned pressure (largest segment) and the pressure limit below, reach marked."""
    a, t = plan.arrays, plan.tether
    distance, tension = tension_line(t, a.route)
    entries = np.concatenate([[0.0], np.cumsum(a.route.length)])
    fig, (top, bottom) = new_figure(2, 1, figsize=(9, 6), sharex=True)
    top.plot(distance, tension, color="C1", lw=1.8, label="tether tension")
    top.set(ylabel="tension [N]", title="tether tension and planned pressure along the route")
    top.set_ylim(bottom=0)
    bottom.stairs(plan.section_pressure / scale, entries, baseline=None, color="C0", lw=2,
                  label="planned pressure (largest segment)")
    bottom.axhline(plan.supply_pressure / scale, color="C3", ls="--", lw=1.2, label="supply pressure")
    for ax in (top, bottom):
        ax.axvline(t.reach.distance, color="k" if t.reach.reachable else "C3", lw=1.2, ls=":",
                   label=("route's end (reached)" if t.reach.reachable
                          else f"reach: {t.reach.distance:.4g} m ({t.reach.limit or t.reach.reason})"))
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8, loc="best")
    bottom.set_ylim(bottom=0)
    bottom.set(xlabel="distance along the route [m]", ylabel=f"gauge pressure [{unit}]")
    return save_figure(fig, folder, "tether_profile.png")
