"""The evaluator's affine form of the closed form (:mod:`pampipe.planning.law`) agrees with the one model's
(:meth:`Muscle.closed_form_pressure`) to 1e-12 on random cases: signs, zeros, beyond 100 MPa, broadcasting;
its order statistics are settled after the partitions."""

from __future__ import annotations

import numpy as np
import pytest

from pampipe.io.mission_schema import load_mission
from pampipe.model.muscle import Anchored, Muscle
from pampipe.planning.confidence import sampling_problem
from pampipe.planning.evaluator import draws_key
from pampipe.planning.law import per_class, per_draw, raw_least, settle
from pampipe.planning.problem import build_elements, mission_muscles
from pampipe.planning.quantiles import order_statistics
from tests.support.problems import PROBLEMS


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_the_affine_law_is_the_closed_form_to_1e_12(radial_pam, seed):
    """law.settle(W·k + (W/μ)·r − f) against :meth:`Muscle.closed_form_pressure` on random coefficients,
    loads and frictions of every sign (zeros too): inf in the same places (F₁ ≤ 0, μ ≤ 0, beyond 100 MPa),
    the floor at 0 taken, and every value within 1e-12 of the terms' size (1e-12 of P* where they do not
    cancel), for drawn friction and one friction per class."""
    rng = np.random.default_rng(seed)
    n, classes = 400, 7

    def spread(shape, scale, zeros=0.05, negative=0.1):
        v = rng.lognormal(0.0, 2.0, shape) * scale
        v[rng.random(shape) < negative] *= -1
        v[rng.random(shape) < zeros] = 0.0
        return v

    c = Anchored(None, spread((1, n), 1.0), spread((1, n), 50.0), spread((1, n), 1e-3), 0.0, 0.0)
    error = spread((1, n), 5.0)
    load = spread((classes, n), 100.0)  # friction drawn: W(μ) per class and draw
    mu = spread((classes, n), 0.3)
    kappa = np.maximum(spread((1, n), 0.5), 0.0)
    muscle = Muscle.from_pam(radial_pam)
    assert muscle.contact is None and not muscle.effects
    for w, m in ((load, mu), (load[:, :1], mu[:, :1])):  # drawn friction, then one value per class
        shifted = Anchored(None, c.amplification, c.at_zero + error, c.slope, 0.0, 0.0)
        with np.errstate(all="ignore"):
            expected = muscle.closed_form_pressure(None, w, kappa=kappa, friction=m, safety_factor=1.5,
                                                   anchored=shifted)
            size = (np.abs(kappa * w / c.slope) + np.abs((c.at_zero + error) / c.slope)
                    + np.abs(1.5 * w / (m * np.pi * c.amplification * c.slope)))
        terms = per_draw(c, kappa, error, 1.5)
        shape = np.broadcast_shapes(w.shape, terms.k.shape)
        raw = raw_least(*per_class(np.broadcast_to(w, shape), np.broadcast_to(m, shape)), terms,
                        np.empty(shape), np.empty(shape))
        found = settle(raw)
        assert found.shape == expected.shape
        finite = np.isfinite(expected)
        assert (~finite).any() and (expected[finite] == 0).any() and (expected[finite] > 0).any()
        assert ((c.slope <= 0) & finite).sum() == 0 and ((m <= 0) & finite).sum() == 0
        np.testing.assert_array_equal(np.isinf(found), ~finite)  # inf where it does not hold
        assert np.all(np.abs(found[finite] - expected[finite]) <= 1e-12 * size[finite])
        plain = finite & (expected > 0.1 * size)  # no cancellation: relative to P* itself
        assert plain.sum() > 100
        np.testing.assert_allclose(found[plain], expected[plain], rtol=1e-12, atol=0)


@pytest.mark.parametrize("seed", range(3))
def test_settled_order_statistics_equal_those_of_the_settled_values(seed):
    """order_statistics(raw, settle=law.settle) gives the sorted settled values at every rank and their
    share ≤ the first, also where settle makes ties (0 below, inf beyond 100 MPa and for NaN)."""
    rng = np.random.default_rng(seed)
    n, c = int(rng.integers(200, 2000)), int(rng.integers(1, 30))
    raw = rng.normal(2e5, 3e5, (n, c))
    raw[rng.random((n, c)) < 0.05] = np.nan
    raw[rng.random((n, c)) < 0.05] = 2e8
    raw[:, 0] = -1.0  # every value floors at 0
    if c > 1:
        raw[: n // 2, 1] = np.nan  # half the column fails to hold
    settled = settle(raw)
    for k in (0, n // 3, n // 2, n - 2):
        ranks = [k, n - 1, n // 4]
        expected = np.sort(settled, axis=0)[ranks]
        found, share = order_statistics(raw.copy(), ranks, share=True, settle=settle)
        np.testing.assert_array_equal(found, expected)
        np.testing.assert_array_equal(share, np.mean(settled <= expected[0], axis=0))


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


def test_the_load_affine_in_friction_equals_the_incline_load():
    """W = μ·∂W/∂μ + W(0) (slip.incline_load_affine, the evaluator's two passes) against slip.incline_load on
    random robots, inclines and frictions, to rounding."""
    from pampipe.model.no_slip import incline_load, incline_load_affine

    rng = np.random.default_rng(11)
    for _ in range(50):
        total, anchor, drag = rng.uniform(1, 20), rng.uniform(0.1, 1), rng.uniform(0, 30)
        phi, mu = rng.uniform(-np.pi / 2, np.pi / 2, 7), rng.uniform(0, 1.2, (7, 30))
        rise, run = np.abs(np.sin(phi)), np.cos(phi)
        slope, at_zero = incline_load_affine(total, anchor, rise, run, drag)
        expected = incline_load(total, anchor, rise[:, None], run[:, None], mu, drag)
        np.testing.assert_allclose(mu * slope[:, None] + at_zero[:, None], expected, rtol=1e-13, atol=1e-12)
