"""Planning with a diagnosed muscle model: PAM files that carry an ``effects:`` block (docs/physics.md §9).

`pampipe diagnose -o` writes the effects it found into the PAM file. With them the radial force is
:func:`pampipe.model.effects.radial_force_with_effects` and no longer affine in P (braid
extensibility, end effects), so the closed-form KKT solution of :mod:`pampipe.plan.solve` does not
apply to those segments. For them the least pressure with no slip,

    μ·π·F_r^eff(P, D, κW) ≥ SF·W,

is found by a vectorized bisection over all sections on [0, 100 MPa]; F_r^eff is non-decreasing in P
above anchoring for every effect in the library at its allowed parameter values. The effects are
applied as diagnosed (as `simulate` does): drop from the PAM file any effect that belonged to the
test rig rather than to the muscle.
"""

from __future__ import annotations

import math

import numpy as np

from pampipe.model import effects as effect_model
from pampipe.plan.problem import PRESSURE_LIMIT, Elements

ITERATIONS = 80  # bisection halvings of [0, 100 MPa]: 1e8 / 2^80 ≈ 1e-16 Pa, below round-off


def diagnosed_segments(mission) -> list[int]:
    """Indices of the segments whose PAM carries effects."""
    return [i for i, seg in enumerate(mission.segments) if seg.pam.effects]


def radial_force(mission, i: int, pressure, diameter, axial_load):
    """F_r^eff [N] of segment i (numpy arrays), its effects, moduli and contact increments included."""
    pam = mission.segments[i].pam
    m = pam.moduli
    contact = m.contact_vector() if np.any(m.contact_vector()) else None
    return effect_model.radial_force_with_effects(pressure, diameter, pam.geometry, m.as_vector(),
                                                  m.reference_pressure, axial_load, contact, pam.effects)


def holding_capacity(mission, i: int, pressure, elements: Elements, load=None):
    """μπF_r^eff(P, D, κW) [N] of segment i in every section (NaN outside the model's range → 0).

    ``load`` W [N] defaults to each section's required hold.
    """
    e = elements
    load = e.load[:, i] if load is None else load
    radial = radial_force(mission, i, pressure, _safe_diameter(mission, i, e), mission.kappa * load)
    return np.nan_to_num(e.friction[:, i] * math.pi * radial, nan=0.0)


def least_pressure(mission, i: int, elements: Elements) -> np.ndarray:
    """Least P [Pa] with capacity ≥ SF·W for segment i in every section (PRESSURE_LIMIT if none)."""
    e = elements
    required = mission.safety_factor * e.load[:, i]
    low = np.zeros(e.load.shape[0])
    high = np.full_like(low, PRESSURE_LIMIT)
    holds_at_zero = holding_capacity(mission, i, low, e) >= required
    for _ in range(ITERATIONS):
        mid = 0.5 * (low + high)
        ok = holding_capacity(mission, i, mid, e) >= required
        high, low = np.where(ok, mid, high), np.where(ok, low, mid)
    return np.where(holds_at_zero, 0.0, high)


def largest_load(mission, i: int, elements: Elements, pressure: float) -> np.ndarray:
    """W_max [N] segment i holds at ``pressure`` in every section: capacity(P, W) = SF·W, by bisection.

    The capacity falls as W grows (κ ≥ 0) while SF·W rises, so the root is unique in
    [0, capacity(P, 0)/SF]. −1 where the muscle does not grip the wall at all at P.
    """
    pressure = np.full(elements.load.shape[0], float(pressure))
    unloaded = holding_capacity(mission, i, pressure, elements, np.zeros_like(pressure))
    low, high = np.zeros_like(pressure), unloaded / mission.safety_factor
    for _ in range(ITERATIONS):
        mid = 0.5 * (low + high)
        ok = holding_capacity(mission, i, pressure, elements, mid) >= mission.safety_factor * mid
        low, high = np.where(ok, mid, low), np.where(ok, high, mid)
    return np.where(unloaded > 0, low, -1.0)


def _safe_diameter(mission, i: int, e: Elements) -> np.ndarray:
    g = mission.segments[i].pam.geometry
    return np.where(e.valid[:, i], e.diameter[:, i], 0.5 * (g.initial_diameter + g.largest_diameter))
