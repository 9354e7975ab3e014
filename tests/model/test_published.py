"""The model against numbers printed in docs/physics.md (§4.4, §5.5, §7, §8), all from the paper's muscles.

Tolerances are half a unit of the last digit printed in the spec, unless stated otherwise.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from pampipe.model import bladder, braid, forces
from pampipe.model.muscle import Muscle

PIPES = {0.0762: dict(anchor=117.00e3, length=286.77e-3, amp=0.951, drop=974.2, slope=16.6),
         0.0889: dict(anchor=165.00e3, length=265.43e-3, amp=1.198, drop=1228.0, slope=15.7)}


@pytest.mark.parametrize("diameter", PIPES)
def test_demo_muscle_anchors_where_the_paper_says(radial_pam, diameter):
    """Issue 2: anchoring at 117.0 / 165.0 kPa (±0.5 kPa) at free lengths 286.77 / 265.43 mm (±0.05 mm)."""
    g, theta = radial_pam.geometry, radial_pam.moduli.as_vector()
    expected = PIPES[diameter]
    anchoring = forces.anchoring_pressure(diameter, g, theta)
    assert anchoring == pytest.approx(expected["anchor"], abs=0.5e3)
    assert Muscle(g, theta).free_length(anchoring)[0] == pytest.approx(expected["length"], abs=0.05e-3)
    assert braid.length_at_diameter(diameter, g) == pytest.approx(expected["length"], abs=0.05e-3)


@pytest.mark.parametrize("diameter", PIPES)
def test_amplification_and_load_drop(radial_pam, diameter):
    """§7: A = 0.951 / 1.198 and a 1024.74 N load lowers F_r by 974.2 / 1228.0 N (moduli-independent)."""
    g, theta = radial_pam.geometry, radial_pam.moduli.as_vector()
    expected = PIPES[diameter]
    assert braid.amplification_factor(diameter, g) == pytest.approx(expected["amp"], abs=5e-4)
    unloaded = forces.radial_force(500e3, diameter, g, theta)
    loaded = forces.radial_force(500e3, diameter, g, theta, axial_load=1024.74)
    assert unloaded - loaded == pytest.approx(expected["drop"], abs=0.05)


@pytest.mark.parametrize("diameter", PIPES)
def test_radial_slope_is_unchanged_by_load(radial_pam, diameter):
    """§5.8/§7: dF_r/dP = A ∂F_ax/∂P = 16.6 / 15.7 N/kPa, with or without axial load (F_r affine in P)."""
    g, theta = radial_pam.geometry, radial_pam.moduli.as_vector()
    for load in (0.0, 1024.74):
        f1 = forces.radial_force(400e3, diameter, g, theta, axial_load=load)
        f2 = forces.radial_force(600e3, diameter, g, theta, axial_load=load)
        assert (f2 - f1) / 200.0 == pytest.approx(PIPES[diameter]["slope"], abs=0.05)


def test_state_at_anchoring_in_3in_pipe(radial_pam):
    """§7: ε₁ = −0.0769, ε₂ = 0.333, σ₁ = −0.115 MPa, σ₂ = 1.30 MPa, t = 2.52 mm, terms +2046/−67/−1979 N."""
    g, theta = radial_pam.geometry, radial_pam.moduli.as_vector()
    length = braid.length_at_diameter(0.0762, g)
    eps1, eps2 = bladder.strains(length, 0.0762, g)
    a1, b1, a2, b2 = bladder.split_moduli(theta)
    assert eps1 == pytest.approx(-0.0769, abs=5e-5)
    assert eps2 == pytest.approx(0.333, abs=5e-4)
    sigma1, sigma2 = bladder.stress(eps1, 0, a1, b1, 1e6), bladder.stress(eps2, 0, a2, b2, 1e6)
    assert sigma1 == pytest.approx(-0.115e6, abs=0.5e3)
    assert sigma2 == pytest.approx(1.30e6, abs=0.005e6)
    assert forces.wall_section(length, g)[2] == pytest.approx(2.52e-3, abs=0.005e-3)
    anchoring = forces.anchoring_pressure(0.0762, g, theta)
    area, lever1, lever2 = forces.axial_levers(length, g)
    assert anchoring * area == pytest.approx(2046, abs=0.5)
    assert sigma1 * lever1 == pytest.approx(-67, abs=0.5)
    assert -sigma2 * lever2 == pytest.approx(-1979, abs=0.5)


def test_free_contraction_range_and_drucker_margin(radial_pam):
    """§7: L_free falls monotonically from 310.7 mm to 209.3 mm at 689 kPa; min tangent modulus 1.32 MPa."""
    g, theta = radial_pam.geometry, radial_pam.moduli.as_vector()
    pressures = np.linspace(0, 689e3, 50)
    lengths = Muscle(g, theta).free_length(pressures)
    assert lengths[0] == pytest.approx(310.7e-3, abs=0.05e-3)
    assert lengths[-1] == pytest.approx(209.3e-3, abs=0.05e-3)
    assert np.all(np.diff(lengths) < 0)
    path = np.linspace(lengths[-1], g.initial_length, 200)
    e1, e2 = bladder.drucker_tangent_moduli(pressures[:, None], path[None, :],
                                            braid.diameter_at_length(path, g)[None, :], g, theta, 1e6)
    assert min(np.min(e1), np.min(e2)) == pytest.approx(1.32e6, abs=0.005e6)


def test_bladder_volume_and_thick_wall_radial_force(radial_pam):
    """§7: V_b = 167.3 cm³; §4.4: the thick force balance gives 4705 N at 400 kPa in the 76.2 mm pipe."""
    g, theta = radial_pam.geometry, radial_pam.moduli.as_vector()
    assert forces.bladder_volume(g) == pytest.approx(167.3e-6, abs=0.05e-6)
    assert forces.radial_force(400e3, 0.0762, g, theta) == pytest.approx(4705, abs=1.0)


def test_axial_load_pam_amplification_crosses_one_just_below_3in(axial_load_pam):
    """§5.5: for the axial-load PAM, A crosses 1 a little below D = 76.2 mm."""
    g = axial_load_pam.geometry
    assert braid.amplification_factor(0.0762, g) > 1.0
    assert braid.amplification_factor(0.0762 * 0.97, g) < 1.0


def test_holding_load_example(radial_pam):
    """§8: demo PAM at 345 kPa in the 76.2 mm pipe, μ = 0.3, κ = 1 holds W_max = 1884 N."""
    g, theta = radial_pam.geometry, radial_pam.moduli.as_vector()
    muscle = Muscle(g, theta, 1e6)
    w_max = muscle.largest_load(345e3, 0.0762, kappa=1.0, friction=0.3, safety_factor=1.0)
    assert w_max == pytest.approx(1884, abs=0.5)
    # at exactly W_max the friction capacity equals the load (independent check of the algebra)
    assert muscle.holding_capacity(345e3, 0.0762, w_max, kappa=1.0, friction=0.3) == pytest.approx(w_max)


def test_stride_table(radial_pam, axial_load_pam):
    """§8: stride L₀ − L(D_p) = 23.90 / 45.24 mm (radial PAM), 25.44 / 48.27 mm (axial-load PAM)."""
    for pam, strides in ((radial_pam, (23.90e-3, 45.24e-3)), (axial_load_pam, (25.44e-3, 48.27e-3))):
        g = pam.geometry
        for diameter, stride in zip((0.0762, 0.0889), strides, strict=True):
            computed = g.initial_length - braid.length_at_diameter(diameter, g)
            assert computed == pytest.approx(stride, abs=0.01e-3)


def test_inferred_radial_pam_geometry(radial_pam):
    """§7: B = 338.92 mm, N = 0.75461 (the YAML stores L₀ and β₀ rounded to 1 µm and 1e-4 deg)."""
    assert radial_pam.geometry.braid_length == pytest.approx(338.92e-3, abs=0.005e-3)
    assert radial_pam.geometry.turns == pytest.approx(0.75461, abs=5e-5)
    assert math.degrees(radial_pam.geometry.braid_angle) == pytest.approx(23.56, abs=0.005)


@pytest.mark.parametrize(("diameter", "shift"), [(0.0762, 58.6e3), (0.0889, 78.3e3)])
def test_axial_load_shifts_anchoring(radial_pam, diameter, shift):
    """§7: a 1024.74 N load shifts anchoring by +58.6 / +78.3 kPa, both by the closed form and by
    the loaded free-contraction root L_free(P; F_a) = L(D_p)."""
    g, theta = radial_pam.geometry, radial_pam.moduli.as_vector()
    base = forces.anchoring_pressure(diameter, g, theta)
    loaded = forces.anchoring_pressure(diameter, g, theta, axial_load=1024.74)
    assert loaded - base == pytest.approx(shift, abs=0.05e3)
    assert Muscle(g, theta).free_length(loaded, axial_load=1024.74)[0] == pytest.approx(
        braid.length_at_diameter(diameter, g), abs=1e-9)
