"""Benchmark: `pampipe identify` as a whole process against the strongest scipy script a user would write.

Peer: ``benchmarks/baseline_identify.py``: pandas' C reader, the same model in numpy written with
products, ``scipy.optimize.least_squares`` (trf, with its ``exact`` and its ``lsmr`` subproblem solver,
both run; the faster is the peer, named in the last column) with the analytic Jacobian (F_ax is linear in the
moduli), pampipe's bounds, no Drucker constraint. Both read the same CSV files (the paper protocol
generated from the demo moduli with 2 N force noise, scaled to 3·10⁴ … 3·10⁶ rows), both run as
whole processes (imports, reading, fit, output) with one BLAS/OpenMP thread, alternating, and the
median of ``--repeat`` runs is taken. The SSE of both is printed: pampipe holds Drucker stability,
so its SSE can only be equal or slightly higher; ``SSE no Drucker`` is pampipe with ``--drucker
none``, the peer's problem, and ``rel diff`` compares that with the peer (≤ 1e-9 or negative: pampipe
reaches the optimum).

pampipe runs with its on-disk NLP cache warm (a first run fills it; its time is printed as the
cold start). Peak memory is measured in separate runs, each command started by a small launcher
process (``os.wait4`` of a child forked from this large benchmark process would count its pages).
The start-up line shows what pint (units) costs pampipe at this commit, measured in the same run.

Second part: geometry calibration on a 10⁵-row isometric data set (ramps at 5 held lengths, the
braid angle stated 3° and the rest length 1 mm off) against the plain fit of the same file, both
whole processes.

Run: ``.venv/bin/python benchmarks/bench_identify.py [--scales 10 100 1000] [--repeat 3]``.
"""

from __future__ import annotations

import argparse
import compileall
import json
import math
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from pampipe.io.pam_schema import load_pam
from pampipe.io.pamfile import write_experiment
from pampipe.model.muscle import Muscle
from pampipe.model.pam import Pam
from pampipe.simulation.synthetic import Protocol, generate
from pampipe.specs.experiment import TestSpec

ROOT = Path(__file__).resolve().parent.parent
THREADS = {"OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1", "MKL_NUM_THREADS": "1"}


def run(args, env) -> tuple[float, dict]:
    """(wall seconds, the JSON it printed) of one child process."""
    started = time.perf_counter()
    child = subprocess.run(args, capture_output=True, env=env, cwd=ROOT)
    wall = time.perf_counter() - started
    if child.returncode:
        raise RuntimeError(f"{args[:4]} failed: {child.stderr.decode()[-2000:]}")
    return wall, json.loads(child.stdout)


LAUNCHER = ("import os, subprocess, sys; p = subprocess.Popen(sys.argv[1:], stdout=subprocess.DEVNULL, "
            "stderr=subprocess.DEVNULL); _, s, u = os.wait4(p.pid, 0); print(u.ru_maxrss)")


def peak(args, env) -> float:
    """Peak resident memory [MB] of ``args``, started by a small launcher process."""
    out = subprocess.run([sys.executable, "-c", LAUNCHER, *args], capture_output=True, env=env, cwd=ROOT)
    return int(out.stdout) / 1024


def paper_protocol(pam: Pam, scale: int, folder: Path) -> tuple[Path, Path, int]:
    """(experiment file, baseline job file, rows) of ≈ 2988·scale rows."""
    tests = generate(pam, Protocol(points_per_leg=30 * scale, radial_points=27 * scale), seed=scale)
    path = write_experiment(folder, "bench", Pam(pam.name, pam.geometry), tests, overwrite=True)
    g = pam.geometry
    geometry = {"initial_length": g.initial_length, "initial_diameter": g.initial_diameter,
                "braid_angle": g.braid_angle, "bladder_thickness": g.bladder_thickness}
    job = {"degree": 3, "geometry": geometry,
           "tests": [{"kind": spec.kind, "csv": str(folder / "data" / "bench" / f"{spec.name}.csv"),
                      "pipe_diameter": spec.pipe_diameter, "axial_load": spec.axial_load}
                     for spec, _ in tests]}
    job_path = folder / "job.json"
    job_path.write_text(json.dumps(job))
    return path, job_path, sum(cols["force"].size for _, cols in tests)


def isometric(pam: Pam, rows: int, folder: Path) -> Path:
    """Ramps 0 → 600 kPa → 0 at 5 held lengths (slack rows read 0 N), stated geometry 3° and 1 mm off."""
    muscle = Muscle.from_pam(pam)
    g = pam.geometry
    lengths = np.linspace(0.25, g.initial_length, 5)
    per = rows // (5 * 2)
    path = np.concatenate([np.linspace(0, 600e3, per, endpoint=False),
                           np.linspace(600e3, 0, per, endpoint=False)])
    pressure, length = np.tile(path, 5), np.repeat(lengths, path.size)
    force = np.asarray(muscle.axial_force(pressure, length), float)
    force = np.where(force > 0, force + 2.0 * np.random.default_rng(7).standard_normal(force.size), 0.0)
    stated = Pam(pam.name, type(g)(g.initial_length + 1e-3, g.initial_diameter,
                                   g.braid_angle + math.radians(3), g.bladder_thickness, g.wall))
    columns = {"time": 0.1 * np.arange(force.size), "pressure": pressure, "length": length, "force": force}
    return write_experiment(folder, "isometric", stated, [(TestSpec("ramps", "axial", Path("x"), None, 0.0),
                                                           columns)], overwrite=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scales", type=int, nargs="+", default=[10, 100, 1000],
                        help="multiples of ≈ 2988 rows (default 10 100 1000: 3·10⁴ … 3·10⁶)")
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--calibration-rows", type=int, default=100_000)
    args = parser.parse_args()
    compileall.compile_dir(ROOT / "pampipe", quiet=1)  # bytecode, as installed (PYTHONDONTWRITEBYTECODE)
    pam = load_pam(ROOT / "problems" / "pams" / "paper-radial-pam.yaml")
    with tempfile.TemporaryDirectory(prefix="bench-identify-") as tmp:
        tmp = Path(tmp)
        env = {**os.environ, **THREADS, "PAMPIPE_NLP_CACHE": str(tmp / "cache")}
        pampipe = [sys.executable, "-m", "pampipe", "identify"]
        baseline = [sys.executable, str(ROOT / "benchmarks" / "baseline_identify.py")]
        load = os.getloadavg()[0]
        print(f"load average {load:.2f}; one BLAS thread; median of {args.repeat} whole processes")
        header = (f"{'rows':>9} {'pampipe s':>10} {'least_sq s':>11} {'lead':>7} {'SSE pampipe':>16} "
                  f"{'SSE no Drucker':>16} {'SSE least_sq':>16} {'rel diff':>9} {'peak MB':>13} peer")
        print(header)
        print("-" * len(header))
        cold = None
        for scale in args.scales:
            folder = tmp / f"scale{scale}"
            experiment, job, rows = paper_protocol(pam, scale, folder)
            ours_args, theirs_args = [*pampipe, str(experiment), "--json"], [*baseline, str(job)]
            if cold is None:
                cold = run(ours_args, env)[0]  # fills the NLP cache
            ours, peers = [], {"exact": [], "lsmr": []}
            for _ in range(args.repeat):
                ours.append(run(ours_args, env))
                for solver, runs in peers.items():
                    runs.append(run([*theirs_args, solver], env))
            t_ours = statistics.median(r[0] for r in ours)
            solver = min(peers, key=lambda k: statistics.median(r[0] for r in peers[k]))  # the stronger peer
            theirs, theirs_args = peers[solver], [*theirs_args, solver]
            t_theirs = statistics.median(r[0] for r in theirs)
            sse_ours, sse_theirs = ours[0][1]["fit"]["sse_N2"], theirs[0][1]["sse_N2"]
            memory = f"{peak(ours_args, env):.0f}/{peak(theirs_args, env):.0f}"
            same = run([*ours_args, "--drucker", "none"], env)[1]["fit"]["sse_N2"]  # the peer's problem
            gap = (same - sse_theirs) / sse_theirs
            print(f"{rows:>9} {t_ours:>10.3f} {t_theirs:>11.3f} {t_theirs / t_ours:>6.2f}x "
                  f"{sse_ours:>16.10g} {same:>16.10g} {sse_theirs:>16.10g} {gap:>9.1e} {memory:>13} "
                  f"trf+{solver}", flush=True)
        print(f"first pampipe run with an empty NLP cache (build included): {cold:.3f} s")
        python = statistics.median(run([sys.executable, "-c", "print('{}')"], env)[0] for _ in range(3))
        units = statistics.median(run([sys.executable, "-c", "from pampipe.units.quantities import to_si; "
                                       "to_si('1 mm', 'length'); print('{}')"], env)[0] for _ in range(3))
        print(f"start-up: python {python:.3f} s; importing pampipe.units.quantities and parsing one quantity "
              f"{units - python:.3f} s more")

        print(f"\ncalibration on {args.calibration_rows:,} isometric rows (braid angle 3 deg and L0 1 mm "
              "off)")
        experiment = isometric(pam, args.calibration_rows, tmp / "isometric")
        run([*pampipe, str(experiment), "--json", "--calibrate", "braid_angle", "--calibrate",
             "initial_length"], env)  # fills the cache for these structures
        run([*pampipe, str(experiment), "--json"], env)
        plain = [run([*pampipe, str(experiment), "--json"], env) for _ in range(args.repeat)]
        calibrated = [run([*pampipe, str(experiment), "--json", "--calibrate", "braid_angle", "--calibrate",
                           "initial_length"], env) for _ in range(args.repeat)]
        g = pam.geometry
        for name, runs in (("plain (stated geometry)", plain), ("calibrated", calibrated)):
            doc = runs[0][1]
            geo = doc["geometry"]
            seconds = statistics.median(r[0] for r in runs)
            print(f"{name:<24} {seconds:7.3f} s   RMSE {doc['fit']['rmse_N']:9.4g} N   angle error "
                  f"{geo['braid_angle_from_axis_deg'] - math.degrees(g.braid_angle):+.4f} deg   L0 error "
                  f"{(geo['initial_length_m'] - g.initial_length) * 1e3:+.4f} mm")
        ratio = statistics.median(r[0] for r in calibrated) / statistics.median(r[0] for r in plain)
        print(f"calibration costs {ratio:.2f}x the plain fit")


if __name__ == "__main__":
    main()
