"""Bladder strains, the nonlinear moduli law and the Drucker stability expressions (docs/physics.md §4, §6).

The moduli vector θ = [a₁, b₁, a₂, b₂] (each of length degree + 1, in Pa) gives the secant moduli
E_k = Σ_j (a_kj + b_kj P/P_ref) ε_k^j, so σ_k = E_k ε_k. Floats and CasADi symbols alike.
"""

from __future__ import annotations

import math

from pampipe.model.braid import turns


def split_moduli(theta):
    """Split θ into (a₁, b₁, a₂, b₂), each a sequence of degree + 1 coefficients [Pa]."""
    n = theta.shape[0] // 4 if hasattr(theta, "shape") else len(theta) // 4
    return tuple(theta[i * n:(i + 1) * n] for i in range(4))


def strains(length, diameter, geometry):
    """Engineering strains (Eqs. 6-7): ε₁ = (L − L₀)/L₀, ε₂ = (D − D₀)/D₀ [-]."""
    eps_axial = (length - geometry.initial_length) / geometry.initial_length
    eps_hoop = (diameter - geometry.initial_diameter) / geometry.initial_diameter
    return eps_axial, eps_hoop


def stress(strain, pressure, a, b, reference_pressure):
    """σ = Σ_{j=0}^{deg} (a_j + b_j P/P_ref) ε^{j+1} [Pa] (Eq. 8)."""
    scaled = pressure / reference_pressure
    total = 0
    power = strain
    for a_j, b_j in zip(_items(a), _items(b), strict=True):
        total = total + (a_j + b_j * scaled) * power
        power = power * strain
    return total


def stress_sums(strain, a, b):
    """(Σ_j a_j ε^{j+1}, Σ_j b_j ε^{j+1}) [Pa], so that σ = first + (P/P_ref)·second (Eq. 8), by Horner."""
    pairs = list(zip(_items(a), _items(b), strict=True))
    sum_a, sum_b = pairs[-1]
    for a_j, b_j in reversed(pairs[:-1]):
        sum_a, sum_b = sum_a * strain + a_j, sum_b * strain + b_j
    return sum_a * strain, sum_b * strain


def stresses(pressure, length, diameter, geometry, theta, reference_pressure):
    """(σ₁, σ₂) [Pa] at (L, D) and P: both laws of Eq. 8 at the strains of Eqs. 6-7, θ = [a₁, b₁, a₂, b₂]."""
    a1, b1, a2, b2 = split_moduli(theta)
    eps_axial, eps_hoop = strains(length, diameter, geometry)
    return (stress(eps_axial, pressure, a1, b1, reference_pressure),
            stress(eps_hoop, pressure, a2, b2, reference_pressure))


def stress_sum_pairs(length, diameter, geometry, theta):
    """((S₁ᵃ, S₁ᵇ), (S₂ᵃ, S₂ᵇ)) [Pa]: :func:`stress_sums` of both laws at (L, D).

    σ_k = S_kᵃ + (P/P_ref)·S_kᵇ (Eq. 8).
    """
    a1, b1, a2, b2 = split_moduli(theta)
    eps_axial, eps_hoop = strains(length, diameter, geometry)
    return stress_sums(eps_axial, a1, b1), stress_sums(eps_hoop, a2, b2)


def tangent_modulus(strain, pressure, a, b, reference_pressure):
    """Eᵗ = ∂σ/∂ε = Σ_j (j + 1)(a_j + b_j P/P_ref) ε^j [Pa]."""
    scaled = pressure / reference_pressure
    total = 0
    power = 1
    for j, (a_j, b_j) in enumerate(zip(_items(a), _items(b), strict=True)):
        total = total + (j + 1) * (a_j + b_j * scaled) * power
        power = power * strain
    return total


def drucker_tangent_moduli(pressure, length, diameter, geometry, theta, reference_pressure):
    """(E₁ᵗ, E₂ᵗ) [Pa]: the per-direction Drucker stability requires both ≥ 0 (docs/physics.md §6)."""
    a1, b1, a2, b2 = split_moduli(theta)
    eps_axial, eps_hoop = strains(length, diameter, geometry)
    return (tangent_modulus(eps_axial, pressure, a1, b1, reference_pressure),
            tangent_modulus(eps_hoop, pressure, a2, b2, reference_pressure))


def drucker_second_order_work(pressure, length, diameter, geometry, theta, reference_pressure):
    """E₁ᵗ(∂ε₁/∂L)² + E₂ᵗ(∂ε₂/∂L)² [Pa/m²], ≥ 0 for stability along the braid path (docs/physics.md §6).

    ∂ε₁/∂L = 1/L₀ and ∂ε₂/∂L = −L/((Nπ)² D D₀).
    """
    e1, e2 = drucker_tangent_moduli(pressure, length, diameter, geometry, theta, reference_pressure)
    n_pi = turns(geometry) * math.pi
    de1 = 1 / geometry.initial_length
    de2 = -length / (n_pi**2 * diameter * geometry.initial_diameter)
    return e1 * de1**2 + e2 * de2**2


def _items(seq):
    """Iterate over the entries of a list, numpy array or CasADi column vector."""
    if hasattr(seq, "nnz") and hasattr(seq, "shape"):  # CasADi SX/MX/DM
        return [seq[i] for i in range(seq.shape[0])]
    return list(seq)
