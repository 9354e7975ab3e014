"""The closed-form least holding pressure with diagnosed effects, against bisection on the full model.

:meth:`Muscle.closed_form_pressure` folds the effects that keep the anchored force affine (plus the
contact quadratic) into the closed form of docs/physics.md §8.3; :meth:`Muscle.least_holding_pressure`
bisects μπF_r(P, D, κW) ≥ SF·W on the effects-aware forces of :mod:`pampipe.model.effects`. The two
are different algorithms on the same model, so they must agree wherever a pressure holds.

Test data: seeded draws of the effect parameters within their declared bounds and of the pipe, load
and friction. Tolerance 1e-9 relative: the bisection resolves 100 MPa/2⁸⁰ ≈ 1e-16 Pa and both sides
carry ~1e-13 relative round-off (seen: ≤ 2e-13).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from pampipe.model import effects
from pampipe.model.muscle import PRESSURE_LIMIT, Muscle

CLOSED = [name for name, effect in effects.LIBRARY.items() if not effect.no_closed_form]
RTOL = 1e-9
SAFETY = 1.5


def sample(geometry, rng, n=400):
    d = rng.uniform(geometry.initial_diameter * 1.001, geometry.largest_diameter * 0.999, n)
    return d, rng.uniform(0.0, 2000.0, n), rng.uniform(0.05, 1.0, n)


def random_values(name, rng):
    return {p.name: float(rng.uniform(p.lower, p.upper)) for p in effects.get_effect(name).parameters}


def assert_same(closed, bisected):
    assert np.array_equal(np.isinf(closed), np.isinf(bisected))
    finite = np.isfinite(bisected)
    assert finite.sum() > 0
    np.testing.assert_allclose(closed[finite], bisected[finite], rtol=RTOL, atol=0)


def test_the_library_says_which_effects_have_a_closed_form():
    assert set(CLOSED) == {"braid_friction", "contact_stiffening", "pressure_offset", "axial_preload",
                           "wall_friction", "pressure_hysteresis"}
    for name in set(effects.LIBRARY) - set(CLOSED):
        assert len(effects.get_effect(name).no_closed_form) > 40  # a sentence for the user


@pytest.mark.parametrize("kappa", [1.0, 0.5, 0.0])
@pytest.mark.parametrize("name", CLOSED)
def test_each_effect_closed_form_equals_bisection(radial_pam, name, kappa):
    rng = np.random.default_rng(sorted(effects.LIBRARY).index(name))
    base = Muscle.from_pam(radial_pam)
    for _ in range(3):
        muscle = Muscle(base.geometry, base.theta, base.reference_pressure,
                        effects={name: random_values(name, rng)})
        d, w, mu = sample(base.geometry, rng)
        closed = muscle.closed_form_pressure(d, w, kappa=kappa, friction=mu, safety_factor=SAFETY)
        bisected = muscle.least_holding_pressure(d, w, kappa=kappa, friction=mu, safety_factor=SAFETY)
        assert_same(closed, bisected)


def test_all_closed_form_effects_with_contact_increments(radial_pam):
    """Every closed-form effect at once, on a muscle whose contact increments make the law quadratic."""
    rng = np.random.default_rng(7)
    base = Muscle.from_pam(radial_pam)
    contact = np.zeros(16)
    contact[0], contact[8], contact[12] = 0.5e6, 0.8e6, -0.05e6  # Δa₁₀, Δa₂₀, Δb₂₀: C₁ > 0 (convex)
    values = {"pressure_offset": {"offset": 12e3, "gain": 1.05}, "axial_preload": {"preload": 40.0},
              "contact_stiffening": {"axial_increment": 0.5e6, "hoop_increment": 0.3e6},
              "wall_friction": {"lock": 0.2}, "braid_friction": {"f0": 8.0}}
    muscle = Muscle(base.geometry, base.theta, base.reference_pressure, contact=contact, effects=values)
    d, w, mu = sample(base.geometry, rng, 2000)
    closed = muscle.closed_form_pressure(d, w, kappa=1.0, friction=mu, safety_factor=SAFETY)
    assert_same(closed, muscle.least_holding_pressure(d, w, kappa=1.0, friction=mu, safety_factor=SAFETY))


def test_quadratic_root_also_when_b_is_negative(radial_pam):
    """With a = C₁/P_ref > 0 the quadratic a x² + b x = R has one positive root even for b < 0."""
    base = Muscle.from_pam(radial_pam)
    contact = np.zeros(16)
    contact[8], contact[12] = 8e6, -0.4e6  # Δa₂₀ > 0: C₀ < 0, so b < 0 near the braid limit; C₁ > 0
    muscle = Muscle(base.geometry, base.theta, base.reference_pressure, contact=contact)
    rng = np.random.default_rng(3)
    _, w, mu = sample(base.geometry, rng, 400)
    d = rng.uniform(0.85, 0.999, 400) * base.geometry.largest_diameter
    c = muscle.affine_coefficients(d)
    anchoring = (w - c.at_zero) / c.slope
    b = c.slope + (c.contact_at_zero + c.contact_slope * anchoring) / muscle.reference_pressure
    assert np.mean(b < 0) > 0.2 and np.all(c.contact_slope > 0)
    closed = muscle.closed_form_pressure(d, w, kappa=1.0, friction=mu, safety_factor=SAFETY)
    # independent bisection on the holding capacity over [P_a, 100 MPa] (monotone there: C₁ > 0)
    low, high = anchoring.copy(), np.full(d.shape, PRESSURE_LIMIT)
    for _ in range(200):
        mid = 0.5 * (low + high)
        ok = muscle.holding_capacity(mid, d, w, kappa=1.0, friction=mu) >= SAFETY * w
        low, high = np.where(ok, low, mid), np.where(ok, mid, high)
    reachable = muscle.holding_capacity(PRESSURE_LIMIT, d, w, kappa=1.0, friction=mu) >= SAFETY * w
    assert_same(closed, np.where(reachable, np.maximum(high, 0.0), math.inf))


@pytest.mark.parametrize("name", ["braid_extensibility", "end_effects"])
def test_effects_without_closed_form_are_refused(radial_pam, name):
    base = Muscle.from_pam(radial_pam)
    muscle = Muscle(base.geometry, base.theta, effects={name: {}, "axial_preload": {"preload": 1.0}})
    assert list(muscle.closed_form_refusals()) == [name]
    with pytest.raises(ValueError, match=name):
        muscle.required_pressure(0.0762, 100.0, kappa=1.0, friction=0.3, safety_factor=SAFETY)
