"""Benchmark of network routes and long missions (issue 12): reading, planning, and the demo plan as the unit.

Times, in one run (one BLAS thread):

* importing wntr, in a fresh interpreter (pampipe imports it only when a mission names a network);
* reading ky4 (1,156 pipes) into :class:`pampipe.specs.network.Network`, its whole-network sections, the route
  J-315 -> J-897, against what a user would write with the same tools: wntr's own ``WaterNetworkModel``
  (which pampipe calls, then turns into arrays) and ``networkx.dijkstra_path`` on wntr's pipes;
* ``plan`` of the mission ``route: {network: ky4}`` (every pipe, with the coverage) and of the route
  J-315 -> J-897 with a 2 % bore tolerance: the mission read (network included, wntr already imported)
  and ``plan_mission``, each against the demo plan (read + plan of the bundled two-section mission);
* a synthetic route of 10⁵ sections written as a YAML mission, a fifth of them with a bore tolerance: parse
  time against plan time, and both against the demo plan;
* the worst-bore search of those 10⁵ sections against the strongest simple alternative: a dense scan of
  65 bores per range with the same vectorised closed form (time ratio, and the scan's largest shortfall);
* ``pampipe plan`` on the whole ky4 network and on the demo as commands (fresh processes: imports, wntr's
  included, and the JSON), and the same two from a process that has already imported wntr.

Goal (issue 12): a whole-network plan of ky4 takes about as long as ``pampipe plan`` on the demo.

    .venv/bin/python benchmarks/bench_network.py [--repeat 5] [--sections 100000]
"""

from __future__ import annotations

import argparse
import itertools
import math
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from threadpoolctl import threadpool_limits

from pampipe.io.epanet import load_network
from pampipe.io.mission_schema import load_mission
from pampipe.planning import plan_mission
from pampipe.planning.bores import worst_bores
from pampipe.planning.problem import mission_muscles
from pampipe.specs.network import route_sections, whole_network

ROOT = Path(__file__).resolve().parent.parent
MISSIONS = ROOT / "problems" / "missions"
DEMO = MISSIONS / "vertical-climb-3in.yaml"
BORES = ("3 in", "3.5 in", "80 mm", "{nps: 3, schedule: 40, tolerance: 1 %}", "{dn: 110, sdr: 26}")


def timed(fn, repeat: int):
    """(best wall time [s], result) over ``repeat`` runs."""
    best, result = math.inf, None
    for _ in range(repeat):
        start = time.perf_counter()
        result = fn()
        best = min(best, time.perf_counter() - start)
    return best, result


def command(*args: str, repeat: int) -> float:
    """Best wall time [s] of a fresh ``python -m pampipe ARGS`` process."""

    def run():
        subprocess.run([sys.executable, "-m", "pampipe", *args], check=False, capture_output=True, cwd=ROOT)

    return timed(run, repeat)[0]


def command_after_wntr(*args: str, repeat: int) -> float:
    """Best wall time [s] of ``pampipe ARGS`` run by ``pampipe.cli.main`` in a fresh process that has
    already imported wntr (so that both commands compared start from the same loaded libraries)."""
    code = ("import sys, time, io, contextlib, wntr\n"
            "t = time.perf_counter()\n"
            "from pampipe.cli import main\n"
            "with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):\n"
            "    main(sys.argv[1:])\n"
            "print(time.perf_counter() - t)")
    runs = [float(subprocess.run([sys.executable, "-c", code, *args], capture_output=True, text=True,
                                 check=True, cwd=ROOT).stdout) for _ in range(repeat)]
    return min(runs)


def write_mission(folder: Path, sections: int, *, robot: Path = DEMO, friction_sd: float = 0.0,
                  distinct: bool = False) -> Path:
    """``robot``'s mission (the demo's) on ``sections`` sections: varied lengths, bores (a fifth with a
    tolerance), inclines (90 values, or a different one per section if ``distinct``), frictions (four
    values, each with ``friction_sd`` if not 0)."""
    head = robot.read_text().split("route:")[0].replace("../pams", str(ROOT / "problems" / "pams"))
    path = folder / f"mission-{sections}{'-distinct' if distinct else ''}.yaml"
    with open(path, "w", encoding="utf-8") as handle:
        handle.write(head + "route:\n")
        for i in range(sections):
            incline = f"{90 * i / sections - 45:.9g}" if distinct else f"{i % 90 - 45}"
            mu = f"{0.2 + 0.05 * (i % 4):g}"
            friction = f"{{value: {mu}, sd: {friction_sd:g}}}" if friction_sd else mu
            handle.write(f"  - {{name: s{i}, length: {1 + i % 7} m, inner_diameter: {BORES[i % 5]}, "
                         f"incline: {incline} deg, friction: {friction}}}\n")
    return path


def ky4_mission(folder: Path, route: str) -> Path:
    path = folder / "ky4.yaml"
    path.write_text(DEMO.read_text().split("route:")[0].replace("../pams", str(ROOT / "problems" / "pams"))
                    + f"route: {route}\n")
    return path


def peer_scan(muscle, low, high, load, *, kappa, friction, safety_factor, points: int = 65):
    """The largest least holding pressure on ``points`` evenly spaced bores of each range (vectorised)."""
    grid = low[:, None] + (high - low)[:, None] * np.linspace(0.0, 1.0, points)
    pressure = muscle.least_holding_pressure(grid, load[:, None], kappa=kappa, friction=friction[:, None],
                                             safety_factor=safety_factor)
    return pressure.max(axis=1)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--repeat", type=int, default=5, help="runs per timing; the best is kept (5)")
    parser.add_argument("--sections", type=int, default=100_000, help="sections of the synthetic route")
    args = parser.parse_args()
    rows: list[tuple[str, float]] = []

    probe = "import time; t = time.perf_counter(); import wntr; print(time.perf_counter() - t)"
    imports = [float(subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True,
                                    check=True).stdout) for _ in range(3)]
    rows.append(("wntr import, fresh interpreter (best of 3) [s]", min(imports)))

    demo_time, _ = timed(lambda: plan_mission(load_mission(DEMO)), args.repeat)
    rows.append(("demo plan: read + plan_mission, 2 sections [ms]", demo_time * 1e3))

    read_time, net = timed(lambda: load_network("ky4"), args.repeat)
    whole_time, sections = timed(lambda: whole_network(net, friction=0.3), args.repeat)
    route_time, route = timed(lambda: route_sections(net, "J-315", "J-897", friction=0.3), args.repeat)
    import networkx as nx
    import wntr
    from wntr.library import model_library

    peer_read_time, model = timed(lambda: wntr.network.WaterNetworkModel(model_library.get_filepath("ky4")),
                                  args.repeat)

    def peer_route():
        graph = nx.Graph()
        for pipe_id, pipe in model.pipes():
            a, b = pipe.start_node_name, pipe.end_node_name
            if a != b and (not graph.has_edge(a, b) or graph[a][b]["length"] > pipe.length):
                graph.add_edge(a, b, length=pipe.length, pipe=pipe_id)
        nodes = nx.dijkstra_path(graph, "J-315", "J-897", weight="length")
        return [graph[a][b]["pipe"] for a, b in itertools.pairwise(nodes)]

    peer_route_time, peer_pipes = timed(peer_route, args.repeat)
    rows += [(f"read ky4 ({len(sections)} pipes) into arrays [ms]", read_time * 1e3),
             ("  wntr WaterNetworkModel alone (the peer's read) [ms]", peer_read_time * 1e3),
             ("  ratio pampipe read / wntr read", read_time / peer_read_time),
             ("whole-network sections [ms]", whole_time * 1e3),
             (f"route J-315 -> J-897 ({len(route)} pipes) [ms]", route_time * 1e3),
             ("  networkx dijkstra_path route (graph built) [ms]", peer_route_time * 1e3),
             ("  ratio pampipe route / networkx route", route_time / peer_route_time)]

    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        for label, spec in (("whole ky4 network", "{network: ky4, friction: 0.3}"),
                            ("ky4 route J-315 -> J-897, 2 % tolerance",
                             "{network: ky4, from: J-315, to: J-897, friction: 0.3, tolerance: 2 %}")):
            path = ky4_mission(folder, spec)
            load_time, mission = timed(lambda path=path: load_mission(path), args.repeat)
            plan_time, plan = timed(lambda mission=mission: plan_mission(mission), args.repeat)
            rows += [(f"{label}: read mission (network, route) [ms]", load_time * 1e3),
                     (f"{label}: plan_mission, {len(mission.route)} sections [ms]", plan_time * 1e3),
                     ("  ratio (read + plan) / demo plan", (load_time + plan_time) / demo_time)]
            if plan.coverage is not None and mission.route.origin.whole:
                rows.append((f"  pipes served of {plan.coverage.pipes_total}", plan.coverage.pipes_feasible))

        path = write_mission(folder, args.sections)
        parse_time, mission = timed(lambda: load_mission(path), 1)
        plan_time, _ = timed(lambda: plan_mission(mission), max(1, args.repeat // 2))
        rows += [(f"synthetic route: parse {args.sections} sections (YAML -> SI columns) [s]", parse_time),
                 (f"synthetic route: plan_mission, {args.sections} sections [s]", plan_time),
                 ("  ratio parse / plan", parse_time / plan_time),
                 ("  ratio plan / demo plan", plan_time / demo_time)]

        r = mission.route
        ranged = np.flatnonzero(r.diameter_high > r.diameter_low)
        muscle = mission_muscles(mission)[0]
        load = np.full(ranged.size, 30.0)
        keys = {"kappa": 1.0, "friction": r.friction[ranged], "safety_factor": 1.5}
        ours_time, worst = timed(lambda: worst_bores(muscle, r.diameter_low[ranged], r.diameter_high[ranged],
                                                      load, **keys), args.repeat)
        exact = muscle.least_holding_pressure(worst, load, **keys)
        scan_time, scanned = timed(lambda: peer_scan(muscle, r.diameter_low[ranged], r.diameter_high[ranged],
                                                      load, **keys), args.repeat)
        rows += [(f"worst bore of {ranged.size} ranges, one segment (pampipe) [ms]", ours_time * 1e3),
                 ("  dense scan of 65 bores per range (peer) [ms]", scan_time * 1e3),
                 ("  ratio pampipe / scan", ours_time / scan_time),
                 ("  scan's largest shortfall below pampipe (relative)",
                  float(np.max((exact - scanned) / exact)))]

        whole_path = ky4_mission(folder, "{network: ky4, friction: 0.3}")
        cli_whole = command("plan", str(whole_path), "--json", repeat=max(1, args.repeat // 2))
        cli_demo = command("plan", str(DEMO), "--json", repeat=max(1, args.repeat // 2))
        after_whole = command_after_wntr("plan", str(whole_path), "--json", repeat=max(1, args.repeat // 2))
        after_demo = command_after_wntr("plan", str(DEMO), "--json", repeat=max(1, args.repeat // 2))
        rows += [("pampipe plan --json, whole ky4 (fresh process) [s]", cli_whole),
                 ("pampipe plan --json, demo (fresh process) [s]", cli_demo),
                 ("  ratio whole ky4 / demo, as commands", cli_whole / cli_demo),
                 ("pampipe plan --json, whole ky4, wntr already imported [s]", after_whole),
                 ("pampipe plan --json, demo, wntr already imported [s]", after_demo),
                 ("  ratio whole ky4 / demo, both after importing wntr", after_whole / after_demo)]

    for label, value in rows:
        print(f"{label:<72}{value:12.4g}")
    print(f"networkx and pampipe choose the same pipes: {list(route.name) == peer_pipes}")


if __name__ == "__main__":
    with threadpool_limits(limits=1):
        main()
