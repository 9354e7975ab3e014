"""The experiment skeleton of `next-test -o`: the entry and the rows to measure, per kind."""

from __future__ import annotations

import numpy as np

from pampipe.io.pam_schema import load_pam
from pampipe.io.skeleton import AXIAL_ROWS, entry, rows
from pampipe.model.muscle import Muscle
from pampipe.specs.menu import MenuTest
from tests.support.problems import PROBLEMS

MUSCLE = Muscle.from_pam(load_pam(PROBLEMS / "pams" / "paper-radial-pam.yaml"))
LEVELS = (100e3, 400e3)


def test_radial_and_slip():
    radial = MenuTest("radial", 1, LEVELS, pipe_diameter=0.0889, axial_load=1024.74)
    assert entry(radial, "d.csv") == {"name": "radial-88.9mm-1025N", "kind": "radial", "data": "d.csv",
                                      "pipe_diameter": "88.9 mm", "axial_load": "1024.74 N"}
    assert rows(radial, MUSCLE) == "pressure [kPa],force [N]\n100,\n400,\n"
    slip = MenuTest("slip", 1, LEVELS, pipe_diameter=0.0762, axial_load=0.0, trials=3)
    assert entry(slip, "s.csv")["kind"] == "slip"
    assert rows(slip, MUSCLE).count("\n") == 1 + 2 * 3


def test_axial_lengths_lie_between_the_free_and_the_rest_length():
    axial = MenuTest("axial", 1, LEVELS)
    header, *lines = rows(axial, MUSCLE).splitlines()
    assert header == "pressure [kPa],length [mm],force [N]" and len(lines) == 2 * AXIAL_ROWS
    for line in lines:
        pressure, length, force = line.split(",")
        free = float(np.ravel(MUSCLE.free_length(float(pressure) * 1e3))[0]) * 1e3
        assert free < float(length) < MUSCLE.geometry.initial_length * 1e3 and force == ""
    isometric = MenuTest("isometric", 1, LEVELS, length=0.25)
    assert entry(isometric, "i.csv")["protocol"] == "isometric"
