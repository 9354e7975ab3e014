"""The evaluator with a tether whose friction is uncertain (docs/physics.md §16): each class's load is the
section's constant drag T (tether_drag + the largest tension) unless the ``tether`` source is drawn, when it
is that draw's tension. Checked per draw against the plain muscle's own least holding pressure under the
load W(μ) + T written from the route (no_slip.anchor_load), and the other sources' P* against the same
mission with a certain tether (issue 40: mutants of the tether key survived every evaluator test)."""

from __future__ import annotations

import math

import numpy as np
import pytest
import yaml

from pampipe.io.mission_schema import load_mission
from pampipe.model import no_slip
from pampipe.planning.confidence import sampling_problem
from pampipe.planning.evaluator import Evaluator
from pampipe.planning.problem import build_elements, mission_muscles
from pampipe.planning.sampling import muscle_draws
from pampipe.planning.sources import keyed_normal
from pampipe.planning.tension import tensions, tether_frictions
from tests.support.problems import PROBLEMS

PAM = str(PROBLEMS / "pams" / "paper-radial-pam.yaml")
N, SEED = 200, 4
ROUTE = [{"name": "run", "length": "40 m", "inner_diameter": "3 in", "incline": "0 deg",
          "friction": {"value": 0.3, "sd": 0.03}, "bend": {"angle": "90 deg", "radius": "20 D"}},
         {"name": "riser", "length": "12 m", "inner_diameter": "3 in", "incline": "60 deg",
          "friction": {"value": 0.35, "sd": 0.03}}]


def mission(tmp_path, tether_sd):
    doc = {"robot": {"segments": [{"name": f"PAM{i}", "pam": PAM, "mass": "0.4 kg"} for i in (1, 2, 3)],
                     "payload": "1 kg"},
           "supply_pressure": "689 kPa", "safety_factor": 1.5, "route": ROUTE,
           "tether": {"weight": "0.8 N/m", "friction": {"value": 0.35, "sd": tether_sd},
                      "back_tension": "5 N", "length": "2000 m"}}
    path = tmp_path / f"tether-{tether_sd}.yaml"
    path.write_text(yaml.safe_dump(doc))
    return load_mission(path)


def evaluator(m):
    muscles = mission_muscles(m)
    problem, classes, _ = sampling_problem(m, muscles, build_elements(m, muscles), 0.95, samples=N, seed=SEED)
    rows = np.arange(len(classes))
    bore = np.zeros((N, rows.size))
    friction = np.column_stack([keyed_normal(SEED, "friction", (classes.mu[c], classes.mu_sd[c]), N)
                                * classes.mu_sd[c] for c in rows])
    return Evaluator(problem, muscle_draws(problem), classes, 0, rows, bore, friction), muscles[0], classes


@pytest.fixture(scope="module")
def both(tmp_path_factory):
    folder = tmp_path_factory.mktemp("tether")
    return mission(folder, 0.05), evaluator(mission(folder, 0.05)), evaluator(mission(folder, 0.0))


def test_tether_draws_give_each_draws_tension_as_the_load(both):
    """P* of draw j with the tether alone = the nominal muscle's P* under W(μ̂) + tether_drag
    + max(T_in, T_out) at that draw's tether friction."""
    m, (ev, muscle, classes), _ = both
    assert classes.drag_draws is not None and len(classes) == 2
    least = ev.evaluate(("tether",))[0]
    t_in, t_out = tensions(m.route, m.tether, tether_frictions(m.tether, N, SEED))
    others = sum(s.mass for s in m.segments) + m.payload
    for c, section in enumerate(m.route):
        assert classes.incline[c] == pytest.approx(section.incline)
        for j in range(0, N, 17):
            drag = m.tether_drag + max(t_in[c, j], t_out[c, j])
            w = no_slip.anchor_load(others, m.segments[0].mass, section.incline, section.friction, drag)
            want = float(muscle.least_holding_pressure(section.diameter, w, kappa=ev.problem.kappa,
                                                       friction=section.friction,
                                                       safety_factor=m.safety_factor))
            assert least[j, c] == pytest.approx(want, rel=1e-9), (c, j)
    assert np.ptp(least, axis=0).min() > 0  # the tension's draws move P* in every class


def test_sources_without_the_tether_keep_its_nominal_tension(both):
    """The route friction alone (or κ) draws no tension: the same P* as with a tether of certain friction."""
    _, (ev, _, _), (certain, _, _) = both
    assert certain.drag_draws is None
    np.testing.assert_allclose(ev.evaluate(("friction",))[0], certain.evaluate(("friction",))[0], rtol=1e-12)
    assert math.isfinite(float(np.max(ev.evaluate(("friction",))[0])))
