"""The sampling evaluator judged per draw against the full model and root finding, on a robot that is not
uniform (issue 40): three segments of unequal mass and two muscle sizes, one PAM with contact increments,
drawn geometry and the model error, one plain, one shorter and wider with contact increments; every bore
a range with a drawn deviation; drawn friction and κ (confidence plans refuse PAMs with effects). For each
sampled draw and class the evaluator's P*, first contact at the largest bore and payload at a given
pressure must equal (to root-finding precision):

- P* = the largest over the range's bores of the least P with μπF_r(P, D, κW − e) = SF·W (brentq on the
  numeric :meth:`Muscle.radial_force`, from the anchoring pressure up);
- first contact = P_a(D_high, −e), the anchoring pressure in the largest bore at no load;
- payload = the smallest over the bores of the payload m with μπF_r(P, D, κW(m) − e) = SF·W(m) (brentq in
  W, then in m on :func:`no_slip.anchor_load`), −inf where the muscle does not touch the largest bore at P.

The evaluator uses closed forms (affine or quadratic in P), the coefficients kept per bore and the order
of the bores; none of that is used here."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from scipy.optimize import brentq

from pampipe.io.mission_schema import load_mission
from pampipe.model import no_slip
from pampipe.model.muscle import Muscle
from pampipe.model.pam import Geometry, Moduli
from pampipe.model.uncertainty import ParameterUncertainty
from pampipe.planning.confidence import sampling_problem
from pampipe.planning.evaluator import Evaluator
from pampipe.planning.problem import build_elements, mission_muscles
from pampipe.planning.sampling import class_deviations, muscle_draws
from pampipe.specs.mission import Route
from tests.support.problems import PROBLEMS

UNCERTAIN = PROBLEMS / "missions" / "riser-uncertain-friction.yaml"


def uneven_mission():
    """The uncertain riser with three unlike segments and a bore range in every section."""
    mission = load_mission(UNCERTAIN)
    base = mission.segments[0].pam
    theta = base.moduli.as_vector()
    delta = np.zeros_like(theta)
    delta[8] = 4e6  # contact.hoop.a0: a stiffer hoop law once anchored [Pa]
    u = base.uncertainty
    stiff = dataclasses.replace(base, moduli=Moduli.from_vector(theta, contact=delta),
                                geometry_sd={"initial_diameter": 5e-4, "braid_angle": math.radians(0.5)})
    stiff = stiff.with_uncertainty(ParameterUncertainty(u.names, u.covariance, 3.0))  # model error 3 N
    other = dataclasses.replace(stiff, geometry=dataclasses.replace(base.geometry, initial_length=0.26,
                                                                    initial_diameter=0.06),
                                geometry_sd={}, name="shorter-wider")
    pams, masses = (stiff, base, other), (0.4, 0.9, 0.25)
    segments = tuple(dataclasses.replace(s, pam=p, pam_file=None, mass=m)
                     for s, p, m in zip(mission.segments, pams, masses, strict=True))
    route = Route.from_sections(dataclasses.replace(s, diameter_low=s.diameter - 2e-3,
                                                    diameter_high=s.diameter + 3e-3, diameter_sd=4e-4)
                                for s in mission.route)
    return dataclasses.replace(mission, segments=segments, route=route, kappa_sd=0.1)


@pytest.fixture(scope="module")
def sampled():
    mission = uneven_mission()
    muscles = mission_muscles(mission)
    elements = build_elements(mission, muscles)
    problem, classes, _ = sampling_problem(mission, muscles, elements, 0.9, samples=120, seed=5,
                                           with_payload=True)
    assert set(problem.active) >= {"moduli", "geometry", "model_error", "kappa", "bore", "friction"}
    return mission, problem, classes


def reference(mission, problem, classes, draws, bore, friction, i, c, j, pressure):
    """(P* [Pa], first contact [Pa], payload at ``pressure`` [kg]) of draw j in class c, segment i."""
    p = problem.uncertainties[i].nominal.copy()
    for key in ("moduli", "geometry", "prior"):
        if key in problem.active:
            p = p + draws.params[key][i][j]
    n = problem.structures[i].n_theta
    muscle = Muscle(Geometry(*p[:4], "thick"), p[5:5 + n], p[4],
                    contact=p[5 + n:5 + 2 * n] if problem.structures[i].contact else None)
    mu = classes.mu[c] + friction[c, j]
    kappa = max(problem.kappa + draws.kappa[j], 0.0)
    e = draws.model_error[i][j]
    others = problem.total_mass - problem.payload

    def load(payload):
        return no_slip.anchor_load(others + payload, problem.masses[i], classes.incline[c], mu,
                                   problem.tether_drag)

    def margin(pressure, d, w):
        return mu * math.pi * muscle.radial_force(pressure, d, kappa * w - e) - problem.safety_factor * w

    w = load(problem.payload)
    bores = sorted({classes.low[c], classes.worst[c, i], classes.high[c]})
    need, held = [], []
    for d in (b + bore[c, j] for b in bores):
        start = max(float(muscle.anchoring_pressure(d, kappa * w - e)), 0.0)
        need.append(start if margin(start, d, w) >= 0 else
                    brentq(lambda x, d=d: margin(x, d, w), start, 1e8, xtol=1e-7, rtol=1e-13))
        if margin(pressure, d, 0.0) < 0:
            held.append(-math.inf)
            continue
        most = brentq(lambda x, d=d: margin(pressure, d, x), 0.0, 1e7, xtol=1e-10, rtol=1e-13)
        held.append(brentq(lambda m, w=most: load(m) - w, -others, 1e7, xtol=1e-10, rtol=1e-13))
    touch = float(muscle.anchoring_pressure(classes.high[c] + bore[c, j], -e))
    return max(need), touch, (min(held) if touch <= pressure else -math.inf)


@pytest.mark.parametrize("worst", ["an-end", "inside"])
@pytest.mark.parametrize("i", [0, 1, 2], ids=["contact-and-model-error", "plain", "other-size"])
@pytest.mark.parametrize("pressure", [689e3, 170e3], ids=["supply", "below-some-contacts"])
def test_general_evaluator_per_draw_against_root_finding(sampled, i, pressure, worst):
    """``worst``: the class's worst bore as classed (the range's largest) or moved inside the range, so
    that the evaluator keeps three bores (the largest must stay last: first contact is read there)."""
    mission, problem, classes = sampled
    if worst == "inside":
        middle = 0.5 * (classes.low + classes.high)
        inside = np.repeat(middle[:, None], classes.worst.shape[1], axis=1)
        classes = dataclasses.replace(classes, worst=inside)
    draws = muscle_draws(problem)
    bore, friction = class_deviations(problem, classes)
    rows = np.flatnonzero(classes.valid[:, i])
    assert rows.size == len(classes) and np.all(classes.high > classes.low)
    ev = Evaluator(problem, draws, classes, i, rows, bore.T, friction.T)
    assert ev.affine == (i == 1) and len(ev.bores) == (3 if worst == "inside" else 2)
    least, touch, payload = ev.evaluate(problem.active, pressure)
    alone = ev.evaluate(problem.active)  # without a pressure: the affine form where the muscle has one
    finite = 0
    for j in range(0, problem.samples, 7):
        for c in range(len(classes)):
            want = reference(mission, problem, classes, draws, bore, friction, i, c, j, pressure)
            for got in ((least[j, c], touch[j, c], payload[j, c]), (alone[0][j, c], alone[1][j, c], None)):
                assert got[0] == pytest.approx(want[0], rel=1e-9), ("P*", j, c)
                assert got[1] == pytest.approx(want[1], rel=1e-9, abs=1e-6), ("first contact", j, c)
            if math.isinf(want[2]):
                assert payload[j, c] == want[2], ("payload", j, c)
            else:
                finite += 1
                assert payload[j, c] == pytest.approx(want[2], rel=1e-8, abs=1e-8), ("payload", j, c)
    assert finite > 0


@pytest.mark.parametrize("i", [0, 1], ids=["contact-and-model-error", "plain"])
def test_payload_on_a_flat_pipe_of_low_friction_against_root_finding(sampled, i):
    """A level pipe (no rise) with μ ≈ 0.05: each kilogram asks g·μ ≈ 0.5 N of grip, under 1 N/kg, yet the
    payload is finite and equals the root-finding payload per draw (the division by g·(rise + μ·run) must
    refuse only a non-positive divisor)."""
    mission, problem, classes = sampled
    count = len(classes)
    classes = dataclasses.replace(classes, incline=np.zeros(count), mu=np.full(count, 0.05),
                                  mu_sd=np.full(count, 0.004))
    draws = muscle_draws(problem)
    bore, friction = class_deviations(problem, classes)
    assert np.all(np.abs(friction) < 0.045)  # every drawn μ in (0.005, 0.095): g·μ < 1 N/kg
    ev = Evaluator(problem, draws, classes, i, np.arange(count), bore.T, friction.T)
    _, _, payload = ev.evaluate(problem.active, 689e3)
    finite = 0
    for j in range(0, problem.samples, 11):
        for c in range(count):
            want = reference(mission, problem, classes, draws, bore, friction, i, c, j, 689e3)[2]
            if math.isinf(want):
                assert payload[j, c] == want, (j, c)
            else:
                finite += 1
                assert payload[j, c] == pytest.approx(want, rel=1e-8, abs=1e-8), (j, c)
    assert finite > 0
