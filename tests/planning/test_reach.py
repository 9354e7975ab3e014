"""planning/reach.py against a reach computed here with plain floats (docs/physics.md §16.2; the first target
of ``make mutate`` for the module, the plan-level checks being tests/planning/test_tether.py).

The independent answer scans the route: the tether's tension T(x) = max(0, T_in + w·x·(μ_t·cos φ + sin φ)),
multiplied by e^(μ_t·θ) at each bend (§16.1, written again here), each segment's load
W_i = g·(M·|sin φ| + μ·cos φ·(M − m_i)) + T(x) (§8.3, written again), its least holding pressure P*_i(W_i)
from the muscle's closed form (checked against a brute-force scan in tests/model/test_muscle_model.py) and
its limit (the supply, or its rated ``max_pressure`` when lower). The first point where max_i P*_i/limit_i
exceeds 1 is found on a grid and narrowed by brentq in x; the binding segment is the one over its limit just
past it.

The robots are not uniform (unequal masses, one segment rated near the supply), so the segment that binds
and the word ``supply``/``rating`` depend on taking the largest ratio. The plan's reasons (``arrays``) and
bends are given here, as the planner would give them: the reach is what is under test."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest
import yaml
from scipy.optimize import brentq

from pampipe.api import load_mission
from pampipe.model.muscle import Muscle
from pampipe.planning.problem import mission_muscles
from pampipe.planning.reach import plan_tether, route_reach
from tests.support.problems import PROBLEMS

G = 9.80665
PAM = yaml.safe_load((PROBLEMS / "pams" / "paper-radial-pam.yaml").read_text())
PAYLOAD, SF, MU = 2.0, 1.5, 0.3  # [kg], safety factor, wall friction of every section
#: w [N/m], μ_t, T₀ [N]
W_T, MU_T, T0 = 0.8, 0.35, 5.0
#: (name, length [m], incline [deg], bend at its end [deg]) of the routes used below
ONE = [("run", 300.0, 0.0, 0.0)]
TWO = [("run-1", 100.0, 0.0, 90.0), ("run-2", 300.0, 0.0, 0.0)]
#: a level run, a 90° bend, a drop that goes slack after ~103 m, a last level run
SLACK = [("run-1", 100.0, 0.0, 90.0), ("drop", 150.0, -60.0, 0.0), ("run-2", 200.0, 0.0, 0.0)]
#: the masses [kg] of the default robot, rear to front: the lightest (PAM1) carries the most load
MASSES = (0.3, 0.5, 0.9)


def mission(route, supply, *, masses=MASSES, rated=None, reel=2000.0, back=T0, tether=True):
    """The mission: three paper radial muscles of ``masses``, the third rated at ``rated`` [Pa] if given."""
    rated_pam = None if rated is None else {**PAM, "max_pressure": f"{rated!r} Pa"}
    segments = [{"name": f"PAM{i + 1}", "mass": f"{m!r} kg",
                 "pam": rated_pam if rated and i == 2 else dict(PAM)} for i, m in enumerate(masses)]
    sections = [{"name": name, "length": f"{length!r} m", "inner_diameter": "76.2 mm",
                 "incline": f"{incline!r} deg", "friction": MU}
                | ({"bend": {"angle": f"{bend!r} deg", "radius": "20 D"}} if bend else {})
                for name, length, incline, bend in route]
    doc = {"robot": {"segments": segments, "payload": f"{PAYLOAD!r} kg"}, "supply_pressure": f"{supply!r} Pa",
           "safety_factor": SF, "route": sections}
    if tether:
        doc["tether"] = {"weight": f"{W_T!r} N/m", "friction": MU_T, "back_tension": f"{back!r} N",
                         "length": f"{reel!r} m"}
    return load_mission(doc)


def stopped(**codes):
    """The plan's arrays with ``codes`` {``s0``, ``s1``… (the section's index): reason code}."""
    codes = {int(k[1:]): v for k, v in codes.items()}
    return SimpleNamespace(reasons={s: f"section {s}: {c}" for s, c in codes.items()}, reason_codes=codes)


def reach_of(m, arrays=None, bends=()):
    return plan_tether(m, mission_muscles(m), arrays or stopped(), bends)


def hand_tensions(route, back=T0):
    """[(T_in, T_out, k)] per section, from the cable-pulling equations."""
    out, t = [], back
    for _, length, incline, bend in route:
        phi = math.radians(incline)
        k = W_T * (MU_T * math.cos(phi) + math.sin(phi))
        out.append((t, max(0.0, t + k * length), k))
        t = max(0.0, t + k * length) * math.exp(MU_T * math.radians(bend))
    return out


def ratios(m, incline, tension):
    """P*_i(W_i + T)/limit_i of each segment (rows) for tensions ``tension`` (columns) in a section."""
    total = sum(s.mass for s in m.segments) + PAYLOAD
    phi = math.radians(incline)
    out = []
    for seg in m.segments:
        weight = G * (total * abs(math.sin(phi)) + MU * math.cos(phi) * (total - seg.mass))
        load = weight + np.asarray(tension)
        least = Muscle.from_pam(seg.pam).least_holding_pressure(0.0762, load, kappa=m.kappa, friction=MU,
                                                                  safety_factor=SF)
        limit = min(m.supply_pressure, math.inf if seg.pam.max_pressure is None else seg.pam.max_pressure)
        out.append(np.asarray(least, dtype=float) / limit)
    return np.array(out)


def hand_reach(m, route, back=T0):
    """(distance [m], section index, tension [N], binding segment) where max_i P*_i/limit_i first exceeds 1
    along ``route``, by a scan of the route and brentq in x; None if it never does."""
    entry = 0.0
    for s, ((_, length, incline, _), (t_in, _, k)) in enumerate(zip(route, hand_tensions(route, back),
                                                                 strict=True)):
        def tension(x, t_in=t_in, k=k):
            return np.maximum(0.0, t_in + k * np.asarray(x, dtype=float))

        def excess(x, incline=incline, tension=tension):
            return float(ratios(m, incline, tension(x)).max()) - 1.0

        grid = np.linspace(0.0, length, 401)
        over = np.flatnonzero(ratios(m, incline, tension(grid)).max(axis=0) > 1.0)
        if over.size:
            j = int(over[0])
            x = 0.0 if j == 0 else brentq(excess, grid[j - 1], grid[j], xtol=1e-12, rtol=1e-15)
            past = ratios(m, incline, float(tension(min(x + 1e-3, length))))
            beyond = np.flatnonzero(past > 1.0)  # at a crossing, one segment; at the entry, maybe all
            return entry + x, s, float(tension(x)), int(beyond[0] if beyond.size == 1 else np.argmax(past))
        entry += length
    return None


def words(m, binding):
    return "rating" if m.segments[binding].pam.max_pressure is not None and \
        m.segments[binding].pam.max_pressure < m.supply_pressure else "supply"


# -- the stop inside a section ------------------------------------------------------------------------------


def test_one_section_the_reach_is_where_the_lightest_segment_meets_the_supply():
    m = mission(ONE, 130e3)
    want = hand_reach(m, ONE)
    distance, s, tension, binding = want
    assert s == 0 and binding == 0 and 100 < distance < 290  # inside the run, PAM1 (the lightest) binds
    got = reach_of(m, stopped(s0="above_supply"))
    r = got.reach
    assert (r.reachable, r.section, r.limit, r.reason, r.index) == (False, "run", "supply", None, 0)
    assert r.distance == pytest.approx(distance, rel=1e-9)
    assert r.tension == pytest.approx(tension, rel=1e-9)
    assert r.tension == pytest.approx(T0 + W_T * MU_T * r.distance, rel=1e-12)  # on the tension's line
    assert r.sentence() == (f"reach: {r.distance:.6g} m from the entry, in section 'run': the least holding "
                            f"pressure reaches the supply (tether tension {r.tension:.4g} N)")
    assert r.sentence(tether=False).endswith("reaches the supply")
    assert got.reason() is None
    assert r.as_document() == {"reachable": False, "distance_m": r.distance, "section": "run",
                               "limit": "supply", "tension_N": r.tension, "reason": None}


def test_two_sections_the_first_failing_section_is_searched():
    """Both sections fail (the tension keeps rising), the first one stops the robot."""
    m = mission(TWO, 122e3)
    distance, s, tension, _ = hand_reach(m, TWO)
    assert s == 0 and 0 < distance < 100
    r = reach_of(m, stopped(s0="above_supply", s1="above_supply")).reach
    assert (r.section, r.index, r.limit) == ("run-1", 0, "supply")
    assert r.distance == pytest.approx(distance, rel=1e-9)
    assert r.tension == pytest.approx(tension, rel=1e-9)


def test_two_sections_the_stop_after_the_bend_is_its_entry_plus_x():
    m = mission(TWO, 130e3)
    (_, t_out0, _), (t_in1, _, k1) = hand_tensions(TWO)
    distance, s, tension, _ = hand_reach(m, TWO)
    assert s == 1 and 100 < distance < 400 and tension > t_in1 > t_out0  # after the capstan of the bend
    r = reach_of(m, stopped(s1="above_supply")).reach
    assert (r.section, r.index, r.limit) == ("run-2", 1, "supply")
    assert r.distance == pytest.approx(distance, rel=1e-9)
    assert r.tension == pytest.approx(tension, rel=1e-9)
    assert r.distance - 100.0 == pytest.approx((tension - t_in1) / k1, rel=1e-9)


def test_a_tension_past_the_limit_at_the_entry_stops_the_robot_at_the_entry():
    """T* lies between the first run's end tension and the second's entry tension (×e^(μ_t·π/2) at the
    bend): the crossing is below T_in, so the robot stops at the entry of run-2, with the tension there."""
    m = mission(TWO, 126e3)
    (_, t_out0, _), (t_in1, _, _) = hand_tensions(TWO)
    distance, s, tension, _ = hand_reach(m, TWO)
    assert (distance, s) == (100.0, 1) and tension == pytest.approx(t_in1, rel=1e-12)
    assert ratios(m, 0.0, t_out0).max() < 1.0 < ratios(m, 0.0, t_in1).max()
    r = reach_of(m, stopped(s1="above_supply")).reach
    assert (r.distance, r.section, r.limit) == (100.0, "run-2", "supply")
    assert r.tension == pytest.approx(t_in1, rel=1e-12)


def test_a_robot_that_cannot_hold_even_without_the_tether_stops_at_the_entry():
    m = mission(TWO, 117e3)
    assert ratios(m, 0.0, 0.0).max() > 1.0
    assert hand_reach(m, TWO)[:3] == (0.0, 0, T0)
    r = reach_of(m, stopped(s0="above_supply", s1="above_supply")).reach
    assert (r.distance, r.section, r.tension, r.limit) == (0.0, "run-1", T0, "supply")


def test_a_limit_met_within_the_first_millimetres_is_found_from_zero_tension():
    """No back tension, and the supply is P* of PAM1 under 0.5 mN of tension: the stop is ~2 mm in."""
    probe = mission(ONE, 689e3, back=0.0)
    load = G * MU * (sum(MASSES) + PAYLOAD - MASSES[0]) + 5e-4
    supply = float(Muscle.from_pam(probe.segments[0].pam).least_holding_pressure(
        0.0762, load, kappa=1.0, friction=MU, safety_factor=SF))
    m = mission(ONE, supply, back=0.0)
    distance, _, tension, _ = hand_reach(m, ONE, back=0.0)
    assert 1e-3 < distance < 3e-3 and tension == pytest.approx(5e-4, rel=1e-6)
    r = reach_of(m, stopped(s0="above_supply")).reach
    assert r.distance == pytest.approx(distance, rel=1e-6)
    assert r.tension == pytest.approx(tension, rel=1e-6)


# -- which segment binds, and its word -----------------------------------------------------------------------


@pytest.mark.parametrize(("rated", "masses", "binding", "word", "least"), [
    (129.9e3, MASSES, 0, "supply", 2),  # rated just below the supply, on the heaviest: PAM1 binds
    (125e3, MASSES, 2, "rating", 1),  # rated well below: the heaviest, rated segment binds first
    (130e3, (0.5, 0.9, 0.3), 2, "supply", None),  # rated at the supply exactly, on the lightest: "supply"
    (130e3 - 1.0, (0.5, 0.9, 0.3), 2, "rating", 1),  # 1 Pa below the supply: "rating"
])
def test_the_binding_segment_is_the_one_with_the_largest_ratio(rated, masses, binding, word, least):
    m = mission(ONE, 130e3, masses=masses, rated=rated)
    distance, _, tension, hand_binding = hand_reach(m, ONE)
    assert hand_binding == binding and words(m, binding) == word
    if least is not None:  # the least ratio would say the other word
        assert int(np.argmin(ratios(m, 0.0, tension))) == least and words(m, least) != word
    r = reach_of(m, stopped(s0="above_supply" if word == "supply" else "above_rating")).reach
    assert r.limit == word
    assert r.distance == pytest.approx(distance, rel=1e-9)
    assert r.tension == pytest.approx(tension, rel=1e-9)
    assert ("a muscle's rated pressure" if word == "rating" else "reaches the supply") in r.sentence()


def test_the_binding_segment_is_taken_at_the_crossing_not_further_on():
    """The rated PAM3's ratio P*/R grows faster than PAM1's P*/supply (R < supply): it overtakes PAM1 past
    the crossing, where PAM1 still binds."""
    m = mission(ONE, 130e3, rated=129.75e3)
    distance, _, tension, binding = hand_reach(m, ONE)
    assert binding == 0
    assert int(np.argmax(ratios(m, 0.0, 2 * tension))) == 2  # PAM3 binds at twice the tension
    r = reach_of(m, stopped(s0="above_supply")).reach
    assert r.limit == "supply" and r.distance == pytest.approx(distance, rel=1e-9)


@pytest.mark.parametrize(("rated", "word"), [(None, "supply"), (689e3, "supply"), (689e3 - 1.0, "rating")])
def test_beyond_reach_names_the_limit_the_pressure_cannot_pass(rated, word):
    """``beyond_reach``: the pipe is wider than a muscle reaches at its limit; ``rating`` as soon as a limit
    is below the supply, ``supply`` at or above it. The robot stops at the section's entry."""
    m = mission(TWO, 689e3, rated=rated)
    (_, _, _), (t_in1, _, _) = hand_tensions(TWO)
    r = reach_of(m, stopped(s1="beyond_reach")).reach
    assert (r.reachable, r.distance, r.section, r.limit, r.reason, r.index) == (False, 100.0, "run-2", word,
                                                                               None, 1)
    assert r.tension == pytest.approx(t_in1, rel=1e-12)


def test_another_reason_stops_the_robot_at_the_entry_with_the_plans_code():
    m = mission(TWO, 689e3)
    (_, _, _), (t_in1, _, _) = hand_tensions(TWO)
    got = reach_of(m, stopped(s1="narrower_than_muscle"))
    r = got.reach
    want = (100.0, "run-2", None, "narrower_than_muscle", 1)
    assert (r.distance, r.section, r.limit, r.reason, r.index) == want
    assert r.tension == pytest.approx(t_in1, rel=1e-12)
    assert r.sentence() == ("reach: 100 m from the entry, in section 'run-2': the plan cannot cross it "
                            f"(narrower_than_muscle) (tether tension {r.tension:.4g} N)")
    assert got.reason() is None


# -- bends ---------------------------------------------------------------------------------------------------


def bend(index, after, passable):
    return SimpleNamespace(index=index, after_section=after, passable=passable)


THREE = [("run-1", 100.0, 0.0, 90.0), ("run-2", 300.0, 0.0, 45.0), ("run-3", 50.0, 0.0, 0.0)]


def test_the_first_bend_the_robot_cannot_pass_stops_it_at_the_sections_end():
    m = mission(THREE, 130e3)
    tensions = hand_tensions(THREE)
    distance = hand_reach(m, THREE)[0]
    assert 100 < distance < 400  # the supply would stop it in run-2, past the first bend
    bends = (bend(1, "run-2", False), bend(0, "run-1", False))
    r = reach_of(m, stopped(s1="above_supply", s2="above_supply"), bends).reach
    assert (r.reachable, r.distance, r.section, r.limit, r.reason, r.index) == (False, 100.0, "run-1", None,
                                                                               "bend", 0)
    assert r.tension == pytest.approx(tensions[0][1], rel=1e-12)  # T_out of run-1, before the bend
    assert r.sentence() == ("reach: 100 m from the entry, in section 'run-1': the robot cannot pass the bend "
                            f"at its end (tether tension {r.tension:.4g} N)")


def test_a_stop_before_the_blocked_bend_comes_first():
    m = mission(THREE, 130e3)
    distance = hand_reach(m, THREE)[0]
    bends = (bend(0, "run-1", True), bend(1, "run-2", False))
    r = reach_of(m, stopped(s1="above_supply", s2="above_supply"), bends).reach
    assert r.limit == "supply" and r.distance == pytest.approx(distance, rel=1e-9) and r.distance < 400.0
    alone = reach_of(mission(THREE, 689e3), stopped(), bends).reach  # the bend alone: at run-2's end
    assert (alone.distance, alone.section, alone.reason) == (400.0, "run-2", "bend")
    assert alone.tension == pytest.approx(hand_tensions(THREE)[1][1], rel=1e-12)


# -- the reel, the floor at 0, the whole route -------------------------------------------------------------


@pytest.mark.parametrize(("reel", "section", "index"), [(150.0, "drop", 1), (220.0, "drop", 1),
                                                        (300.0, "run-2", 2)])
def test_the_reel_runs_out_where_its_length_ends(reel, section, index):
    m = mission(SLACK, 689e3, reel=reel)
    entries = [0.0, 100.0, 250.0]
    t_in, _, k = hand_tensions(SLACK)[index]
    want = max(0.0, t_in + k * (reel - entries[index]))
    got = reach_of(m)
    r = got.reach
    assert (r.reachable, r.distance, r.section, r.limit, r.reason, r.index) == (False, reel, section,
                                                                               "tether_length", None, index)
    assert r.tension == pytest.approx(want, rel=1e-12, abs=0.0)
    assert got.reason() == (f"the tether ({reel:.6g} m on the reel) runs out {reel:.6g} m from the entry, in "
                            f"section {section!r}: give a longer tether (tether.length).")
    assert "the tether on the reel runs out" in r.sentence()


def test_the_slack_tether_pulls_with_zero_not_less():
    """220 m: 120 m down the drop, where T_in + k·x < 0: the tension is 0 exactly."""
    t_in, _, k = hand_tensions(SLACK)[1]
    assert t_in + k * 120.0 < -5.0
    r = reach_of(mission(SLACK, 689e3, reel=220.0)).reach
    assert r.tension == 0.0


def test_the_whole_route_is_reachable_with_a_reel_exactly_as_long():
    tensions = hand_tensions(SLACK)
    got = reach_of(mission(SLACK, 689e3, reel=450.0))
    r = got.reach
    want = (True, 450.0, "run-2", None, None, 2)
    assert (r.reachable, r.distance, r.section, r.limit, r.reason, r.index) == want
    assert r.tension == pytest.approx(tensions[2][1], rel=1e-12) and r.tension > 0
    assert r.sentence() == f"reach: the whole route, 450 m (tether tension at the end {r.tension:.4g} N)"
    assert r.sentence(tether=False) == "reach: the whole route, 450 m"
    assert got.reason() is None


def test_the_carried_tension_is_the_larger_of_entry_and_end():
    got = reach_of(mission(SLACK, 689e3))
    tensions = hand_tensions(SLACK)
    assert tensions[1][1] < tensions[1][0]  # the drop: falling
    assert got.largest == pytest.approx([max(a, b) for a, b, _ in tensions], rel=1e-12)
    assert got.section_document(1) == {"tension_in_N": pytest.approx(tensions[1][0], rel=1e-12),
                                       "tension_out_N": pytest.approx(tensions[1][1], rel=1e-12, abs=0.0)}


# -- without a tether --------------------------------------------------------------------------------------


def test_without_a_tether_the_reach_carries_no_tension():
    m = mission(TWO, 689e3, tether=False)
    whole = route_reach(m, mission_muscles(m), stopped(), ()).reach
    assert (whole.reachable, whole.distance, whole.section, whole.tension) == (True, 400.0, "run-2", 0.0)
    first = route_reach(m, mission_muscles(m), stopped(s0="narrower_than_muscle", s1="narrower_than_muscle"),
                        ()).reach
    assert (first.distance, first.section, first.tension, first.reason) == (0.0, "run-1", 0.0,
                                                                            "narrower_than_muscle")
    climb = [("run", 100.0, 0.0, 90.0), ("riser", 10.0, 90.0, 0.0)]
    up = mission(climb, 689e3, tether=False)
    top = route_reach(up, mission_muscles(up), stopped(), ()).reach  # no weight: nothing grows up the riser
    assert (top.reachable, top.distance, top.section, top.tension) == (True, 110.0, "riser", 0.0)
    m = mission(climb, 121e3, tether=False)
    assert ratios(m, 0.0, 0.0).max() < 1.0 < ratios(m, 90.0, 0.0).max()  # the run holds, the riser does not
    held = route_reach(m, mission_muscles(m), stopped(s1="above_supply"), ()).reach
    assert (held.distance, held.section, held.tension, held.limit) == (100.0, "riser", 0.0, "supply")
