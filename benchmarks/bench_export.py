"""`pampipe export`: the exported C against the Python a skilled user would write, on the host (issue 15).

Least pressures of the demo robot's three segments at N random sections (bore, incline, friction,
payload), in the same run:

1. the exported ``pampipe_required_pressure`` (double, gcc -O2), called once per section in a C loop
   timed inside the program (inputs read before the clock starts);
2. the strongest Python baseline: pampipe's own vectorised numpy path,
:func:`pampipe.model.no_slip.anchor_load`
   and :meth:`Muscle.least_holding_pressure` on whole arrays (what `plan` does), checks included;
3. the CasADi SX function the C is generated from, mapped over the sections (CasADi's virtual machine).

Also: the time to generate the export (law and C text; the gait table is timed apart). On the chip
itself see tests/export/test_avr.py (cycles on the ATmega2560).

Scale (issue 27): `pampipe plan` and `pampipe export` of the demo robot on ``--distinct`` sections whose
bore, incline and friction all differ (so every section has its own gait and its own chamber fits), each
command a fresh process with one BLAS thread, CPU time (user + system of the child), median of
``--repeat`` alternating runs after one warm-up run of each (the on-disk caches warm). Goal: export CPU
within 3 s of plan CPU at 2000 sections.
Usage: python benchmarks/bench_export.py [--sections N] [--distinct N] [--repeat R]
"""

from __future__ import annotations

import argparse
import math
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from bench_big_mission import THREADS, measured

from pampipe.export import Provenance, generate
from pampipe.export.law import mission_law
from pampipe.export.sources import source
from pampipe.io.mission_schema import load_mission
from pampipe.model import no_slip
from pampipe.planning.problem import mission_muscles

ROOT = Path(__file__).resolve().parent.parent
MISSION = ROOT / "problems" / "missions" / "vertical-climb-3in.yaml"

HARNESS = r"""
#define _POSIX_C_SOURCE 199309L
#include <stdio.h>
#include <stdlib.h>
#include <time.h>
#include "pampipe_plan.h"

int main(int argc, char **argv)
{
    long n = atol(argv[1]), i;
    double *in = malloc(4 * n * sizeof(double)), sum = 0, p[PAMPIPE_SEGMENTS];
    struct timespec t0, t1;
    int codes = 0;
    if (fread(in, sizeof(double), 4 * n, stdin) != (size_t)(4 * n)) { return 1; }
    clock_gettime(CLOCK_MONOTONIC, &t0);
    for (i = 0; i < n; ++i) {
        codes += pampipe_required_pressure(in[4 * i], in[4 * i + 1], in[4 * i + 2], in[4 * i + 3], p);
        sum += p[0] + p[1] + p[2];
    }
    clock_gettime(CLOCK_MONOTONIC, &t1);
    printf("%.9f %d %.17g\n", (t1.tv_sec - t0.tv_sec) + 1e-9 * (t1.tv_nsec - t0.tv_nsec), codes, sum);
    return 0;
}
"""


def sections(mission, n: int, rng) -> np.ndarray:
    """N feasible-looking sections inside the demo's envelope: (D, φ, μ, payload) rows."""
    g = mission.segments[0].pam.geometry
    return np.column_stack([rng.uniform(g.initial_diameter * 1.01, g.largest_diameter * 0.99, n),
                            rng.uniform(-math.pi / 2, math.pi / 2, n), rng.uniform(0.1, 1.0, n),
                            rng.uniform(0.0, 10.0, n)])


def numpy_baseline(mission, muscles, rows: np.ndarray) -> np.ndarray:
    d, incline, friction, payload = rows.T
    total = sum(s.mass for s in mission.segments) + payload
    out = []
    for seg, muscle in zip(mission.segments, muscles, strict=True):
        load = no_slip.anchor_load(total, seg.mass, incline, friction, mission.tether_drag)
        out.append(muscle.least_holding_pressure(d, load, kappa=mission.kappa, friction=friction,
                                                 safety_factor=mission.safety_factor))
    return np.stack(out, axis=1)


def distinct_mission(folder: Path, count: int) -> Path:
    """The demo robot on ``count`` sections, each with its own bore (76-90 mm), incline (±89°) and friction
    (0.2-0.8), spread by irrational steps so that no two sections share a value."""
    head = MISSION.read_text().split("route:")[0].replace("../pams", str(ROOT / "problems" / "pams"))
    lines = [f"  - {{name: s{i}, length: {1 + i % 7} m, "
             f"inner_diameter: {76.0 + 14.0 * (i * 0.618034 % 1.0):.4f} mm, "
             f"incline: {-89.0 + 178.0 * (i * 0.414214 % 1.0):.4f} deg, "
             f"friction: {0.2 + 0.6 * (i * 0.732051 % 1.0):.4f}}}\n" for i in range(count)]
    path = folder / f"distinct-{count}.yaml"
    path.write_text(head + "route:\n" + "".join(lines), encoding="utf-8")
    return path


def scale(count: int, repeat: int) -> None:
    """Plan against export CPU on ``count`` all-distinct sections (see the module docstring)."""
    with tempfile.TemporaryDirectory() as tmp:
        mission = distinct_mission(Path(tmp), count)
        commands = {"plan": ["plan", str(mission)],
                    "export": ["export", str(mission), "-o", str(Path(tmp) / "firmware"), "--force"]}
        times: dict[str, list[float]] = {name: [] for name in commands}
        for run in range(repeat + 1):
            for name, args in commands.items():
                cpu = measured([sys.executable, "-m", "pampipe", *args], {**os.environ, **THREADS})[0]
                if run:  # the first run of each warms the caches
                    times[name].append(cpu)
    plan, export = (statistics.median(times[name]) for name in commands)
    print(f"{count} all-distinct sections (median of {repeat}, CPU of the whole process):")
    print(f"  plan CPU {plan:.2f} s; export CPU {export:.2f} s; export - plan CPU {export - plan:.2f} s")


def best(fn, repeat: int = 5) -> float:
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t)
    return min(times)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sections", type=int, default=200_000)
    parser.add_argument("--distinct", type=int, default=2000, help="sections of the scale case (2000)")
    parser.add_argument("--repeat", type=int, default=3, help="runs of the scale case; the median (3)")
    args = parser.parse_args()
    scale(args.distinct, args.repeat)
    n = args.sections
    compiler = shutil.which("gcc") or shutil.which("cc")
    mission = load_mission(MISSION)
    muscles = mission_muscles(mission)
    rows = sections(mission, n, np.random.default_rng(0))
    provenance = Provenance(str(MISSION), ())

    t_all = time.perf_counter()
    export = generate(mission, provenance=provenance)
    t_all = time.perf_counter() - t_all
    t_law = best(lambda: source(mission_law(mission), export.sections, provenance), 3)

    t_numpy = best(lambda: numpy_baseline(mission, muscles, rows))
    reference = numpy_baseline(mission, muscles, rows)
    mapped = export.law.function.map(n)
    t_casadi = best(lambda: mapped(*rows.T), 3)
    print(f"{n} sections, 3 segments each")
    print(f"  export: law and C text {t_law * 1e3:.1f} ms; whole export (with the gait table of "
          f"{len(mission.route)} sections) {t_all:.2f} s")
    print(f"  numpy, pampipe's vectorised path (baseline): {t_numpy / n * 1e9:8.1f} ns per section")
    print(f"  CasADi SX function, map(N):                  {t_casadi / n * 1e9:8.1f} ns per section "
          f"({t_numpy / t_casadi:.2f}x the baseline's speed)")
    if compiler is None:
        print("  exported C: no host C compiler found")
        return
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        for name, text in export.files.items():
            (folder / name).write_text(text)
        (folder / "harness.c").write_text(HARNESS)
        exe = folder / "harness"
        sources = [str(folder / "harness.c"), str(folder / "pampipe_plan.c")]
        subprocess.run([compiler, "-O2", "-std=c99", "-I", str(folder), "-o", str(exe), *sources, "-lm"],
                       check=True)
        data = rows.astype("<f8").tobytes()
        runs = [subprocess.run([str(exe), str(n)], input=data, capture_output=True, check=True).stdout.split()
                for _ in range(5)]
    t_c = min(float(r[0]) for r in runs)
    total = float(runs[0][2])
    print(f"  exported C (double, gcc -O2), one call each:  {t_c / n * 1e9:8.1f} ns per section "
          f"({t_numpy / t_c:.1f}x the baseline's speed)")
    agree = abs(total - reference.sum()) / reference.sum()
    print(f"  sum of all pressures, C vs numpy: relative difference {agree:.1e}")


if __name__ == "__main__":
    main()
