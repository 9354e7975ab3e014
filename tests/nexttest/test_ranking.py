"""The linearised ranking: common draws, a test that says nothing changes nothing, order by drop per cost."""

from __future__ import annotations

import dataclasses
import math

import pytest

from pampipe.errors import InputError
from pampipe.io.mission_schema import load_mission
from pampipe.io.pam_schema import load_pam
from pampipe.nexttest.ranking import Planner, drop, order_key, rank_menu
from pampipe.specs.menu import MenuTest
from tests.support.problems import PROBLEMS

PAM_FILE = PROBLEMS / "pams" / "paper-radial-pam-uncertain.yaml"
MISSION = PROBLEMS / "missions" / "riser-uncertain-friction.yaml"
LEVELS = tuple(69e3 * k for k in range(1, 10))


def _planner(**options) -> Planner:
    return Planner(load_mission(MISSION), load_pam(PAM_FILE), PAM_FILE, 0.95, samples=2000, **options)


def test_ranked_by_drop_per_cost():
    # the first, the same dearer, one below contact (no information), an axial test
    tests = (MenuTest("radial", 3600, LEVELS, pipe_diameter=0.0889, axial_load=0.0, entry=0),
             MenuTest("radial", 7200, LEVELS, pipe_diameter=0.0889, axial_load=0.0, entry=1),
             MenuTest("radial", 3600, (10e3, 20e3), pipe_diameter=0.0889, axial_load=0.0, entry=2),
             MenuTest("axial", 3600, LEVELS, entry=3))
    ranking = rank_menu(_planner(), tests)
    current = ranking.current
    by_entry = {o.tests[0].entry: o for o in ranking.ranked}
    assert by_entry[2].pressure == current.pressure  # no information, the same draws: the same plan
    assert by_entry[2].information_gain == 0.0
    assert by_entry[0].pressure == by_entry[1].pressure < current.pressure  # what it buys, not what it costs
    keys = [order_key(current, o) for o in ranking.ranked]
    assert keys == sorted(keys)
    entries = [o.tests[0].entry for o in ranking.ranked]
    assert entries.index(0) < entries.index(1) and entries[-1] == 2
    assert ranking.d_optimal.tests[0].entry in (0, 3)


def test_pairs_and_air():
    # the first, the same dearer, one below contact (no information), an axial test
    tests = (MenuTest("radial", 3600, LEVELS, pipe_diameter=0.0889, axial_load=0.0, entry=0),
             MenuTest("isometric", 1800, LEVELS, length=0.25, entry=1))
    ranking = rank_menu(_planner(objective="air"), tests, pairs=True)
    assert len(ranking.ranked) == 3
    pair = next(o for o in ranking.ranked if len(o.tests) == 2)
    assert pair.cost == 5400
    assert pair.pressure <= min(o.pressure for o in ranking.ranked if len(o.tests) == 1) + 1.0


def test_drop():
    assert drop(math.inf, 2e5) == math.inf and drop(math.inf, math.inf) == 0.0 and drop(3e5, 2e5) == 1e5


def test_a_pam_the_mission_does_not_carry():
    other = dataclasses.replace(load_pam(PAM_FILE), name="other")
    with pytest.raises(InputError, match="no segment of the mission carries"):
        Planner(load_mission(MISSION), other, PROBLEMS / "pams" / "paper-radial-pam.yaml", 0.95)
