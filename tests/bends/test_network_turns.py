"""Elbows of routes through a network (docs/physics.md §14.4, docs/commands.md §4.4 and §7): which way each
turns (left/right/up/down along travel, from the node coordinates and elevations), the muscle the steering
command fills, no command below STEERING_LEAST_ANGLE, radii marked assumed, `route --template` with a
steering module reaching `plan`. Expected directions are worked out by hand from the polylines."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
import yaml

from pampipe.bends.plan import STEERING_LEAST_ANGLE
from pampipe.io.epanet import load_network
from pampipe.io.routes import turn_directions_after
from pampipe.specs.network import route_sections
from pampipe.specs.turns import turn_directions, turn_name
from tests.support.problems import PROBLEMS

pytest.importorskip("wntr")

# Junctions: id, elevation [m]; coordinates x east, y north [m]; pipes of 100 mm (Units LPS: mm and m).
POLYLINE = """\
[JUNCTIONS]
A  0  0
B  0  0
C  0  0
D  0  0
E  30 0
[PIPES]
P1  A  B  100  100  100  0  Open
P2  B  C  100  100  100  0  Open
P3  C  D  100  100  100  0  Open
P4  D  E  50   100  100  0  Open
[OPTIONS]
Units LPS
[COORDINATES]
A  0    0
B  100  0
C  100  100
D  0    100
E  -40  100
[END]
"""


@pytest.fixture
def polyline(tmp_path):
    path = tmp_path / "polyline.inp"
    path.write_text(POLYLINE)
    return load_network(path)


@pytest.mark.parametrize(("incline_in", "incline_out", "deflection", "expected", "name"), [
    (0.0, 0.0, math.radians(90), 90.0, "left"),  # east, then north: the centre of the turn on the left
    (0.0, 0.0, math.radians(-30), -90.0, "right"),
    (0.0, math.radians(45), 0.0, 0.0, "up"),  # level, then climbing: the centre above
    (math.radians(90), 0.0, 0.0, 180.0, "down"),  # a riser into a level pipe, seen from the riser
    (0.0, math.radians(45), math.radians(90), 45.0, "up-left"),  # across: (left, up) = (cos 45°, sin 45°)
])
def test_turn_direction_of_known_turns(incline_in, incline_out, deflection, expected, name):
    direction = float(turn_directions(incline_in, incline_out, deflection))
    assert math.degrees(direction) == pytest.approx(expected, abs=1e-3)
    assert turn_name(direction) == name


def test_a_left_turn_of_a_polyline_is_left(polyline):
    """A → B east, B → C north (left), C → D west (left), D → E west climbing 30 m in 50 m (up)."""
    sections = route_sections(polyline, "A", "E", friction=0.3)
    np.testing.assert_allclose(np.degrees(sections.deflection[1:]), [90, 90, 0], atol=1e-9)
    directions = turn_directions_after(sections)
    assert [turn_name(d) for d in directions[:-1]] == ["left", "left", "up"]
    np.testing.assert_allclose(np.degrees(directions[:-1]), [90, 90, 0], atol=1e-9)
    reverse = route_sections(polyline, "D", "A", friction=0.3)  # the same corners, travelled back: right
    assert [turn_name(d) for d in turn_directions_after(reverse)[:-1]] == ["right", "right"]


def _mission(tmp_path, route) -> str:
    """The demo robot with the steering module (problems/missions/elbows-3in.yaml) on ``route``."""
    doc = yaml.safe_load((PROBLEMS / "missions" / "elbows-3in.yaml").read_text())
    for block in (*doc["robot"]["segments"], doc["robot"]["steering"]):
        block["pam"] = str(PROBLEMS / "pams" / block["pam"].split("/")[-1])
    doc["route"] = route
    path = tmp_path / "m.yaml"
    path.write_text(yaml.safe_dump(doc))
    return path


def test_steering_fills_the_muscle_outside_the_turn(tmp_path, cli):
    """PAM 1 at the top, PAM 2 lower left, PAM 3 lower right: a left turn lengthens PAM 3 (outside), a
    right turn PAM 2, a turn down PAM 1 alone, a turn up PAMs 2 and 3; a 5 deg bend gets no command."""
    turns = {"left": 90, "right": -90, "down": 180, "up": 0}
    route = [{"name": name, "length": "2 m", "inner_diameter": "3 in", "friction": 0.3,
              "bend": {"angle": "30 deg", "radius": "8 D", "direction": f"{angle} deg"}}
             for name, angle in turns.items()]
    route.append({"name": "small", "length": "2 m", "inner_diameter": "3 in", "friction": 0.3,
                  "bend": {"angle": "5 deg", "direction": "90 deg"}})
    route.append({"name": "end", "length": "2 m", "inner_diameter": "3 in", "friction": 0.3})
    out = cli("plan", _mission(tmp_path, route), "--json")
    assert out.returncode == 0, out.stderr
    bends = {b["after_section"]: b for b in json.loads(out.stdout)["bends"]}
    assert {name: bends[name]["turn"] for name in turns} == {name: name for name in turns}
    outside = {"left": [3], "right": [2], "down": [1], "up": [2, 3]}
    for name, fills in outside.items():
        steering = bends[name]["steering"]
        assert set(fills) <= set(steering["fills"]), name
        assert max(range(3), key=lambda k: steering["pressures_Pa"][k]) + 1 in fills
        assert bends[name]["radius_assumed"] is False and bends[name]["steering_note"] is None
    small = bends["small"]
    assert math.radians(small["angle_deg"]) < STEERING_LEAST_ANGLE
    assert small["steering"] is None and small["gait"] is None and "below 10 deg" in small["steering_note"]
    assert small["radius_assumed"] is True and small["radius_m"] == pytest.approx(1.5 * 3 * 0.0254)


def test_passes_bent_is_computed_for_every_segment(tmp_path, cli):
    """ρ_min = (D₀/2)/(B/L₀ − 1) fits an 8 D bend (it passes rigid too) and not a 1.5 D one: by hand from
    the PAM's geometry, whatever the bend_model."""
    pam = yaml.safe_load((PROBLEMS / "pams" / "paper-radial-pam.yaml").read_text())["geometry"]
    rest_length = float(pam["initial_length"].split()[0]) * 1e-3
    rest_diameter = float(pam["initial_diameter"].split()[0]) * 1e-3
    from_axis = math.radians(90 - float(pam["braid_angle_from_transverse"].split()[0]))
    braid = rest_length / math.cos(from_axis)
    least = rest_diameter / 2 / (braid / rest_length - 1)
    bore = 3 * 0.0254
    route = [{"name": "wide", "length": "2 m", "inner_diameter": "3 in", "friction": 0.3,
              "bend": {"angle": "30 deg", "radius": "8 D"}},
             {"name": "tight", "length": "2 m", "inner_diameter": "3 in", "friction": 0.3,
              "bend": {"angle": "30 deg", "radius": "1.5 D"}},
             {"name": "end", "length": "2 m", "inner_diameter": "3 in", "friction": 0.3}]
    doc = json.loads(cli("plan", _mission(tmp_path, route), "--json").stdout)
    for bend, radius in zip(doc["bends"], (8 * bore, 1.5 * bore), strict=True):
        for segment in bend["segments"]:
            assert segment["least_bend_radius_m"] == pytest.approx(least, rel=1e-6)
            assert segment["passes_bent"] is (least <= radius + (bore - rest_diameter) / 2)
    assert doc["bends"][0]["segments"][0]["passes_bent"] is True
    assert doc["bends"][0]["segments"][0]["passable"] is True  # and it passes rigid


def test_route_with_a_steering_template_reaches_the_plan(tmp_path, cli):
    """`route --template elbows-3in.yaml -o sub/r.yaml` rewrites the steering PAM's path too; `plan` of the
    file runs to its verdict with every radius assumed, every turn named and no command below 10 deg."""
    target = tmp_path / "sub" / "r.yaml"
    target.parent.mkdir()
    out = cli("route", "ky4", "--from", "J-315", "--to", "J-897", "--max-bore", "4.5 in", "--template",
              PROBLEMS / "missions" / "elbows-3in.yaml", "-o", target, "--json")
    assert out.returncode == 0, out.stderr
    routed = json.loads(out.stdout)
    written = yaml.safe_load(target.read_text())
    steering = (target.parent / written["robot"]["steering"]["pam"]).resolve()
    assert steering == (PROBLEMS / "pams" / "extensile-steering.yaml").resolve()
    elbows = [s for s in written["route"] if "bend" in s]
    assert [s["name"] for s in elbows] == [b["after_section"] for b in routed["bends"]]
    assert all("direction" in s["bend"] and "radius" not in s["bend"] for s in elbows)
    plan = cli("plan", target, "--json")
    assert plan.returncode in (0, 3), plan.stderr
    bends = json.loads(plan.stdout)["bends"]
    assert [b["turn"] for b in bends] == [b["turn"] for b in routed["bends"]]
    assert all(b["radius_assumed"] for b in bends)
    for bend in bends:
        small = math.radians(bend["angle_deg"]) < STEERING_LEAST_ANGLE
        assert (bend["steering"] is None) is small
        assert all(isinstance(s["passes_bent"], bool) for s in bend["segments"])
    text = cli("plan", target)
    assert "1.5 D (assumed)" in text.stdout and "no steering" in text.stdout
