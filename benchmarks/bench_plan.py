"""Benchmark of `pampipe plan` (issue 17 item 5): the core solver against a numpy closed form.

The peer is what a skilled numpy user writes for the same formula (docs/physics.md §8, thick wall,
no contact increments, as in the demo PAM): L(D), A, the wall section, the moduli sums by Horner
(products, no powers), F₀ and F₁, W, and P* = max((κW − F₀)/F₁ + SF·W/(μπA·F₁), 0), one pass per
segment over the route's (diameter, incline, friction) arrays. pampipe's core is
``solve(muscles, build_elements(mission, muscles, route=columns))``: the element table (loads, loaded
anchoring pressures, validity, each element's KKT point) and which constraint binds, from the same
arrays; what only the report needs (lengths, air volumes, unloaded anchoring) is computed later, by
``plan_mission``, and timed in its row.

Printed, in one run with one BLAS thread, the best of ``--repeat`` alternating runs (CPU time, and
wall time in brackets: on a shared 2-core machine wall time mostly measures the other processes):
* the core and the peer at each size (default 10⁶ and 10⁷ elements), their ratio and agreement; the
  peer also chunked as pampipe is (its temporaries then stay in cache: the stronger of the two at
  10⁷ elements on a 2-core machine), and the goal is judged against the faster peer;
* the peak memory of each per element (tracemalloc, a separate run): linear means equal per element;
* ``plan_mission`` end to end from a route of Section objects (arrays, reasons, payloads) with and
  without its cross-check, at the smallest size;
* the IPOPT path on a subset, and a per-section scipy ``brentq`` on the model (an independent root
  finder: agreement only, it is no speed peer);
* ``pampipe plan`` on the demo mission in a fresh interpreter.

Goals (issue 17): core within 2× of the peer at 10⁷ elements; memory linear in elements.

    .venv/bin/python benchmarks/bench_plan.py [--elements 1e6 1e7] [--repeat 3]
"""

from __future__ import annotations

import argparse
import dataclasses
import gc
import math
import statistics
import subprocess
import sys
import time
import tracemalloc
from pathlib import Path

import numpy as np
from scipy.optimize import brentq
from threadpoolctl import threadpool_limits

from pampipe.io.mission_schema import load_mission
from pampipe.model import forces, no_slip
from pampipe.planning import plan_mission
from pampipe.planning.problem import CHUNK, build_elements, mission_muscles
from pampipe.planning.solve import solve
from pampipe.specs.mission import Section

ROOT = Path(__file__).resolve().parent.parent
DEMO = ROOT / "problems" / "missions" / "vertical-climb-3in.yaml"


@dataclasses.dataclass(frozen=True)
class Columns:
    """A route as arrays (what :func:`pampipe.planning.problem.route_columns` reads)."""

    diameter: np.ndarray
    incline: np.ndarray
    friction: np.ndarray


def random_columns(rng, sections: int) -> Columns:
    """Diameters 3–3.8 in, inclines −90…90°, friction 0.15–0.5: every section feasible at 689 kPa."""
    return Columns(rng.uniform(3.0, 3.8, sections) * 0.0254, rng.uniform(-math.pi / 2, math.pi / 2, sections),
                   rng.uniform(0.15, 0.5, sections))


def numpy_closed_form(mission, route: Columns) -> np.ndarray:
    """The least holding pressure (sections, segments) [Pa], written directly with numpy."""
    d, mu = route.diameter, route.friction
    total = sum(s.mass for s in mission.segments) + mission.payload
    rise, run = np.abs(np.sin(route.incline)), np.cos(route.incline)
    out = np.empty((d.size, len(mission.segments)))
    for i, seg in enumerate(mission.segments):
        g, m = seg.pam.geometry, seg.pam.moduli
        theta, k = m.as_vector(), m.degree + 1
        a1, b1, a2, b2 = (theta[j * k:(j + 1) * k] for j in range(4))
        l0, d0 = g.initial_length, g.initial_diameter
        braid = l0 / math.cos(g.braid_angle)
        turns = l0 * math.tan(g.braid_angle) / (math.pi * d0)
        r0 = d0 / 2
        vb = math.pi * (r0 * r0 - (r0 - g.bladder_thickness) ** 2) * l0
        c2 = 2 * math.pi * turns * turns

        def horner(c, e):
            acc = c[-1] * e
            for cj in c[-2::-1]:
                acc = (acc + cj) * e
            return acc

        length = np.sqrt(braid * braid - (turns * math.pi * d) ** 2)
        ro = 0.5 * d
        ri = np.sqrt(ro * ro - vb / (math.pi * length))
        e1, e2 = (length - l0) / l0, (d - d0) / d0
        lever1, shared = vb / length, length * length / (c2 * ro)
        lever2 = (ro - ri) * shared
        f0 = horner(a1, e1) * lever1 - horner(a2, e2) * lever2
        f1 = ri * shared - math.pi * ri * ri + (horner(b1, e1) * lever1 - horner(b2, e2) * lever2
                                                 ) / m.reference_pressure
        w = no_slip.STANDARD_GRAVITY * (total * rise + mu * run * (total - seg.mass)) + mission.tether_drag
        amplification = c2 * d / length
        p = np.maximum((mission.kappa * w - f0) / f1
                       + mission.safety_factor * w / (mu * math.pi * amplification * f1), 0.0)
        ok = (f1 > 0) & (mu > 0) & (d > d0) & (p <= 1e8)
        out[:, i] = np.where(ok, p, np.inf)
    return out


def numpy_chunked(mission, route: Columns, chunk: int = CHUNK) -> np.ndarray:
    """:func:`numpy_closed_form` over ``chunk`` sections at a time (temporaries stay in cache)."""
    out = np.empty((route.diameter.size, len(mission.segments)))
    for start in range(0, route.diameter.size, chunk):
        part = slice(start, start + chunk)
        out[part] = numpy_closed_form(mission, Columns(route.diameter[part], route.incline[part],
                                                       route.friction[part]))
    return out


def pampipe_core(mission, muscles, route: Columns) -> np.ndarray:
    return solve(muscles, build_elements(mission, muscles, route=route), mission.supply_pressure).pressure


def brentq_plan(mission, route, indices) -> np.ndarray:
    """Per section and segment: the least P with μπF_r(P, D, κW) ≥ SF·W, by brentq on the model."""
    out = np.empty((len(indices), len(mission.segments)))
    total = sum(s.mass for s in mission.segments) + mission.payload
    for row, s in enumerate(indices):
        d, phi, mu = route.diameter[s], route.incline[s], route.friction[s]
        for i, seg in enumerate(mission.segments):
            m = seg.pam.moduli
            args = (seg.pam.geometry, m.as_vector(), m.reference_pressure)
            load = no_slip.anchor_load(total, seg.mass, phi, mu, mission.tether_drag)
            start = float(forces.anchoring_pressure(d, *args, mission.kappa * load))

            def margin(p, d=d, mu=mu, args=args, load=load):
                radial = forces.radial_force(p, d, *args, mission.kappa * load)
                return mu * math.pi * radial - mission.safety_factor * load

            out[row, i] = start if margin(start) >= 0 else brentq(margin, start, 1e8, xtol=1e-9, rtol=1e-14)
    return out


def timed(fn, repeat: int = 1):
    """(best wall time [s], result) over ``repeat`` runs."""
    best, result = math.inf, None
    for _ in range(repeat):
        result = None
        gc.collect()
        t = time.perf_counter()
        result = fn()
        best = min(best, time.perf_counter() - t)
    return best, result


def peak_bytes(fn) -> int:
    """Peak traced memory [B] while ``fn`` runs (numpy reports its buffers to tracemalloc)."""
    gc.collect()
    tracemalloc.start()
    result = fn()
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    del result
    return peak


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--elements", type=float, nargs="+", default=[1e6, 1e7])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--baseline-sections", type=int, default=1000)
    parser.add_argument("--ipopt-sections", type=int, default=2000)
    args = parser.parse_args()
    rng = np.random.default_rng(0)
    demo = load_mission(DEMO)
    muscles = mission_muscles(demo)
    segments = len(demo.segments)
    print(f"core solver vs the numpy closed form (whole arrays, and chunked by {CHUNK} sections as pampipe "
          f"is); one BLAS thread; best of {args.repeat} alternating runs.\nTimes are CPU seconds (user + "
          "system: on a shared machine they exclude the waits for other processes; wall in brackets); "
          "B/el = peak bytes per element.")
    print(f"{'elements':>10}{'pampipe [s]':>17}{'numpy [s]':>17}{'chunked [s]':>17}{'vs numpy':>9}"
          f"{'vs chunked':>11}{'max rel diff':>13}{'pampipe B/el':>13}{'numpy':>6}{'chunked':>8}")
    ratios, per_element = [], []
    for size in args.elements:
        route = random_columns(rng, int(size) // segments)
        n = route.diameter.size * segments
        runs = {"ours": lambda route=route: pampipe_core(demo, muscles, route),
                "numpy": lambda route=route: numpy_closed_form(demo, route),
                "chunked": lambda route=route: numpy_chunked(demo, route)}
        cpu, wall = dict.fromkeys(runs, math.inf), dict.fromkeys(runs, math.inf)
        for _ in range(args.repeat):
            for key, run in runs.items():
                gc.collect()
                start, start_cpu = time.perf_counter(), time.process_time()
                run()
                cpu[key] = min(cpu[key], time.process_time() - start_cpu)
                wall[key] = min(wall[key], time.perf_counter() - start)
        ours, peer = runs["ours"](), runs["numpy"]()
        diff = float(np.max(np.abs(ours - peer) / peer))
        del ours, peer
        memory = {key: peak_bytes(run) / n for key, run in runs.items()}
        ratios.append(cpu["ours"] / min(cpu["numpy"], cpu["chunked"]))
        per_element.append(memory["ours"])
        print(f"{n:>10.3g}" + "".join(f"{cpu[k]:>9.3f} ({wall[k]:>5.2f})" for k in runs)
              + f"{cpu['ours'] / cpu['numpy']:>9.2f}{cpu['ours'] / cpu['chunked']:>11.2f}{diff:>13.1e}"
              f"{memory['ours']:>13.0f}{memory['numpy']:>6.0f}{memory['chunked']:>8.0f}")

    sections = int(args.elements[0]) // segments
    route = random_columns(np.random.default_rng(1), sections)
    mission = dataclasses.replace(demo, route=tuple(
        Section(f"s{k}", 1.0, d, phi, mu, 0.0)
        for k, (d, phi, mu) in enumerate(zip(route.diameter, route.incline, route.friction, strict=True))))
    n = sections * segments
    full, plan = timed(lambda: plan_mission(mission, check=False))
    checked, plan_c = timed(lambda: plan_mission(mission))
    assert plan.feasible and plan_c.feasible
    size = min(args.baseline_sections, sections)
    subset = np.sort(np.random.default_rng(2).choice(sections, size=size, replace=False))
    base_time, base = timed(lambda: brentq_plan(mission, route, subset))
    disagreement = float(np.max(np.abs(plan.arrays.pressure[subset] - base) / base))
    small = dataclasses.replace(mission, route=mission.route[:args.ipopt_sections])
    ipopt_time, ipopt = timed(lambda: solve(muscles, build_elements(small, muscles), small.supply_pressure,
                                            method="ipopt"))
    ipopt_diff = float(np.max(np.abs(ipopt.pressure - plan.arrays.pressure[:args.ipopt_sections])
                              / plan.arrays.pressure[:args.ipopt_sections]))
    print(f"\n{'route of Section objects':<46}{'elements':>9}{'wall [s]':>9}{'elements/s':>12}"
          f"{'max rel diff':>14}")
    for name, count, wall, diff in [
            ("plan_mission (arrays, reasons, payloads)", n, full, "-"),
            ("plan_mission + cross-check (4096 per segment)", n, checked,
             f"{plan_c.checks['bisection_max_rel_diff']:.2e}"),
            (f"IPOPT path ({args.ipopt_sections} sections)", ipopt.pressure.size, ipopt_time,
             f"{ipopt_diff:.2e}"),
            (f"brentq per section ({size}; agreement only)", base.size, base_time, f"{disagreement:.2e}")]:
        print(f"{name:<46}{count:>9}{wall:>9.3f}{count / wall:>12.4g}{diff:>14}")

    demo_times = []
    for _ in range(3):
        t = time.perf_counter()
        subprocess.run([sys.executable, "-m", "pampipe", "plan", str(DEMO)], check=True, capture_output=True)
        demo_times.append(time.perf_counter() - t)
    print("\n`pampipe plan` on the demo mission, fresh interpreter: median "
          f"{statistics.median(demo_times):.2f} s")
    linear = max(per_element) <= 1.1 * min(per_element)
    print(f"goals: core within 2x (CPU) of the faster numpy at {args.elements[-1]:.3g} elements: "
          f"{ratios[-1]:.2f} "
          f"({'met' if ratios[-1] <= 2 else 'MISSED'}); memory linear (bytes per element within 10 %): "
          f"{'met' if linear else 'MISSED'}; agreement with brentq 1e-6: "
          f"{'met' if disagreement <= 1e-6 else 'MISSED'}")
    return 0


if __name__ == "__main__":
    with threadpool_limits(limits=1):
        sys.exit(main())
