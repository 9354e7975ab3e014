"""Benchmark of network routes (issue 12): reading a network into columnar sections vs the demo plan.

Times, in one run: importing wntr (once), reading ky4 (1,156 pipes) into :class:`pampipe.network.Network`,
its whole-network sections, the route J-315 -> J-897, and ``plan_mission`` on the bundled two-section demo.
Prints the ratio of the network read to the demo plan. Goal (issue 12): a whole-network plan of ky4 takes
about as long as the demo plan; the read, measured here, must be a small part of it.

Against what a user would write with the same tools, in the same run (one BLAS thread): the read
against wntr's own ``WaterNetworkModel`` (which pampipe calls, then turns into arrays), and the route
against ``wntr``'s graph with ``networkx.dijkstra_path`` weighted by pipe length (same pipes expected).

    .venv/bin/python benchmarks/bench_network.py [--network ky4] [--repeat 5]
"""

from __future__ import annotations

import argparse
import itertools
import math
import time
from pathlib import Path

from threadpoolctl import threadpool_limits

from pampipe.io.config import load_mission
from pampipe.network import load_network, route_sections, whole_network
from pampipe.plan import plan_mission

DEMO = Path(__file__).resolve().parent.parent / "problems" / "missions" / "vertical-climb-3in.yaml"


def timed(fn, repeat: int):
    """(best wall time [s], result) over ``repeat`` runs."""
    best, result = math.inf, None
    for _ in range(repeat):
        start = time.perf_counter()
        result = fn()
        best = min(best, time.perf_counter() - start)
    return best, result


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--network", default="ky4", help="wntr network name or .inp file (default ky4)")
    parser.add_argument("--repeat", type=int, default=5, help="runs per timing; the best is kept (5)")
    args = parser.parse_args()

    import_time, _ = timed(lambda: __import__("wntr"), 1)
    read_time, net = timed(lambda: load_network(args.network), args.repeat)
    whole_time, sections = timed(lambda: whole_network(net, friction=0.3), args.repeat)
    start, end = ("J-315", "J-897") if net.name == "ky4" else (net.node_ids[0], net.node_ids[-1])
    route_time, route = timed(lambda: route_sections(net, start, end, friction=0.3), args.repeat)
    import networkx as nx
    import wntr
    from wntr.library import model_library

    path = model_library.get_filepath(args.network) if args.network in model_library.model_name_list \
        else args.network
    peer_read_time, model = timed(lambda: wntr.network.WaterNetworkModel(str(path)), args.repeat)

    def peer_route():
        graph = nx.Graph()
        for pipe_id, pipe in model.pipes():
            a, b = pipe.start_node_name, pipe.end_node_name
            if a != b and (not graph.has_edge(a, b) or graph[a][b]["length"] > pipe.length):
                graph.add_edge(a, b, length=pipe.length, pipe=pipe_id)
        nodes = nx.dijkstra_path(graph, start, end, weight="length")
        return [graph[a][b]["pipe"] for a, b in itertools.pairwise(nodes)]

    peer_route_time, peer_pipes = timed(peer_route, args.repeat)
    same = list(route.name) == peer_pipes
    mission = load_mission(DEMO)
    plan_mission(mission)  # build the planner once, as a running service would have
    plan_time, _ = timed(lambda: plan_mission(load_mission(DEMO)), args.repeat)

    rows = [("wntr import (first, once) [ms]", import_time * 1e3),
            (f"read {net.name} ({len(sections)} pipes) into arrays [ms]", read_time * 1e3),
            ("whole-network sections [ms]", whole_time * 1e3),
            (f"route {start} -> {end} ({len(route)} pipes) [ms]", route_time * 1e3),
            ("demo plan (load + plan_mission, 2 sections) [ms]", plan_time * 1e3),
            ("ratio (read + sections) / demo plan", (read_time + whole_time) / plan_time),
            ("wntr WaterNetworkModel alone (the peer's read) [ms]", peer_read_time * 1e3),
            ("ratio pampipe read / wntr read", read_time / peer_read_time),
            ("networkx dijkstra_path route (graph built) [ms]", peer_route_time * 1e3),
            ("ratio pampipe route / networkx route", route_time / peer_route_time)]
    for label, value in rows:
        print(f"{label:<52}{value:10.3f}")
    print(f"networkx and pampipe choose the same pipes: {same}")

if __name__ == "__main__":
    with threadpool_limits(limits=1):
        main()
