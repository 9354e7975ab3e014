"""The design NLP (issue 16): KKT conditions by finite differences, a 20³ grid search, the scaling identity,
and the group reduction checked pipe by pipe.

Test data: the bundled riser inventory (one vertical 3 in pipe, problems/inventories/riser.yaml) and
inventories built here; nothing in these tests was used to tune the solver (its options were chosen on
problems/inventories/plant.yaml and ky4.yaml).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from pampipe.design import design_nlp, solve_inventory
from pampipe.design.evaluate import designed_pam, evaluate_pipes, objective_value
from pampipe.design.groups import make_groups, segment_loads
from pampipe.design.multistart import make_problem, multistart
from pampipe.io.inventory_file import load_inventory
from pampipe.model.muscle import Muscle
from pampipe.model.pam import Geometry
from pampipe.runtime.executors import SerialExecutor
from pampipe.specs.inventory import Objective, Pipes
from tests.support.problems import PROBLEMS

RISER = PROBLEMS / "inventories" / "riser.yaml"
#: Central differences with h = 1e-6 in the scaled variables (each in [0, 1]): truncation ~h²·|L'''| ≈ 1e-12,
#: round-off ~1e-16·|L|/h ≈ 1e-10; IPOPT stops at tol 1e-10. A stationarity residual of 1e-6 is far
#: above both and far below a wrong multiplier (the gradients are O(0.1 … 10)).
FD_STEP = 1e-6
STATIONARITY = 1e-6
ACTIVE = 1e-7  # a constraint within this (scaled) distance of its bound counts as active


@pytest.fixture(scope="module")
def riser():
    return load_inventory(RISER)


def _solve(inventory, objective):
    groups = make_groups(inventory)
    relaxed = objective is Objective.MAX_PRESSURE
    problem = make_problem(inventory, groups, objective=objective, relaxed=relaxed)
    run = multistart(problem, starts=8, seed=0, pool=SerialExecutor())
    assert run.best is not None, [r.status for r in run.results]
    return problem, run


def _gradient(fun, x):
    out = []
    for k in range(len(x)):
        e = np.zeros(len(x))
        e[k] = FD_STEP
        out.append((fun(x + e) - fun(x - e)) / (2 * FD_STEP))
    return np.array(out)


@pytest.mark.parametrize("objective", [Objective.MAX_PRESSURE, Objective.AIR])
def test_one_pipe_design_satisfies_the_kkt_conditions(riser, objective):
    """∇f + J_gᵀλ_g + λ_x = 0 by central differences of the Lagrangian; feasibility; multiplier signs;
    complementary slackness (CasADi's convention: λ > 0 on an active upper bound, < 0 on a lower one)."""
    problem, run = _solve(riser, objective)
    best = run.best
    x, lam_g, lam_x = best.x, best.lam_g, best.lam_x

    def lagrangian(z):
        f, g = problem.evaluate(z)
        return f + lam_g @ g + lam_x @ z

    assert np.max(np.abs(_gradient(lagrangian, x))) < STATIONARITY
    _, g = problem.evaluate(x)
    assert np.all(g >= problem.lbg - ACTIVE) and np.all(g <= problem.ubg + ACTIVE)
    assert np.all(x >= problem.lbx - ACTIVE) and np.all(x <= problem.ubx + ACTIVE)
    scale = max(1.0, np.max(np.abs(lam_g)))
    at_lower = np.isfinite(problem.lbg) & (g - problem.lbg < ACTIVE)
    at_upper = np.isfinite(problem.ubg) & (problem.ubg - g < ACTIVE)
    assert np.all(lam_g[at_upper] >= -1e-9 * scale) and np.all(lam_g[at_lower] <= 1e-9 * scale)
    assert np.all(np.abs(lam_g[~(at_lower | at_upper)]) < 1e-8 * scale)  # complementary slackness
    if objective is Objective.MAX_PRESSURE:
        # the stride floor binds (the least pressure would otherwise take the least expansion)
        stride = design_nlp.ROWS.index("stride") * problem.size
        assert at_lower[stride] and lam_g[stride] < 0
    else:
        # the braid angle is interior: its stationarity rests on the gradient alone, no multiplier
        assert 0.05 < x[2] < 0.95 and abs(lam_x[2]) < 1e-9
        hoop = design_nlp.ROWS.index("hoop_stability_supply") * problem.size
        assert at_lower[hoop]  # the air objective expands the muscle up to the moduli law's stable limit


def test_the_constraint_rows_are_the_muscle_s_own_numbers(riser):
    """At the optimum, the NLP's rows equal what the public Muscle API says of the designed PAM."""
    problem, run = _solve(riser, Objective.MAX_PRESSURE)
    x = run.best.x
    _, g = problem.evaluate(x)
    rows = g.reshape(len(design_nlp.ROWS), problem.size)[:, 0]
    muscle = Muscle.from_pam(designed_pam(riser, problem.geometry(x), "check"))
    d, mu = riser.pipes.diameter[0], riser.pipes.friction[0]
    load = segment_loads(riser).max()
    pressure = muscle.least_holding_pressure(d, load, kappa=1.0, friction=mu, safety_factor=1.5)
    assert rows[0] + x[3] == pytest.approx(pressure / riser.supply_pressure, rel=1e-12)
    g0 = muscle.geometry
    assert rows[design_nlp.ROWS.index("stride")] == pytest.approx(
        (g0.initial_length - muscle.anchored_length(d) - 0.02) / g0.initial_length, abs=1e-12)
    reach = 0.95 * g0.largest_diameter / d - 1
    assert rows[design_nlp.ROWS.index("reach")] == pytest.approx(reach, rel=1e-12)


def test_the_design_is_no_worse_than_a_20_cubed_grid_search(riser):
    """The grid evaluates the public Muscle API on 8000 geometries (vectorised), keeps the feasible ones
    (clearance, contact margin, stride, stable moduli) and takes the least largest pressure."""
    result = solve_inventory(riser)
    s = riser.space
    n = 20
    grids = [np.linspace(*bounds, n) for bounds in (s.initial_length, s.initial_diameter, s.braid_angle)]
    length, diameter, angle = (v.ravel() for v in np.meshgrid(*grids, indexing="ij"))
    t0 = riser.material.geometry.bladder_thickness
    muscle = Muscle(Geometry(length, diameter, angle, t0), riser.material.moduli.as_vector(), 1e6)
    g = muscle.geometry
    bore = riser.pipes.diameter[0]
    loads = segment_loads(riser)[0]
    with np.errstate(all="ignore"):
        pressure = np.max([muscle.least_holding_pressure(bore, w, kappa=1.0, friction=0.3, safety_factor=1.5)
                           for w in loads], axis=0)
        lp = muscle.anchored_length(bore)
        stable = np.all([np.asarray(e) >= 0 for p in (0.0, riser.supply_pressure)
                         for e in muscle.drucker_tangent_moduli(p, lp)], axis=0)
        ok = ((diameter <= bore - s.clearance) & (bore <= (1 - s.contact_margin) * g.largest_diameter)
              & (length - lp >= s.min_stride) & stable & np.isfinite(pressure))
    grid_best = pressure[ok].min()
    assert ok.sum() > 100  # the grid is not vacuous
    designed = result.as_document()["objective"]
    assert designed <= grid_best * (1 + 1e-9)
    print(f"design {designed:.6g} Pa, grid {grid_best:.6g} Pa over {ok.sum()} feasible points")


@pytest.mark.parametrize("scale", [0.5, 2.0, 3.7])
def test_scaling_identity(radial_pam, scale):
    """Scaling every length (wall included) and the bore by s: the anchoring pressure is unchanged and the
    unloaded radial force is multiplied by s² (the moduli law is in strain, the forces are stress × area)."""
    g = radial_pam.geometry
    theta = radial_pam.moduli.as_vector()
    base = Muscle(g, theta, 1e6)
    scaled = Muscle(Geometry(scale * g.initial_length, scale * g.initial_diameter, g.braid_angle,
                             scale * g.bladder_thickness, g.wall), theta, 1e6)
    bore = 0.0762
    assert scaled.anchoring_pressure(scale * bore) == pytest.approx(base.anchoring_pressure(bore), rel=1e-12)
    for pressure in (2e5, 4e5, 6.89e5):
        assert scaled.radial_force(pressure, scale * bore) == pytest.approx(
            scale**2 * base.radial_force(pressure, bore), rel=1e-12)
    # the identity is not vacuous: a held load W does not scale, so the holding pressure changes
    hold = {m: m.least_holding_pressure(b, 500.0, kappa=1.0, friction=0.3, safety_factor=1.5)
            for m, b in ((base, bore), (scaled, scale * bore))}
    assert abs(hold[scaled] / hold[base] - 1) > 1e-3


def _inventory(riser, diameters, inclines, objective=Objective.MAX_PRESSURE):
    n = len(diameters)
    d = np.array(diameters, dtype=float)
    pipes = Pipes(tuple(f"p{i}" for i in range(n)), d, d.copy(), d.copy(), np.linspace(5, 50, n),
                  np.radians(inclines), np.full(n, 0.3))
    space = dataclasses.replace(riser.space, objective=objective, min_stride=0.0,
                                initial_diameter=(0.03, 0.07))
    return dataclasses.replace(riser, pipes=pipes, space=space)


@pytest.mark.parametrize("objective", list(Objective))
def test_the_group_reduction_is_exact(riser, objective):
    """Pipes of one bore but different inclines collapse to one group; the NLP's optimum equals the
    objective evaluated pipe by pipe and segment by segment at that design (no contact increments)."""
    inv = _inventory(riser, [0.0762, 0.0762, 0.0762, 0.0889, 0.0889], [90, 10, 0, 45, 3], objective)
    groups = make_groups(inv)
    assert len(groups) == 2
    problem = make_problem(inv, groups, relaxed=objective is Objective.MAX_PRESSURE)
    run = multistart(problem, starts=6, seed=1, pool=SerialExecutor())
    best = run.best
    table = evaluate_pipes(inv, problem.geometry(best.x))
    assert table.served.all()
    exact = objective_value(objective, table, inv.pipes, table.served)
    assert problem.physical(best.objective) == pytest.approx(exact, rel=1e-9)


def test_starts_are_a_latin_hypercube_and_reproducible(riser):
    groups = make_groups(riser)
    problem = make_problem(riser, groups, relaxed=True)
    from pampipe.design.multistart import latin_hypercube, start_points

    unit = latin_hypercube(10, 3)
    for k in range(3):  # one point per tenth of each axis
        assert sorted(np.floor(unit[:, k] * 10).astype(int)) == list(range(10))
    assert np.array_equal(start_points(problem, 10, 3), start_points(problem, 10, 3))
    assert not np.array_equal(start_points(problem, 10, 3), start_points(problem, 10, 4))


def test_build_size_does_not_grow_with_the_pipes(riser):
    """Up to 4 distinct groups share one solver, whatever the number of pipes."""
    few = make_problem(riser, make_groups(_inventory(riser, [0.0762], [90])))
    many = make_problem(riser, make_groups(_inventory(riser, [0.0762] * 200 + [0.0889] * 300,
                                                      np.linspace(0, 90, 500))))
    assert few.size == many.size == 4
    assert design_nlp.build(few.structure, few.objective, few.size) is \
        design_nlp.build(many.structure, many.objective, many.size)
    assert math.isfinite(few.evaluate(np.array([0.5, 0.9, 0.1, 1.0]))[0])


def test_contact_increments_enter_the_nlp_as_in_plan(riser):
    """With contact increments (docs/physics.md §9d) the NLP's largest pressure is what
    Muscle.least_holding_pressure (plan's function) gives at the design, pipe by pipe."""
    m = riser.material.moduli
    contact = np.zeros(16)
    contact[[0, 8, 9, 12]] = [0.2e6, 0.5e6, -0.1e6, 0.1e6]
    material = dataclasses.replace(riser.material, moduli=dataclasses.replace(m, contact=tuple(contact)))
    inv = dataclasses.replace(_inventory(riser, [0.0762, 0.0889], [90, 10]), material=material)
    problem = make_problem(inv, make_groups(inv), relaxed=True)
    assert problem.structure.contact
    run = multistart(problem, starts=4, seed=0, pool=SerialExecutor())
    table = evaluate_pipes(inv, problem.geometry(run.best.x))
    assert problem.physical(run.best.objective) == pytest.approx(table.largest.max(), rel=1e-9)
    plain = evaluate_pipes(_inventory(riser, [0.0762, 0.0889], [90, 10]), problem.geometry(run.best.x))
    assert not np.allclose(table.pressure, plain.pressure)  # the increments change the answer
