"""Drucker stability of fitted moduli, checked everywhere in the tested range, not only on the grid.

The NLP enforces the constraint on a (P, L) grid (docs/physics.md §6). Between grid points a
polynomial law can still dip below zero, so after the solve the exact minimum over the whole box
[P_min, P_max] × [L_min, L₀] is computed and, if it is negative, that point becomes a constraint
row (a cutting plane) and the fit is solved again (:data:`ROUNDS` times at most).

Exact minimum of the tangent form: E_kᵗ(ε, P) = Σ_j (j+1)(a_j + b_j P/P_ref) ε^j is affine in P,
so its minimum over a pressure interval lies at an end; at each end it is a polynomial in ε whose
minimum over the strain interval is at an end or at a real root of its derivative. The strain
intervals are the images of [L_min, L_max] (ε₁ = (L − L₀)/L₀ rises with L, ε₂ = (D(L) − D₀)/D₀
falls). The ``sum`` form E₁ᵗ(∂ε₁/∂L)² + E₂ᵗ(∂ε₂/∂L)² is affine in P too; along L it is minimised on
a fine grid (:data:`SUM_POINTS`) refined by golden-section search around the smallest value.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from pampipe.identify.statistics import drucker_rows, tangent_rows
from pampipe.model import bladder, braid
from pampipe.model.pam import Geometry

#: Cutting-plane rounds at most (each adds the worst point of every violated direction).
ROUNDS = 4
#: A margin above −this [Pa] counts as stable (IPOPT's constraint tolerance on rows of unit size in MPa).
TOLERANCE = 1.0
SUM_POINTS = 2001


@dataclass(frozen=True)
class Minimum:
    """The smallest Drucker quantity over the tested box and where it is."""

    value: float  # [Pa] (tangent) or [Pa] scaled by L₀² (sum)
    pressure: float  # [Pa]
    length: float  # [m]
    direction: str  # axial | hoop | sum

    @property
    def stable(self) -> bool:
        return self.value >= -TOLERANCE


def minimum(theta, reference_pressure, geometry: Geometry, pressures, lengths, form: str) -> Minimum:
    """The exact minimum of the Drucker quantity of ``theta`` [Pa] over the box spanned by
    ``pressures`` and ``lengths`` (their extremes)."""
    p_ends = (float(np.min(pressures)), float(np.max(pressures)))
    l_low, l_high = float(np.min(lengths)), float(np.max(lengths))
    if form == "sum":
        return _sum_minimum(theta, reference_pressure, geometry, p_ends, l_low, l_high)
    a1, b1, a2, b2 = (np.asarray(v, float) for v in bladder.split_moduli(np.asarray(theta, float)))
    eps1 = sorted(float(e) for e in bladder.strains(np.array([l_low, l_high]), 0.0, geometry)[0])
    diameters = braid.diameter_at_length(np.array([l_low, l_high]), geometry)
    eps2 = sorted(float(e) for e in (diameters - geometry.initial_diameter) / geometry.initial_diameter)
    best = None
    for direction, a, b, (lo, hi) in (("axial", a1, b1, eps1), ("hoop", a2, b2, eps2)):
        for pressure in p_ends:
            value, eps = _polynomial_minimum((a + b * pressure / reference_pressure)
                                             * np.arange(1, a.size + 1), lo, hi)
            if best is None or value < best.value:
                best = Minimum(value, pressure, _length_of(direction, eps, geometry), direction)
    return best


def _polynomial_minimum(coefficients, low, high) -> tuple[float, float]:
    """(min, argmin) of Σ c_j ε^j over [low, high]: at an end or at a real critical point."""
    poly = np.polynomial.Polynomial(coefficients)
    candidates = [low, high]
    if coefficients.size > 2:
        roots = poly.deriv().roots()
        candidates += [float(r.real) for r in roots if abs(r.imag) < 1e-12 and low < r.real < high]
    values = [float(poly(c)) for c in candidates]
    k = int(np.argmin(values))
    return values[k], candidates[k]


def _length_of(direction: str, eps: float, geometry: Geometry) -> float:
    """L at which the braid path has strain ``eps`` in ``direction`` (Eqs. 3, 6, 7)."""
    if direction == "axial":
        return geometry.initial_length * (1 + eps)
    return float(braid.length_at_diameter(geometry.initial_diameter * (1 + eps), geometry))


def _sum_minimum(theta, pref, geometry, p_ends, l_low, l_high) -> Minimum:
    def work(pressure, length):
        d = braid.diameter_at_length(length, geometry)
        w = bladder.drucker_second_order_work(pressure, length, d, geometry, theta, pref)
        return np.asarray(w, float) * geometry.initial_length**2

    best = None
    lengths = np.linspace(l_low, l_high, SUM_POINTS)
    step = lengths[1] - lengths[0]
    for pressure in p_ends:
        values = work(pressure, lengths)
        k = int(np.argmin(values))
        low, high = max(l_low, lengths[k] - step), min(l_high, lengths[k] + step)
        ratio = (math.sqrt(5) - 1) / 2
        for _ in range(40):  # golden section in the bracketing interval
            c, d = high - ratio * (high - low), low + ratio * (high - low)
            if work(pressure, c) < work(pressure, d):
                high = d
            else:
                low = c
        length = 0.5 * (low + high)
        value = float(min(work(pressure, length), values[k]))
        if best is None or value < best.value:
            best = Minimum(value, pressure, length if value < values[k] else float(lengths[k]), "sum")
    return best


def cut_row(low: Minimum, geometry: Geometry, degree: int, reference_pressure: float) -> np.ndarray:
    """The constraint row(s) (unit max-norm, θ in MPa) that keep the law stable at ``low``'s point."""
    if low.direction == "sum":
        return drucker_rows(geometry, degree, [low.pressure], [low.length], form="sum")
    eps1, eps2 = bladder.strains(low.length, braid.diameter_at_length(low.length, geometry), geometry)
    eps, first = (eps1, 0) if low.direction == "axial" else (eps2, 2)
    row = tangent_rows(float(eps), low.pressure / reference_pressure, degree, first)
    return row / np.max(np.abs(row))
