"""planning/solve.py's label of what sets each pressure (the JSON's ``binding``): ``no_slip`` where the
pressure is above max(P_a(κW), 0), the loaded anchoring pressure floored at 0 Pa, by more than round-off
(relative 1e-12 plus 1e-9 Pa); ``contact`` where the muscle holds as soon as it touches; neither an
infinite pressure (issue 40: mutants of the label's threshold survived)."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np

from pampipe.planning.solve import slip_binds


def test_no_slip_binds_above_the_floored_anchoring_pressure_only():
    anchoring = np.array([[1e5, -2e4, 3e5], [2e5, 0.0, 1.5e5], [-5e3, 4e5, 1e5], [-1.0, 0.0, 0.0]])
    pressure = np.array([[1e5, 5e3, 3.2e5],  # at P_a: contact; > 0 with P_a < 0: slip; 7 % above P_a: slip
                         [3.9e5, 0.0, np.inf],  # 1.95 P_a: slip; 0 with P_a = 0: contact; inf: neither
                         [0.0, 4e5 * (1 + 1e-13), 1e5 + 0.5],  # P_a < 0, P = 0: contact; within round-off
                         [1e-4, 5e-10, 2e-9]])  # the floor is 0 Pa exactly, the padding 1e-9 Pa
    want = np.array([[False, True, True], [True, False, False], [False, False, True], [True, False, True]])
    np.testing.assert_array_equal(slip_binds(pressure, SimpleNamespace(anchoring=anchoring)), want)


def test_the_label_is_per_element_over_many_sections():
    """More sections than one chunk of the planner: every row labelled as its own."""
    rows = 5000
    anchoring = np.tile([[1e5, -1e3]], (rows, 1))
    pressure = np.tile([[1.2e5, 1e5]], (rows, 1))
    pressure[::7, 0] = 1e5  # contact binds in every 7th section
    got = slip_binds(pressure, SimpleNamespace(anchoring=anchoring))
    assert got.shape == (rows, 2) and got[:, 1].all()
    np.testing.assert_array_equal(got[:, 0], np.arange(rows) % 7 != 0)
