"""Benchmark of network routes (issue 12): reading a network into columnar sections vs the demo plan.

Times, in one run: importing wntr (once), reading ky4 (1,156 pipes) into :class:`pampipe.network.Network`,
its whole-network sections, the route J-315 -> J-897, and ``plan_mission`` on the bundled two-section demo.
Prints the ratio of the network read to the demo plan. Goal (issue 12): a whole-network plan of ky4 takes
about as long as the demo plan; the read, measured here, must be a small part of it.

    .venv/bin/python benchmarks/bench_network.py [--network ky4] [--repeat 5]
"""

from __future__ import annotations

import argparse
import math
import time
from pathlib import Path

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
    mission = load_mission(DEMO)
    plan_mission(mission)  # build the planner once, as a running service would have
    plan_time, _ = timed(lambda: plan_mission(load_mission(DEMO)), args.repeat)

    rows = [("wntr import (first, once) [ms]", import_time * 1e3),
            (f"read {net.name} ({len(sections)} pipes) into arrays [ms]", read_time * 1e3),
            ("whole-network sections [ms]", whole_time * 1e3),
            (f"route {start} -> {end} ({len(route)} pipes) [ms]", route_time * 1e3),
            ("demo plan (load + plan_mission, 2 sections) [ms]", plan_time * 1e3),
            ("ratio (read + sections) / demo plan", (read_time + whole_time) / plan_time)]
    for label, value in rows:
        print(f"{label:<52}{value:10.3f}")

if __name__ == "__main__":
    main()
