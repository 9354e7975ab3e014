"""The pressure-dependent friction law's slip load (pampipe/slip/law.py) against the one written apart in
tests/support/slip_data.py: F solving F = μ₀(p/p_ref)^n·π·F_r(P, D, κF), p = F_r/(D·L_p), with A and L_p
from the braid geometry and F_r = A·(F_ax(P, L_p) − κF) (Coulomb, n = 0: F = μπA·F_ax/(1 + κμπA))."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pampipe.model.muscle import Muscle
from pampipe.slip.law import power_law_model
from tests.support import slip_data

BORES = (0.0635, 0.0762, 0.0889)
PRESSURES = (2.6e5, 4.0e5, 6.0e5)


@pytest.fixture(scope="module")
def muscle(radial_pam):
    return Muscle.from_pam(radial_pam)


@pytest.mark.parametrize(("mu0", "exponent", "kappa", "reference"),
                         [(0.3, 0.0, 0.8, 2e5), (0.3, 0.4, 0.8, 2e5), (0.25, -0.3, 0.5, 1.5e5),
                          (0.4, 0.8, 1.2, 3e5)])
def test_slip_load_equals_the_law_written_apart(muscle, mu0, exponent, kappa, reference):
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
