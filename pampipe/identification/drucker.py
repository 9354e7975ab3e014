"""Drucker stability of the fitted moduli everywhere in the tested range, not only on grid points.

**Constraint (tangent form, the default).** E_kᵗ(ε, P) = Σ_j (j+1)(a_kj + b_kj P/P_ref) ε^j is affine
in P, so it is non-negative over a pressure interval iff it is at both ends; at each end it is a
polynomial in ε. A polynomial is non-negative on [a, b] if its Bernstein coefficients on [a, b] are
(the polynomial lies in their convex hull), and those coefficients are linear in θ. So
:func:`bernstein_rows` gives rows C with C·θ ≥ 0 ⇒ E₁ᵗ, E₂ᵗ ≥ 0 on every strain interval between the
grid's lengths, at every pressure of the tested range: stability between grid points by
construction (a sufficient condition, slightly conservative on each short interval).

**Check.** After the fit, :func:`minimum` finds the exact minimum over the whole box: at a pressure
end, at a strain end or at a real root of the derivative. The ``sum`` form
E₁ᵗ(∂ε₁/∂L)² + E₂ᵗ(∂ε₂/∂L)² is affine in P too; along L it is constrained on the grid points only
and minimised on a fine grid (:data:`SUM_POINTS`) refined by golden-section search, so the report
states its true minimum, between grid points included.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass
from math import comb

import numpy as np

from pampipe.model import bladder, braid
from pampipe.model.pam import Geometry

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


def bernstein_rows(geometries, degree: int, pressures, lengths, *, reference_pressure: float) -> np.ndarray:
    """Rows C (unit max-norm, θ in MPa) with C·θ ≥ 0 ⇒ E₁ᵗ, E₂ᵗ ≥ 0 for every P in the range of
    ``pressures`` and every strain the grid's ``lengths`` reach (see the module docstring).

    One geometry: the intervals between the strains of consecutive grid lengths. Several (the
    corners of a calibration's bounds): the union of their strain ranges, cut into as many equal
    intervals, so that the constraint holds whatever geometry the fit settles on.
    """
    lengths = np.sort(np.asarray(lengths, float))  # not unique: the row count depends on len(lengths) only
    strains = [_strains(g, lengths) for g in geometries]
    if len(geometries) == 1:
        edges = [np.sort(strains[0][0]), np.sort(strains[0][1])]
    else:
        edges = [np.linspace(min(s[k].min() for s in strains), max(s[k].max() for s in strains), lengths.size)
                 for k in (0, 1)]
    k = degree + 1
    ends = (float(np.min(pressures)) / reference_pressure, float(np.max(pressures)) / reference_pressure)
    rows = []
    for first, eps in ((0, edges[0]), (2, edges[1])):
        for a, b in itertools.pairwise(eps):
            to_bernstein = _bernstein(a, b, degree)
            for x in ends:
                coefficients = np.zeros((k, 4 * k))  # c_j = (j+1)(a_j + b_j x): rows over θ
                for j in range(k):
                    coefficients[j, first * k + j] = j + 1
                    coefficients[j, (first + 1) * k + j] = (j + 1) * x
                rows.append(to_bernstein @ coefficients)
    out = np.vstack(rows)
    return out / np.max(np.abs(out), axis=1, keepdims=True)


def _strains(geometry: Geometry, lengths):
    d0 = geometry.initial_diameter
    return ((lengths - geometry.initial_length) / geometry.initial_length,
            (braid.diameter_at_length(lengths, geometry) - d0) / d0)


def _bernstein(a: float, b: float, degree: int) -> np.ndarray:
    """B with β = B·c: the Bernstein coefficients on [a, b] of Σ_j c_j ε^j (ε = a + (b − a)t)."""
    h = b - a
    shift = np.zeros((degree + 1, degree + 1))  # t-monomial m_k = Σ_j C(j, k) a^(j−k) h^k c_j
    for j in range(degree + 1):
        for kk in range(j + 1):
            shift[kk, j] = comb(j, kk) * a ** (j - kk) * h**kk
    basis = np.zeros((degree + 1, degree + 1))  # β_i = Σ_{k≤i} C(i, k)/C(d, k) m_k
    for i in range(degree + 1):
        for kk in range(i + 1):
            basis[i, kk] = comb(i, kk) / comb(degree, kk)
    return basis @ shift


def grid_low(geometry, low: float) -> float:
    """The shortest grid length [m]: ``low``, but above the braid's shortest length B/√3 of ``geometry``."""
    return max(low, geometry.shortest_length * 1.001)


def grid_lengths(geometry, pipes, low, options) -> np.ndarray:
    """``grid_lengths`` lengths from ``low`` to L₀ and the pipes' anchored lengths, sorted (a fixed count:
    the NLP's Drucker rows keep their number when a calibrated geometry moves them)."""
    pipe_lengths = [float(braid.length_at_diameter(d, geometry)) for d in pipes]
    return np.sort(np.concatenate([np.linspace(low, geometry.initial_length, options.grid_lengths),
                                   pipe_lengths]))
