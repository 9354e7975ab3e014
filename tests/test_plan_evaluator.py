"""The evaluator's numpy forms of the closed forms agree bit for bit with the one model's
(:meth:`Muscle.closed_form_pressure`) on random cases: signs, zeros, beyond 100 MPa, broadcasting."""

from __future__ import annotations

import numpy as np
import pytest

from pampipe.io.config import load_mission
from pampipe.model.muscle import Anchored, Muscle
from pampipe.planning.confidence import sampling_problem
from pampipe.planning.evaluator import draws_key, least_pressure
from pampipe.planning.problem import build_elements, mission_muscles
from tests.conftest import PROBLEMS


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_least_pressure_is_the_closed_form_bit_for_bit(radial_pam, seed):
    rng = np.random.default_rng(seed)
    n, classes = 400, 7

    def spread(shape, scale, zeros=0.05, negative=0.1):
        v = rng.lognormal(0.0, 2.0, shape) * scale
        v[rng.random(shape) < negative] *= -1
        v[rng.random(shape) < zeros] = 0.0
        return v

    c = Anchored(None, spread((1, n), 1.0), spread((1, n), 50.0), spread((1, n), 1e-3), 0.0, 0.0)
    load = spread((classes, n), 100.0)  # friction drawn: W(μ) per class and draw
    mu = spread((classes, n), 0.3)
    kappa = np.maximum(spread((1, n), 0.5), 0.0)
    muscle = Muscle.from_pam(radial_pam)
    assert muscle.contact is None and not muscle.effects
    for w, m in ((load, mu), (load[:, :1], mu[:, :1])):  # drawn friction, then one value per class
        with np.errstate(all="ignore"):
            expected = muscle.closed_form_pressure(None, w, kappa=kappa, friction=m, safety_factor=1.5,
                                                   anchored=c)
        found = least_pressure(c, w, kappa, m, 1.5)
        assert found.shape == expected.shape
        assert np.isinf(found).any() and (found == 0).any() and (found > 0).any()  # every branch taken
        np.testing.assert_array_equal(found.view(np.int64), expected.view(np.int64))
        kept = least_pressure(c, w, kappa, m, 1.5, (m * np.pi, 1.5 * w))  # the evaluator's (μπ, SF·W)
        np.testing.assert_array_equal(kept.view(np.int64), expected.view(np.int64))


def test_the_problem_names_its_draws_by_their_key():
    """The chunks find the route's draws and coefficients per process by ``Problem.key``, computed once."""
    mission = load_mission(PROBLEMS / "missions" / "riser-uncertain-friction.yaml")
    muscles = mission_muscles(mission)
    elements = build_elements(mission, muscles)
    keys = []
    for seed in (3, 4):
        problem = sampling_problem(mission, muscles, elements, 0.95, samples=200, seed=seed)[0]
        assert problem.key == draws_key(problem.uncertainties, 200, seed, problem.kappa_sd)
        keys.append(problem.key)
    assert keys[0] != keys[1]
