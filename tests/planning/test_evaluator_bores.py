"""The evaluator's general path (a PAM with contact increments) on a route of exactly two bores: each class
takes its own bore's coefficients (issue 40: reading the first bore's for both survived every evaluator
test, whose routes had one bore or three). Per draw of the route friction against the muscle's own least
holding pressure under the load W(μ) written from the route (no_slip.anchor_load)."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
import yaml

from pampipe.io.mission_schema import load_mission
from pampipe.model import no_slip
from pampipe.model.pam import Moduli
from pampipe.planning.confidence import sampling_problem
from pampipe.planning.evaluator import Evaluator
from pampipe.planning.problem import build_elements, mission_muscles
from pampipe.planning.sampling import muscle_draws
from pampipe.planning.sources import keyed_normal
from tests.support.problems import PROBLEMS

PAM = str(PROBLEMS / "pams" / "paper-radial-pam.yaml")
N, SEED = 200, 2


@pytest.fixture(scope="module")
def two_bores(tmp_path_factory):
    doc = {"robot": {"segments": [{"name": f"PAM{i}", "pam": PAM, "mass": "0.4 kg"} for i in (1, 2, 3)],
                     "payload": "1 kg"},
           "supply_pressure": "689 kPa", "safety_factor": 1.5,
           "route": [{"name": "narrow", "length": "5 m", "inner_diameter": "3 in", "incline": "30 deg",
                      "friction": {"value": 0.3, "sd": 0.04}},
                     {"name": "wide", "length": "5 m", "inner_diameter": "3.5 in", "incline": "30 deg",
                      "friction": {"value": 0.3, "sd": 0.04}}]}
    path = tmp_path_factory.mktemp("bores") / "two-bores.yaml"
    path.write_text(yaml.safe_dump(doc))
    mission = load_mission(path)
    pam = mission.segments[0].pam
    delta = np.zeros(16)
    delta[8] = 4e6  # contact.hoop.a0 [Pa]: the general path, not the affine one
    stiff = dataclasses.replace(pam, moduli=Moduli.from_vector(pam.moduli.as_vector(), contact=delta))
    mission = dataclasses.replace(mission, segments=tuple(dataclasses.replace(s, pam=stiff, pam_file=None)
                                                          for s in mission.segments))
    muscles = mission_muscles(mission)
    problem, classes, _ = sampling_problem(mission, muscles, build_elements(mission, muscles), 0.95,
                                           samples=N, seed=SEED)
    rows = np.arange(len(classes))
    friction = np.column_stack([keyed_normal(SEED, "friction", (classes.mu[c], classes.mu_sd[c]), N)
                                * classes.mu_sd[c] for c in rows])
    ev = Evaluator(problem, muscle_draws(problem), classes, 0, rows, np.zeros((N, rows.size)), friction)
    return mission, muscles[0], classes, ev


def test_each_class_uses_its_own_bore(two_bores):
    mission, muscle, classes, ev = two_bores
    assert not ev.affine and len(classes) == 2
    assert sorted(classes.high) == pytest.approx([0.0762, 0.0889])
    least = ev.evaluate(("friction",))[0]
    others = sum(s.mass for s in mission.segments) + mission.payload
    for c in range(2):
        for j in range(0, N, 13):
            mu = classes.mu[c] + ev.friction[j, c]
            w = no_slip.anchor_load(others, mission.segments[0].mass, classes.incline[c], mu,
                                    mission.tether_drag)
            want = float(muscle.least_holding_pressure(classes.high[c], w, kappa=ev.problem.kappa,
                                                       friction=mu, safety_factor=mission.safety_factor))
            assert least[j, c] == pytest.approx(want, rel=1e-9), (c, j)


def test_one_class_in_a_bore_range_on_the_affine_path(tmp_path):
    """A plain PAM (the affine path) on one section whose bore is a range: one class, so one group per bore
    of the range; P* per draw = the largest of the muscle's P* at the range's ends and worst bore, and first
    contact = its anchoring pressure in the largest bore."""
    doc = {"robot": {"segments": [{"name": f"PAM{i}", "pam": PAM, "mass": "0.4 kg"} for i in (1, 2, 3)],
                     "payload": "1 kg"},
           "supply_pressure": "689 kPa", "safety_factor": 1.5,
           "route": [{"name": "ranged", "length": "5 m", "incline": "50 deg",
                      "inner_diameter": {"nps": 3, "schedule": 40, "tolerance": "1 %"},
                      "friction": {"value": 0.3, "sd": 0.04}}]}
    path = tmp_path / "one-class.yaml"
    path.write_text(yaml.safe_dump(doc))
    mission = load_mission(path)
    muscles = mission_muscles(mission)
    problem, classes, _ = sampling_problem(mission, muscles, build_elements(mission, muscles), 0.95,
                                           samples=N, seed=SEED)
    friction = keyed_normal(SEED, "friction", (classes.mu[0], classes.mu_sd[0]), N)[:, None]
    friction = friction * classes.mu_sd[0]
    ev = Evaluator(problem, muscle_draws(problem), classes, 0, np.arange(1), np.zeros((N, 1)), friction)
    assert ev.affine and len(classes) == 1 and classes.low[0] < classes.high[0]
    least, touch, _ = ev.evaluate(("friction",))
    others = sum(s.mass for s in mission.segments) + mission.payload
    muscle = muscles[0]
    bores = (classes.low[0], classes.worst[0, 0], classes.high[0])
    for j in range(0, N, 11):
        mu = classes.mu[0] + friction[j, 0]
        w = no_slip.anchor_load(others, mission.segments[0].mass, classes.incline[0], mu, mission.tether_drag)
        want = max(float(muscle.least_holding_pressure(d, w, kappa=problem.kappa, friction=mu,
                                                       safety_factor=mission.safety_factor)) for d in bores)
        assert least[j, 0] == pytest.approx(want, rel=1e-9), j
    assert touch == pytest.approx(float(muscle.anchoring_pressure(classes.high[0])), rel=1e-9)
