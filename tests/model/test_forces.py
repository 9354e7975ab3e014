"""pampipe/model/forces.py term by term against the equations of docs/physics.md written out here from the
geometry's fields (B = L₀/cos α₀, N = L₀ tan α₀/(πD₀), V_b from the wall), and against limit cases: the
stretched braid's levers, the affine split of the bladder force, the axial share of the braid tension,
contact stiffening and the unloaded radial force."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pampipe.model import bladder, forces
from pampipe.model.pam import Geometry

L0, D0, T0 = 0.3143, 0.05715, 0.003175
ALPHA0 = math.radians(90 - 65.92)  # the braid angle from the axis


def _geometry(wall):
    return Geometry.from_transverse_angle(initial_length=L0, initial_diameter=D0,
                                          braid_angle_from_transverse=math.radians(65.92),
                                          bladder_thickness=T0, wall=wall)


def _moduli():
    theta = np.random.default_rng(7).uniform(-0.5e6, 0.5e6, 16)
    theta[0], theta[8] = 1.5e6, 4.4e6
    return theta


TURNS = L0 * math.tan(ALPHA0) / (math.pi * D0)
BRAID = L0 / math.cos(ALPHA0)


def _volume(wall):
    if wall == "thin":
        return math.pi * D0 * T0 * L0
    return math.pi * ((D0 / 2) ** 2 - (D0 / 2 - T0) ** 2) * L0


def test_the_fields_give_the_braid_of_eqs_1_2():
    geometry = _geometry("thin")
    assert geometry.braid_angle == pytest.approx(ALPHA0, rel=1e-12)
    assert forces.bladder_volume(geometry) == pytest.approx(_volume("thin"), rel=1e-12)
    assert forces.bladder_volume(_geometry("thick")) == pytest.approx(_volume("thick"), rel=1e-12)


@pytest.mark.parametrize("stretch", [1.0, 1.04, 1.1])
def test_stretched_thin_levers_are_gaylord_on_the_longer_braid(stretch):
    """docs/physics.md §9b: a braid stretched to B' (N fixed) at (L, D) with B'² = L² + (NπD)²; Gaylord's
    thin levers on it: area = (3L² − B'²)/(4πN²), lever₁ = V_b/L, lever₂ = V_b·L/(B'² − L²). At B' = B (no
    stretch) they are the inextensible braid's levers at D(L)."""
    geometry = _geometry("thin")
    length = 0.27
    diameter = stretch * math.sqrt(BRAID**2 - length**2) / (TURNS * math.pi)
    longer2 = length**2 + (TURNS * math.pi * diameter) ** 2
    v_b = _volume("thin")
    want = ((3 * length**2 - longer2) / (4 * math.pi * TURNS**2), v_b / length,
            v_b * length / (longer2 - length**2))
    got = forces.axial_levers(length, geometry, diameter, stretched=True)
    np.testing.assert_allclose(got, want, rtol=1e-10)
    if stretch == 1.0:
        np.testing.assert_allclose(got, forces.axial_levers(length, geometry), rtol=1e-10)
    else:
        assert got[0] < forces.axial_levers(length, geometry)[0]  # a longer braid pulls less at L


@pytest.mark.parametrize("wall", ["thin", "thick"])
def test_the_affine_bladder_force_is_its_value_and_its_slope_in_pressure(wall):
    """bladder_force is affine in P at fixed L (the stresses of Eq. 8 are): B₀ = bladder_force(0) and
    B₁ = (bladder_force(P₂) − bladder_force(P₁))/(P₂ − P₁), from the stresses σ(P) themselves."""
    geometry, theta = _geometry(wall), _moduli()
    for length in (0.24, 0.28, 0.305):
        at_zero, slope = forces.bladder_force_affine(length, geometry, theta, 1e6)
        low, high = (forces.bladder_force(p, length, geometry, theta, 1e6) for p in (1e5, 7e5))
        assert at_zero == pytest.approx(forces.bladder_force(0.0, length, geometry, theta, 1e6), rel=1e-10)
        assert slope == pytest.approx((high - low) / 6e5, rel=1e-8)
        assert slope != pytest.approx(0.0, abs=1e-9)  # the P-dependent moduli matter here


def test_the_axial_share_of_the_braid_tension_from_eq_12():
    """T cos α − F_ax = PπR_i² − σ₁V_b/L (Eq. 12), R_i = √(R_o² − V_b/(πL)), σ₁ the axial law at ε₁."""
    geometry, theta = _geometry("thick"), _moduli()
    v_b = _volume("thick")
    for pressure, length, stretch in ((3e5, 0.27, 1.0), (6e5, 0.25, 1.05)):
        diameter = stretch * math.sqrt(BRAID**2 - length**2) / (TURNS * math.pi)
        r_i = math.sqrt((diameter / 2) ** 2 - v_b / (math.pi * length))
        sigma_axial = bladder.stresses(pressure, length, diameter, geometry, theta, 1e6)[0]
        want = pressure * math.pi * r_i**2 - sigma_axial * v_b / length
        assert forces.tension_axial_part(pressure, length, diameter, geometry, theta, 1e6) == pytest.approx(
            want, rel=1e-10)


def test_contact_stiffening_is_zero_at_anchoring_and_grows_with_the_pressure_above_it():
    """docs/physics.md §9d: ΔF = ((P − P_anchor)₊/P_ref)·(bladder terms of Δθ at P)."""
    geometry, theta = _geometry("thick"), _moduli()
    extra = 0.3 * theta
    length, anchoring = 0.27, 2.5e5
    assert forces.contact_force_increment(anchoring, length, geometry, extra, 1e6, anchoring) == 0.0
    assert forces.contact_force_increment(1.5e5, length, geometry, extra, 1e6, anchoring) == 0.0
    pressure = 4.5e5
    terms = forces.bladder_force(pressure, length, geometry, extra, 1e6)
    assert terms != pytest.approx(0.0, abs=1e-6)
    assert forces.contact_force_increment(pressure, length, geometry, extra, 1e6, anchoring) == pytest.approx(
        (pressure - anchoring) / 1e6 * terms, rel=1e-12)


def test_the_unloaded_radial_force_is_the_amplified_free_force():
    """F_r = max(0, A·F_ax(P, L_p)) with no axial load given (docs/physics.md §5.3), A = 2πN²D/L_p."""
    geometry, theta = _geometry("thick"), _moduli()
    diameter = 0.052
    length = math.sqrt(BRAID**2 - (TURNS * math.pi * diameter) ** 2)
    amp = 2 * math.pi * TURNS**2 * diameter / length
    for pressure in (3e5, 6e5):
        want = amp * forces.axial_force(pressure, length, geometry, theta, diameter=diameter)
        assert want > 1.0
        assert forces.radial_force(pressure, diameter, geometry, theta) == pytest.approx(want, rel=1e-10)
