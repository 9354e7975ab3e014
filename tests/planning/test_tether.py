"""The tether in the plan (docs/physics.md §16): tensions by the cable-pulling equations, the plan with the
tension equal to a plan with that constant drag, the reach found exactly inside a section, the reel, the JSON
keys and bad input."""

from __future__ import annotations

import copy
import math

import numpy as np
import pytest

import pampipe
from tests.support.problems import PROBLEMS

PAM = str(PROBLEMS / "pams" / "paper-radial-pam.yaml")
ROBOT = {"segments": [{"name": f"PAM{i}", "pam": PAM, "mass": "0.4 kg"} for i in (1, 2, 3)],
         "payload": "2 kg"}
TETHER = {"weight": "0.8 N/m", "friction": 0.35, "back_tension": "5 N", "length": "2000 m"}
#: Horizontal runs, risers, a downhill run that goes slack, bends of 15 to 180 deg (wide: the robot passes).
ROUTE = [
    {"name": "run-1", "length": "40 m", "inner_diameter": "3 in", "incline": "0 deg", "friction": 0.3,
     "bend": {"angle": "15 deg", "radius": "20 D"}},
    {"name": "riser", "length": "12 m", "inner_diameter": "3 in", "incline": "90 deg", "friction": 0.3,
     "bend": {"angle": "90 deg", "radius": "20 D"}},
    {"name": "drop", "length": "100 m", "inner_diameter": "3 in", "incline": "-60 deg", "friction": 0.3,
     "bend": {"angle": "180 deg", "radius": "20 D"}},
    {"name": "climb", "length": "30 m", "inner_diameter": "3 in", "incline": "20 deg", "friction": 0.3,
     "bend": {"angle": "45 deg", "radius": "20 D"}},
    {"name": "gentle", "length": "50 m", "inner_diameter": "3 in", "incline": "-25 deg", "friction": 0.3,
     "bend": {"angle": "120 deg", "radius": "20 D"}},
    {"name": "run-2", "length": "300 m", "inner_diameter": "3 in", "incline": "0 deg", "friction": 0.3},
]


def mission(**changes) -> dict:
    base = {"robot": copy.deepcopy(ROBOT), "supply_pressure": "689 kPa", "safety_factor": 1.5,
            "route": copy.deepcopy(ROUTE), "tether": dict(TETHER)}
    base.update(changes)
    return {k: v for k, v in base.items() if v is not None}


def hand_tensions(route: list[dict], w: float, mu: float, t0: float) -> list[tuple[float, float]]:
    """(T_in, T_out) per section, written out from the cable-pulling equations with plain floats."""
    out, tension = [], t0
    for section in route:
        length = float(section["length"].split()[0])
        phi = math.radians(float(section["incline"].split()[0]))
        start = tension
        tension = max(0.0, tension + w * length * (mu * math.cos(phi) + math.sin(phi)))
        out.append((start, tension))
        if "bend" in section:
            tension *= math.exp(mu * math.radians(float(section["bend"]["angle"].split()[0])))
    return out


def test_tensions_follow_the_cable_pulling_equations():
    doc = pampipe.plan(mission()).to_dict()
    expected = hand_tensions(ROUTE, 0.8, 0.35, 5.0)
    assert expected[2][1] == 0.0 and expected[3][0] == 0.0  # the drop goes slack; the 180 deg bend keeps it 0
    assert expected[4][1] < expected[4][0]  # gentle downhill: falling, not slack
    for section, (t_in, t_out) in zip(doc["sections"], expected, strict=True):
        got = section["tether"]
        for key, value in (("tension_in_N", t_in), ("tension_out_N", t_out)):
            assert got[key] == pytest.approx(value, rel=5e-3, abs=1e-9), (section["name"], key)


def test_the_tension_grows_with_weight_friction_and_bends():
    """The equations can fail: a heavier tether, more friction or a sharper bend raise the last tension."""
    base = pampipe.plan(mission()).to_dict()["sections"][-1]["tether"]["tension_out_N"]
    heavier = mission(tether={**TETHER, "weight": "0.9 N/m"})
    rougher = mission(tether={**TETHER, "friction": 0.4})
    sharper = mission()
    sharper["route"][4]["bend"]["angle"] = "150 deg"
    for changed in (heavier, rougher, sharper):
        assert pampipe.plan(changed).to_dict()["sections"][-1]["tether"]["tension_out_N"] > base * 1.01


def test_a_mass_per_length_is_a_weight_per_length_times_g():
    grams = mission(tether={**TETHER, "weight": f"{0.8 / 9.80665 * 1e3!r} g/m"})
    a = pampipe.plan(mission()).to_dict()["sections"][-1]["tether"]["tension_out_N"]
    b = pampipe.plan(grams).to_dict()["sections"][-1]["tether"]["tension_out_N"]
    assert b == pytest.approx(a, rel=1e-12)


def test_each_section_plans_as_with_its_largest_tension_as_a_constant_drag():
    doc = pampipe.plan(mission(tether_drag="3 N")).to_dict()
    for k, section in enumerate(doc["sections"]):
        largest = max(section["tether"].values())
        alone = mission(route=[ROUTE[k]], tether=None, tether_drag=largest + 3.0)
        reference = pampipe.plan(alone).to_dict()["sections"][0]
        for got, want in zip(section["segments"], reference["segments"], strict=True):
            assert abs(got["pressure_Pa"] - want["pressure_Pa"]) < 100.0  # 0.1 kPa
            assert got["required_hold_N"] == pytest.approx(want["required_hold_N"], rel=1e-12)
    first, last = (doc["sections"][k]["segments"][0]["pressure_Pa"] for k in (0, -1))
    assert last > first


def _tension_at(doc: dict, distance: float) -> float:
    """T at ``distance`` from the JSON tensions (affine inside a section)."""
    start = 0.0
    for section in doc["sections"]:
        if distance <= start + section["length_m"]:
            t = section["tether"]
            return max(0.0, t["tension_in_N"] + (t["tension_out_N"] - t["tension_in_N"])
                       * (distance - start) / section["length_m"])
        start += section["length_m"]
    raise AssertionError("beyond the route")


@pytest.mark.parametrize("supply", ["130 kPa", "134 kPa"])
def test_the_reach_is_where_a_constant_drag_of_that_tension_first_fails(supply):
    doc = pampipe.plan(mission(supply_pressure=supply)).to_dict()
    reach = doc["reach"]
    assert reach["reachable"] is False and reach["limit"] == "supply"
    k = next(i for i, s in enumerate(doc["sections"]) if s["name"] == reach["section"])
    entry = sum(s["length_m"] for s in doc["sections"][:k])
    assert entry < reach["distance_m"] < entry + doc["sections"][k]["length_m"]  # inside, not rounded
    assert reach["tension_N"] == pytest.approx(_tension_at(doc, reach["distance_m"]), rel=1e-9)

    def feasible_with(drag: float) -> bool:
        return pampipe.plan(mission(route=[ROUTE[k]], tether=None, tether_drag=drag,
                                    supply_pressure=supply)).feasible

    before, after = (_tension_at(doc, reach["distance_m"] * f) for f in (0.99, 1.01))
    assert feasible_with(before) and not feasible_with(after)
    assert not doc["feasible"]


def test_the_reach_is_the_route_when_nothing_stops_it_and_the_reel_when_short():
    whole = pampipe.plan(mission()).to_dict()
    length = sum(s["length_m"] for s in whole["sections"])
    assert whole["reach"]["reachable"] is True and whole["reach"]["limit"] is None
    assert whole["reach"]["distance_m"] == pytest.approx(length)
    assert whole["feasible"] is True
    short = pampipe.plan(mission(tether={**TETHER, "length": "250 m"}))
    doc = short.to_dict()
    assert doc["reach"] == {**doc["reach"], "reachable": False, "limit": "tether_length", "distance_m": 250.0,
                            "section": "run-2"}
    assert doc["reach"]["tension_N"] == pytest.approx(_tension_at(doc, 250.0), rel=1e-9)
    assert not doc["feasible"] and any("runs out" in r for r in short.reasons)


def test_the_command_shows_the_tensions_the_reach_and_exits_3_on_a_short_reel(cli, tmp_path):
    import yaml

    path = tmp_path / "m.yaml"
    path.write_text(yaml.safe_dump(mission(tether={**TETHER, "length": "250 m"})))
    out = cli("plan", path, "--plots", tmp_path / "plots")
    assert out.returncode == 3
    assert "tether tension" in out.stdout and "reach: 250 m from the entry" in out.stdout
    assert "runs out" in out.stderr
    assert (tmp_path / "plots" / "tether_profile.png").exists()


def test_no_tether_no_reach_and_no_tether_keys():
    doc = pampipe.plan(mission(tether=None)).to_dict()
    assert "reach" not in doc and all("tether" not in s for s in doc["sections"])


def test_the_tether_friction_sd_is_a_source_of_plan_confidence():
    uncertain = mission(tether={**TETHER, "friction": {"value": 0.35, "sd": 0.05}})
    plan = pampipe.plan(uncertain, confidence=0.95, samples=400)
    doc = plan.to_dict()
    assert "tether" in doc["confidence"]["dominant"]
    nominal = pampipe.plan(uncertain).to_dict()
    last = doc["sections"][-1]["segments"][0]
    assert last["pressure_Pa"] > nominal["sections"][-1]["segments"][0]["pressure_Pa"]
    assert last["holding_probability"] >= 0.95
    # the sampled tension never lowers a section's hold below its nominal tension's in the certain plan
    assert np.all(plan.uncertainty.certain >= 0)


@pytest.mark.parametrize(("key", "value", "words"), [
    ("weight", "-0.8 N/m", "tether.weight"), ("friction", -0.1, "tether.friction"),
    ("length", "-1 m", "tether.length"), ("hose", {"inner_diameter": "0 mm"}, "tether.hose.inner_diameter"),
    ("compressor", {"free_air_delivery": "0 L/min"}, "tether.compressor.free_air_delivery"),
    ("weight", "3 kg", "tether.weight")])
def test_bad_tether_input_exits_2_naming_the_key_and_value(cli, tmp_path, key, value, words):
    import yaml

    path = tmp_path / "m.yaml"
    path.write_text(yaml.safe_dump(mission(tether={**TETHER, key: value})))
    out = cli("plan", path)
    assert out.returncode == 2
    assert words in out.stderr
    shown = value if isinstance(value, str | float) else next(iter(value.values()))
    assert str(shown).split()[0] in out.stderr
