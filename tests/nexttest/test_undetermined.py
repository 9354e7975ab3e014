"""A fit that leaves hoop.a0 open over ±2 MPa stops plan (exit 3); next-test says which test removes it."""

from __future__ import annotations

from pampipe.io.mission_schema import load_mission
from pampipe.nexttest.ranking import Planner, rank_menu
from pampipe.specs.menu import MenuTest
from tests.support.open_direction import open_direction_files

LEVELS = tuple(69e3 * k for k in range(1, 11))


def test_a_radial_test_closes_the_direction_and_exit_3_goes(tmp_path, radial_pam):
    pam, pam_file, mission_file = open_direction_files(tmp_path, radial_pam)
    planner = Planner(load_mission(mission_file), pam, pam_file, 0.95, samples=2000)
    below = MenuTest("radial", 3600, (10e3,), pipe_diameter=0.0889, axial_load=0.0, entry=1)  # no contact
    ranking = rank_menu(planner, (MenuTest("radial", 3600, LEVELS, pipe_diameter=0.0889, axial_load=0.0),
                                  below))
    assert ranking.current.stops and ranking.current.left_open == 1
    best, useless = ranking.ranked
    assert best.tests[0].entry == 0 and best.closes == 1 and not best.stops and best.left_open == 0
    assert useless.closes == 0 and useless.stops and useless.pressure == ranking.current.pressure
    # the plan with the direction closed holds the demo climb near its nominal 166 kPa (certain muscle)
    assert 160e3 < best.pressure < 175e3 < ranking.current.pressure
