"""`plan --confidence` at network scale (issue 25 item 5): classes of alike sections sampled in chunks on any
executor, draws shared where they are in reality, the grouped law equal to the per-section law, and the
plan still checked against an independent Monte Carlo."""

from __future__ import annotations

import dataclasses
import json
import math
import os
import subprocess
import sys

import numpy as np
import pytest

from pampipe.io.mission_schema import load_mission
from pampipe.model import no_slip
from pampipe.model.muscle import Muscle
from pampipe.model.pam import Geometry
from pampipe.planning.confidence import plan_confidence, sampling_problem
from pampipe.planning.evaluator import Evaluator
from pampipe.planning.problem import build_elements, mission_muscles
from pampipe.planning.quantiles import order_statistics, share_at_most
from pampipe.planning.sampling import chunk_classes, muscle_draws
from pampipe.planning.sources import keyed_normal
from tests.support.problems import PROBLEMS, ROOT

UNCERTAIN = PROBLEMS / "missions" / "riser-uncertain-friction.yaml"
BORES = ("3 in", "{value: 3.5 in, sd: 0.4 mm}", "{nps: 3, schedule: 40, tolerance: 1 %}")


def route_mission(folder, sections: int):
    """The riser robot (fit covariance) on ``sections`` sections of 3 bores (one with an sd, one with a
    tolerance), 5 inclines and 2 frictions with sds: 30 kinds."""
    head = UNCERTAIN.read_text().split("route:")[0].replace("../pams", str(PROBLEMS / "pams"))
    lines = [f"  - {{name: s{i}, length: 2 m, inner_diameter: {BORES[i % 3]}, "
             f"incline: {20 * (i % 5) - 40} deg, friction: {{value: {0.25 + 0.05 * (i % 2):g}, sd: 0.03}}}}"
             for i in range(sections)]
    path = folder / f"route-{sections}.yaml"
    path.write_text(head + "route:\n" + "\n".join(lines) + "\n")
    return path


def _plan(mission, **options):
    muscles = mission_muscles(mission)
    return plan_confidence(mission, muscles, build_elements(mission, muscles), 0.95, samples=2000, **options)


def test_chunks_of_one_class_give_the_same_arrays_as_one_chunk(tmp_path):
    """Each class is computed from its own keyed draws: the chunking (here 1 class per chunk against all 30
    in one) cannot change a bit; sections of one kind get one answer."""
    mission = load_mission(route_mission(tmp_path, 60))
    one, many = _plan(mission), _plan(mission, budget=1)
    for name in ("pressure", "holding_probability", "contact_probability", "pressure_ci95", "certain"):
        np.testing.assert_array_equal(getattr(one, name), getattr(many, name))
    for key in one.shifts:
        np.testing.assert_array_equal(one.shifts[key], many.shifts[key])
    np.testing.assert_array_equal(one.pressure[:30], one.pressure[30:])  # section s and s + 30: one kind
    assert set(one.shifts) == {"moduli", "bore", "friction"}


def _json(mission, *extra):
    env = {**os.environ, "OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1"}
    out = subprocess.run([sys.executable, "-m", "pampipe", "plan", str(mission), "--confidence", "0.95",
                          "--samples", "12000", "--json", "--reproducible", *extra], capture_output=True,
                         cwd=ROOT, env=env, timeout=600)
    assert out.returncode == 0, out.stderr.decode()
    return out.stdout


def test_serial_two_workers_and_dask_give_byte_identical_json(tmp_path):
    """30 kinds at 12 000 draws are two chunks (MEMORY_BUDGET: 27 kinds): each a task with the seed and plain
    numbers, so local processes and a Dask cluster give the serial document byte for byte."""
    assert chunk_classes(12000) < 30  # more than one chunk
    mission = route_mission(tmp_path, 45)
    serial = _json(mission)
    assert json.loads(serial)["confidence"]["samples"] == 12000
    assert serial == _json(mission, "--workers", "2")
    distributed = pytest.importorskip("distributed", reason="Dask is the optional extra pampipe[dask]")
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None,
                                  host="127.0.0.1") as cluster:
        assert serial == _json(mission, "--scheduler", cluster.scheduler_address)


def test_workers_without_confidence_is_an_input_error(cli):
    out = cli("plan", UNCERTAIN, "--workers", "2")
    assert out.returncode == 2 and "--workers" in out.stderr and "--confidence" in out.stderr


def _evaluator(tmp_path, sections=9):
    mission = load_mission(route_mission(tmp_path, sections))
    muscles = mission_muscles(mission)
    elements = build_elements(mission, muscles)
    problem, classes, inverse = sampling_problem(mission, muscles, elements, 0.95, samples=3000, seed=7)
    draws = muscle_draws(problem)
    rows = np.arange(len(classes))
    bore = np.column_stack([keyed_normal(7, "bore", (classes.low[c], classes.high[c], classes.bore_sd[c]),
                                         3000) * classes.bore_sd[c] for c in rows])
    friction = np.column_stack([keyed_normal(7, "friction", (classes.mu[c], classes.mu_sd[c]), 3000)
                                * classes.mu_sd[c] for c in rows])
    return mission, problem, classes, inverse, draws, Evaluator(problem, draws, classes, 0, rows, bore,
                                                                 friction)


def test_grouped_law_equals_the_per_section_law_on_random_draws(tmp_path):
    """The evaluator computes the muscle's coefficients once per draw and drawn bore and broadcasts the
    load's closed form over classes; the per-section law (Muscle.least_holding_pressure of one muscle
    built for one draw, at one bore, load and μ) agrees to 1e-12 on random draws, for every class."""
    _, problem, classes, _, draws, ev = _evaluator(tmp_path)
    least = ev.evaluate(problem.active)[0]
    p = ev.nominal + draws.params["moduli"][0]
    structure = problem.structures[0]
    n = structure.n_theta
    rng = np.random.default_rng(5)
    for k in rng.choice(problem.samples, 12, replace=False):
        for c in range(len(classes)):
            muscle = Muscle(Geometry(*p[k, :4], structure.wall), p[k, 5:5 + n], p[k, 4])
            mu = classes.mu[c] + ev.friction[k, c]
            load = no_slip.anchor_load(problem.total_mass, problem.masses[0], classes.incline[c], mu,
                                    problem.tether_drag)
            bores = {classes.low[c], classes.worst[c, 0], classes.high[c]}
            expected = max(float(muscle.least_holding_pressure(b + ev.bore[k, c], load, kappa=problem.kappa,
                                                               friction=mu,
                                                               safety_factor=problem.safety_factor))
                           for b in bores)
            assert least[k, c] == pytest.approx(expected, rel=1e-12, abs=1e-6), (k, c)


def test_one_muscle_is_one_draw_in_every_section(tmp_path):
    """Sections in different bores see the same muscle draw: their holding at the planned pressures is
    one event far more than independent draws allow (joint share ≫ the product 0.95² = 0.9025), and the
    three segments of one PAM file share that draw; sections of one friction statement share its draw."""
    _, problem, classes, _, draws, ev = _evaluator(tmp_path)
    assert draws.params["moduli"][0] is draws.params["moduli"][1] is draws.params["moduli"][2]
    least = ev.evaluate(("moduli",))[0]
    planned = np.sort(least, axis=0)[math.ceil(0.95 * problem.samples) - 1]
    holds = least <= planned
    a, b = 0, int(np.flatnonzero(classes.low != classes.low[0])[0])  # two classes, two bores
    assert holds[:, [a, b]].mean(axis=0) == pytest.approx([0.95, 0.95], abs=1e-3)
    joint = np.mean(holds[:, a] & holds[:, b])
    se = math.sqrt(0.9025 * 0.0975 / problem.samples)
    assert joint > 0.9025 + 5 * se  # independent draws: 0.9025 ± se
    same = np.flatnonzero((classes.mu == classes.mu[a]) & (classes.mu_sd == classes.mu_sd[a]))
    assert same.size > 1
    for c in same:
        np.testing.assert_array_equal(ev.friction[:, c], ev.friction[:, a])


def test_chunked_plan_holds_in_c_of_independent_monte_carlo(tmp_path):
    """Every kind of a 30-kind route, planned one class per chunk, holds in 0.95 ± 2 % of 10⁴ independent
    draws of (θ, bore, μ) on the numeric model (the test's own draws and code path)."""
    mission = load_mission(route_mission(tmp_path, 30))
    plan = _plan(mission, budget=1)
    seg = mission.segments[0]
    m = seg.pam.moduli
    rng = np.random.default_rng(2025)
    n = 10_000
    theta = rng.multivariate_normal(m.as_vector(), seg.pam.covariance, size=n, method="eigh").T
    muscle = Muscle(seg.pam.geometry, theta, m.reference_pressure)
    total = sum(x.mass for x in mission.segments) + mission.payload
    r = mission.route
    for s in range(0, 30, 4):
        mu = rng.normal(r.friction[s], r.friction_sd[s], n)
        delta = rng.normal(0.0, r.diameter_sd[s], n) if r.diameter_sd[s] > 0 else np.zeros(n)
        load = no_slip.anchor_load(total, seg.mass, r.incline[s], mu, mission.tether_drag)
        bores = np.linspace(r.diameter_low[s], r.diameter_high[s], 9)  # the range, holds over all of it
        holds = np.ones(n, dtype=bool)
        for d in bores:
            capacity = muscle.holding_capacity(plan.pressure[s, 0], d + delta, load, kappa=mission.kappa,
                                               friction=mu)
            holds &= capacity >= mission.safety_factor * load
        assert np.mean(holds) == pytest.approx(0.95, abs=0.02), (s, np.mean(holds))


def test_draws_do_not_depend_on_the_route_around_a_section(tmp_path):
    """A bore's and a friction's draws are keyed by their statement: planning the first 9 sections alone
    gives them the same plan as inside the 60-section route."""
    whole = _plan(load_mission(route_mission(tmp_path, 60)))
    mission = load_mission(route_mission(tmp_path, 60))
    part = _plan(dataclasses.replace(mission, route=mission.route[:9]))
    np.testing.assert_array_equal(part.pressure, whole.pressure[:9])


@pytest.mark.parametrize("seed", range(4))
def test_order_statistics_and_shares_equal_the_sorted_values(seed):
    """The partitions give the full sort's order statistics at any ranks, and the shares at most a limit
    equal the direct count, with ties, inf and a column-constant (broadcast) array."""
    rng = np.random.default_rng(seed)
    n, c = int(rng.integers(100, 3000)), int(rng.integers(1, 40))
    values = np.round(rng.normal(size=(n, c)), int(rng.integers(1, 4)))  # ties
    values[rng.random((n, c)) < 0.05] = np.inf
    ranks = [int(k) for k in rng.integers(0, n, 6)] + [0, n - 1]
    expected = np.sort(values, axis=0)[ranks]
    found, share = order_statistics(values, ranks, share=True)
    np.testing.assert_array_equal(found, expected)
    np.testing.assert_array_equal(share, np.mean(values <= expected[0], axis=0))
    column = np.broadcast_to(values[:, :1], (n, c))
    limits = np.concatenate([[np.inf], values[rng.integers(0, n, c - 1), 0]])
    np.testing.assert_array_equal(share_at_most(column, limits), np.mean(column <= limits, axis=0))
    np.testing.assert_array_equal(share_at_most(values, limits), np.mean(values <= limits, axis=0))
