"""The pressure-dependent friction law's slip load (pampipe/slip/law.py) against the one written apart in
tests/support/slip_data.py: F solving F = μ₀(p/p_ref)^n·π·F_r(P, D, κF), p = F_r/(D·L_p), with A and L_p
from the braid geometry and F_r = A·(F_ax(P, L_p) − κF) (Coulomb, n = 0: F = μπA·F_ax/(1 + κμπA))."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pampipe.model.muscle import Muscle
from pampipe.slip.law import evidence, power_law_model, reference_pressure, verdict
from tests.support import slip_data

BORES = (0.0635, 0.0762, 0.0889)
PRESSURES = (2.6e5, 4.0e5, 6.0e5)


@pytest.fixture(scope="module")
def muscle(radial_pam):
    return Muscle.from_pam(radial_pam)


@pytest.mark.parametrize(("mu0", "exponent", "kappa", "reference"),
                         [(0.3, 0.0, 0.8, 2e5), (0.3, 0.4, 0.8, 2e5), (0.25, -0.3, 0.5, 1.5e5),
                          (0.4, 0.8, 1.2, 3e5), (3.0, 0.0, 0.8, 2e5), (3.0, 0.0, 0.0, 2e5)])
def test_slip_load_equals_the_law_written_apart(muscle, mu0, exponent, kappa, reference):
    """μ₀ = 3 (a rubber-like grip) without load coupling (κ = 0): the slip load is 3π·F_r, beyond a
    bracket of π·F_r."""
    pressure, diameter = (np.array(v) for v in zip(*[(p, d) for p in PRESSURES for d in BORES], strict=True))
    got = power_law_model(muscle, pressure, diameter, kappa, reference)(mu0, exponent)
    want = [slip_data.true_slip_load(muscle, p, d, mu0, kappa, exponent, reference)
            for p, d in zip(pressure, diameter, strict=True)]
    assert np.all(np.asarray(want) > 10.0)  # every trial grips: no floor, no cap at work
    np.testing.assert_allclose(got, want, rtol=1e-7)


def test_a_muscle_that_does_not_touch_slips_at_no_load(muscle):
    """Below first contact the unloaded radial force is 0: the slip load is 0, whatever μ₀ and n; above
    it, the law's."""
    diameter = np.array([0.0889, 0.0889])
    touch = float(muscle.anchoring_pressure(0.0889, 0.0))
    pressure = np.array([0.5 * touch, 1.5 * touch + 1e4])
    got = power_law_model(muscle, pressure, diameter, 0.8, 2e5)(0.3, 0.4)
    assert got[0] == 0.0
    assert got[1] == pytest.approx(slip_data.true_slip_load(muscle, pressure[1], 0.0889, 0.3, 0.8, 0.4, 2e5),
                                   rel=1e-7)
    assert math.isfinite(got[1]) and got[1] > 0


def test_friction_is_capped_at_10(muscle):
    """μ₀ = 12 with n = 0 asks μ = 12; the law caps μ at 10: the slip load is Coulomb's at μ = 10."""
    pressure, diameter = np.array([2.6e5, 6.0e5]), np.array([0.0635, 0.0889])
    got = power_law_model(muscle, pressure, diameter, 0.8, 2e5)(12.0, 0.0)
    want = [slip_data.true_slip_load(muscle, p, d, 10.0, 0.8)
            for p, d in zip(pressure, diameter, strict=True)]
    np.testing.assert_allclose(got, want, rtol=1e-7)


@pytest.mark.parametrize(("delta_bic", "p_value", "supported"),
                         [(-1.0, 0.01, "pressure_dependent"), (-1e-9, 0.0499, "pressure_dependent"),
                          (0.0, 0.01, "coulomb"), (-1.0, 0.05, "coulomb"), (-1.0, 0.0502, "coulomb"),
                          (2.0, 0.001, "coulomb")])
def test_the_verdict_needs_both_bic_and_p_value(delta_bic, p_value, supported):
    """docs/physics.md §13.4: pressure-dependent only where ΔBIC < 0 and p < 0.05 (both strict)."""
    assert verdict(delta_bic, p_value) == supported


def _trials(muscle, slipped: int):
    """``slipped`` slipped trials in a 3 in bore (slip loads of μ = 0.3, κ = 0.8, scattered ±2 %) and one
    held below first contact (censored at 1 N)."""
    touch = float(muscle.anchoring_pressure(0.0762, 0.0))
    pressures = np.linspace(3.0e5, 6.0e5, slipped)
    loads = [slip_data.true_slip_load(muscle, p, 0.0762, 0.3, 0.8) * (1 + 0.02 * (-1) ** k)
             for k, p in enumerate(pressures)]
    pressure = np.array([*pressures, 0.5 * touch])
    censored = np.arange(pressure.size) == slipped
    return pressure, np.full(pressure.size, 0.0762), np.array([*loads, 1.0]), censored


def test_check_law_evidence_from_its_definitions(muscle):
    """check_law on 3 slipped trials and one below contact: p_ref is the geometric mean of the unloaded
    contact pressures F_r/(D·L_p) of the trials that touch (L_p from the braid, slip_data); LR = 2(ℓ_n −
    ℓ_0) moves by −2 per unit of the Coulomb fit's ℓ_0; under 3 slipped: no check."""
    from pampipe.slip.fit import Fit
    from pampipe.slip.law import check_law

    pressure, diameter, load, censored = _trials(muscle, 3)
    coulomb = [Fit(0.3, 0.8, math.log(0.05), loglik, True) for loglik in (-40.0, -41.0)]
    checks = [check_law(muscle, pressure, diameter, load, censored, c, "relative") for c in coulomb]
    length = slip_data.amplification(muscle.geometry, 0.0762)[1]
    touching = [float(muscle.radial_force(p, 0.0762, 0.0)) / (0.0762 * length) for p in pressure[:3]]
    assert checks[0].reference_pressure == pytest.approx(math.exp(np.mean(np.log(touching))), rel=1e-9)
    assert checks[1].likelihood_ratio - checks[0].likelihood_ratio == pytest.approx(2.0, rel=1e-6)
    assert check_law(muscle, *_trials(muscle, 2)[:3], _trials(muscle, 2)[3], coulomb[0], "relative") is None


class _Linear:
    """A muscle whose radial force is c·P − A·F_a [N] (negative: not touching) and contact pressure
    F_r/(D·L) with L = 0.3 m: every answer below by hand."""

    c, amp, length = 1e-3, 3.0, 0.3

    def radial_force(self, pressure, diameter, axial_load):
        return self.c * np.asarray(pressure, float) - self.amp * np.asarray(axial_load, float) + 0 * diameter

    def contact_pressure(self, radial, diameter):
        return np.asarray(radial, float) / (np.asarray(diameter, float) * self.length)


def test_the_reference_pressure_is_the_geometric_mean_over_the_trials_that_touch():
    """p_ref (docs/physics.md §13.4) over unloaded trials (no axial load): one pulling off the wall (F_r < 0),
    one just at it (F_r = 0), one pressing 0.3 Pa, two pressing hundreds of N; with one touching trial p_ref
    is its pressure, with none there is no check."""
    muscle, bore = _Linear(), 0.08
    pressure = np.array([-1e5, 0.0, 0.3 * bore * 0.3 / 1e-3, 2e5, 8e5])
    touching = [0.3, 200.0 / (bore * 0.3), 800.0 / (bore * 0.3)]
    got = reference_pressure(muscle, pressure, np.full(5, bore))
    assert got == pytest.approx((touching[0] * touching[1] * touching[2]) ** (1 / 3), rel=1e-12)
    assert reference_pressure(muscle, pressure[[0, 1, 3]], np.full(3, bore)) == pytest.approx(touching[1],
                                                                                               rel=1e-12)
    assert reference_pressure(muscle, pressure[:2], np.full(2, bore)) is None


def test_the_evidence_from_two_log_likelihoods_by_hand():
    """LR = 2(ℓ_n − ℓ_0) floored at 0 (n = 0 is Coulomb, so ℓ_n ≥ ℓ_0 but for the optimiser), p = P(χ²₁ > LR)
    = erfc(√(LR/2)), ΔBIC = ln N − LR."""
    ratio, p_value, delta_bic = evidence(-37.0, -40.0, 20)
    assert ratio == pytest.approx(6.0, rel=1e-12)
    assert p_value == pytest.approx(math.erfc(math.sqrt(3.0)), rel=1e-9)
    assert delta_bic == pytest.approx(math.log(20) - 6.0, rel=1e-12)
    assert evidence(-40.0, -40.0, 20) == (0.0, 1.0, math.log(20))
    assert evidence(-40.000001, -40.0, 12) == (0.0, 1.0, math.log(12))  # the optimiser fell short of Coulomb


def test_a_muscle_that_barely_touches_slips_at_coulombs_closed_form():
    """F = μπ·F_r(κF) with F_r = r₀ − A·κF gives F = μπr₀/(1 + μπAκ): r₀ = 0.1 mN, far below any floor of the
    radial force; r₀ ≤ 0 slips at 0."""
    muscle, mu, kappa = _Linear(), 0.5, 0.8
    pressure = np.array([0.1, -5.0, 0.0])  # r0 = 1e-4 N, -5e-3 N, 0
    got = power_law_model(muscle, pressure, np.full(3, 0.08), kappa, 2e5)(mu, 0.0)
    r0 = 1e-4
    assert got[0] == pytest.approx(mu * math.pi * r0 / (1 + mu * math.pi * muscle.amp * kappa), rel=1e-9)
    assert got[1] == 0.0 and got[2] == 0.0


@pytest.mark.parametrize(("exponent", "bound"), [(2.0, 1.0), (-2.0, -0.5)])
def test_the_exponent_is_searched_over_the_documented_range(exponent, bound):
    """docs/physics.md §13.4: n is searched over [−0.5, 1]; slip loads made with n = ±2 (8 trials, ±1 %) fit
    at the nearer end."""
    from pampipe.slip.fit import Fit
    from pampipe.slip.law import check_law

    muscle, trials = _Linear(), 8
    pressure, diameter = np.linspace(1e5, 8e5, trials), np.full(trials, 0.08)
    load = power_law_model(muscle, pressure, diameter, 0.0, 1.5e4)(0.3, exponent)
    load = load * (1 + 0.01 * (-1) ** np.arange(trials))
    coulomb = Fit(0.3, 0.0, math.log(0.05), -100.0, True)
    check = check_law(muscle, pressure, diameter, load, np.zeros(trials, bool), coulomb, "relative")
    assert check.exponent == bound
