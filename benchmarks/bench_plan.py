"""Benchmark of `pampipe plan` (the plan issue): a 10⁵-section route, 3 segments.

Compares the planner (the NLP solved through its KKT conditions, all elements at once) with a
per-section scipy ``brentq`` on the same model (:func:`pampipe.model.forces.radial_force` on
floats). brentq is timed on a random subset of sections (``--baseline-sections``) and its rate
extrapolated; the largest disagreement is measured on that subset. Also times the IPOPT path on a
subset, and ``pampipe plan`` on the demo mission in a fresh interpreter (import included).

Goals: ≥ 10⁵ section-segments/s, agreement 1e-6, demo < 2 s wall.

    .venv/bin/python benchmarks/bench_plan.py [--sections 100000] [--baseline-sections 1000]
"""

from __future__ import annotations

import argparse
import dataclasses
import math
import statistics
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
from scipy.optimize import brentq

from pampipe.io.config import load_mission
from pampipe.mission import Section
from pampipe.model import forces, slip
from pampipe.plan import plan_mission
from pampipe.plan.problem import build_elements, mission_muscles
from pampipe.plan.solve import solve

ROOT = Path(__file__).resolve().parent.parent
DEMO = ROOT / "problems" / "missions" / "vertical-climb-3in.yaml"


def random_route(rng, sections: int) -> tuple[Section, ...]:
    """Diameters 3–3.8 in, inclines −90…90°, friction 0.15–0.5: every section feasible at 689 kPa."""
    return tuple(Section(f"s{k}", 1.0, d * 0.0254, phi, mu, 0.0) for k, (d, phi, mu) in enumerate(zip(
        rng.uniform(3.0, 3.8, sections), rng.uniform(-math.pi / 2, math.pi / 2, sections),
        rng.uniform(0.15, 0.5, sections), strict=True)))


def brentq_plan(mission, indices) -> np.ndarray:
    """Per section and segment: the least P with μπF_r(P, D, κW) ≥ SF·W, by brentq on the model."""
    out = np.empty((len(indices), len(mission.segments)))
    total = sum(s.mass for s in mission.segments) + mission.payload
    for row, s in enumerate(indices):
        sec = mission.route[s]
        for i, seg in enumerate(mission.segments):
            m = seg.pam.moduli
            args = (seg.pam.geometry, m.as_vector(), m.reference_pressure)
            load = slip.anchor_load(total, seg.mass, sec.incline, sec.friction, mission.tether_drag)
            start = float(forces.anchoring_pressure(sec.diameter, *args, mission.kappa * load))

            def margin(p, sec=sec, args=args, load=load):
                radial = forces.radial_force(p, sec.diameter, *args, mission.kappa * load)
                return sec.friction * math.pi * radial - mission.safety_factor * load

            out[row, i] = start if margin(start) >= 0 else brentq(margin, start, 1e8, xtol=1e-9,
                                                                  rtol=1e-14)
    return out


def timed(fn, repeat: int = 3):
    """(best wall time [s], result) over ``repeat`` runs."""
    best, result = math.inf, None
    for _ in range(repeat):
        t = time.perf_counter()
        result = fn()
        best = min(best, time.perf_counter() - t)
    return best, result


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sections", type=int, default=100_000)
    parser.add_argument("--baseline-sections", type=int, default=1000)
    parser.add_argument("--ipopt-sections", type=int, default=2000)
    args = parser.parse_args()
    rng = np.random.default_rng(0)
    demo = load_mission(DEMO)
    mission = dataclasses.replace(demo, route=random_route(rng, args.sections))
    n = args.sections * len(mission.segments)
    print(f"route: {args.sections} sections x {len(mission.segments)} segments = {n} section-segments",
          file=sys.stderr)

    muscles = mission_muscles(mission)
    core, solution = timed(lambda: solve(muscles, build_elements(mission, muscles), mission.supply_pressure))
    full, plan = timed(lambda: plan_mission(mission, check=False), repeat=1)
    objects, _ = timed(lambda: plan_mission(mission, check=False).sections, repeat=1)
    checked, plan_c = timed(lambda: plan_mission(mission), repeat=1)
    assert plan.feasible and plan_c.feasible
    pressures = solution.pressure

    size = min(args.baseline_sections, args.sections)
    subset = np.sort(rng.choice(args.sections, size=size, replace=False))
    print(f"brentq baseline on {subset.size} sections ...", file=sys.stderr)
    base_time, base = timed(lambda: brentq_plan(mission, subset), repeat=1)
    base_rate = base.size / base_time
    disagreement = float(np.max(np.abs(pressures[subset] - base) / base))

    small = dataclasses.replace(mission, route=mission.route[:args.ipopt_sections])
    ipopt_time, ipopt = timed(lambda: solve(muscles, build_elements(small, muscles), small.supply_pressure,
                                            method="ipopt"), repeat=1)
    ipopt_diff = float(np.max(np.abs(ipopt.pressure - pressures[:args.ipopt_sections])
                              / pressures[:args.ipopt_sections]))

    demo_times = []
    for _ in range(3):
        t = time.perf_counter()
        subprocess.run([sys.executable, "-m", "pampipe", "plan", str(DEMO)], check=True, capture_output=True)
        demo_times.append(time.perf_counter() - t)

    rows = [
        ("pampipe KKT point (elements + closed form)", n, core, n / core, "-"),
        ("pampipe plan_mission (arrays, reasons)", n, full, n / full, "-"),
        ("pampipe plan_mission + all SectionPlan objects", n, objects, n / objects, "-"),
        ("pampipe plan_mission (+ cross-checks)", n, checked, n / checked,
         f"{plan_c.checks['bisection_max_rel_diff']:.2e}"),
        (f"pampipe IPOPT path ({args.ipopt_sections} sections)", ipopt.pressure.size, ipopt_time,
         ipopt.pressure.size / ipopt_time, f"{ipopt_diff:.2e}"),
        (f"scipy brentq per section ({subset.size} sections)", base.size, base_time, base_rate,
         f"{disagreement:.2e}"),
    ]
    print(f"{'method':<48} {'elements':>9} {'wall [s]':>9} {'elements/s':>11} {'max rel diff':>13}")
    for name, count, wall, rate, diff in rows:
        print(f"{name:<48} {count:>9} {wall:>9.3f} {rate:>11.4g} {diff:>13}")
    print(f"speed-up of plan_mission over brentq: {n / full / base_rate:.0f}x "
          f"(KKT solve alone: {n / core / base_rate:.0f}x)")
    print(f"largest disagreement with brentq: {disagreement:.2e} (goal 1e-6)")
    print(f"`pampipe plan` on the demo mission, fresh interpreter: median "
          f"{statistics.median(demo_times):.2f} s wall (runs: "
          f"{', '.join(f'{t:.2f}' for t in demo_times)}; goal < 2 s)")
    goals = (n / full >= 1e5) and disagreement <= 1e-6
    print("goals (>= 1e5 section-segments/s, agreement 1e-6):", "met" if goals else "NOT met")
    return 0


if __name__ == "__main__":
    sys.exit(main())
