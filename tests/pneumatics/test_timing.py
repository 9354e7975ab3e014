"""Pneumatic timing of `pampipe gait`: closed forms and independent derivations of the chamber model."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pampipe.model import braid, forces
from pampipe.model.muscle import Muscle
from pampipe.pneumatics.options import Gas, Valve
from pampipe.pneumatics.timing import (
    GAS_CONSTANT,
    ISO_DENSITY,
    ISO_TEMPERATURE,
    Chamber,
    flow_function,
    mass_flow,
    transition_time,
)

ATM = 101325.0


@pytest.mark.parametrize("volume", [2e-4, 1e-3])
@pytest.mark.parametrize("index", [1.0, 1.4])
@pytest.mark.parametrize("conductance", [2e-9, 8e-9])
def test_rigid_chamber_choked_filling_matches_closed_form(volume, index, conductance):
    """While p/p_s ≤ b the flow is choked and constant, ṁ = C ρ₀ p_s √(T₀/T), so a rigid chamber
    fills linearly: V ṗ = n R T ṁ  ⇒  t = V (p₁ − p₀) / (n R T ṁ)."""
    valve = Valve(sonic_conductance=conductance, critical_pressure_ratio=0.4)
    gas = Gas(temperature=300.0, polytropic_index=index, atmospheric_pressure=ATM)
    supply = 600e3  # gauge; absolute 701 kPa, so choked up to 0.4 × 701 = 280 kPa absolute
    start, target = 0.0, 0.4 * (supply + ATM) - ATM - 1.0  # gauge, just below the choke limit
    flow = conductance * ISO_DENSITY * (supply + ATM) * math.sqrt(ISO_TEMPERATURE / 300.0)
    expected = volume * (target - start) / (index * GAS_CONSTANT * 300.0 * flow)
    got = transition_time(Chamber.rigid(volume), start, target, supply=supply, valve=valve, gas=gas)
    # t = ∫dP/ṗ with a constant integrand here: the quadrature is exact to rounding
    assert got == pytest.approx(expected, rel=1e-13)


def test_iso_flow_function_limits():
    """φ = 1 when choked, continuous at r = b, zero when the pressures meet, decreasing in between."""
    valve = Valve(critical_pressure_ratio=0.3, subsonic_index=0.5)
    r = np.array([0.0, 0.1, 0.3, 0.3 + 1e-9, 0.6, 0.9, 1.0, 1.2])
    phi = flow_function(r, valve)
    assert phi[:3] == pytest.approx([1.0, 1.0, 1.0], abs=1e-12)
    assert phi[3] == pytest.approx(1.0, abs=1e-8)
    assert phi[6] == 0.0 and phi[7] == 0.0
    assert np.all(np.diff(phi[3:7]) < 0)
    # the ISO ellipse; the regularisation ((x + ε)^½ − ε^½)/((1 + ε)^½ − ε^½) moves φ by ≤ √ε = 1e-3
    exact = math.sqrt(1 - ((0.6 - 0.3) / 0.7) ** 2)
    assert phi[4] == pytest.approx(exact, abs=1e-3)
    assert float(mass_flow(2e5, 3e5, valve, Gas())) == 0.0  # no flow uphill


def test_chamber_volume_follows_the_free_contraction_curve(radial_pam):
    """V(P) fitted from the braid model matches πD²L/4 − V_b along L_free(P), and V′ is its slope."""
    geometry, theta = radial_pam.geometry, radial_pam.moduli.as_vector()
    pipe = 0.0762
    chamber = Chamber.of_muscle(Muscle(geometry, theta, 1e6), pipe)
    pressures = np.linspace(0.0, 0.97 * chamber.anchoring_pressure, 57)
    exact = (braid.enclosed_volume(Muscle(geometry, theta, 1e6).free_length(pressures), geometry)
             - forces.bladder_volume(geometry))
    # quintic fit of a smooth curve: 0.1 % of the anchored volume is a loose bound (fit error ~1e-4)
    assert np.max(np.abs(chamber.volume(pressures) - exact)) < 1e-3 * chamber.anchored_volume
    # above contact the braid is held: the anchored volume, from L(D_p) directly; the rounded
    # contact corner (w = 0.004) leaves c₁·w²/(4·0.2)·(V_p − V₀) ≈ 1.5e-5 V_p at 1.2 P_a
    anchored = braid.enclosed_volume(braid.length_at_diameter(pipe, geometry), geometry)
    assert chamber.volume(1.2 * chamber.anchoring_pressure) == pytest.approx(
        anchored - forces.bladder_volume(geometry), rel=5e-5)
    # compliance = derivative of the volume (central differences, step 1 Pa: error ~1e-7)
    mid = pressures[5:-5]
    numeric = (chamber.volume(mid + 1.0) - chamber.volume(mid - 1.0)) / 2.0
    assert chamber.compliance(mid) == pytest.approx(numeric, rel=1e-5)


def test_filling_and_venting_take_longer_with_a_smaller_valve(radial_pam):
    """Time scales as 1/C exactly (the flow law is proportional to C)."""
    chamber = Chamber.of_muscle(Muscle.from_pam(radial_pam), 0.0762)
    times = []
    for c in (4e-9, 8e-9):
        valve = Valve(sonic_conductance=c)
        times.append((transition_time(chamber, 500.0, 121e3, supply=689e3, valve=valve, gas=Gas()),
                      transition_time(chamber, 121e3, 500.0, supply=689e3, valve=valve, gas=Gas())))
    assert times[0][0] == pytest.approx(2 * times[1][0], rel=1e-7)
    assert times[0][1] == pytest.approx(2 * times[1][1], rel=1e-7)
