"""`pampipe export`: the exported C against the Python a skilled user would write, on the host (issue 15).

Least pressures of the demo robot's three segments at N random sections (bore, incline, friction,
payload), in the same run:

1. the exported ``pampipe_required_pressure`` (double, gcc -O2), called once per section in a C loop
   timed inside the program (inputs read before the clock starts);
2. the strongest Python baseline: pampipe's own vectorised numpy path, :func:`pampipe.model.slip.anchor_load`
   and :meth:`Muscle.least_holding_pressure` on whole arrays (what `plan` does), checks included;
3. the CasADi SX function the C is generated from, mapped over the sections (CasADi's virtual machine).

Also: the time to generate the export (law and C text; the gait table simulates each section and is
timed apart). On the chip itself see tests/test_export_avr.py (cycles on the ATmega2560).
Usage: python benchmarks/bench_export.py [--sections N]
"""

from __future__ import annotations

import argparse
import math
import shutil
import subprocess
import tempfile
import time
from pathlib import Path

import numpy as np

from pampipe.export import Provenance, generate
from pampipe.export.law import mission_law
from pampipe.export.sources import source
from pampipe.io.config import load_mission
from pampipe.model import slip
from pampipe.planning.problem import mission_muscles

MISSION = Path(__file__).resolve().parent.parent / "problems" / "missions" / "vertical-climb-3in.yaml"

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
        load = slip.anchor_load(total, seg.mass, incline, friction, mission.tether_drag)
        out.append(muscle.least_holding_pressure(d, load, kappa=mission.kappa, friction=friction,
                                                 safety_factor=mission.safety_factor))
    return np.stack(out, axis=1)


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
    args = parser.parse_args()
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
