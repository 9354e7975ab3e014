"""The preposterior check: truths drawn from what the fit knows, synthesised data, refit, plan; the same
numbers serially and on two processes."""

from __future__ import annotations

import numpy as np
import pytest

from pampipe.io.mission_schema import load_mission
from pampipe.model.uncertainty import moduli_names
from pampipe.nexttest.posterior import prior_covariance
from pampipe.nexttest.preposterior import check, synthesise, truth
from pampipe.nexttest.ranking import Planner
from pampipe.specs.menu import MenuTest
from tests.support.open_direction import open_direction_files

LEVELS = tuple(69e3 * k for k in range(1, 11))


def test_truths_follow_the_prior(tmp_path, radial_pam):
    """2000 truths: mean θ̂ and covariance Σ₀ (the open hoop.a0 at its 2 MPa width) within sampling error."""
    pam, _, _ = open_direction_files(tmp_path, radial_pam)
    names = moduli_names(3)
    drawn = [truth(pam, pam.uncertainty, 5, k).moduli.as_vector() for k in range(2000)]
    draws = np.array(drawn) - pam.moduli.as_vector()
    units = pam.uncertainty.scaled_units()
    expected = prior_covariance(pam.uncertainty) * np.outer(units, units)
    assert np.cov(draws.T)[8, 8] == pytest.approx(expected[8, 8], rel=0.1) == (2e6) ** 2
    assert np.abs(draws.mean(axis=0))[names.index("hoop.a0")] < 4 * 2e6 / np.sqrt(2000)
    assert np.all(draws[:, 9:] == 0)  # what the PAM states without variance stays


def test_synthesised_radial_test_is_the_truths(tmp_path, radial_pam):
    pam, _, _ = open_direction_files(tmp_path, radial_pam)
    test = MenuTest("radial", 3600, LEVELS, pipe_diameter=0.0889, axial_load=0.0)
    (data,) = synthesise(pam, test, 3)
    assert data.points == 40 * len(LEVELS) and data.spec.pipe_diameter == 0.0889


def test_check_is_the_same_serially_and_on_two_processes(tmp_path, radial_pam):
    pam, pam_file, mission_file = open_direction_files(tmp_path, radial_pam)
    planner = Planner(load_mission(mission_file), pam, pam_file, 0.95, samples=500)
    radial = (MenuTest("radial", 3600, LEVELS, pipe_diameter=0.0889, axial_load=0.0),)
    slip = (MenuTest("slip", 3600, LEVELS, pipe_diameter=0.0889, axial_load=0.0, trials=3),)
    serial = check(planner, [radial, slip], truths=2, seed=1)
    for done in serial:  # a slip test too (tests/nexttest/test_slip_check.py)
        assert done["truths"] == 2 and done["failed"] == 0 and 100e3 < done["pressure_Pa"] < 689e3
    assert check(planner, [radial, slip], truths=2, seed=1, workers=2) == serial
