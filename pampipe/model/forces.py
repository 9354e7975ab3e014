"""Axial force balance, anchoring and the radial (split-pipe) force (docs/physics.md §4.3, §5, §7).

Floats and CasADi symbols alike. ``theta`` is the moduli vector [a₁, b₁, a₂, b₂] in Pa
(see :mod:`pampipe.model.bladder`); ``reference_pressure`` is P_ref [Pa]. SI units throughout.
"""

from __future__ import annotations

import math

from pampipe.model import ops
from pampipe.model.bladder import split_moduli, strains, stress, stress_sum_pairs, stresses
from pampipe.model.braid import (
    amplification_factor,
    braid_length,
    diameter_at_length,
    length_at_diameter,
    turns,
)


def bladder_volume(geometry):
    """V_b [m³]: π(R₀² − (R₀ − t₀)²)L₀ for a thick wall, πD₀t₀L₀ for a thin one (incompressible)."""
    r_o = geometry.initial_diameter / 2
    t0 = geometry.bladder_thickness
    if geometry.wall == "thin":
        return math.pi * geometry.initial_diameter * t0 * geometry.initial_length
    return math.pi * (r_o**2 - (r_o - t0) ** 2) * geometry.initial_length


def wall_section(length, geometry, diameter=None):
    """(R_o, R_i, t) [m] at length L (``diameter``: D(L) if already known).

    Thick wall: R_o = D(L)/2, R_i = √(R_o² − V_b/(πL)), t = R_o − R_i (incompressible bladder).
    Thin wall: R_i = R_o and t = V_b/(πDL).
    """
    r_o = (diameter_at_length(length, geometry) if diameter is None else diameter) / 2
    v_b = bladder_volume(geometry)
    if geometry.wall == "thin":
        return r_o, r_o, v_b / (2 * math.pi * r_o * length)
    r_i = ops.sqrt(inner_room(length, r_o, v_b))
    return r_o, r_i, r_o - r_i


def inner_room(length, r_o, v_b):
    """R_i² = R_o² − V_b/(πL) [m²] of a thick wall at length L (outer radius R_o, bladder volume V_b);
    negative where the bladder does not fit inside the braid."""
    return r_o**2 - v_b / (math.pi * length)


def axial_levers(length, geometry, diameter=None, *, stretched=False):
    """(pressure area, σ₁ lever, σ₂ lever) such that F_ax = P·area + σ₁·lever₁ − σ₂·lever₂ (Eq. 9).

    Thick: area = R_i L²/(2πN²R_o) − πR_i² [m²], lever₁ = V_b/L [m²], lever₂ = t L²/(2πN²R_o) [m²].
    Thin:  area = (3L² − B²)/(4πN²) (Gaylord), lever₂ = V_b L/(B² − L²). ``stretched``: the braid is
    longer than B (docs/physics.md §9b) and ``diameter`` is given: B'² − L² = (NπD)² (N fixed), so the thin
    levers are area = (2L² − (NπD)²)/(4πN²), lever₂ = V_b L/(NπD)²; thick levers depend on D alone.
    """
    n2 = turns(geometry) ** 2
    v_b = bladder_volume(geometry)
    if geometry.wall == "thin" and stretched:
        circ2 = n2 * math.pi**2 * diameter**2  # (NπD)² = B'² − L²
        return ((2 * length**2 - circ2) / (4 * math.pi * n2), v_b / length, v_b * length / circ2)
    if geometry.wall == "thin":
        b = braid_length(geometry)
        return ((3 * length**2 - b**2) / (4 * math.pi * n2), v_b / length,
                v_b * length / (b**2 - length**2))
    r_o, r_i, t = wall_section(length, geometry, diameter)
    shared = length**2 / ((2 * math.pi * n2) * r_o)  # L²/(2πN²R_o)
    return r_i * shared - math.pi * r_i**2, v_b / length, t * shared


def bladder_force(pressure, length, geometry, theta, reference_pressure, *, diameter=None, levers=None):
    """σ₁V_b/L − σ₂(lever₂) [N]: the bladder terms of Eq. 9 (negative in contraction).

    ``diameter`` = D(L) and ``levers`` = :func:`axial_levers` may be passed when already computed.
    """
    if diameter is None:
        diameter = diameter_at_length(length, geometry)
    _, lever1, lever2 = axial_levers(length, geometry, diameter) if levers is None else levers
    sigma_axial, sigma_hoop = stresses(pressure, length, diameter, geometry, theta, reference_pressure)
    return sigma_axial * lever1 - sigma_hoop * lever2


def axial_force(pressure, length, geometry, theta, reference_pressure=1e6, *, diameter=None, stretched=False):
    """F_ax(P, L) [N] (Eq. 9): tension the free muscle holds at length L and gauge pressure P.

    Thick wall: F_ax = P[R_iL²/(2πN²R_o) − πR_i²] + σ₁V_b/L − σ₂tL²/(2πN²R_o).
    ``diameter`` = D(L) may be passed when already known (it saves a square root per point), and must be
    when the braid is ``stretched`` (docs/physics.md §9b: (L, D) then lie on a longer braid, see
    :func:`axial_levers`).
    """
    if diameter is None:
        diameter = diameter_at_length(length, geometry)
    levers = axial_levers(length, geometry, diameter, stretched=stretched)
    return pressure * levers[0] + bladder_force(pressure, length, geometry, theta, reference_pressure,
                                                diameter=diameter, levers=levers)


def bladder_force_affine(length, geometry, theta, reference_pressure, *, diameter=None, levers=None):
    """(B₀, B₁) [N, N/Pa] with :func:`bladder_force` = B₀ + B₁·P at fixed L: the stresses are affine in P.

    B₀ = S₁ᵃ·lever₁ − S₂ᵃ·lever₂ and B₁ = (S₁ᵇ·lever₁ − S₂ᵇ·lever₂)/P_ref with S^a = Σ a_j ε^{j+1},
    S^b = Σ b_j ε^{j+1} (:func:`pampipe.model.bladder.stress_sums`). ``diameter`` and ``levers`` as in
    :func:`bladder_force`.
    """
    if diameter is None:
        diameter = diameter_at_length(length, geometry)
    _, lever1, lever2 = axial_levers(length, geometry, diameter) if levers is None else levers
    (axial_a, axial_b), (hoop_a, hoop_b) = stress_sum_pairs(length, diameter, geometry, theta)
    return (axial_a * lever1 - hoop_a * lever2,
            (axial_b * lever1 - hoop_b * lever2) / reference_pressure)


def axial_force_affine(length, geometry, theta, reference_pressure=1e6, *, diameter=None):
    """(F_ax(0, L), ∂F_ax/∂P) at fixed L [N, N/Pa]: F_ax is affine in P (docs/physics.md §7).

    ``diameter`` = D(L) may be passed when already known (it saves a square root per point).
    """
    if diameter is None:
        diameter = diameter_at_length(length, geometry)
    levers = axial_levers(length, geometry, diameter)
    at_zero, slope = bladder_force_affine(length, geometry, theta, reference_pressure, diameter=diameter,
                                          levers=levers)
    return at_zero, levers[0] + slope


def axial_force_regressors(pressure, length, geometry, degree, reference_pressure=1e6):
    """(offset, φ) with F_ax = offset + φ·θ: F_ax is linear in the moduli θ (for identification).

    offset = P·area [N]; φ has 4(degree + 1) entries [N/Pa] ordered like θ: ε₁^(j+1)·lever₁,
    (P/P_ref)ε₁^(j+1)·lever₁, −ε₂^(j+1)·lever₂, −(P/P_ref)ε₂^(j+1)·lever₂, powers by repeated products.
    """
    diameter = diameter_at_length(length, geometry)
    area, lever1, lever2 = axial_levers(length, geometry, diameter)
    eps_axial, eps_hoop = strains(length, diameter, geometry)
    scaled = pressure / reference_pressure
    rows = []
    for eps, lever in ((eps_axial, lever1), (eps_hoop, -lever2)):
        terms = [eps * lever]
        for _ in range(degree):
            terms.append(terms[-1] * eps)
        rows.append(terms)
        rows.append([scaled * t for t in terms])
    return pressure * area, [t for block in rows for t in block]


def tension_axial_part(pressure, length, diameter, geometry, theta, reference_pressure):
    """T cos α − (pull) = PπR_i² − σ₁V_b/L [N] (Eq. 12) at (L, D), with pull = F_ax (free) or F_a (pipe).

    The axial share of the total braid tension T, which stretches an extensible braid (docs/physics.md §9b).
    """
    _, r_i, _ = wall_section(length, geometry, diameter) if geometry.wall == "thick" else (0, diameter / 2, 0)
    a1, b1, _, _ = split_moduli(theta)
    eps_axial = strains(length, diameter, geometry)[0]
    sigma_axial = stress(eps_axial, pressure, a1, b1, reference_pressure)
    return pressure * math.pi * r_i**2 - sigma_axial * bladder_volume(geometry) / length


def anchoring_pressure(diameter, geometry, theta, reference_pressure=1e6, axial_load=0.0):
    """P_anchor(D_p, F_a) = (F_a − F_ax(0, L_p)) / ∂_P F_ax(L_p) [Pa] (docs/physics.md §7).

    The pressure at which the free-contraction curve reaches the pipe wall, L_free(P) = L(D_p).
    """
    at_zero, slope = axial_force_affine(length_at_diameter(diameter, geometry), geometry, theta,
                                        reference_pressure, diameter=diameter)
    return (axial_load - at_zero) / slope


def contact_force_increment(pressure, length, geometry, contact_theta, reference_pressure, anchoring):
    """ΔF_ax [N] from contact stiffening (docs/physics.md §9d): ((P − P_anchor)₊/P_ref) × bladder terms of Δθ.

    Zero at the anchoring pressure, so stresses are compatible there by construction.
    """
    engaged = ops.fmax(pressure - anchoring, 0) / reference_pressure
    return engaged * bladder_force(pressure, length, geometry, contact_theta, reference_pressure)


def contact_switch(unclipped, smoothing=None, clip=True):
    """F_r = max(0, u) [N] (docs/physics.md §5.3): the wall pushes, it never pulls.

    ``smoothing`` s [N] replaces max by the softplus s·log(1 + exp(u/s)) for gradient-based fitting
    across the anchoring point (docs/physics.md §12); ``clip=False`` returns u itself (the holding
    force of an anchored muscle, smooth, for constraints that only hold where the muscle presses).
    """
    if not clip:
        return unclipped
    if smoothing is None:
        return ops.fmax(unclipped, 0)
    return smoothing * ops.softplus(unclipped / smoothing)


def radial_force(pressure, diameter, geometry, theta, reference_pressure=1e6, axial_load=0.0,
                 contact_theta=None, smoothing=None, *, clip=True):
    """F_r = max(0, A·(F_ax(P, L_p) − F_a)) [N] (docs/physics.md §5.3): the split-pipe separating force.

    ``smoothing`` and ``clip``: see :func:`contact_switch`.
    """
    length = length_at_diameter(diameter, geometry)
    holding = (axial_force(pressure, length, geometry, theta, reference_pressure, diameter=diameter)
               - axial_load)
    if contact_theta is not None:
        anchoring = anchoring_pressure(diameter, geometry, theta, reference_pressure, axial_load)
        holding = holding + contact_force_increment(pressure, length, geometry, contact_theta,
                                                    reference_pressure, anchoring)
    return contact_switch(amplification_factor(diameter, geometry) * holding, smoothing, clip)


def radial_force_terms(pressure, diameter, geometry, theta, reference_pressure=1e6, axial_load=0.0):
    """Term-by-term Eq. 14 (before the contact clip) [N]; the values sum to A·(F_ax − F_a).

    Keys: ``pressure_wall`` 2PR_iL, ``pressure_end_caps`` −A·PπR_i², ``hoop_stress`` −2σ₂tL,
    ``axial_stress`` A·σ₁V_b/L, ``axial_load`` −A·F_a.
    """
    length = length_at_diameter(diameter, geometry)
    _, r_i, t = wall_section(length, geometry)
    amp = amplification_factor(diameter, geometry)
    sigma_axial, sigma_hoop = stresses(pressure, length, diameter, geometry, theta, reference_pressure)
    return {
        "pressure_wall": 2 * pressure * r_i * length,
        "pressure_end_caps": -amp * pressure * math.pi * r_i**2,
        "hoop_stress": -2 * sigma_hoop * t * length,
        "axial_stress": amp * sigma_axial * bladder_volume(geometry) / length,
        "axial_load": -amp * axial_load,
    }


def contact_pressure(radial, diameter, length, paper_literal=False):
    """Mean wall contact pressure [Pa]: p_c = F_r/(D·L) (docs/physics.md §5.6); F_r/(πDL) if paper_literal."""
    projected = diameter * length
    return radial / (math.pi * projected) if paper_literal else radial / projected


def force_per_length(radial, length):
    """f_r = F_r / L [N/m] (Eq. 15)."""
    return radial / length


def total_normal_force(radial):
    """N_tot = ∮p_c dA = π F_r [N] (docs/physics.md §5.4): what wall friction acts on."""
    return math.pi * radial
