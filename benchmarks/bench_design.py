"""Benchmark of `pampipe design` (issue 16): time per start, 2 workers against serial, objective against grid.

1. *Objective against a grid search*, on the bundled riser (one vertical 3 in pipe): the baseline a
   skilled user would write is a vectorised 20³ grid over (L₀, D₀, α₀) on the public Muscle API with
   the same constraints, then scipy SLSQP (finite differences) polished from the best grid point. The
   ratio design / baseline ≤ 1 means the NLP is at least as good.
2. *Time per start*: the mean wall time of one IPOPT solve from a Latin-hypercube start, over
   ``--starts`` starts of the plant inventory's 3-6 in pipes (serial, solver already built).
3. *Speed-up of 2 workers over serial*: the same ``--starts`` starts on a warm 2-process pool and
   serially, and the whole ky4 design (``--ky4``) end to end, pool start-up included. The results
   must be identical.

    .venv/bin/python benchmarks/bench_design.py [--starts 64] [--ky4]
"""

from __future__ import annotations

import argparse
import math
import os
import time
from pathlib import Path

import numpy as np
from scipy.optimize import minimize

from pampipe.design import solve_inventory
from pampipe.design.groups import make_groups, segment_loads
from pampipe.design.multistart import make_problem, multistart
from pampipe.io.inventory_file import load_inventory
from pampipe.model.muscle import Muscle
from pampipe.model.pam import Geometry
from pampipe.runtime.executors import SerialExecutor, executor, run_all

ROOT = Path(__file__).resolve().parent.parent
INVENTORIES = ROOT / "problems" / "inventories"


def largest_pressure(inventory, length, diameter, angle):
    """Vectorised: the largest least holding pressure over the pipes and segments [Pa], inf where a
    constraint fails (clearance, contact margin, stride, stable moduli, supply)."""
    s = inventory.space
    t0 = inventory.material.geometry.bladder_thickness
    muscle = Muscle(Geometry(length, diameter, angle, t0), inventory.material.moduli.as_vector(),
                    inventory.material.moduli.reference_pressure)
    g = muscle.geometry
    loads = segment_loads(inventory)
    worst = np.zeros(np.shape(length))
    ok = np.ones(np.shape(length), dtype=bool)
    with np.errstate(all="ignore"):
        for j, bore in enumerate(inventory.pipes.diameter):
            for w in loads[j]:
                worst = np.maximum(worst, muscle.least_holding_pressure(
                    bore, w, kappa=inventory.kappa, friction=inventory.pipes.friction[j],
                    safety_factor=inventory.safety_factor))
            lp = muscle.anchored_length(bore)
            for p in (0.0, inventory.supply_pressure):
                e1, e2 = muscle.drucker_tangent_moduli(p, lp)
                ok &= (np.asarray(e1) >= 0) & (np.asarray(e2) >= 0)
            ok &= (diameter <= bore - s.clearance) & (bore <= (1 - s.contact_margin) * g.largest_diameter)
            ok &= g.initial_length - lp >= s.min_stride
    return np.where(ok & np.isfinite(worst) & (worst <= inventory.supply_pressure), worst, np.inf)


def grid_baseline(inventory, n: int = 20):
    """(objective [Pa], seconds): 20³ grid, then SLSQP from its best point on the same function."""
    started = time.perf_counter()
    s = inventory.space
    axes = [np.linspace(*b, n) for b in (s.initial_length, s.initial_diameter, s.braid_angle)]
    mesh = [v.ravel() for v in np.meshgrid(*axes, indexing="ij")]
    values = largest_pressure(inventory, *mesh)
    k = int(np.argmin(values))
    grid = float(values[k])
    grid_time = time.perf_counter() - started
    bounds = [s.initial_length, s.initial_diameter, s.braid_angle]
    scale = np.array([b[1] - b[0] for b in bounds])
    low = np.array([b[0] for b in bounds])

    def f(u):
        value = float(largest_pressure(inventory, *(low + scale * u)))
        return value / inventory.supply_pressure if math.isfinite(value) else 1e3

    start = (np.array([m[k] for m in mesh]) - low) / scale
    polished = minimize(f, start, method="SLSQP", bounds=[(0, 1)] * 3, options={"ftol": 1e-12})
    best = min(grid, f(polished.x) * inventory.supply_pressure)
    return grid, grid_time, best, time.perf_counter() - started


def burn(seconds: float) -> float:
    """Pure CPU work for ``seconds`` of process time: the best case any task can get from a pool."""
    started = time.process_time()
    count = 0.0
    while time.process_time() - started < seconds:
        count += 1
    return count


def time_burns(count: int, seconds: float, pool) -> float:
    started = time.perf_counter()
    run_all(burn, [seconds] * count, pool)
    return time.perf_counter() - started


def time_starts(problem, starts: int, pool) -> tuple[float, object]:
    started = time.perf_counter()
    run = multistart(problem, starts=starts, seed=0, pool=pool)
    return time.perf_counter() - started, run


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--starts", type=int, default=64)
    parser.add_argument("--ky4", action="store_true",
                        help="also time the whole ky4 design, serial and on 2 workers")
    args = parser.parse_args()

    riser = load_inventory(INVENTORIES / "riser.yaml")
    started = time.perf_counter()
    designed = solve_inventory(riser)
    design_time = time.perf_counter() - started
    objective = designed.as_document()["objective"]
    grid, grid_time, polished, polished_time = grid_baseline(riser)
    print("1. riser (one vertical 3 in pipe), objective max_pressure")
    print(f"   design NLP, {riser.space.starts} starts: {objective:.8g} Pa in {design_time:.3f} s")
    print(f"   20^3 grid:                  {grid:.8g} Pa in {grid_time:.3f} s   "
          f"design/grid = {objective / grid:.6f}")
    print(f"   grid + SLSQP polish:        {polished:.8g} Pa in {polished_time:.3f} s   "
          f"design/polished = {objective / polished:.6f}")

    plant = load_inventory(INVENTORIES / "plant.yaml")
    pipes = plant.pipes.subset(plant.pipes.diameter < 0.16)
    problem = make_problem(plant, make_groups(plant, pipes), relaxed=True)
    multistart(problem, starts=1, seed=0, pool=SerialExecutor())  # build the solver once
    serial_time, serial = time_starts(problem, args.starts, SerialExecutor())
    print(f"2. plant 3-6 in pipes ({len(pipes)} pipes, {len(problem.groups)} groups): "
          f"{1e3 * serial_time / args.starts:.1f} ms per start (serial, {args.starts} starts, "
          f"{np.mean([r.iterations for r in serial.results]):.1f} IPOPT iterations per start, "
          f"{serial.reached}/{len(serial.results)} reach the best)")
    per_start = serial_time / args.starts
    burn_serial = time_burns(args.starts, per_start, SerialExecutor())
    with executor(workers=2) as pool:
        time_starts(problem, 2, pool)  # start the processes and build their solvers
        parallel_time, parallel = time_starts(problem, args.starts, pool)
        burn_parallel = time_burns(args.starts, per_start, pool)
    same = [r.objective for r in serial.results] == [r.objective for r in parallel.results]
    print(f"3. the same {args.starts} starts on 2 warm worker processes: {parallel_time:.3f} s against "
          f"{serial_time:.3f} s serial: speed-up {serial_time / parallel_time:.2f}x (identical: {same})")
    print(f"   machine check, {args.starts} pure-CPU tasks of {1e3 * per_start:.1f} ms on the same pool: "
          f"speed-up {burn_serial / burn_parallel:.2f}x (the most any task gets from 2 workers on this "
          f"machine now; {os.getloadavg()[0]:.1f} load average on {os.cpu_count()} cores)")
    if args.ky4:
        ky4 = load_inventory(INVENTORIES / "ky4.yaml")
        times = {}
        documents = {}
        for workers in (None, 2):
            started = time.perf_counter()
            with executor(workers=workers) as pool:
                result = solve_inventory(ky4, pool=pool)
            times[workers] = time.perf_counter() - started
            doc = result.as_document()
            doc["solver"].pop("wall_time_s")
            for size in doc["sizes"]:
                for r in size["starts"]["runs"]:
                    r.pop("wall_time_s")
            documents[workers] = doc
        print(f"   ky4 whole design ({result.solves} NLP solves, pool start-up included): serial "
              f"{times[None]:.2f} s, 2 workers {times[2]:.2f} s: speed-up {times[None] / times[2]:.2f}x "
              f"(identical: {documents[None] == documents[2]})")


if __name__ == "__main__":
    main()
