"""`pampipe.gait(..., optimal=True)` re-solves warm from the last solution of the same structure (issue 25).

The warm solve must land on the same optimum as a cold one (IPOPT tolerance 1e-8 on a problem whose
cycle time is ~10 s: 1e-6 relative covers it), and a mission of another structure (a different
control grid) must not start from it.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import pampipe
from pampipe import api
from pampipe.io.mission_schema import load_mission
from pampipe.locomotion import gait_options, optimal_gait, sequential_gait
from tests.support.problems import PROBLEMS

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
    # from its own optimum, pushed only 1e-9 off the bounds (point, multipliers, slacks): at most 2 steps
    # (3 with IPOPT's 1e-6 default push of the cold solver)
    assert warm.optimal.solver["iterations"] <= 2
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


def test_warm_calls_on_changing_inputs_equal_cold_solves_of_each(monkeypatch):
    """Three missions in a row (payload, supply), then the first again: every warm answer equals a cold
    solve of that mission alone, so neither the kept sequential schedule nor the warm start leaks the
    previous input. The cold reference calls the locomotion layer directly (no kept state)."""
    monkeypatch.setattr(api, "_GAIT_WARM_STARTS", {})
    monkeypatch.setattr(api, "_GAIT_SEQUENTIAL", {})
    demo = load_mission(DEMO)
    missions = [dataclasses.replace(demo, payload=2.0), dataclasses.replace(demo, payload=3.0),
                dataclasses.replace(demo, payload=3.0, supply_pressure=0.8e6)]
    options = gait_options(demo.gait, source=demo.source)
    cold = [(sequential_gait(m, options=options), optimal_gait(m, options=options)) for m in missions]
    times = [c[1].cycle_time for c in cold]
    assert min(abs(times[i] / times[j] - 1) for i, j in [(0, 1), (1, 2), (0, 2)]) > 1e-3
    assert abs(cold[0][0].cycle_time / cold[1][0].cycle_time - 1) > 1e-3  # the schedules differ too
    calls = [*zip(missions, cold, strict=True), (missions[0], cold[0])]
    for k, (mission, (sequential, best)) in enumerate(calls):
        warm = pampipe.gait(mission, optimal=True)
        assert warm.optimal.solver["warm_start"] is (k > 0)
        assert warm.sequential.cycle_time == pytest.approx(sequential.cycle_time, rel=1e-12)
        np.testing.assert_allclose(warm.sequential.trajectory.pressures, sequential.trajectory.pressures,
                                   rtol=1e-12, atol=1e-9)
        assert warm.optimal.cycle_time == pytest.approx(best.cycle_time, rel=1e-6)
        np.testing.assert_allclose(durations(warm), [s.duration for s in best.steps], rtol=1e-6, atol=1e-9)
        warm.sequential.trajectory.pressures[:] = -1.0  # a caller's edit never reaches the kept schedule


def test_content_that_does_not_pickle_is_never_reused():
    """A mission holding an object pickle refuses gets no key (so no reuse), not a crash."""
    from pampipe.api import _content_key

    assert _content_key(lambda: 0) is None
    assert _content_key({"a": 1}) == _content_key({"a": 1}) != _content_key({"a": 2})
