"""Independent cross-checks of the planning NLP's solution (the plan issue, item 2).

* Closed form (docs/physics.md §8, :func:`pampipe.model.slip.required_pressure`), for muscles without
  contact increments: P* = max(P_req, P_a(κW)).
* Bisection on the full model: the least P with μπF_r(P, D, κW) ≥ SF·W and F_ax(P, L_p) ≥ κW
  (the muscle touches the wall), evaluated with :func:`pampipe.model.slip.holding_capacity` and
  :func:`pampipe.model.forces.axial_force`, which share no code with the NLP's coefficients.

Each check returns the largest relative difference |ΔP| / max(P, 1 kPa) over the elements it covers.
"""

from __future__ import annotations

import numpy as np

from pampipe.model import braid, forces, slip
from pampipe.plan.problem import Elements

PRESSURE_FLOOR = 1e3  # [Pa] floor of the relative difference, so P ≈ 0 cannot blow it up


def closed_form_pressure(mission, elements: Elements) -> np.ndarray:
    """P* from the closed form, NaN for muscles with contact increments or invalid elements."""
    out = np.full(elements.load.shape, np.nan)
    for i, seg in enumerate(mission.segments):
        m = seg.pam.moduli
        if np.any(m.contact_vector()):
            continue
        e, col = elements, elements.valid[:, i]
        d, w, mu = e.diameter[col, i], e.load[col, i], e.friction[col, i]
        args = (seg.pam.geometry, m.as_vector(), m.reference_pressure)
        required = slip.required_pressure(d, *args, w, mission.kappa, mu, mission.safety_factor)
        contact = forces.anchoring_pressure(d, *args, mission.kappa * w)
        out[col, i] = np.maximum(np.maximum(required, contact), 0.0)
    return out


def bisection_pressure(mission, elements: Elements, upper: np.ndarray, *, iterations: int = 64):
    """Least holding pressure by bisection on [0, upper] of the full model (NaN where not bracketed)."""
    out = np.full(elements.load.shape, np.nan)
    for i, seg in enumerate(mission.segments):
        m = seg.pam.moduli
        geometry, theta, pref = seg.pam.geometry, m.as_vector(), m.reference_pressure
        contact = m.contact_vector() if np.any(m.contact_vector()) else None
        col = elements.valid[:, i] & np.isfinite(upper[:, i])
        d, w, mu = elements.diameter[col, i], elements.load[col, i], elements.friction[col, i]
        length = braid.length_at_diameter(d, geometry)

        def holds(p, d=d, w=w, mu=mu, length=length, geometry=geometry, theta=theta, pref=pref,
                  contact=contact):
            capacity = slip.holding_capacity(p, d, geometry, theta, pref, w, mission.kappa, mu, contact)
            touching = forces.axial_force(p, length, geometry, theta, pref) >= mission.kappa * w
            return (capacity >= mission.safety_factor * w) & touching

        low, high = np.zeros_like(d), upper[col, i].copy()
        bracketed = holds(high) & ~holds(low)
        for _ in range(iterations):
            mid = 0.5 * (low + high)
            ok = holds(mid)
            high, low = np.where(ok, mid, high), np.where(ok, low, mid)
        out[col, i] = np.where(bracketed, high, np.nan)
    return out


def largest_difference(reference: np.ndarray, pressure: np.ndarray) -> float | None:
    """max |P − P_ref| / max(P_ref, 1 kPa) over the finite entries of both; None if there are none."""
    both = np.isfinite(reference) & np.isfinite(pressure)
    if not both.any():
        return None
    diff = np.abs(pressure[both] - reference[both]) / np.maximum(np.abs(reference[both]), PRESSURE_FLOOR)
    return float(diff.max())


def cross_check(mission, elements: Elements, pressure: np.ndarray) -> dict:
    """{'closed_form_max_rel_diff': …, 'bisection_max_rel_diff': …} for the solved pressures."""
    upper = np.where(np.isfinite(pressure), 2 * pressure + PRESSURE_FLOOR, np.nan)
    return {"closed_form_max_rel_diff": largest_difference(closed_form_pressure(mission, elements), pressure),
            "bisection_max_rel_diff": largest_difference(bisection_pressure(mission, elements, upper),
                                                         pressure)}
