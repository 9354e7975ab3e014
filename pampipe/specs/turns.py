"""Which way a route turns, in the steering module's frame (docs/physics.md §14.4).

The robot travels without rolling, its steering module seen from behind (looking along travel) with PAM 1 at
the top, PAM 2 120° counter-clockwise from it (lower left) and PAM 3 at the lower right. A bend's
``direction`` φ_b is where the centre of the turn lies, measured from PAM 1 toward PAM 2: 0 up, 90° left,
180° down, 270° (−90°) right.

From a network (node coordinates and elevations): the incoming pipe along u₁ = (cos i₁, 0, sin i₁) (its plan
heading as x), the outgoing u₂ = (cos i₂ cos δ, cos i₂ sin δ, sin i₂), δ the signed plan deflection (+ to the
left, counter-clockwise in plan). The turn's centre lies along the part of u₂ across u₁, whose components on
the axes ``left`` = (0, 1, 0) and ``up`` = (−sin i₁, 0, cos i₁) are cos i₂ sin δ and
cos i₁ sin i₂ − sin i₁ cos i₂ cos δ; φ_b = atan2(left, up). Angles in rad.
"""

from __future__ import annotations

import math

import numpy as np

#: The names of the eight 45° sectors of φ_b, from up toward left.
_SECTORS = ("up", "up-left", "left", "down-left", "down", "down-right", "right", "up-right")


def turn_directions(incline_in, incline_out, deflection) -> np.ndarray:
    """φ_b [rad] in (−π, π] of the turn from a pipe of incline ``incline_in`` into one of ``incline_out``,
    its plan heading deflected by ``deflection`` (signed, + left; NaN: no plan data, taken as 0)."""
    i1, i2 = np.asarray(incline_in, dtype=float), np.asarray(incline_out, dtype=float)
    delta = np.nan_to_num(np.asarray(deflection, dtype=float))
    left = np.cos(i2) * np.sin(delta)
    up = np.cos(i1) * np.sin(i2) - np.sin(i1) * np.cos(i2) * np.cos(delta)
    return np.arctan2(left, up)


def turn_name(direction: float) -> str:
    """The turn's direction in words along travel (``up``, ``up-left``, ``left``, …): its 45° sector."""
    sector = round(math.degrees(direction) / 45.0) % len(_SECTORS)
    return _SECTORS[sector]

