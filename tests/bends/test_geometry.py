"""Passability of a rigid cylinder through an elbow against an independent 3-D brute-force search
(tests/support/bend_check.py), closed forms and limit cases (docs/physics.md §14)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pampipe.bends.geometry import (
    chord_interval,
    elbow_radius_needed,
    flexible_bend_radius,
    rigid_passage,
)
from tests.support.bend_check import longest_passing

BORE = 0.0762  # 3 in
TOLERANCE = 0.5e-3  # [m]: the agreement on the limiting length


def _bends(count: int, seed: int):
    """(angle [deg], radius [D], diameter [D]) spread over 15–180°, 1–5 D and tight to loose fits."""
    rng = np.random.default_rng(seed)
    angles = np.concatenate([[15, 180], rng.uniform(15, 180, count - 2)])
    radii = np.concatenate([[1, 5], rng.uniform(1, 5, count - 2)])
    fits = rng.uniform(0.4, 0.95, count)
    return list(zip(angles.tolist(), radii.tolist(), fits.tolist(), strict=True))


def chord(psi, **bend):
    """chord(ψ) [m]: the length of the module's interval of a cylinder on the inner wall's tangent at ψ."""
    back, front = chord_interval(psi, **bend)
    return front - back


def classical(radius, d):
    """Pigging's mid-bend chord 2√(R_o² − (R_i + d)²) [m], both ends on the arc."""
    return 2 * math.sqrt((radius + BORE / 2) ** 2 - (radius - BORE / 2 + d) ** 2)


def _compare(angle_deg, radius_d, fit_d):
    theta, radius, diameter = math.radians(angle_deg), radius_d * BORE, fit_d * BORE
    exact = rigid_passage(bore=BORE, radius=radius, angle=theta, diameter=diameter).longest
    check = longest_passing(bore=BORE, radius=radius, angle=theta, diameter=diameter)
    return exact, check


@pytest.mark.parametrize("bend", [(15, 1.0, 0.75), (90, 1.5, 0.75), (180, 2.0, 0.9), (60, 1.0, 0.97)])
def test_agrees_with_brute_force_search(bend):
    exact, check = _compare(*bend)
    assert abs(exact - check) <= TOLERANCE


@pytest.mark.parametrize("bend", [(15, 1.0, 0.75), (90, 1.5, 0.6), (135, 3.0, 0.9), (180, 1.2, 0.5)])
def test_the_longest_length_is_the_least_chord_over_directions(bend):
    """L* = min over ψ ∈ [0, θ/2] of chord(ψ), to 1e-9 m: the minimum found by a scan of 20,001 directions and
    scipy's bounded Brent search around its best, against the module's closed form chord(0) (§14.2)."""
    from scipy.optimize import minimize_scalar

    theta, radius, diameter = math.radians(bend[0]), bend[1] * BORE, bend[2] * BORE

    def length(psi):
        return chord(psi, bore=BORE, radius=radius, angle=theta, diameter=diameter)

    scan = np.linspace(0.0, theta / 2, 20001)
    values = np.array([length(psi) for psi in scan])
    k = int(np.argmin(values))
    found = minimize_scalar(length, bounds=(scan[max(k - 1, 0)], scan[min(k + 1, scan.size - 1)]),
                            method="bounded", options={"xatol": 1e-13})
    least = min(float(found.fun), float(values[k]))
    assert rigid_passage(bore=BORE, radius=radius, angle=theta, diameter=diameter).longest == \
        pytest.approx(least, abs=1e-9)


def test_no_bend_binds_away_from_the_symmetric_direction():
    """§14.2's proof that ψ = 0 binds (E convex and non-increasing in the room left, the outer side binding),
    checked on 300 random bends (1–180°, R 0.5–6 D, fits 0.05–0.999 D): no direction of a 401-point scan of
    chord(ψ) over [0, θ/2] is shorter than chord(0), which is what rigid_passage returns; its ends lie on the
    arc exactly where chord(0) is the classical chord."""
    rng = np.random.default_rng(14)
    for _ in range(300):
        theta = rng.uniform(math.radians(1), math.pi)
        radius, diameter = rng.uniform(0.5, 6) * BORE, rng.uniform(0.05, 0.999) * BORE
        kw = {"bore": BORE, "radius": radius, "angle": theta, "diameter": diameter}
        least = min(chord(psi, **kw) for psi in np.linspace(0.0, theta / 2, 401))
        assert rigid_passage(**kw).longest == pytest.approx(chord(0.0, **kw), rel=1e-12)
        assert least >= chord(0.0, **kw) * (1 - 1e-12)
        on_arc = chord(0.0, **kw) == pytest.approx(classical(radius, diameter), rel=1e-9)
        assert rigid_passage(**kw).where == ("mid-bend, ends on the arc" if on_arc
                                             else "mid-bend, ends in the straight pipes")


@pytest.mark.slow
def test_agrees_on_fifty_bends_passable_and_not():
    """≥ 50 bends, angles 15–180°, radii 1–5 D: |L* − L_check| ≤ 0.5 mm; the paper's segment (L₀ = 314 mm)
    passes some of them and not others, and the verdicts agree."""
    length = 0.314325
    verdicts = []
    worst = 0.0
    for bend in _bends(52, seed=28):
        exact, check = _compare(*bend)
        worst = max(worst, abs(exact - check))
        verdicts.append((exact >= length, check >= length))
    assert worst <= TOLERANCE
    assert all(a == b for a, b in verdicts)
    assert any(a for a, _ in verdicts) and not all(a for a, _ in verdicts)


def test_long_bend_gives_the_classical_chord():
    """Where the bend holds the whole chord, L* = 2√(R_o² − (R_i + d)²), computed by hand here."""
    radius, d = 1.5 * BORE, 0.75 * BORE
    by_hand = 2 * math.sqrt((radius + BORE / 2) ** 2 - (radius - BORE / 2 + d) ** 2)
    passage = rigid_passage(bore=BORE, radius=radius, angle=math.pi / 2, diameter=d)
    assert passage.longest == pytest.approx(by_hand, rel=1e-9)
    assert passage.where == "mid-bend, ends on the arc"


def test_short_bend_is_roomier_than_the_classical_chord():
    """At 15° the chord's ends lie in the straight pipes: by hand, 2(R_o − h cos(θ/2))/sin(θ/2)."""
    radius, d, theta = BORE, 0.75 * BORE, math.radians(15)
    h = radius - BORE / 2 + d
    by_hand = 2 * (radius + BORE / 2 - h * math.cos(theta / 2)) / math.sin(theta / 2)
    passage = rigid_passage(bore=BORE, radius=radius, angle=theta, diameter=d)
    assert passage.longest == pytest.approx(by_hand, rel=1e-6)
    assert passage.longest > 2 * classical(radius, d)
    assert passage.where == "mid-bend, ends in the straight pipes"


def test_limits():
    """A cylinder exactly as wide as the bore does not fit, and the report says "bore"."""
    snug = rigid_passage(bore=BORE, radius=BORE, angle=1.0, diameter=BORE)
    assert (snug.longest, snug.where) == (0.0, "bore")
    wide = rigid_passage(bore=BORE, radius=50 * BORE, angle=math.pi / 2, diameter=0.5 * BORE).longest
    tight = rigid_passage(bore=BORE, radius=BORE, angle=math.pi / 2, diameter=0.5 * BORE).longest
    assert wide > tight


def test_elbow_radius_needed_passes_and_is_least():
    d, length, theta = 0.75 * BORE, 0.25, math.pi / 2
    needed = elbow_radius_needed(bore=BORE, angle=theta, diameter=d, length=length)
    assert rigid_passage(bore=BORE, radius=needed, angle=theta, diameter=d).longest >= length
    assert rigid_passage(bore=BORE, radius=0.99 * needed, angle=theta, diameter=d).longest < length


def test_flexible_radius_stretches_the_outer_side_to_the_braid_length():
    """At ρ_min the outer side, L₀(1 + D₀/(2ρ)), is exactly B = L₀/cos α₀."""
    l0, d0, alpha = 0.314325, 0.05715, math.radians(24.08)
    rho = flexible_bend_radius(rest_length=l0, rest_diameter=d0, braid_length=l0 / math.cos(alpha))
    assert l0 * (1 + d0 / 2 / rho) == pytest.approx(l0 / math.cos(alpha))


@pytest.mark.parametrize("theta", [5e-4, 1e-3, 0.02])
def test_a_slight_bend_is_a_bend_not_a_straight_run(theta):
    """θ down to 0.03°: the chord's ends lie in the straight pipes, L* = 2(R_o − h cos(θ/2))/sin(θ/2) by hand
    (finite: a long enough cylinder still jams); only θ = 0 is a straight run."""
    radius, d = 1.5 * BORE, 0.75 * BORE
    h = radius - BORE / 2 + d
    by_hand = 2 * (radius + BORE / 2 - h * math.cos(theta / 2)) / math.sin(theta / 2)
    passage = rigid_passage(bore=BORE, radius=radius, angle=theta, diameter=d)
    assert math.isfinite(passage.longest) and passage.longest == pytest.approx(by_hand, rel=1e-6)
    assert passage.where == "mid-bend, ends in the straight pipes"
    straight = rigid_passage(bore=BORE, radius=radius, angle=0.0, diameter=d)
    assert (straight.longest, straight.where) == (math.inf, "straight")


def test_elbow_radius_needed_below_two_bores():
    """A 120 mm cylinder of 0.75 D at 90° passes from R ≈ 0.87 D: the least radius, by the classical chord
    2√(R_o² − (R_i + d)²) = L solved for R by hand, not the 2 D of a coarser search."""
    d, length = 0.75 * BORE, 0.12
    a = BORE / 2
    # (R + a)² − (R − a + d)² = (L/2)²  ⇒  R = ((L/2)² + (d − a)² − a²)/(2(a − (d − a)))
    by_hand = ((length / 2) ** 2 + (d - a) ** 2 - a**2) / (2 * (a - (d - a)))
    needed = elbow_radius_needed(bore=BORE, angle=math.pi / 2, diameter=d, length=length)
    assert needed == pytest.approx(by_hand, rel=1e-9) and needed < 2 * BORE


def test_elbow_radius_needed_is_inf_beyond_a_hundred_bores_and_never_below_half_a_bore():
    """A short thin cylinder passes the tightest elbow, R = D/2 (docs/physics.md §14.1: R ≥ D/2). A 250 mm
    cylinder 1 mm narrower than a 50 mm bore needs R = ((L/2)²/(D − d) − d)/2 ≈ 156 D at 90° (the classical
    chord 2√((D − d)(2R + d)) = L solved by hand; the chord is far shorter than the arc there): inf within
    the default 100 bores, that R within 200."""
    assert elbow_radius_needed(bore=0.05, angle=math.pi / 2, diameter=0.01, length=0.01) == 0.025
    bore, d, length = 0.05, 0.049, 0.25
    by_hand = ((length / 2) ** 2 / (bore - d) - d) / 2
    assert 150 * bore < by_hand < 200 * bore
    assert elbow_radius_needed(bore=bore, angle=math.pi / 2, diameter=d, length=length) == math.inf
    needed = elbow_radius_needed(bore=bore, angle=math.pi / 2, diameter=d, length=length, largest=200.0)
    assert needed == pytest.approx(by_hand, rel=1e-9)
