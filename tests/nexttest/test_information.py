"""The information a test adds and the posterior it leaves: exact Jacobians against finite differences, the
Gaussian update against its textbook form, closed directions."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from pampipe.io.pam_schema import load_pam
from pampipe.model.muscle import Muscle
from pampipe.model.pam import Pam
from pampipe.model.uncertainty import ParameterUncertainty, UndeterminedDirection, moduli_names
from pampipe.nexttest.information import predictions
from pampipe.nexttest.posterior import (
    extended,
    information_gain,
    planned_uncertainty,
    posterior,
    prior_covariance,
)
from pampipe.specs.menu import MenuTest
from tests.support.problems import PROBLEMS

PAM = load_pam(PROBLEMS / "pams" / "paper-radial-pam-uncertain.yaml")
LEVELS = (300e3, 450e3, 600e3)


def _muscle_at(p: np.ndarray, structure) -> Muscle:
    n = structure.n_theta
    g = dataclasses.replace(PAM.geometry, initial_length=p[0], initial_diameter=p[1], braid_angle=p[2],
                            bladder_thickness=p[3])
    return Muscle(g, p[5:5 + n], p[4])


@pytest.mark.parametrize("test", [
    MenuTest("radial", 3600, LEVELS, pipe_diameter=0.0762, axial_load=0.0),
    MenuTest("radial", 3600, LEVELS, pipe_diameter=0.0889, axial_load=1024.74),
    MenuTest("isometric", 1800, LEVELS, length=0.25),
    MenuTest("axial", 3600, LEVELS),
])
def test_jacobian_is_the_models_slope(test):
    """∂y/∂p equals central differences of Muscle.radial_force / axial_force (relative 1e-5)."""
    muscle = Muscle.from_pam(PAM)
    p = muscle.parameter_vector()
    value, jac, _ = predictions(muscle, test)
    assert np.all(value > 0)
    for k in (1, 2, 5, 6, 13):  # D₀, α₀, axial.a0, axial.a1, hoop.a0
        h = 1e-6 * max(abs(p[k]), 1e-3)
        up, down = p.copy(), p.copy()
        up[k] += h
        down[k] -= h
        if test.kind == "radial":
            f = [np.asarray(_muscle_at(q, muscle.structure).radial_force(
                np.array(LEVELS), test.pipe_diameter, test.axial_load)) for q in (up, down)]
            numeric = (f[0] - f[1]) / (2 * h)
        elif test.kind == "isometric":
            f = [np.asarray(_muscle_at(q, muscle.structure).axial_force(np.array(LEVELS), test.length))
                 for q in (up, down)]
            numeric = (f[0] - f[1]) / (2 * h)
        else:
            continue  # the axial lengths move with p (the free length): checked through the value below
        assert jac[:, k] == pytest.approx(numeric, rel=1e-5, abs=1e-6 * np.abs(jac).max())
    if test.kind == "axial":
        assert value.size == len(LEVELS) * 12


def _uncertainty() -> ParameterUncertainty:
    names = moduli_names(3)
    rng = np.random.default_rng(3)
    a = rng.normal(size=(16, 14)) * 0.2e6
    v = np.zeros(16)
    v[[1, 2]] = [0.6, 0.8]
    w = np.zeros(16)
    w[[3, 7]] = [0.8, -0.6]
    cov = a @ a.T
    project = np.eye(16) - np.outer(v, v) - np.outer(w, w)  # zero variance along the two open directions
    cov = project @ cov @ project
    directions = (UndeterminedDirection(v, 40.0), UndeterminedDirection(w, 30.0))
    return ParameterUncertainty(names, cov, 1.5, directions)


def test_gaussian_update_and_closed_directions():
    u = _uncertainty()
    prior = prior_covariance(u)
    v = np.asarray(u.undetermined[0].vector)
    assert v @ prior @ v == pytest.approx(40.0**2)
    assert posterior(u, np.zeros((16, 16))).closed == 0
    rng = np.random.default_rng(4)
    j = rng.normal(size=(3, 16))
    f = j.T @ j
    post = posterior(u, f)
    textbook = np.linalg.inv(np.linalg.inv(prior) + f)
    assert post.covariance == pytest.approx(textbook, rel=1e-6, abs=1e-9 * np.abs(textbook).max())
    assert information_gain(u, f) == pytest.approx(np.linalg.slogdet(prior)[1]
                                                   - np.linalg.slogdet(textbook)[1], rel=1e-8)
    strong = posterior(u, 1e6 * np.outer(v, v))  # pins v alone: one closed, w still open at its width
    assert strong.closed == 1 and len(strong.open_vectors) == 1
    assert abs(strong.open_vectors[0] @ np.asarray(u.undetermined[1].vector)) == pytest.approx(1.0, abs=1e-6)
    assert strong.open_widths[0] == pytest.approx(30.0, rel=1e-3)
    listed = planned_uncertainty(u, strong, on_prior=False)
    assert len(listed.undetermined) == 1
    units = u.scaled_units()
    left = listed.covariance / np.outer(units, units)
    assert strong.open_vectors[0] @ left @ strong.open_vectors[0] == pytest.approx(0.0, abs=1e-9)
    assert planned_uncertainty(u, strong, on_prior=True).undetermined == ()


def test_below_contact_a_radial_test_says_nothing():
    """At pressures below first contact F_r = 0 at every row: no information, no gain."""
    muscle = Muscle.from_pam(PAM)
    test = MenuTest("radial", 3600, (10e3, 20e3), pipe_diameter=0.0889, axial_load=0.0)
    value, jac, _ = predictions(muscle, test)
    assert np.all(value == 0) and not np.any(jac)
    assert isinstance(PAM, Pam)


def test_a_tested_muscle_adds_its_uncalibrated_stated_geometry():
    """unit: tested: the stated braid-angle sd the fit did not calibrate is one more parameter (variance sd²,
    uncorrelated); a radial test informs it."""
    from pampipe.nexttest.information import fisher
    from pampipe.nexttest.posterior import extended

    sd = np.radians(1.0)
    pam = dataclasses.replace(PAM, geometry_sd={"braid_angle": sd})
    u = extended(pam, True)
    assert u.names[-1] == "braid_angle" and u.covariance[-1, -1] == pytest.approx(sd**2)
    assert np.all(u.covariance[-1, :-1] == 0) and extended(pam, False) is pam.uncertainty
    muscle = Muscle.from_pam(pam)
    radial = fisher(muscle, u, MenuTest("radial", 1, LEVELS, pipe_diameter=0.0762, axial_load=0.0))
    assert radial[-1, -1] > 0
    assert posterior(u, radial).covariance[-1, -1] < 0.5 * (sd / np.radians(1.0)) ** 2  # in deg²


@pytest.mark.parametrize("on_prior", [False, True])
def test_the_planned_uncertainty_keeps_the_model_errors_dof(on_prior):
    """A test changes what the fit knows of the parameters, not the model error: the posterior a plan samples
    keeps the PAM's model_error and its dof (its t draw, docs/physics.md §15), and so does a tested muscle's
    extended uncertainty."""
    vector = np.zeros(16)
    vector[8] = 1.0
    u = ParameterUncertainty(moduli_names(3), np.diag(np.r_[np.full(8, 0.05e6), np.zeros(8)] ** 2), 6.0,
                             (UndeterminedDirection(vector, 2.0, {}, "a radial test"),), model_error_dof=4)
    planned = planned_uncertainty(u, posterior(u, np.zeros((16, 16))), on_prior=on_prior)
    assert (planned.model_error, planned.model_error_dof) == (6.0, 4)
    pam = load_pam(PROBLEMS / "pams" / "paper-radial-pam.yaml")
    stated = dataclasses.replace(pam, geometry_sd={"braid_angle": 0.01}).with_uncertainty(u)
    wider = extended(stated, tested=True)
    assert wider.names[-1] == "braid_angle" and wider.model_error_dof == 4
