"""The gait schedules: stride from the simulated positions, always held, optimal vs sequential."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from pampipe.io.mission_schema import load_mission
from pampipe.locomotion import gait_options, optimal_gait, schedule, sequential_gait
from pampipe.locomotion.optimal import _problem
from pampipe.locomotion.schedule import ANCHORS
from pampipe.pneumatics import timing as pneumatics
from tests.support.problems import PROBLEMS

DEMO = PROBLEMS / "missions" / "vertical-climb-3in.yaml"
DOWNHILL = PROBLEMS / "missions" / "downhill-drain.yaml"
# The exact re-simulation places the pressures to ~1e-3 Pa; near the no-slip pressure the margin
# changes by SF/(P_req − P_anchor(κW)) ≈ 1.5 / 3 kPa per Pa, so 1e-6 of SF bounds that error.
HOLD_TOLERANCE = 1e-6


@pytest.fixture(scope="module")
def demo():
    return load_mission(DEMO)


@pytest.fixture(scope="module")
def demo_gaits(demo):
    """Sequential and optimal gaits in both sections of the demo mission."""
    out = {}
    for section in ("riser", "run"):
        seq = sequential_gait(demo, section)
        out[section] = (seq, optimal_gait(demo, section, baseline=seq))
    return out


def _ideal_stride(result):
    need = result.needs[1]  # the middle segment sets the stride (docs/physics.md §8)
    return need.rest_length - need.anchored_length


def _deflated_shortfall(result, vented):
    """L₀ − L_free(vented pressure): how much a muscle vented only to ``vented`` is still contracted."""
    muscle = result.needs[1].muscle
    return muscle.geometry.initial_length - float(muscle.free_length([vented])[0])


@pytest.mark.parametrize("section", ["riser", "run"])
def test_stride_equals_rest_minus_anchored_length(demo, section):
    """With venting to 1 Pa the simulated stride is L₀ − L(D_p) to 1e-6 m·(shortfall ≈ 2e-7 m)."""
    options = dataclasses.replace(gait_options(demo.gait), vented_pressure=1.0)
    result = sequential_gait(demo, section, options=options)
    shortfall = _deflated_shortfall(result, 1.0)
    assert shortfall < 1e-6
    ideal = _ideal_stride(result)
    # every point of the worm advances by the same stride over one cycle
    advance = result.ends[-1] - result.ends[0]
    assert advance == pytest.approx([ideal] * 4, abs=shortfall + 1e-9)
    assert result.stride == pytest.approx(ideal, abs=shortfall + 1e-9)


def test_stride_of_both_default_schedules(demo_gaits):
    """Vented to 0.5 kPa, PAM2 is L₀ − L_free(0.5 kPa) short of L₀, and the stride by that much."""
    for seq, best in demo_gaits.values():
        ideal = _ideal_stride(seq)
        shortfall = _deflated_shortfall(seq, seq.plan.start[0])
        for result in (seq, best):
            assert ideal - shortfall - 1e-6 <= result.stride <= ideal + 1e-9
            assert result.kinematic_slip < 1e-12  # no anchor pair ever disagrees


def test_always_held_with_the_safety_factor(demo_gaits):
    """At every sample (10 per optimiser interval for the optimal gait) some anchor holds with
    margin ≥ SF, and each step's designated anchors hold at its end."""
    for seq, best in demo_gaits.values():
        sf = seq.needs[0].safety_factor
        for result in (seq, best):
            assert result.hold_margin.min() >= sf * (1 - HOLD_TOLERANCE)
            for k, step in enumerate(result.steps):
                assert set(step.anchored) == {result.names[i] for i in ANCHORS[k]}
                assert min(step.slip_margins.values()) >= sf * (1 - HOLD_TOLERANCE)


def test_optimal_gait_is_resimulated_on_a_ten_times_finer_grid(demo_gaits):
    _, best = demo_gaits["riser"]
    intervals = best.plan.commands.shape[1]
    assert best.trajectory.times.size == 1 + 10 * intervals * len(best.plan.durations)


def test_optimal_is_never_slower_and_faster_on_the_demo(demo_gaits):
    for seq, best in demo_gaits.values():
        assert best.cycle_time <= seq.cycle_time * (1 + 1e-9)
        assert best.solver["status"] == "Solve_Succeeded"
    seq, best = demo_gaits["riser"]
    # pre-filling the next anchor while the previous one vents saves most of two fills (~0.4 s each)
    assert best.speed > 1.05 * seq.speed


def test_sequential_cycle_is_the_sum_of_its_steps(demo_gaits):
    seq, _ = demo_gaits["riser"]
    assert seq.steps[0].duration == 0.0
    assert seq.cycle_time == pytest.approx(sum(s.duration for s in seq.steps), rel=1e-12)
    assert seq.speed == pytest.approx(seq.stride / seq.cycle_time, rel=1e-12)


def test_problem_is_built_once_and_warm_started(demo_gaits):
    """A second mission with the same structure reuses the NLP and starts from a given solution;
    without one it starts cold, whatever ran before (no hidden state)."""
    size = _problem.cache_info().currsize
    downhill = load_mission(DOWNHILL)
    seq = sequential_gait(downhill, "entry")
    earlier = demo_gaits["riser"][1]
    best = optimal_gait(downhill, "entry", baseline=seq, warm_start=earlier.warm_start)
    assert _problem.cache_info().currsize == size
    assert best.solver["warm_start"] is True
    cold = optimal_gait(downhill, "entry", baseline=seq)
    assert cold.solver["warm_start"] is False
    # both starts reach the same optimum (IPOPT tol 1e-8 on a cycle of ~10 s)
    assert cold.cycle_time == pytest.approx(best.cycle_time, rel=1e-5)
    assert best.cycle_time <= seq.cycle_time * (1 + 1e-9)
    assert best.hold_margin.min() >= best.needs[0].safety_factor * (1 - HOLD_TOLERANCE)


def test_lengths_from_the_interpolant_equal_the_exact_free_length(demo_gaits, monkeypatch):
    """The kept interpolant of L_free on [0, P_a] gives the exact roots to 1e-13·L0 at every sample of the
    sequential cycle; with no interpolant within tolerance the lengths are the exact roots themselves."""
    seq = demo_gaits["riser"][0]
    pressures = seq.trajectory.pressures
    size = schedule.lengths(seq.needs, pressures)
    for i, need in enumerate(seq.needs):
        free = np.maximum(pressures[:, i], 0.0) < need.contact_pressure
        assert free.sum() > 100 and schedule.free_length_on(need.muscle, need.contact_pressure) is not None
        exact = np.maximum(need.muscle.free_length(np.maximum(pressures[free, i], 0.0)), need.anchored_length)
        assert np.max(np.abs(size[free, i] - exact)) <= 1e-13 * need.rest_length
        assert np.all(size[~free, i] == need.anchored_length)
    monkeypatch.setattr(schedule, "_CURVES", {})
    monkeypatch.setattr(pneumatics, "FREE_LENGTH_TOLERANCE", -1.0)  # no interpolant passes: exact roots
    assert schedule.free_length_on(seq.needs[0].muscle, seq.needs[0].contact_pressure) is None
    i = 0
    free = np.maximum(pressures[:, i], 0.0) < seq.needs[i].contact_pressure
    exact = np.maximum(seq.needs[i].muscle.free_length(np.maximum(pressures[free, i], 0.0)),
                       seq.needs[i].anchored_length)
    assert np.array_equal(schedule.lengths(seq.needs, pressures)[free, i], exact)
