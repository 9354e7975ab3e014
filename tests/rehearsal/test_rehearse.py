"""`pampipe rehearse` (docs/commands.md §13, docs/physics.md §16.3-16.4): the walk against `gait`, the hose
against the valve and fluids, the air against the chamber volumes, the compressor, the reach, the Monte Carlo
against `plan --confidence`, the JSON keys and bad input."""

from __future__ import annotations

import copy
import itertools
import json
import math

import numpy as np
import pytest
import yaml

import pampipe
from pampipe.pneumatics.hose import hose_flow, supply_curve
from pampipe.pneumatics.options import Gas, Valve
from pampipe.pneumatics.timing import GAS_CONSTANT, ISO_DENSITY, Chamber, mass_flow, transition_times
from pampipe.specs.tether import Hose
from tests.support.problems import PROBLEMS

DEMO = PROBLEMS / "missions" / "vertical-climb-3in.yaml"
TETHERED = PROBLEMS / "missions" / "tethered-climb.yaml"
PAM = str(PROBLEMS / "pams" / "paper-radial-pam.yaml")
ROBOT = {"segments": [{"name": f"PAM{i}", "pam": PAM, "mass": "0.4 kg"} for i in (1, 2, 3)],
         "payload": "2 kg"}
#: Alike horizontal sections: with a weightless tether their plans are equal, only the hose grows.
FLAT = [{"name": f"run-{k}", "length": "50 m", "inner_diameter": "3 in", "incline": "0 deg", "friction": 0.3}
        for k in range(4)]
SECTION_KEYS = {"name", "length_m", "time_s", "cycles", "stride_m", "cycle_time_s", "free_air_m3", "tether"}


def mission(tether=None, route=None, **changes) -> dict:
    doc = {"robot": copy.deepcopy(ROBOT), "supply_pressure": "689 kPa", "safety_factor": 1.5,
           "route": copy.deepcopy(route or FLAT), **changes}
    if tether is not None:
        doc["tether"] = tether
    return doc


def test_without_tether_or_hose_each_section_takes_its_gait_cycles():
    doc = pampipe.rehearse(DEMO).to_dict()
    assert doc["completed"] and doc["reach"]["reachable"]
    for section in doc["sections"]:
        gait = pampipe.gait(DEMO, section=section["name"]).to_dict()
        expected = section["length_m"] / gait["stride_m"] * gait["cycle_time_s"]
        assert section["time_s"] == pytest.approx(expected, rel=1e-2)
        assert section["cycle_time_s"] == pytest.approx(gait["cycle_time_s"], rel=1e-2)
        assert set(section) >= SECTION_KEYS
    assert doc["time_s"] == pytest.approx(sum(s["time_s"] for s in doc["sections"]), rel=1e-12)
    assert doc["free_air_m3"] == pytest.approx(sum(s["free_air_m3"] for s in doc["sections"]), rel=1e-12)


def test_the_free_air_is_the_chambers_fill_at_the_reference_atmosphere():
    """Each fill takes the chamber from the vented pressure at its rest volume to the plan's pressure at its
    anchored volume (the plan's air volume less the bladder): [(P + p_atm) V] / (R T) / 1.185 kg/m³."""
    from pampipe.model.forces import bladder_volume

    result = pampipe.rehearse(DEMO)
    plan, gas = result.plan, result.gas
    muscle = plan.muscles[0]
    bladder = bladder_volume(muscle.geometry)
    rest = float(muscle.enclosed_volume(muscle.geometry.initial_length)) - bladder
    atm = gas.atmospheric_pressure
    for s in range(len(result.route)):
        anchored = plan.arrays.air_volume[s] - bladder
        filled = ((plan.arrays.pressure[s] + atm) * anchored - (500.0 + atm) * rest) / (GAS_CONSTANT * 293.15)
        assert result.walk.air_per_cycle[s] == pytest.approx(filled.sum() / ISO_DENSITY, rel=1e-2)


def test_a_negligible_hose_is_the_valve_and_a_long_one_agrees_with_fluids():
    valve, gas, hose = Valve(), Gas(), Hose(0.006, 1.5e-6)
    supply = 689e3
    pressure = np.array([500.0, 1e5, 3e5, 5e5, 6.5e5])
    short = supply_curve(hose, 1e-3, supply=supply, valve=valve, gas=gas)
    direct = mass_flow(supply + gas.atmospheric_pressure, pressure + gas.atmospheric_pressure, valve, gas)
    assert short(pressure) == pytest.approx(direct, rel=1e-4)
    chamber = Chamber(4e-4, 3e-4, 1.2e5, (1.0, 0.0, 0.0, 0.0, 0.0))
    alone = transition_times(chamber, 500.0, 1.4e5, supply=supply, valve=valve, gas=gas)
    through = transition_times(chamber, 500.0, 1.4e5, supply=supply, valve=valve, gas=gas,
                               fill_flow=lambda p, rows: short(p))
    assert through == pytest.approx(alone, rel=1e-4)
    long = supply_curve(hose, 300.0, supply=supply, valve=valve, gas=gas)
    assert np.all(long(pressure) < 0.6 * direct)  # 300 m of 6 mm hose throttles the fill
    # at a point of the curve, the hose (fluids) and the valve pass the same flow
    from fluids.compressible import isothermal_gas
    from fluids.friction import friction_factor

    inlet, atm = supply + gas.atmospheric_pressure, gas.atmospheric_pressure
    outlet = 5.5e5
    flow = hose_flow(inlet, outlet, hose=hose, length=300.0, temperature=gas.temperature)
    reynolds = 4 * flow / (math.pi * 0.006 * 1.8134e-5)
    fd = friction_factor(Re=reynolds, eD=1.5e-6 / 0.006)
    density = inlet / (GAS_CONSTANT * gas.temperature)
    assert flow == pytest.approx(isothermal_gas(density, fd, P1=inlet, P2=outlet, L=300.0, D=0.006), rel=1e-3)
    chamber_pressure = np.linspace(long.pressure[0], long.pressure[-1], 7)[1:-1]
    hose_end = [_hose_end(long_flow, inlet, hose, gas) for long_flow in long(chamber_pressure)]
    valve_flow = mass_flow(np.array(hose_end), chamber_pressure + atm, valve, gas)
    assert valve_flow == pytest.approx(long(chamber_pressure), rel=2e-3)


def test_many_hose_lengths_read_a_grid_of_curves_within_its_interpolation_error():
    from pampipe.pneumatics.hose import SupplyCurves

    valve, gas, hose = Valve(), Gas(), Hose(0.006, 1.5e-6)
    lengths = np.linspace(10.0, 100.0, 120)
    curves = SupplyCurves(hose, lengths, supply=689e3, valve=valve, gas=gas)
    assert len(curves.curves) < lengths.size  # a grid, not a curve per length
    pressure = np.tile([500.0, 1e5, 3e5, 5e5], (3, 1))
    which = np.array([7, 60, 113])
    exact = np.stack([supply_curve(hose, lengths[k], supply=689e3, valve=valve, gas=gas)(pressure[0])
                      for k in which])
    assert curves.flow(pressure, which) == pytest.approx(exact, rel=2e-4)
    few = SupplyCurves(hose, lengths[:3], supply=689e3, valve=valve, gas=gas)  # one curve per length
    assert len(few.curves) == 3 and np.all(few.weight == 0)


def _hose_end(flow: float, inlet: float, hose, gas) -> float:
    """The outlet pressure at which the hose passes ``flow`` (bisection on :func:`hose_flow`)."""
    low, high = 1.0, inlet
    for _ in range(80):
        middle = 0.5 * (low + high)
        if hose_flow(inlet, middle, hose=hose, length=300.0, temperature=gas.temperature) > flow:
            low = middle
        else:
            high = middle
    return 0.5 * (low + high)


def test_with_a_hose_the_cycles_grow_with_the_deployed_length():
    tether = {"weight": 0, "friction": 0.3, "length": "1 km", "hose": {"inner_diameter": "6 mm"}}
    hosed = pampipe.rehearse(mission(tether)).to_dict()
    bare = pampipe.rehearse(mission()).to_dict()
    cycles = [s["cycle_time_s"] for s in hosed["sections"]]
    assert all(b > a for a, b in itertools.pairwise(cycles))
    for with_hose, without in zip(hosed["sections"], bare["sections"], strict=True):
        assert with_hose["gait_cycle_time_s"] == pytest.approx(without["cycle_time_s"], rel=1e-12)
        assert with_hose["time_s"] > without["time_s"]
        assert with_hose["free_air_m3"] == pytest.approx(without["free_air_m3"], rel=1e-12)
    assert [s["hose_length_m"] for s in hosed["sections"]] == [0.0, 50.0, 100.0, 150.0]
    assert hosed["hose"]["fill_free_air_m3"] == pytest.approx(
        math.pi / 4 * 0.006**2 * 200 * (689e3 + 101325) / (GAS_CONSTANT * 293.15) / ISO_DENSITY, rel=1e-12)


def test_a_small_compressor_makes_the_fills_wait():
    slow = {"weight": 0, "friction": 0.3, "length": "1 km", "compressor": {"free_air_delivery": "10 L/min"}}
    fast = {**slow, "compressor": {"free_air_delivery": "1000 L/min"}}
    waited, free = (pampipe.rehearse(mission(t)).to_dict() for t in (slow, fast))
    assert waited["compressor"]["limited_sections"] == [s["name"] for s in FLAT]
    assert free["compressor"]["limited_sections"] == []
    for s in waited["sections"]:
        assert s["compressor_limited"]
        assert s["cycle_time_s"] == pytest.approx(s["air_per_cycle_m3"] / (10e-3 / 60), rel=1e-12)
    assert waited["compressor"]["duty"] == pytest.approx(1.0, rel=1e-9)
    assert 0 < free["compressor"]["duty"] < 1


def test_the_walk_stops_at_the_reach_and_the_command_exits_3(cli, tmp_path):
    tether = {"weight": "0.8 N/m", "friction": 0.35, "back_tension": "5 N", "length": "120 m"}
    doc = pampipe.rehearse(mission(tether)).to_dict()
    assert doc["reach"]["limit"] == "tether_length" and doc["reach"]["distance_m"] == 120.0
    assert doc["walked_m"] == 120.0 and not doc["completed"]
    assert [s["walked_m"] for s in doc["sections"]] == [50.0, 50.0, 20.0, 0.0]
    assert doc["sections"][3]["time_s"] == 0.0 and doc["sections"][3]["stride_m"] is None
    path = tmp_path / "m.yaml"
    path.write_text(yaml.safe_dump(mission(tether)))
    out = cli("rehearse", path, "--json")
    assert out.returncode == 3
    assert json.loads(out.stdout)["reach"] == doc["reach"]
    assert "NOT COMPLETED" in out.stderr


def test_the_tethered_mission_reports_the_tensions_and_its_plots(cli, tmp_path):
    out = cli("rehearse", TETHERED, "--plots", tmp_path, "--report", tmp_path / "r.html")
    assert out.returncode == 0, out.stderr
    assert "largest tether tension" in out.stdout and "compressor" in out.stdout
    assert {p.name for p in tmp_path.iterdir()} >= {"timeline.png", "tether_profile.png", "r.html"}
    doc = pampipe.plan(TETHERED).to_dict()
    result = pampipe.rehearse(TETHERED).to_dict()
    for planned, walked in zip(doc["sections"], result["sections"], strict=True):
        assert walked["tether"] == planned["tether"]
    assert result["reach"] == doc["reach"]
    largest = max(max(s["tether"].values()) for s in doc["sections"])
    assert result["largest_tension_N"] == pytest.approx(largest)


def test_completion_is_consistent_with_plan_confidence():
    riser = PROBLEMS / "missions" / "riser-uncertain-friction.yaml"
    plan = pampipe.plan(riser, confidence=0.95, samples=1000).to_dict()
    doc = pampipe.rehearse(riser, confidence=0.95, samples=1000).to_dict()
    holding = [min(x["holding_probability"] for x in s["segments"]) for s in plan["sections"]]
    first = {f["section"]: f["probability"] for f in doc["monte_carlo"]["first_slip"]}
    # the first section's first slips are its own slips; later sections can only add
    assert first[plan["sections"][0]["name"]] == pytest.approx(1 - holding[0], abs=1e-12)
    assert doc["completion_probability"] <= min(holding) + 1e-12
    assert doc["completion_probability"] == pytest.approx(1 - sum(first.values()), abs=1e-12)
    assert doc["confidence"] == 0.95 and doc["monte_carlo"]["samples"] == 1000
    assert doc["monte_carlo"]["time_s"] <= doc["time_s"] + 1e-9


def test_the_tether_friction_is_drawn_and_makes_the_robot_slip():
    doc = pampipe.rehearse(TETHERED, confidence=0.95, samples=500).to_dict()
    assert doc["monte_carlo"]["sources"] == ["tether"]
    assert 0.9 <= doc["completion_probability"] <= 0.96


def test_the_optimal_gait_is_faster():
    sequential = pampipe.rehearse(DEMO).to_dict()
    best = pampipe.rehearse(DEMO, optimal=True).to_dict()
    assert best["schedule"] == "optimal"
    assert best["time_s"] < 0.95 * sequential["time_s"]


def test_the_api_result_shows_like_every_result():
    result = pampipe.rehearse(DEMO)
    assert repr(result).startswith("<Rehearsal ") and "time_s=" in repr(result)
    assert "rehearsal of" in str(result)


@pytest.mark.parametrize(("key", "value", "words"), [
    ("weight", "-1 N/m", "tether.weight"), ("friction", -0.2, "tether.friction"),
    ("length", "-5 m", "tether.length"), ("hose", {"inner_diameter": 0}, "tether.hose.inner_diameter"),
    ("compressor", {"free_air_delivery": 0}, "tether.compressor.free_air_delivery")])
def test_bad_input_exits_2_naming_the_key_and_the_value(cli, tmp_path, key, value, words):
    tether = {"weight": "0.8 N/m", "friction": 0.35, "length": "1 km", key: value}
    path = tmp_path / "m.yaml"
    path.write_text(yaml.safe_dump(mission(tether)))
    out = cli("rehearse", path)
    assert out.returncode == 2
    assert words in out.stderr
    shown = value if not isinstance(value, dict) else next(iter(value.values()))
    assert str(shown).split()[0] in out.stderr.split(words, 1)[1]
