"""The exported law's Python twin at the edges of its domain, with the numbers docs/commands.md §9 states
(not read from the module): return codes 0 OK, 1 narrow, 2 wide, 3 no friction, 4 above the supply, 5 bad
argument; 0 < D ≤ 10 m, |φ| ≤ π/2, 0 ≤ μ ≤ 10 with μ < 10⁻⁶ no friction, 0 ≤ m ≤ 10⁵ kg (issue 40: the
constants of the domain and the codes survived mutation)."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from pampipe.export.law import Reason, in_domain, mission_law
from pampipe.io.mission_schema import load_mission
from tests.support.problems import PROBLEMS


@pytest.fixture(scope="module")
def law():
    return mission_law(load_mission(PROBLEMS / "missions" / "vertical-climb-3in.yaml"))


def test_the_return_codes_are_the_documented_numbers():
    assert [int(r) for r in (Reason.OK, Reason.NARROW, Reason.WIDE, Reason.NO_FRICTION, Reason.ABOVE_SUPPLY,
                             Reason.BAD_ARGUMENT)] == [0, 1, 2, 3, 4, 5]


@pytest.mark.parametrize(("args", "inside"), [
    ((10.0, 0.0, 0.3, 1.0), True), ((10.05, 0.0, 0.3, 1.0), False), ((1e-300, 0.0, 0.3, 1.0), True),
    ((0.0, 0.0, 0.3, 1.0), False),
    ((1.0, math.pi / 2, 0.3, 1.0), True), ((1.0, -math.pi / 2, 0.3, 1.0), True),
    ((1.0, -1.2, 0.3, 1.0), True), ((1.0, 1.58, 0.3, 1.0), False), ((1.0, -1.58, 0.3, 1.0), False),
    ((1.0, 0.0, 10.0, 1.0), True), ((1.0, 0.0, 10.05, 1.0), False), ((1.0, 0.0, 0.0, 1.0), True),
    ((1.0, 0.0, -1e-300, 1.0), False),
    ((1.0, 0.0, 0.3, 1e5), True), ((1.0, 0.0, 0.3, 1.0005e5), False), ((1.0, 0.0, 0.3, 0.0), True),
    ((1.0, 0.0, 0.3, -1e-9), False), ((1.0, 0.0, 0.3, math.nan), False), ((None, 0.0, 0.3, 1.0), False)])
def test_the_domain_is_the_documented_one(args, inside):
    assert in_domain(*args) is inside


def test_friction_below_one_millionth_is_no_friction(law):
    assert law.evaluate(0.0762, 1.0, 1e-6, 2.0)[0] != Reason.NO_FRICTION
    assert law.evaluate(0.0762, 1.0, 1.005e-6, 2.0)[0] != Reason.NO_FRICTION
    assert law.evaluate(0.0762, 1.0, 0.99e-6, 2.0)[0] == Reason.NO_FRICTION


def test_the_limits_are_each_segments_or_the_supply(law):
    n = len(law.segments)
    assert law.limits == pytest.approx(law.pressure_limits) and len(law.pressure_limits) == n
    lower = dataclasses.replace(law, pressure_limits=(law.supply_pressure, 120e3, law.supply_pressure))
    assert list(lower.limits) == [law.supply_pressure, 120e3, law.supply_pressure]
    none = dataclasses.replace(law, pressure_limits=())
    assert list(none.limits) == [law.supply_pressure] * n
    reason, pressure = law.evaluate(0.0762, 1.0, 0.3, 2.0)
    assert reason == Reason.OK and np.all(pressure > 120e3)  # the lower limit of one segment is passed
    assert lower.evaluate(0.0762, 1.0, 0.3, 2.0)[0] == Reason.ABOVE_SUPPLY


def test_the_widest_bore_is_where_the_braid_or_its_rating_stops(law):
    """D(L) = √(B² − L²)/(Nπ) with B = L₀/cos α₀, Nπ = B·sin α₀/D₀ (docs/physics.md §1-§2): the widest bore
    is D(B/√3), or D((1 − c)L₀) where the maker's max_contraction c stops the muscle first; the segment
    with the lowest such bore sets the law's WIDE (reason 2)."""
    mission = load_mission(PROBLEMS / "missions" / "vertical-climb-3in.yaml")
    g = mission.segments[0].pam.geometry
    braid = g.initial_length / math.cos(g.braid_angle)
    n_pi = braid * math.sin(g.braid_angle) / g.initial_diameter

    def diameter(length):
        return math.sqrt(braid**2 - length**2) / n_pi

    assert law.largest_diameters[0] == pytest.approx(diameter(braid / math.sqrt(3)), rel=1e-12)
    rated = dataclasses.replace(mission.segments[1].pam, max_contraction=0.2)
    loose = dataclasses.replace(mission.segments[2].pam, max_contraction=0.9)  # beyond B/√3: the braid stops
    segments = (mission.segments[0], dataclasses.replace(mission.segments[1], pam=rated),
                dataclasses.replace(mission.segments[2], pam=loose))
    rated_law = mission_law(dataclasses.replace(mission, segments=segments))
    want = diameter(0.8 * g.initial_length)
    assert want < diameter(braid / math.sqrt(3))
    assert rated_law.largest_diameters[1] == pytest.approx(want, rel=1e-12)
    assert rated_law.largest_diameters[2] == pytest.approx(law.largest_diameters[2], rel=1e-12)
    assert rated_law.widest == pytest.approx(want, rel=1e-12)
    assert rated_law.evaluate(want * 1.001, 1.0, 0.3, 2.0)[0] == Reason.WIDE
    assert law.evaluate(want * 1.001, 1.0, 0.3, 2.0)[0] != Reason.WIDE


def test_the_edges_belong_to_the_refusals_and_a_pressure_at_its_limit_is_ok(law):
    """D = D₀ (the sleeve at rest) is narrow (1), D = D(B/√3) wide (2), both as documented ("not wider than
    a muscle at rest", "wider than the braid can fill" from that diameter on); a pressure exactly at its
    segment's limit is OK (P ≤ limit), a limit one ulp below it is exceeded (4)."""
    assert law.evaluate(law.narrowest, 1.0, 0.3, 2.0)[0] == Reason.NARROW
    assert law.evaluate(law.widest, 1.0, 0.3, 2.0)[0] == Reason.WIDE
    assert law.evaluate(math.nextafter(law.widest, 0.0), 1.0, 0.3, 2.0)[0] != Reason.WIDE
    _, pressure = law.evaluate(0.0762, 1.0, 0.3, 2.0)
    at = dataclasses.replace(law, pressure_limits=tuple(float(p) for p in pressure))
    assert at.evaluate(0.0762, 1.0, 0.3, 2.0)[0] == Reason.OK
    below = dataclasses.replace(law, pressure_limits=tuple(math.nextafter(float(p), 0.0) for p in pressure))
    assert below.evaluate(0.0762, 1.0, 0.3, 2.0)[0] == Reason.ABOVE_SUPPLY
