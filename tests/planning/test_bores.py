"""Plans that hold over a bore range (issue 12, item 2): the planned pressure is the largest least holding
pressure over [bore − tol, bore + tol], checked against a dense brute-force scan of the range.

Tolerance: 1e-6 relative (the issue's). The scan itself is within ½·max|P''|·h² of the true maximum: with
h = range / 20 000 ≤ 0.5 µm and |P''| ≲ 1e9 Pa/m² here, that is below 1e-4 Pa, i.e. 1e-9 of the
pressures (0.1 to 2 MPa), so a correct search meets 1e-6 with a wide margin, while a search that took the
nominal bore or the wrong end of the range misses by 0.5 % to 1.5 % in the constructed cases below.

The cases where P*(D) is not monotone (physics in :mod:`pampipe.planning.bores`):

* **U** (amplification against anchoring): the demo muscle holding a heavy load (a 255 kg robot up a
  riser, μ = 0.1, SF 2): the slip term SF·W/(μπA F₁) falls with D faster than the anchoring pressure
  rises near the rest diameter, so P* falls, then rises; over 58.5-68 mm the worst bore is the smallest.
* **hump** (a softening bladder): moduli whose hoop law stiffens then softens (Drucker-stable, checked)
  bend the anchoring pressure itself into a hump: the worst bore of 68-74 mm is inside, near 70.8 mm.
  The moduli were found by a seeded random search over Drucker-stable laws (seed 1, trial 703; tuning
  data, not used elsewhere); the test data are the ranges and loads below.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from pampipe.io.mission_schema import load_mission
from pampipe.model.pam import Moduli
from pampipe.planning import plan_mission
from pampipe.planning.bores import worst_bores
from pampipe.planning.problem import mission_muscles
from pampipe.specs.mission import Section
from tests.support.bore_scan import SCAN, scan_maximum
from tests.support.problems import PROBLEMS

DEMO = PROBLEMS / "missions" / "vertical-climb-3in.yaml"
RELATIVE = 1e-6  # the tolerance (see the module docstring)
#: Hoop law that stiffens then softens [MPa]: a hump in the anchoring pressure (see the module docstring).
SOFTENING = [0.5343, -1.6844, 1.9533, -1.0704, -0.0862, -0.2331, -0.3913, 0.0276,
             1.8362, -5.8004, 6.9788, -1.9128, -0.1049, 0.0327, 0.1581, 0.3864]


def check_against_scan(mission, plan, points: int = SCAN) -> None:
    """Every element's planned pressure against the scan of its section's range."""
    muscles = mission_muscles(mission)
    a = plan.arrays
    for s, sec in enumerate(mission.route):
        for i, muscle in enumerate(muscles):
            best, _ = scan_maximum(muscle, sec.diameter_low, sec.diameter_high, a.required_hold[s, i],
                                   kappa=mission.kappa, friction=sec.friction,
                                   safety_factor=mission.safety_factor, points=points)
            gap = abs(a.pressure[s, i] - best) / best
            assert gap <= RELATIVE, (sec.name, i, a.pressure[s, i], best)


def ranged_mission(base, sections, **changes):
    return dataclasses.replace(base, route=tuple(sections), **changes)


def section(name, low, high, incline_deg, friction):
    middle = 0.5 * (low + high)
    return Section(name, 1.0, middle, math.radians(incline_deg), friction, 0.0, low, high)


def test_u_shaped_pressure_worst_bore_is_the_smallest():
    """Heavy load near the rest diameter: P*(D) falls, then rises; the plan is the scan's maximum."""
    demo = load_mission(DEMO)
    mission = ranged_mission(demo, [section("heavy", 0.0585, 0.068, 90, 0.1)], payload=255 - 1.2,
                             safety_factor=2.0, supply_pressure=2e6)
    plan = plan_mission(mission)
    muscle = mission_muscles(mission)[0]
    a = plan.arrays
    grid = np.linspace(0.0585, 0.068, 41)
    shape = muscle.least_holding_pressure(grid, a.required_hold[0, 0], kappa=1.0, friction=0.1,
                                          safety_factor=2.0)
    assert np.argmin(shape) not in (0, 40)  # an interior minimum: not monotone
    assert a.diameter[0, 0] == pytest.approx(0.0585, abs=1e-12)  # the smallest bore is the worst
    check_against_scan(mission, plan)
    # the naive answers (the nominal bore, the largest bore) are far below the plan: the test can fail
    nominal = muscle.least_holding_pressure(0.06325, a.required_hold[0, 0], kappa=1.0, friction=0.1,
                                            safety_factor=2.0)
    largest = muscle.least_holding_pressure(0.068, a.required_hold[0, 0], kappa=1.0, friction=0.1,
                                            safety_factor=2.0)
    assert a.pressure[0, 0] > 1.005 * max(nominal, largest)


def softening_mission():
    """The demo robot with the softening moduli, no load through the anchor (κ = 0), on a flat run."""
    demo = load_mission(DEMO)
    moduli = Moduli.from_vector(np.array(SOFTENING) * 1e6, reference_pressure=1e6)
    segments = tuple(dataclasses.replace(s, pam=dataclasses.replace(s.pam, moduli=moduli, covariance=None))
                     for s in demo.segments)
    return ranged_mission(demo, [section("soft", 0.068, 0.074, 0, 0.3)], segments=segments, payload=1.0,
                          load_path="none")


def test_hump_in_the_anchoring_pressure_worst_bore_is_inside_the_range():
    mission = softening_mission()
    plan = plan_mission(mission)
    muscle = mission_muscles(mission)[0]
    a = plan.arrays
    load = a.required_hold[0, 0]
    _, where = scan_maximum(muscle, 0.068, 0.074, load, kappa=0.0, friction=0.3, safety_factor=1.5)
    assert 0.0685 < where < 0.0735  # an interior maximum
    assert a.diameter[0, 0] == pytest.approx(where, abs=2e-6)  # the scan's resolution is 0.3 µm
    check_against_scan(mission, plan)
    ends = muscle.least_holding_pressure(np.array([0.068, 0.071, 0.074]), load, kappa=0.0, friction=0.3,
                                         safety_factor=1.5)
    assert a.pressure[0, 0] > 1.005 * max(ends[0], ends[2])  # neither end is the answer
    # a physical muscle: both Drucker tangent moduli are positive at the planned point (docs/physics.md §6)
    e1, e2 = muscle.drucker_tangent_moduli(a.pressure[0, 0], muscle.anchored_length(a.diameter[0, 0]))
    assert e1 > 0 and e2 > 0


def test_a_maximum_just_inside_an_end_cell_is_found():
    """The hump's peak 0.1 mm inside the smallest bore: the grid's largest value is at the end, but the
    slope there points inwards, so the end cell is searched (taking the end would miss by ~3e-5)."""
    mission = softening_mission()
    muscle = mission_muscles(mission)[0]
    load = plan_mission(mission).arrays.required_hold[0, 0]
    _, peak = scan_maximum(muscle, 0.068, 0.074, load, kappa=0.0, friction=0.3, safety_factor=1.5)
    for low, high in ((peak - 1e-4, peak + 4.9e-3), (peak - 4.9e-3, peak + 1e-4)):
        moved = dataclasses.replace(mission, route=(section("edge", low, high, 0, 0.3),))
        plan = plan_mission(moved)
        check_against_scan(moved, plan)
        end = muscle.least_holding_pressure(np.array([low, high]), load, kappa=0.0, friction=0.3,
                                            safety_factor=1.5).max()
        assert plan.arrays.pressure[0, 0] > end * (1 + 5 * RELATIVE)


@pytest.mark.parametrize("seed", [11, 12, 13])
def test_random_missions_equal_the_brute_force_scan(seed):
    """Random bores, tolerances (0 to 5 %), inclines, frictions and payloads, U and hump cases mixed in."""
    rng = np.random.default_rng(seed)
    demo = load_mission(DEMO)
    sections = []
    for k in range(8):
        middle = rng.uniform(0.062, 0.1)
        half = middle * rng.uniform(0.0, 0.05)
        sections.append(section(f"s{k}", middle - half, middle + half, rng.uniform(-90, 90),
                                rng.uniform(0.1, 0.6)))
    heavy = ranged_mission(demo, sections, payload=float(rng.uniform(0, 300)), supply_pressure=5e6,
                           safety_factor=float(rng.uniform(1, 3)))
    soft = dataclasses.replace(softening_mission(), route=tuple(
        section(f"t{k}", lo, lo + rng.uniform(0.001, 0.008), 0, 0.3)
        for k, lo in enumerate(rng.uniform(0.063, 0.08, 6))))
    for mission in (heavy, soft):
        check_against_scan(mission, plan_mission(mission))


def test_a_muscle_with_effects_takes_the_bisection_path():
    """braid_extensibility has no closed form: the search runs on the bisected pressure (golden section
    only), on the softening muscle, whose hump survives a stretchable braid."""
    base = softening_mission()
    effects = {"braid_extensibility": {"compliance": 1e-5}}
    segments = tuple(dataclasses.replace(s, pam=dataclasses.replace(s.pam, effects=effects))
                     for s in base.segments)
    route = (section("a", 0.068, 0.074, 0, 0.3), section("b", 0.075, 0.079, 30, 0.3))
    mission = dataclasses.replace(base, segments=segments, route=route)
    muscle = mission_muscles(mission)[0]
    assert muscle.closed_form_refusals()
    plan = plan_mission(mission)
    # each scanned pressure is a bisection: 2001 points (h ≤ 3 µm, scan error ≲ 1e-8 relative) keep it short
    check_against_scan(mission, plan, points=2001)
    assert 0.0685 < plan.arrays.diameter[0, 0] < 0.0735  # an interior maximum


def test_exact_bores_are_left_alone_and_ranges_cost_no_section_objects():
    """low = high gives the bore itself; the search works on arrays (no per-section Python)."""
    muscle = mission_muscles(load_mission(DEMO))[0]
    low = np.array([0.07, 0.072, 0.075])
    high = np.array([0.07, 0.074, 0.075])
    worst = worst_bores(muscle, low, high, np.full(3, 30.0), kappa=1.0, friction=np.full(3, 0.3),
                        safety_factor=1.5)
    assert worst[0] == 0.07 and worst[2] == 0.075
    assert worst[1] == pytest.approx(0.074)  # P* rises with D for a light load on the demo muscle
