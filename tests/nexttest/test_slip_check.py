"""The slip test's preposterior refit: the moduli (with ln μ a nuisance) from slip loads, against the
linearised information of the same test."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from pampipe.model.muscle import Muscle
from pampipe.model.pam import Moduli
from pampipe.nexttest.information import fisher
from pampipe.nexttest.posterior import posterior
from pampipe.nexttest.slip_check import refit_slip, trials
from pampipe.specs.menu import MenuTest
from tests.support.open_direction import open_direction_files

LEVELS = tuple(69e3 * k for k in range(1, 11))
SLIP = MenuTest("slip", 7200, LEVELS, pipe_diameter=0.0889, axial_load=0.0, trials=3)


def _loads(pam, kappa):
    pressure = np.repeat(LEVELS, SLIP.trials)
    load = Muscle.from_pam(pam).largest_load(pressure, SLIP.pipe_diameter, kappa=kappa, friction=0.3,
                                             safety_factor=1.0)
    return pressure[load > 0], load[load > 0]


def test_exact_loads_keep_the_estimate_and_give_the_linearised_posterior(tmp_path, radial_pam):
    """With κ = 0 the slip load is μπF_r(P, D, 0), the model the linearised information differentiates
    exactly (CasADi); the refit's finite-difference Gauss-Newton posterior at the unmoved estimate must be
    the same Σ₁, and the open hoop.a0 direction must close as the linearised criterion says."""
    pam, _, _ = open_direction_files(tmp_path, radial_pam)
    pressure, load = _loads(pam, 0.0)
    fitted = refit_slip(pam, pam.uncertainty, SLIP.pipe_diameter, pressure, load, 0.3, 0.0)
    assert np.allclose(fitted.moduli.as_vector(), pam.moduli.as_vector(), rtol=0, atol=1e3)  # 1 kPa
    expected = posterior(pam.uncertainty, fisher(Muscle.from_pam(pam), pam.uncertainty, SLIP))
    units = pam.uncertainty.scaled_units()
    written = fitted.uncertainty.covariance / np.outer(units, units)
    assert expected.closed == 1 and fitted.uncertainty.undetermined == ()
    sd = np.sqrt(np.diag(expected.covariance))
    assert np.sqrt(np.diag(written)) == pytest.approx(sd, rel=1e-3, abs=1e-9)


def test_a_shifted_truth_is_found_from_its_detected_slips(tmp_path, radial_pam):
    """A truth 1 MPa off along the open hoop.a0: the slips pampipe's detector finds in its synthetic traces
    (3 % scatter) bring the refit's hoop.a0 within 3 posterior sd (below 0.1 MPa) of it, from 2 MPa of
    prior sd."""
    pam, _, _ = open_direction_files(tmp_path, radial_pam)
    u = pam.uncertainty
    names = list(u.names)
    theta = pam.moduli.as_vector().copy()
    theta[names.index("hoop.a0")] += 1e6
    truth = dataclasses.replace(pam, moduli=Moduli.from_vector(theta,
                                                               reference_pressure=pam.moduli.reference_pressure))
    pressure, load = trials(truth, SLIP, 4, 0.3, 1.0)
    assert pressure.size >= 20
    fitted = refit_slip(pam, u, SLIP.pipe_diameter, pressure, load, 0.3, 1.0)
    k = names.index("hoop.a0")
    sd = np.sqrt(fitted.uncertainty.covariance[k, k])
    assert sd < 0.1e6
    assert abs(fitted.moduli.as_vector()[k] - theta[k]) < 3 * sd
