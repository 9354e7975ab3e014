"""`plan` on routes through a pipe network (docs/commands.md §7): `route: {network, from, to}` in a mission.

Independent answers: wntr's own model of ky4 (read here, not through pampipe.specs.network), networkx for the
shortest path, the closed form of the anchoring pressure (docs/physics.md §7, pampipe.model.forces) for
the contact margins, and a dense scan of each bore range (tests/planning/test_bores.py) for the worst bore.
"""

from __future__ import annotations

import dataclasses
import itertools
import json
import math

import numpy as np
import pytest

from pampipe import api
from pampipe.errors import InfeasibleError, InputError
from pampipe.model import forces
from pampipe.planning.problem import mission_muscles
from tests.support.bore_scan import scan_maximum
from tests.support.problems import PROBLEMS

wntr = pytest.importorskip("wntr")
nx = pytest.importorskip("networkx")

PAM = "../pams/paper-radial-pam.yaml"
TOLERANCE = 0.02  # the route's bore tolerance: 2 %


def mission(route: dict, **changes) -> dict:
    """The demo robot (three radial-test muscles, 2 kg, 689 kPa, SF 1.5) on ``route``."""
    doc = {"robot": {"segments": [{"name": f"PAM{i}", "pam": PAM, "mass": "0.4 kg"} for i in (1, 2, 3)],
                     "payload": "2 kg"},
           "supply_pressure": "689 kPa", "safety_factor": 1.5, "route": route}
    return {**doc, **changes}


def load(doc: dict):
    return api.load_mission(doc, base=PROBLEMS / "missions")


@pytest.fixture(scope="module")
def ky4_model():
    from wntr.library import model_library

    return wntr.network.WaterNetworkModel(model_library.get_filepath("ky4"))


@pytest.fixture(scope="module")
def route_plan():
    doc = mission({"network": "ky4", "from": "J-315", "to": "J-897", "friction": 0.3,
                   "tolerance": f"{TOLERANCE:.0%}"})
    model = load(doc)
    return model, api.plan(model)


def elevation(model, node: str) -> float:
    item = model.get_node(node)
    return item.base_head if item.node_type == "Reservoir" else item.elevation


def test_route_is_the_networkx_path_through_the_pipes_the_robot_passes(route_plan, ky4_model):
    model, _ = route_plan
    geometry = model.segments[0].pam.geometry
    rest, reach = geometry.initial_diameter, geometry.largest_diameter
    graph = nx.Graph()
    for name, pipe in ky4_model.pipes():
        d = pipe.diameter
        if d * (1 - TOLERANCE) > rest and d * (1 + TOLERANCE) < reach:
            u, v = pipe.start_node_name, pipe.end_node_name
            if not graph.has_edge(u, v) or pipe.length < graph[u][v]["length"]:
                graph.add_edge(u, v, length=pipe.length, pipe=name)
    nodes = nx.dijkstra_path(graph, "J-315", "J-897", weight="length")
    pipes = [graph[a][b]["pipe"] for a, b in itertools.pairwise(nodes)]
    route = model.route
    assert route.name.tolist() == pipes
    lengths = [ky4_model.get_link(p).length for p in pipes]
    rise = [elevation(ky4_model, b) - elevation(ky4_model, a) for a, b in itertools.pairwise(nodes)]
    np.testing.assert_allclose(route.length, lengths, rtol=1e-15)
    np.testing.assert_allclose(route.incline, np.arcsin(np.array(rise) / lengths), rtol=0, atol=1e-15)
    np.testing.assert_allclose(route.diameter_low, route.diameter * (1 - TOLERANCE), rtol=1e-15)
    np.testing.assert_allclose(route.diameter_high, route.diameter * (1 + TOLERANCE), rtol=1e-15)


def test_route_plan_holds_in_the_worst_bore_with_contact_margins_and_coverage(route_plan):
    model, plan = route_plan
    doc = plan.to_dict()
    # every section is planned; the plan as a whole fails only on the elbows (tests/bends/test_plan_bends.py)
    assert all(sec["feasible"] for sec in doc["sections"]) and not plan.arrays.reasons
    assert plan.feasible == all(b["passable"] for b in doc["bends"])
    muscles = mission_muscles(model)
    pam = model.segments[0].pam
    for s, sec in enumerate(doc["sections"]):
        low, high = sec["inner_diameter_range_m"]
        assert sec["inner_diameter_m"] == pytest.approx(0.5 * (low + high), rel=1e-15)
        assert sec["pipe"] == sec["name"] and sec["length_m"] > 0 and sec["friction"] == 0.3
        assert sec["incline_deg"] == pytest.approx(math.degrees(model.route.incline[s]), rel=1e-15)
        for i, seg in enumerate(sec["segments"]):
            # worst bore: a scan of the range (tolerance 1e-6, see tests/planning/test_bores.py)
            best, _ = scan_maximum(muscles[i], low, high, seg["required_hold_N"], kappa=1.0, friction=0.3,
                                   safety_factor=1.5, points=2001)
            assert seg["pressure_Pa"] == pytest.approx(best, rel=1e-6)
            # contact margin: the plan above first touching the largest bore, closed form of physics.md §7
            touch = forces.anchoring_pressure(high, pam.geometry, pam.moduli.as_vector(), 1e6)
            assert seg["largest_bore_anchoring_pressure_Pa"] == pytest.approx(touch, rel=1e-12)
            assert seg["contact_margin_Pa"] == pytest.approx(seg["pressure_Pa"] - touch, rel=1e-9)
            # thin: a 1 mm wider bore or a 1° braid angle error costs more than the margin (closed forms)
            wider = forces.anchoring_pressure(high + 1e-3, pam.geometry, pam.moduli.as_vector(), 1e6)
            assert seg["contact_cost_1mm_bore_Pa"] == pytest.approx(wider - touch, rel=1e-9)
            tilted = [forces.anchoring_pressure(high, dataclasses.replace(
                pam.geometry, braid_angle=pam.geometry.braid_angle + math.radians(d)), pam.moduli.as_vector(),
                1e6) for d in (1.0, -1.0)]
            assert seg["contact_cost_1deg_braid_Pa"] == pytest.approx(max(tilted) - touch, rel=1e-9)
            cost = max(wider, *tilted) - touch
            assert seg["thin_contact_margin"] == (seg["contact_margin_Pa"] < cost)
    coverage = doc["coverage"]
    assert coverage["scope"] == "route"
    assert coverage["pipes_total"] == coverage["pipes_feasible"] == len(doc["sections"])
    assert coverage["length_total_m"] == pytest.approx(sum(s["length_m"] for s in doc["sections"]), rel=1e-12)
    assert doc["route"]["from"] == "J-315" and doc["route"]["to"] == "J-897"
    # where the network has coordinates, the bends are reported (first pipe: none)
    assert doc["sections"][0]["bend_deg"] is None
    assert all(0 <= s["bend_deg"] <= 180 for s in doc["sections"][1:])


def test_whole_network_coverage_equals_the_sum_over_pipes(ky4_model):
    model = load(mission({"network": "ky4", "friction": 0.3}))
    plan = api.plan(model)
    geometry = model.segments[0].pam.geometry
    pipes = list(ky4_model.pipes())
    fits = [p for _, p in pipes if geometry.initial_diameter < p.diameter < geometry.largest_diameter]
    wide = [p for _, p in pipes if p.diameter >= geometry.largest_diameter]
    coverage = plan.to_dict()["coverage"]
    assert coverage["scope"] == "network" and coverage["pipes_total"] == len(pipes) == 1156
    assert coverage["length_total_m"] == pytest.approx(sum(p.length for _, p in pipes), rel=1e-12)
    # at 689 kPa the demo robot anchors in every pipe it fits: served = fits
    assert coverage["pipes_feasible"] == len(fits)
    assert coverage["length_feasible_m"] == pytest.approx(sum(p.length for p in fits), rel=1e-12)
    assert coverage["reasons"] == {"wider_than_braid": len(wide)}
    assert (model.route.incline >= 0).all()  # direction unknown: |asin(dz/length)|


def write(tmp_path, doc: dict):
    import yaml

    (tmp_path / "pams").mkdir(exist_ok=True)
    source = PROBLEMS / "pams" / "paper-radial-pam.yaml"
    (tmp_path / "pams" / "paper-radial-pam.yaml").write_text(source.read_text())
    (tmp_path / "missions").mkdir(exist_ok=True)
    path = tmp_path / "missions" / "m.yaml"
    path.write_text(yaml.safe_dump(doc))
    return path


def test_cli_route_plan_prints_the_per_pipe_plan_and_draws_the_profile(tmp_path, cli):
    path = write(tmp_path, mission({"network": "ky4", "from": "J-315", "to": "J-897", "friction": 0.3}))
    out = cli("plan", path, "--json", "--plots", tmp_path / "plots")
    assert out.returncode == 3, out.stderr  # the paper's muscle cannot pass five of the route's elbows
    doc = json.loads(out.stdout)
    assert all(sec["feasible"] for sec in doc["sections"]) and "bends cannot be passed" in out.stderr
    assert len(doc["sections"]) == 24 and doc["coverage"]["pipes_feasible"] == 24
    assert any("above first touching the largest bore" in w for w in doc["warnings"])
    assert "warning:" in out.stderr and "coverage of the route" in out.stderr and "bend [deg]" in out.stderr
    for name in ("route_profile.png", "network_pressure.png", "required_pressure.png"):
        assert (tmp_path / "plots" / name).stat().st_size > 10_000
    whole = write(tmp_path, mission({"network": "ky4", "friction": 0.3}))
    out = cli("plan", whole)
    assert out.returncode == 0, out.stderr  # a whole network: exit 0 while some pipe can be served
    assert "coverage of the network: 191 of 1156 pipes" in out.stdout and "by bore:" in out.stdout


TINY = """\
[JUNCTIONS]
A  0  0
B  1  0
C  2  0
[PIPES]
P1  A  B  100  80   100  0  Open
P2  B  C  100  300  100  0  Open
[OPTIONS]
Units LPS
[END]
"""


def test_route_errors_name_what_is_wrong(tmp_path):
    keys = r"\(allowed keys here: network, from, to, friction, tolerance, sd, pipe_material\)"
    with pytest.raises(InputError, match=r"unknown key 'route.frm'; did you mean 'from'\? " + keys):
        load(mission({"network": "ky4", "frm": "J-315", "to": "J-897", "friction": 0.3}))
    with pytest.raises(InputError, match="give both 'from' and 'to'"):
        load(mission({"network": "ky4", "from": "J-315", "friction": 0.3}))
    with pytest.raises(InputError, match="did you mean J-897"):
        load(mission({"network": "ky4", "from": "J-315", "to": "J-8977", "friction": 0.3}))
    with pytest.raises(InputError, match=r"route.network: .*did you mean"):
        load(mission({"network": "ky44", "from": "J-315", "to": "J-897", "friction": 0.3}))
    (tmp_path / "tiny.inp").write_text(TINY)
    doc = mission({"network": str(tmp_path / "tiny.inp"), "from": "A", "to": "C", "friction": 0.3})
    with pytest.raises(InfeasibleError, match=r"no route from A to C .* narrower than its braids open to"):
        load(doc)
    assert len(load({**doc, "route": {**doc["route"], "to": "B"}}).route) == 1  # the 80 mm pipe passes
