"""The radial moments' d³ and d⁴ by products change only rounding: the optimum identify finds moves by
< 1e-12 (relative) against the form they replace (d**3 and d**4 by pow()), on synthetic data of known
moduli."""

from __future__ import annotations

import numpy as np
import pytest

from pampipe.identification import FitOptions, identify, statistics
from pampipe.identification.predict import predict
from pampipe.model.pam import Pam
from pampipe.simulation.synthetic import Protocol, generate
from pampipe.specs.experiment import ExperimentData, make_test_data
from tests.support.problems import PROBLEMS


@pytest.fixture(scope="module")
def data(radial_pam):
    tests = [make_test_data(spec, cols) for spec, cols in
             generate(radial_pam, Protocol(points_per_leg=300, radial_points=100), seed=3)]
    return ExperimentData(PROBLEMS / "generated.yaml", Pam(radial_pam.name, radial_pam.geometry),
                          tuple(tests), {})


def test_the_powers_are_pows_to_two_ulp():
    rng = np.random.default_rng(1)
    d = rng.standard_normal(100_000) * 10.0 ** rng.uniform(-8, 2, 100_000)
    for power, exponent in zip(statistics.powers(d), (2, 3, 4), strict=True):
        exact = d**exponent
        assert np.all(np.abs(power - exact) <= 2 * np.spacing(np.abs(exact))), exponent


@pytest.mark.parametrize("degree", [1, 3])
def test_the_optimum_moves_less_than_1e_12_against_the_replaced_form(data, monkeypatch, degree):
    """Degree 1: every modulus is determined, each moves < 1e-12 of the largest. Degree 3 leaves
    directions the data do not determine (rank < 16), where IPOPT's path, not the data, sets the
    moduli: there the fitted axial forces at every row and the SSE move < 1e-12."""
    new = identify(data, FitOptions(degree=degree))
    monkeypatch.setattr(statistics, "powers", lambda d: (d * d, d**3, d**4))
    old = identify(data, FitOptions(degree=degree))
    assert abs(new.sse - old.sse) < 1e-12 * old.sse
    a, b = new.moduli.as_vector(), old.moduli.as_vector()
    if degree == 1:
        assert new.uncertainty.rank == a.size
        assert np.max(np.abs(a - b)) < 1e-12 * np.max(np.abs(b))
    for test in data.tests:
        if test.kind == "axial":
            f_new = np.asarray(predict(Pam("new", data.pam.geometry, new.moduli), test))
            f_old = np.asarray(predict(Pam("old", data.pam.geometry, old.moduli), test))
            assert np.max(np.abs(f_new - f_old)) < 1e-12 * np.max(np.abs(f_old))
