"""Routes through EPANET networks (docs/commands.md §7) against an independent networkx computation."""

from __future__ import annotations

import itertools
import json
import math
import random
from pathlib import Path

import numpy as np
import pytest
import yaml

from pampipe.cli import main
from pampipe.errors import InfeasibleError, InputError
from pampipe.io.epanet import load_network
from pampipe.io.mission_schema import load_mission
from pampipe.specs.network import coverage, route_sections, whole_network
from tests.support.problems import PROBLEMS

wntr = pytest.importorskip("wntr")
nx = pytest.importorskip("networkx")

INCH = 0.0254
TINY = """\
[JUNCTIONS]
A  0  0
B  10 0
C  10 0
D  4  0
[RESERVOIRS]
R  50
[PIPES]
P1  R  A  100  100  100  0  Open
P2  A  B  5    100  100  0  Open
P3  B  C  20   80   100  0  Open
P4  C  D  30   80   100  0  Open
P5  D  C  20   80   100  0  Open
[OPTIONS]
Units LPS
[COORDINATES]
A  -10  0
B  10 0
C  10 10
D  10 20
[VERTICES]
P3  20  0
[END]
"""


@pytest.fixture(scope="module")
def ky4():
    return load_network("ky4")


@pytest.fixture(scope="module")
def ky4_model():
    """wntr's own model of ky4, read independently of pampipe.specs.network."""
    from wntr.library import model_library

    return wntr.network.WaterNetworkModel(model_library.get_filepath("ky4"))


def _elevation(model, node: str) -> float:
    item = model.get_node(node)
    return item.base_head if item.node_type == "Reservoir" else item.elevation


def _networkx_route(model, start: str, end: str, keep=lambda pipe: True):
    """(pipe ids, lengths, inclines) of the shortest path, with networkx on wntr's pipes."""
    graph = nx.Graph()
    for name, pipe in model.pipes():
        if not keep(pipe):
            continue
        u, v = pipe.start_node_name, pipe.end_node_name
        if not graph.has_edge(u, v) or pipe.length < graph[u][v]["length"]:
            graph.add_edge(u, v, length=pipe.length, pipe=name)
    nodes = nx.dijkstra_path(graph, start, end, weight="length")
    names, lengths, inclines = [], [], []
    for u, v in itertools.pairwise(nodes):
        edge = graph[u][v]
        names.append(edge["pipe"])
        lengths.append(edge["length"])
        inclines.append(math.asin((_elevation(model, v) - _elevation(model, u)) / edge["length"]))
    return names, lengths, inclines


def _pairs(model, count: int, seed: int):
    """``count`` random node pairs of ky4's main component (fixed seed)."""
    graph = nx.Graph([(p.start_node_name, p.end_node_name) for _, p in model.pipes()])
    main_component = sorted(max(nx.connected_components(graph), key=len))
    rng = random.Random(seed)
    return [tuple(rng.sample(main_component, 2)) for _ in range(count)]


def test_route_equals_an_independent_networkx_computation(ky4, ky4_model):
    for start, end in [("J-315", "J-897"), *_pairs(ky4_model, 20, seed=1)]:
        names, lengths, inclines = _networkx_route(ky4_model, start, end)
        route = route_sections(ky4, start, end, friction=0.3)
        assert route.name.tolist() == names
        # same floats from the same file: only summation order could differ, hence 1e-12
        np.testing.assert_allclose(route.length, lengths, rtol=1e-12)
        np.testing.assert_allclose(route.incline, inclines, rtol=0, atol=1e-12)
        assert route.from_node[0] == start and route.to_node[-1] == end
        assert (route.to_node[:-1] == route.from_node[1:]).all()  # consecutive pipes share a node
        assert not route.clipped.any()


def test_route_through_passable_pipes_only(ky4, ky4_model):
    # the route: only pipes up to 4.5 in take 24 pipes instead of 21
    names, _, _ = _networkx_route(ky4_model, "J-315", "J-897", keep=lambda p: p.diameter <= 4.5 * INCH)
    narrow = route_sections(ky4, "J-315", "J-897", friction=0.3, passable=lambda d: d <= 4.5 * INCH)
    wide = route_sections(ky4, "J-315", "J-897", friction=0.3)
    assert narrow.name.tolist() == names and len(narrow) == 24 and len(wide) == 21
    assert (narrow.diameter <= 4.5 * INCH).all() and (wide.diameter > 4.5 * INCH).any()
    assert narrow.length.sum() >= wide.length.sum()
    with pytest.raises(InfeasibleError, match="no route from J-315 to J-897 in network ky4 through the 0 "):
        route_sections(ky4, "J-315", "J-897", friction=0.3, passable=lambda d: d < 2 * INCH)


def test_reversed_route_has_opposite_inclines(ky4):
    forward = route_sections(ky4, "J-315", "J-897", friction=0.3)
    backward = route_sections(ky4, "J-897", "J-315", friction=0.3)
    assert backward.name.tolist() == forward.name.tolist()[::-1]
    np.testing.assert_array_equal(backward.length, forward.length[::-1])
    np.testing.assert_array_equal(backward.incline, -forward.incline[::-1])
    # a joint deflects by the same angle both ways
    np.testing.assert_allclose(backward.bend[1:], forward.bend[1:][::-1], rtol=0, atol=1e-12)
    assert np.isfinite(forward.bend[1:]).all() and math.isnan(forward.bend[0])


def test_coverage_totals_equal_the_sum_over_pipes(ky4, ky4_model):
    pipes = list(ky4_model.pipes())
    every = whole_network(ky4, friction=0.3)
    narrow = every.diameter <= 4.5 * INCH
    reasons = [None if ok else "wider than the braid" for ok in narrow]
    summary = coverage(every, feasible=narrow, reasons=reasons)
    assert summary.pipes_total == len(pipes) == 1156
    assert summary.length_total == pytest.approx(sum(p.length for _, p in pipes), rel=1e-12)
    assert summary.pipes_feasible == sum(p.diameter <= 4.5 * INCH for _, p in pipes)
    assert summary.length_feasible == pytest.approx(
        sum(p.length for _, p in pipes if p.diameter <= 4.5 * INCH), rel=1e-12)
    assert summary.reasons == {"wider than the braid": summary.pipes_total - summary.pipes_feasible}
    assert set(summary.as_document()) >= {"pipes_total", "pipes_feasible", "length_total_m",
                                          "length_feasible_m"}
    with pytest.raises(ValueError, match="one per pipe"):
        coverage(every, feasible=narrow[:-1])


def test_whole_network_reports_absolute_inclines(ky4, ky4_model):
    every = whole_network(ky4, friction=0.25)
    rise = [_elevation(ky4_model, p.end_node_name) - _elevation(ky4_model, p.start_node_name)
            for _, p in ky4_model.pipes()]
    expected = [abs(math.asin(dz / p.length)) for dz, (_, p) in zip(rise, ky4_model.pipes(), strict=True)]
    np.testing.assert_allclose(every.incline, expected, rtol=0, atol=1e-12)
    assert every.name.tolist() == list(ky4_model.pipe_name_list)
    assert (every.friction == 0.25).all() and np.isnan(every.bend).all()


def test_pipes_shorter_than_their_rise_are_taken_as_vertical():
    # ky10 has 4 pipes whose model length is shorter than the elevation difference of their nodes
    every = whole_network(load_network("ky10"), friction=0.3)
    assert sorted(every.name[every.clipped]) == ["P-238", "P-246", "P-344", "P-431"]
    np.testing.assert_array_equal(every.incline[every.clipped], math.pi / 2)
    assert (every.incline[~every.clipped] < math.pi / 2).all()


@pytest.fixture
def tiny(tmp_path):
    path = tmp_path / "tiny.inp"
    path.write_text(TINY)
    return load_network(path)


def test_tiny_network_known_answers(tiny):
    route = route_sections(tiny, "R", "D", friction=0.3)
    # P5 (20 m) is the shorter of the two parallel pipes C-D, travelled against its stored direction
    assert route.name.tolist() == ["P1", "P2", "P3", "P5"]
    assert route.from_node.tolist() == ["R", "A", "B", "C"]
    # R's head is 50 m, A at 0 m, 100 m apart: asin(-0.5) = -30 deg
    assert route.incline[0] == pytest.approx(-math.pi / 6, abs=1e-12)
    # A -> B rises 10 m in 5 m of pipe: clipped to vertical and flagged
    assert route.incline[1] == math.pi / 2 and route.clipped.tolist() == [False, True, False, False]
    assert route.incline[3] == pytest.approx(math.asin(-6 / 20), abs=1e-12)
    # R has no coordinates (wntr would put it at 0, 0): no bend at A. P3 leaves B towards its vertex
    # (20, 0), straight on from A -> B; at C it arrives from that vertex and leaves north towards D
    # (10, 20): a 45 deg deflection.
    assert math.isnan(route.bend[1])
    assert route.bend[2] == pytest.approx(0.0, abs=1e-12)
    assert route.bend[3] == pytest.approx(math.radians(45), abs=1e-12)


def test_unknown_nodes_and_networks_name_the_nearest(ky4, tiny):
    with pytest.raises(InputError, match=r"to node 'J-8977': no such node in network ky4; did you mean J-8"):
        route_sections(ky4, "J-315", "J-8977", friction=0.3)
    with pytest.raises(InputError, match="did you mean ky4"):
        load_network("ky44")
    with pytest.raises(InputError, match="not found"):
        load_network("missing.inp")
    with pytest.raises(InputError, match="same node"):
        route_sections(tiny, "A", "A", friction=0.3)


def test_a_bad_inp_file_is_an_input_error(tmp_path):
    bad = tmp_path / "bad.inp"
    bad.write_text("[PIPES]\nP1 X Y not-a-number 100 100 0 Open\n[END]\n")
    with pytest.raises(InputError, match=r"bad.inp: cannot read it as an EPANET .inp file"):
        load_network(bad)


# ----------------------------------------------------------------------------------------------- CLI
def _cli(capsys, *args):
    code = main([str(a) for a in args])
    out = capsys.readouterr()
    return code, out.out, out.err


def test_cli_writes_a_mission_that_plan_reads(tmp_path, capsys, ky4):
    target = tmp_path / "sub" / "ky4.yaml"
    target.parent.mkdir()  # -o never creates folders (issue 14): a typo in the path is exit 2
    code, out, err = _cli(capsys, "route", "ky4", "--from", "J-315", "--to", "J-897", "--max-bore", "4.5 in",
                          "-o", target, "--json")
    assert code == 0, err
    document = json.loads(out)
    assert document["pipes"] == 24 and document["output"] == str(target)
    assert [s["name"] for s in document["sections"]][:2] == ["P-188", "P-159"]
    mission = load_mission(target)
    expected = route_sections(ky4, "J-315", "J-897", friction=0.3, passable=lambda d: d <= 4.5 * INCH)
    assert [s.name for s in mission.route] == expected.name.tolist()
    # 12 significant digits written, so 1e-11 relative (inclines: 1e-11 deg)
    np.testing.assert_allclose([s.length for s in mission.route], expected.length, rtol=1e-11)
    np.testing.assert_allclose([s.diameter for s in mission.route], expected.diameter, rtol=1e-11)
    np.testing.assert_allclose([s.incline for s in mission.route], expected.incline, rtol=0, atol=1e-12)
    template = load_mission(PROBLEMS / "missions" / "vertical-climb-3in.yaml")
    assert (mission.safety_factor, mission.supply_pressure, mission.load_path, mission.payload) == (
        template.safety_factor, template.supply_pressure, template.load_path, template.payload)
    # the PAM files are the template's, reached from the new file's folder
    assert [Path(s.pam_file).resolve() for s in mission.segments] == [
        Path(s.pam_file).resolve() for s in template.segments]
    assert {s.friction for s in mission.route} == {0.3}  # the template's
    assert yaml.safe_load(target.read_text())["route"][0]["name"] == "P-188"
    assert target.read_text().startswith("# Route through network ky4")


def test_cli_exit_codes(tmp_path, capsys):
    code, _, err = _cli(capsys, "route", "ky4", "--from", "J-315", "--to", "J-8977")
    assert code == 2 and "did you mean J-897" in err
    code, _, err = _cli(capsys, "route", "Net33", "--from", "1", "--to", "2")
    assert code == 2 and "did you mean Net3" in err
    code, _, err = _cli(capsys, "route", "ky4", "--from", "J-315", "--to", "J-897", "--max-bore", "2 in")
    assert code == 3 and "no route from J-315 to J-897" in err
    template = PROBLEMS / "missions" / "vertical-climb-3in.yaml"
    code, _, err = _cli(capsys, "route", "Net3", "--from", "10", "--to", "20", "-o", template)
    assert code == 2 and "refusing to write over the input file" in err
    target = tmp_path / "route.yaml"
    assert _cli(capsys, "route", "Net3", "--from", "10", "--to", "20", "-o", target)[0] == 0
    code, _, err = _cli(capsys, "route", "Net3", "--from", "10", "--to", "20", "-o", target)
    assert code == 2 and "--force" in err
    assert _cli(capsys, "route", "Net3", "--from", "10", "--to", "20", "-o", target, "--force",
                "--friction", "0.2")[0] == 0
    assert {s.friction for s in load_mission(target).route} == {0.2}
    uncertain = PROBLEMS / "missions" / "riser-uncertain-friction.yaml"
    code, _, err = _cli(capsys, "route", "Net3", "--from", "10", "--to", "20", "--template", uncertain)
    assert code == 2 and "give --friction" in err
