"""The per-source breakdown of `plan --confidence` (docs/physics.md §15, *Breakdown*): where P* is monotone in
the one drawn scalar source (κ, the model error e), its quantiles are P* at the source's order statistics;
they must equal, bit for bit, the quantiles of the full sampled P*, and a source in which P* is not monotone
must be sampled in full."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from pampipe.io.mission_schema import load_mission
from pampipe.model.pam import Moduli
from pampipe.model.uncertainty import ParameterUncertainty, moduli_names
from pampipe.planning.confidence import sampling_problem
from pampipe.planning.evaluator import Evaluator
from pampipe.planning.problem import build_elements, mission_muscles
from pampipe.planning.quantiles import order_statistics
from pampipe.planning.sampling import muscle_draws
from pampipe.planning.sources import keyed_normal
from tests.support.problems import PROBLEMS

RISER = PROBLEMS / "missions" / "riser-uncertain-friction.yaml"
BORES = ("3 in", "{value: 3.5 in, sd: 0.4 mm}", "{nps: 3, schedule: 40, tolerance: 1 %}", "80 mm")
N = 2000


def _mission(tmp_path, pam, inclines, frictions, *, kappa=1.0, kappa_sd=0.0):
    """The riser robot, every segment's PAM ``pam``, on one section per (incline [deg], μ ± sd)."""
    head = RISER.read_text().split("route:")[0].replace("../pams", str(PROBLEMS / "pams"))
    lines = [f"  - {{name: s{k}, length: 1 m, inner_diameter: {BORES[k % len(BORES)]}, incline: {a:.6g} deg, "
             f"friction: {{value: {mu:.6g}, sd: {sd:.6g}}}}}" for k, (a, (mu, sd)) in
             enumerate(zip(inclines, frictions, strict=True))]
    path = tmp_path / "route.yaml"
    path.write_text(head + "route:\n" + "\n".join(lines) + "\n")
    mission = load_mission(path)
    segments = tuple(dataclasses.replace(s, pam=pam, pam_file=None) for s in mission.segments)
    return dataclasses.replace(mission, segments=segments, load_coupling=kappa, kappa_sd=kappa_sd)


def _evaluator(mission, seed=3, **changes):
    muscles = mission_muscles(mission)
    problem, classes, _ = sampling_problem(mission, muscles, build_elements(mission, muscles), 0.95,
                                           samples=N, seed=seed)
    draws = muscle_draws(problem)
    problem = dataclasses.replace(problem, **changes)
    rows = np.arange(len(classes))
    bore = np.column_stack([keyed_normal(seed, "bore", (classes.low[c], classes.high[c], classes.bore_sd[c]),
                                         N) * classes.bore_sd[c] for c in rows])
    friction = np.column_stack([keyed_normal(seed, "friction", (classes.mu[c], classes.mu_sd[c]), N)
                                * classes.mu_sd[c] for c in rows])
    return Evaluator(problem, draws, classes, 0, rows, bore, friction)


def _with_error(pam, error):
    return pam.with_uncertainty(ParameterUncertainty(moduli_names(3), np.zeros((16, 16)), error))


def _sampled(ev, name, ranks):
    """The order statistics of P* from every draw of ``name`` alone, by the full sort (the reference)."""
    return np.sort(ev.evaluate((name,))[0], axis=0)[ranks]


def _ranks(rng):
    extremes = [0, N - 1, math.ceil(0.95 * N) - 1, math.ceil(0.05 * N) - 1]
    return sorted({*extremes, *rng.integers(0, N, 4).tolist()})


@pytest.mark.parametrize("seed", range(5))
def test_monotone_breakdown_equals_the_sampled_quantiles(tmp_path, radial_pam, seed):
    """Random routes (incline, μ, bores), κ̂, κ's sd and model errors: P* at the order statistics of κ (of e,
    reversed) is the same number as the order statistic of the sampled P*, at every rank."""
    rng = np.random.default_rng(seed)
    k = 6
    frictions = list(zip(rng.uniform(0.1, 0.6, k), rng.uniform(0.0, 0.05, k), strict=True))
    mission = _mission(tmp_path, _with_error(radial_pam, rng.uniform(1.0, 20.0)), rng.uniform(-90, 90, k),
                       frictions, kappa=rng.uniform(0.2, 1.2), kappa_sd=rng.uniform(0.05, 0.5))
    ev = _evaluator(mission, seed=seed)
    assert (ev.monotone("kappa"), ev.monotone("model_error")) == (1, -1)
    ranks = _ranks(rng)
    for name in ("kappa", "model_error"):
        sampled = _sampled(ev, name, ranks)
        assert np.all(np.ptp(sampled, axis=0) > 0)  # the source moves P* in every class
        np.testing.assert_array_equal(ev.alone(name, ranks), sampled)


def test_friction_is_not_monotone_and_is_sampled_in_full(tmp_path, radial_pam):
    """μ raises the load's sliding part κμW₁ and lowers the grip's SF·W/μ: on shallow inclines P* falls then
    rises over μ's draws. Mapping μ's order statistics (either way) would give another quantile there."""
    mission = _mission(tmp_path, radial_pam, [0, 3, 6, 10, 15, 20], [(0.3, 0.1)] * 6)
    ev = _evaluator(mission)
    assert ev.monotone("friction") == 0
    ranks = [math.ceil(0.05 * N) - 1, math.ceil(0.95 * N) - 1]
    sampled = _sampled(ev, "friction", ranks)
    np.testing.assert_array_equal(ev.alone("friction", ranks), sampled)
    values = ev.evaluate(("friction",))[0]
    wrong = 0
    for c in range(values.shape[1]):
        along = values[np.argsort(ev.friction[:, c], kind="stable"), c]
        with np.errstate(invalid="ignore"):  # inf − inf where μ ≤ 0 cannot hold
            step = np.diff(along)
        if np.any(step > 0) and np.any(step < 0):
            mapped = [along[ranks], along[[N - 1 - r for r in ranks]]]
            wrong += all(not np.array_equal(m, sampled[:, c]) for m in mapped)
    assert wrong > 0


def test_kappa_under_a_negative_load_is_sampled_in_full(tmp_path, radial_pam):
    """With W < 0 (a tether pushing the robot up the pipe) P* falls as κ grows: the rising map would take the
    wrong tail, so the breakdown samples κ in full and still equals the sorted draws."""
    mission = _mission(tmp_path, radial_pam, [90, 60], [(0.3, 0.0)] * 2, kappa=0.8, kappa_sd=0.3)
    ev = _evaluator(mission, tether_drag=-400.0)
    assert np.all(ev.friction_load(False)[1] < 0)
    assert ev.monotone("kappa") == 0
    ranks = [math.ceil(0.05 * N) - 1, math.ceil(0.95 * N) - 1]
    sampled = _sampled(ev, "kappa", ranks)
    np.testing.assert_array_equal(ev.alone("kappa", ranks), sampled)
    rising = ev.evaluate(("kappa",), drawn_scalar=order_statistics(ev.draws.kappa[:, None], ranks)[:, 0])[0]
    assert not np.array_equal(rising, sampled)


def test_contact_increments_are_sampled_in_full(tmp_path, radial_pam):
    """With contact increments P* is a rising plus a falling term in κ and e (monotone in exact arithmetic,
    not by rounding): no shortcut, and the breakdown is the sorted draws'."""
    theta = radial_pam.moduli.as_vector()
    delta = np.zeros_like(theta)
    delta[8] = 4e6
    pam = _with_error(dataclasses.replace(radial_pam, moduli=Moduli.from_vector(theta, contact=delta)), 8.0)
    mission = _mission(tmp_path, pam, [90, 30, 0], [(0.3, 0.02)] * 3, kappa_sd=0.2)
    ev = _evaluator(mission)
    ranks = [math.ceil(0.05 * N) - 1, math.ceil(0.95 * N) - 1]
    for name in ("kappa", "model_error"):
        assert ev.monotone(name) == 0
        np.testing.assert_array_equal(ev.alone(name, ranks), _sampled(ev, name, ranks))
