"""`pampipe.gait(..., optimal=True)` re-solves warm from the last solution of the same structure (issue 25).

The warm solve must land on the same optimum as a cold one (IPOPT tolerance 1e-8 on a problem whose
cycle time is ~10 s: 1e-6 relative covers it), and a mission of another structure (a different
control grid) must not start from it.
"""

from __future__ import annotations

import numpy as np
import pytest

import pampipe
from pampipe import api
from tests.conftest import PROBLEMS

DEMO = PROBLEMS / "missions" / "vertical-climb-3in.yaml"


def durations(report) -> np.ndarray:
    return np.array([step.duration for step in report.optimal.steps])


def test_a_second_call_is_warm_and_lands_on_the_cold_optimum(monkeypatch):
    monkeypatch.setattr(api, "_GAIT_WARM_STARTS", {})
    cold = pampipe.gait(DEMO, optimal=True)
    warm = pampipe.gait(DEMO, optimal=True)
    assert cold.optimal.solver["warm_start"] is False
    assert warm.optimal.solver["warm_start"] is True
    assert warm.optimal.solver["iterations"] < cold.optimal.solver["iterations"]
    assert warm.optimal.cycle_time == pytest.approx(cold.optimal.cycle_time, rel=1e-6)
    np.testing.assert_allclose(durations(warm), durations(cold), rtol=1e-6, atol=1e-9)


def test_another_structure_starts_cold_and_each_keeps_its_own_start(monkeypatch, tmp_path):
    monkeypatch.setattr(api, "_GAIT_WARM_STARTS", {})
    coarse = tmp_path / "coarse.yaml"
    coarse.write_text(DEMO.read_text().replace("../pams", str(PROBLEMS / "pams"))
                      + "gait: {optimal: {intervals: 6}}\n")
    assert pampipe.gait(DEMO, optimal=True).optimal.solver["warm_start"] is False
    other = pampipe.gait(coarse, optimal=True)
    assert other.optimal.solver["warm_start"] is False  # a 6-interval grid: not the 8-interval solution
    assert other.optimal.solver["intervals_per_phase"] == 6
    assert pampipe.gait(DEMO, optimal=True).optimal.solver["warm_start"] is True
    assert pampipe.gait(coarse, optimal=True).optimal.solver["warm_start"] is True
