"""`plan` and `--max-payload` on a robot that is not uniform (tests/support/uneven.py: two muscle sizes,
unequal masses, an effect on one PAM, one PAM rated below the supply), judged per segment and section
against brentq on the full model (issue 40). Both solvers; routes where a segment can anchor in a single
section only (the 60 mm pipe is narrower than the big muscle at rest, the 120 mm pipe wider than the
small muscles' braid)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import brentq

from pampipe.planning import max_payload, plan_mission
from tests.support.uneven import RATED, least_holding_pressure, uneven_mission


def section(name, bore, incline, friction):
    return {"name": name, "length": "2 m", "inner_diameter": bore, "incline": incline, "friction": friction}


ROUTES = {
    "one-section-each": [section("tight", "60 mm", "90 deg", 0.3), section("wide", "120 mm", "20 deg", 0.4)],
    "mixed": [section("tight", "60 mm", "90 deg", 0.3), section("riser", "3 in", "90 deg", 0.3),
              section("wide", "120 mm", "20 deg", 0.4), section("run", "3.5 in", "-30 deg", 0.25)],
    "passable": [section("riser", "3 in", "90 deg", 0.3), section("run", "3.5 in", "0 deg", 0.3),
                 section("down", "100 mm", "-30 deg", 0.45)],
}


def independent(mission, payload):
    return np.array([[least_holding_pressure(mission, i, s.diameter, s.incline, s.friction, payload)
                      for i in range(len(mission.segments))] for s in mission.route])


@pytest.mark.parametrize("method", ["kkt", "ipopt"])
@pytest.mark.parametrize("route", list(ROUTES))
def test_plan_per_segment_against_the_model(tmp_path, route, method):
    mission = uneven_mission(tmp_path, ROUTES[route])
    plan = plan_mission(mission, method=method, check=False)
    want = independent(mission, mission.payload)
    got = plan.arrays.pressure
    assert (plan.iterations > 0) if method == "ipopt" else (plan.iterations == 0)  # IPOPT's, summed
    np.testing.assert_array_equal(np.isfinite(got), np.isfinite(want))
    np.testing.assert_allclose(got[np.isfinite(want)], want[np.isfinite(want)], rtol=1e-8)
    for sec, planned in zip(mission.route, plan.sections, strict=True):  # p_c = F_r/(D·L_p), §5.6
        if not planned.feasible:  # an infeasible section lists no segments
            continue
        for seg, element in zip(mission.segments, planned.segments, strict=True):
            if math.isfinite(element.pressure):
                g = seg.pam.geometry
                braid = g.initial_length / math.cos(g.braid_angle)
                anchored = math.sqrt(braid**2 - (braid * math.sin(g.braid_angle) * sec.diameter
                                                 / g.initial_diameter) ** 2)
                assert element.contact_pressure == pytest.approx(
                    element.radial_force / (sec.diameter * anchored), rel=1e-9)
    if route == "one-section-each":  # each muscle size anchors in exactly one of the two sections
        assert np.isfinite(got).sum(axis=0).tolist() == [1, 1, 1]


def test_max_payload_per_segment_against_the_model(tmp_path):
    """The largest payload: the least over sections and segments of the payload m at which the segment's
    least holding pressure reaches its own limit (689 kPa, 400 kPa for the rated one): brentq in m."""
    mission = uneven_mission(tmp_path, ROUTES["passable"])
    limits = [mission.supply_pressure, mission.supply_pressure, RATED]
    best = (math.inf, None)
    for s, sec in enumerate(mission.route):
        for i, limit in enumerate(limits):
            def over(m, i=i, sec=sec, limit=limit):
                return least_holding_pressure(mission, i, sec.diameter, sec.incline, sec.friction, m) - limit
            assert over(0.0) < 0
            m = brentq(over, 0.0, 1e4, xtol=1e-9, rtol=1e-12)
            best = min(best, (m, (s, i)))
    found = max_payload(mission)
    assert found.payload == pytest.approx(best[0], rel=1e-6)
    where, who = best[1]
    assert (found.section, found.segment) == (mission.route[where].name, mission.segments[who].name)


def test_ipopt_counts_no_iteration_where_no_element_holds(tmp_path):
    """The limit case of the iteration count (the sum of IPOPT's iterations over the blocks it solves): on a
    route no muscle can anchor in (narrower than every muscle at rest, wider than every braid) IPOPT
    solves no block, so the plan reports 0 iterations and no finite pressure."""
    route = [section("tight", "50 mm", "90 deg", 0.3), section("wide", "200 mm", "0 deg", 0.3)]
    mission = uneven_mission(tmp_path, route)
    assert np.all(np.isinf(independent(mission, mission.payload)))
    plan = plan_mission(mission, method="ipopt", check=False)
    assert plan.iterations == 0
    assert not np.any(np.isfinite(plan.arrays.pressure))
