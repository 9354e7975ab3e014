"""Model identities: two derivations of one quantity must agree (docs/physics.md §3, §4.4, §5.3, §5.7, §7)."""

from __future__ import annotations

import math

import casadi as ca
import numpy as np
import pytest
from scipy.optimize import brentq

from pampipe.model import bladder, braid, forces
from pampipe.model.muscle import Muscle
from pampipe.model.pam import Geometry

ROUND_OFF = 1e-9  # relative: both sides are O(10³) N sums of O(10³) N terms in double precision


def _geometry(wall="thick"):
    return Geometry.from_transverse_angle(initial_length=0.3143, initial_diameter=0.05715,
                                          braid_angle_from_transverse=math.radians(65.92),
                                          bladder_thickness=0.003175, wall=wall)


def _random_moduli(seed):
    """Cubic moduli with P-dependence, large enough to matter, small enough to keep F_ax sensible."""
    rng = np.random.default_rng(seed)
    theta = rng.uniform(-0.5e6, 0.5e6, 16)
    theta[0], theta[8] = 1.5e6, 4.4e6
    return theta


def _symbolic(geometry_values, wall):
    g = ca.SX.sym("g", 4)
    return g, Geometry(g[0], g[1], g[2], g[3], wall)


@pytest.mark.parametrize("seed", range(3))
def test_thin_wall_force_balance_equals_virtual_work(seed):
    """§4.4: F_ax = −P dV/dL + V_b(σ₁/L + σ₂ (dD/dL)/D) with log strain increments, dV/dL by AD."""
    geometry = _geometry("thin")
    theta = _random_moduli(seed)
    length_sym = ca.SX.sym("L")
    volume = braid.enclosed_volume(length_sym, geometry)
    diameter = braid.diameter_at_length(length_sym, geometry)
    dv = ca.Function("dv", [length_sym], [ca.jacobian(volume, length_sym)])
    dd = ca.Function("dd", [length_sym], [ca.jacobian(diameter, length_sym)])
    a1, b1, a2, b2 = bladder.split_moduli(theta)
    for pressure in (0.0, 2e5, 6e5):
        for length in np.linspace(0.23, 0.31, 5):
            d = float(braid.diameter_at_length(length, geometry))
            eps1, eps2 = bladder.strains(length, d, geometry)
            s1, s2 = bladder.stress(eps1, pressure, a1, b1, 1e6), bladder.stress(eps2, pressure, a2, b2, 1e6)
            work = (-pressure * float(dv(length))
                    + forces.bladder_volume(geometry) * (s1 / length + s2 * float(dd(length)) / d))
            balance = forces.axial_force(pressure, length, geometry, theta)
            assert balance == pytest.approx(work, rel=ROUND_OFF, abs=1e-9)


def test_zero_moduli_thin_wall_axial_force_is_gaylord():
    """§3/§4.3: with zero moduli the thin-wall F_ax is exactly the Gaylord force."""
    geometry = Geometry(0.3143, 0.05715, math.radians(24.08), 3.175e-3, "thin")
    for length in np.linspace(0.22, 0.31, 7):
        assert forces.axial_force(4e5, length, geometry, np.zeros(16)) == pytest.approx(
            braid.gaylord_force(4e5, length, geometry), rel=ROUND_OFF)


def test_zero_moduli_thick_wall_tends_to_gaylord():
    """§4.3: the thick-wall pressure term reduces to Gaylord as R_i → R_o; the gap is O(t₀)."""
    lengths = np.linspace(0.22, 0.31, 7)
    gaps = []
    for thickness in (1e-3, 1e-4, 1e-5):
        geometry = Geometry(0.3143, 0.05715, math.radians(24.08), thickness, "thick")
        force = forces.axial_force(4e5, lengths, geometry, np.zeros(16))
        gaps.append(np.max(np.abs(force / braid.gaylord_force(4e5, lengths, geometry) - 1)))
    # first order in t₀: each tenfold thinner wall shrinks the gap about tenfold (allow 8x..12x)
    assert 8 < gaps[0] / gaps[1] < 12 and 8 < gaps[1] / gaps[2] < 12
    assert gaps[2] < 1e-3


@pytest.mark.parametrize("wall", ["thin", "thick"])
@pytest.mark.parametrize("load", [0.0, 1024.74, -300.0])
def test_eq14_terms_sum_to_identity(wall, load):
    """§5.2-§5.3: the five Eq. 14 terms sum to A·(F_ax(P, L_p) − F_a)."""
    geometry, theta = _geometry(wall), _random_moduli(7)
    for diameter in (0.0762, 0.0889):
        for pressure in (1e5, 4e5, 7e5):
            terms = forces.radial_force_terms(pressure, diameter, geometry, theta, axial_load=load)
            length = braid.length_at_diameter(diameter, geometry)
            identity = braid.amplification_factor(diameter, geometry) * (
                forces.axial_force(pressure, length, geometry, theta) - load)
            assert sum(terms.values()) == pytest.approx(identity, rel=ROUND_OFF, abs=1e-8)


@pytest.mark.parametrize("load", [0.0, 1024.74])
def test_radial_virtual_work_equals_force_balance(load):
    """§5.7: (2/π)[P dV/dD − V_b(σ₁ dε₁/dD + σ₂ dε₂/dD) + F_a dL/dD] = A(F_ax − F_a), thin wall, by AD."""
    geometry, theta = _geometry("thin"), _random_moduli(3)
    d = ca.SX.sym("D")
    length = braid.length_at_diameter(d, geometry)
    volume = math.pi * d**2 * length / 4
    jac = ca.Function("j", [d], [ca.jacobian(volume, d), ca.jacobian(length, d), length])
    a1, b1, a2, b2 = bladder.split_moduli(theta)
    for diameter in (0.07, 0.0762, 0.0889):
        dv, dl, lp = (float(v) for v in jac(diameter))
        eps1, eps2 = bladder.strains(lp, diameter, geometry)
        for pressure in (2e5, 5e5):
            s1, s2 = bladder.stress(eps1, pressure, a1, b1, 1e6), bladder.stress(eps2, pressure, a2, b2, 1e6)
            work = (2 / math.pi) * (pressure * dv - forces.bladder_volume(geometry)
                                    * (s1 * dl / lp + s2 / diameter) + load * dl)
            identity = braid.amplification_factor(diameter, geometry) * (
                forces.axial_force(pressure, lp, geometry, theta) - load)
            assert work == pytest.approx(identity, rel=ROUND_OFF)


def test_amplification_factor_is_minus_two_over_pi_dl_dd():
    """§5.3: A = 2πN²D/L = 2N tan α = (2/π)(−dL/dD)."""
    geometry = _geometry()
    for diameter in (0.06, 0.0762, 0.09):
        amp = braid.amplification_factor(diameter, geometry)
        assert amp == pytest.approx(-2 / math.pi * braid.dlength_ddiameter(diameter, geometry), rel=1e-12)
        alpha = braid.braid_angle_at_length(braid.length_at_diameter(diameter, geometry), geometry)
        assert amp == pytest.approx(2 * braid.turns(geometry) * math.tan(alpha), rel=1e-12)


@pytest.mark.parametrize("load", [0.0, 1024.74])
def test_closed_form_anchoring_equals_free_length_root(radial_pam, load):
    """§7: P_anchor closed form equals the root of L_free(P) = L(D_p) found by brentq on the model."""
    g, theta = radial_pam.geometry, radial_pam.moduli.as_vector()
    for diameter in (0.0762, 0.0889):
        target = braid.length_at_diameter(diameter, g)
        if load == 0.0:
            root = brentq(lambda p, t=target: Muscle(g, theta).free_length(p)[0] - t, 1e3, 689e3, xtol=1e-6)
        else:  # with a load the anchoring point is where F_ax(P, L_p) = F_a
            root = brentq(lambda p, t=target: forces.axial_force(p, t, g, theta) - load, 1e3, 2e6, xtol=1e-6)
        # 1e-3 Pa: free_length bisects to ~1e-15 m; dL/dP ≈ 4e-7 m/Pa converts that to well under 1e-3 Pa
        assert forces.anchoring_pressure(diameter, g, theta, axial_load=load) == pytest.approx(root, abs=1e-3)


def test_free_length_is_the_largest_root(radial_pam):
    """L_free solves F_ax = 0, and F_ax > 0 on (L_free, L₀]: no larger root exists."""
    g, theta = radial_pam.geometry, radial_pam.moduli.as_vector()
    for pressure in (50e3, 300e3, 689e3):
        lf = Muscle(g, theta).free_length(pressure)[0]
        assert abs(forces.axial_force(pressure, lf, g, theta)) < 1e-6
        above = np.linspace(lf + 1e-6, g.initial_length, 500)
        assert np.all(forces.axial_force(pressure, above, g, theta) > 0)
