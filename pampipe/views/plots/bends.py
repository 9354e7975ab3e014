"""``tightest_bend.png``: the robot's limiting segment in the route's tightest bend, to scale (docs/physics.md
§14.2).

The bend is the one whose limiting segment has the least clearance. Drawn in the bend's plane with equal axes:
the pipe walls (inlet, arc, outlet), the segment as the rectangle L × D₀ at the position that binds (axis
direction ψ*, its inner side on the inner wall's tangent, centred on the room there) in red where it is too
long, and the longest cylinder that passes there, dashed. Everything comes from the plan's ``bends``.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from pampipe.views.tables import new_figure, save_figure


def tightest_bend(plan, folder: Path) -> Path | None:
    """Write tightest_bend.png (None if the route has no bend or its tightest segment passes bent)."""
    bends = [b for b in plan.bends if not b.limiting.flexible and b.limiting.where != "bore"]
    if not bends:
        return None
    bend = min(bends, key=lambda b: b.limiting.clearance)
    s = bend.limiting
    a, radius, theta = bend.bore / 2, bend.radius, bend.angle
    fig, ax = new_figure(figsize=(7, 7))
    straight = max(s.length, s.longest, 2 * bend.bore)
    for offset in (-a, a, 0.0):  # the walls, and the centreline dash-dotted
        ax.plot(*_wall(radius + offset, theta, straight), color="k" if offset else "0.6",
                lw=1.5 if offset else 0.8, ls="-" if offset else "-.")
    back, front = bend.binding_chord
    middle = 0.5 * (back + front)
    too_long = s.length > s.longest
    for length, style, label in (
            (s.length, {"color": "C3" if too_long else "C0", "alpha": 0.35},
             f"{s.name}: {s.length * 1e3:.4g} mm × {s.diameter * 1e3:.4g} mm"
             + (" (too long)" if too_long else "")),
            (s.longest, {"fill": False, "ls": "--", "color": "k"},
             f"longest that passes: {s.longest * 1e3:.4g} mm")):
        corners = _rectangle(radius - a, middle, length, s.diameter)
        ax.fill(*corners.T, label=label, **({"lw": 1.2} | style))
    ax.set_aspect("equal")
    ax.set(xlabel="x from the elbow's centre of curvature [m]",
           ylabel="y from the elbow's centre of curvature [m]",
           title=f"tightest bend: after {bend.after_section!r}, {math.degrees(theta):.1f}°, R = "
                 f"{radius * 1e3:.4g} mm, bore {bend.bore * 1e3:.4g} mm (to scale)\nbinding: {s.where}")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="best")
    return save_figure(fig, folder, "tightest_bend.png")


def _wall(r: float, theta: float, straight: float) -> np.ndarray:
    """A wall at distance r from the elbow's centre: inlet line, arc over [−θ/2, θ/2], outlet line."""
    phi = np.linspace(-theta / 2, theta / 2, 200)
    arc = r * np.stack([np.cos(phi), np.sin(phi)])
    start, end = arc[:, 0], arc[:, -1]
    t_in = np.array([-math.sin(-theta / 2), math.cos(-theta / 2)])
    t_out = np.array([-math.sin(theta / 2), math.cos(theta / 2)])
    inlet = np.stack([start - straight * t_in, start], axis=1)
    outlet = np.stack([end, end + straight * t_out], axis=1)
    return np.concatenate([inlet, arc, outlet], axis=1)


def _rectangle(inner: float, middle: float, length: float, width: float) -> np.ndarray:
    """Corners of the L × d rectangle in the binding mid-bend position (ψ = 0): its inner side on x = R_i,
    centred at y = ``middle``."""
    e, t = np.array([1.0, 0.0]), np.array([0.0, 1.0])
    base = inner * e + middle * t
    half = 0.5 * length * t
    return np.array([base - half, base + half, base + half + width * e, base - half + width * e])
