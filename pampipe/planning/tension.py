"""The tether's tension along the route: the cable-pulling model (docs/physics.md §16.1).

From the entry toward the robot, with w the tether's weight per length [N/m] and μ_t its friction on the wall:

* along a straight run of length ℓ at incline φ (positive uphill in the direction of travel) the tension
  grows by w·ℓ·(μ_t·cos φ + sin φ), and never falls below 0 (the tether lies slack):
  T_out = max(0, T_in + w·ℓ·(μ_t·cos φ + sin φ));
* through the bend of angle θ at the end of a section it is multiplied by the capstan factor e^(μ_t·θ):
  T_in(next) = T_out·e^(μ_t·θ);
* at the entry it is the back tension T₀ (reel brake, guide).

Inside a section the tension is affine in the distance x from its entry, T(x) = max(0, T_in + k·x) with
k = w·(μ_t·cos φ + sin φ) [N/m], so its largest value in the section is max(T_in, T_out). The robot carries
that largest tension on top of the load W of docs/physics.md §8 (:func:`section_drag`).
"""

from __future__ import annotations

import numpy as np


def tension_slope(route, tether, friction=None) -> np.ndarray:
    """k = w·(μ_t·cos φ + sin φ) [N/m] of each section (S,), or (S, n) for n frictions ``friction``."""
    mu = np.asarray(tether.friction if friction is None else friction, dtype=float)
    incline = np.asarray(route.incline, dtype=float).reshape(-1, *([1] * mu.ndim))
    return tether.weight * (mu * np.cos(incline) + np.sin(incline))


def tensions(route, tether, friction=None) -> tuple[np.ndarray, np.ndarray]:
    """(T_in, T_out) [N]: the tension at each section's entry (after the previous bend) and at its end
    (before its own bend), (S,); or (S, n) for the n tether frictions ``friction`` (draws)."""
    mu = np.asarray(tether.friction if friction is None else friction, dtype=float)
    along = np.asarray(route.length, dtype=float).reshape(-1, *([1] * mu.ndim))
    gain = tension_slope(route, tether, mu) * along
    count = gain.shape[0]
    bend = np.zeros(count) if route.bend_angle is None else np.asarray(route.bend_angle, dtype=float)
    capstan = np.exp(mu * bend.reshape(-1, *([1] * mu.ndim)))
    t_in, t_out = np.empty_like(gain), np.empty_like(gain)
    tension = np.full(mu.shape, float(tether.back_tension))
    for s in range(count):
        t_in[s] = tension
        tension = np.maximum(tension + gain[s], 0.0)
        t_out[s] = tension
        tension = tension * capstan[s]
    return t_in, t_out


def section_drag(mission):
    """The constant axial load [N] every anchor adds in each section: ``tether_drag`` (a number) without
    a tether; with one, ``tether_drag`` plus the largest tether tension in the section, max(T_in, T_out)
    (S,)."""
    if mission.tether is None:
        return mission.tether_drag
    t_in, t_out = tensions(mission.route, mission.tether)
    return mission.tether_drag + np.maximum(t_in, t_out)


def tether_frictions(tether, samples: int, seed: int) -> np.ndarray:
    """(n,) seeded draws of μ_t ~ N(μ_t, sd), floored at 0 (the ``tether`` stream of
    :func:`pampipe.planning.sources.keyed_normal`: the same in `plan --confidence` and `rehearse`)."""
    from pampipe.planning.sources import keyed_normal

    normal = keyed_normal(seed, "tether", (tether.friction, tether.friction_sd), samples)
    return np.maximum(tether.friction + tether.friction_sd * normal, 0.0)


def drawn_drag(mission, samples: int, seed: int) -> np.ndarray | None:
    """(S, n) [N] :func:`section_drag` in each of ``samples`` draws of the tether's friction
    (:func:`tether_frictions`); None without a tether or without a friction sd."""
    tether = mission.tether
    if tether is None or not tether.friction_sd > 0:
        return None
    t_in, t_out = tensions(mission.route, tether, tether_frictions(tether, samples, seed))
    return mission.tether_drag + np.maximum(t_in, t_out)
