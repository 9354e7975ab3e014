"""What small errors cost the contact margin (docs/physics.md §15).

The plan holds only if the muscle touches the wall, i.e. the pressure is above the unloaded first-contact
pressure of the largest bore, P_a(D_high, 0) (docs/physics.md §7). Two errors a user cannot rule out move
it: a bore 1 mm wider than stated, and a braid angle 1° off (the angle is the hardest geometry entry to
measure). Their costs are
    ΔP_D = P_a(D_high + 1 mm) − P_a(D_high),  ΔP_α = max over ±1° of P_a(D_high; α₀ ± 1°) − P_a(D_high) [Pa],
and a plan whose contact margin is below the larger one is "thin": an error of that size loses contact.
``plan --confidence`` replaces this rule by the probability of contact under the stated sds.
"""

from __future__ import annotations

import dataclasses
import math
from functools import partial

import numpy as np

from pampipe.model.muscle import Muscle

BORE_STEP = 1e-3  # [m]
ANGLE_STEP = math.radians(1.0)  # [rad]


def contact_costs(muscles, elements) -> np.ndarray:
    """(ΔP_D, ΔP_α) [Pa] per element of ``elements`` (:class:`~pampipe.planning.problem.Elements`), shape
    (sections, segments, 2), at each element's largest bore; NaN where the element is invalid. Once per
    distinct section (:meth:`~pampipe.planning.problem.Elements.per_section`)."""
    valid = elements.valid
    out = np.full((*valid.shape, 2), np.nan)
    for i, muscle in enumerate(muscles):
        if valid[:, i].any():
            costs = elements.per_section(partial(_costs, muscle), elements.diameter_high[:, i])
            out[:, i] = np.where(valid[:, i, None], costs, np.nan)
    return out


def _costs(muscle: Muscle, d: np.ndarray) -> np.ndarray:
    """(ΔP_D, ΔP_α) [Pa] of ``muscle`` at each largest bore ``d`` [m], shape (n, 2)."""
    with np.errstate(invalid="ignore", divide="ignore"):
        touch = muscle.anchoring_pressure(d, 0.0)
        tilted = [_tilted(muscle, sign).anchoring_pressure(d, 0.0) for sign in (1.0, -1.0)]
        return np.stack([muscle.anchoring_pressure(d + BORE_STEP, 0.0) - touch, np.maximum(*tilted) - touch],
                        axis=1)


def _tilted(muscle: Muscle, sign: float) -> Muscle:
    g = muscle.geometry
    geometry = dataclasses.replace(g, braid_angle=g.braid_angle + sign * ANGLE_STEP)
    return Muscle(geometry, muscle.theta, muscle.reference_pressure, contact=muscle.contact,
                  effects=muscle.effects, name=muscle.name)
