"""Benchmark: `diagnose` on the bundled example (time per step) and on 10⁴…3·10⁵ rows (time, memory).

Goals (issues 13 and 17): every candidate of the bundled example in under 60 s on a 2-core machine;
10⁵ rows in under 15 s with flat memory (the refits see cells, whose number does not grow with
the rows).

Baselines measured in the same run:

* ``identify`` in shared-moduli mode on the same data: the cost of the baseline fit alone (the
  ratio says how many baseline fits the whole diagnosis costs);
* ``diagnose(..., reduce=False)``: cells that keep every distinct (P, L), i.e. no binning; the
  strongest form of the row-level refits of round 1, which grew with the data.

Each large case runs in a fresh process (BLAS threads fixed to 1) so that its peak memory (ru_maxrss)
is its own. Run: .venv/bin/python benchmarks/bench_diagnose.py [--quick]
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
EXAMPLE = ROOT / "problems" / "experiments" / "hidden-contact-stiffening.yaml"
#: (cycles, points per leg, radial readings per level) → rows: 10 levels × 2 legs × cycles × points
#: axial, 6 radial tests × 11 levels × readings radial.
SIZES = {"1e4": (2, 150, 60), "1e5": (4, 500, 900), "3e5": (6, 1250, 2700)}

CHILD = """
import json, resource, sys, time
from pampipe.diagnosis.hidden import hidden_experiment, hidden_protocol
from pampipe.io.pam_schema import load_pam
cycles, points, radial, mode = int(sys.argv[1]), int(sys.argv[2]), int(sys.argv[3]), sys.argv[4]
pam = load_pam(sys.argv[5])
data = hidden_experiment(pam, "contact_stiffening", seed=3,
                         protocol=hidden_protocol(cycles=cycles, points_per_leg=points, radial_points=radial))
before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
started = time.perf_counter()
if mode == "identify":
    from pampipe.identification import identify, parse_fit_options
    identify(data, parse_fit_options({}).with_overrides(mode="shared"))
    doc = {}
else:
    from pampipe.diagnosis.workflow import diagnose
    result = diagnose(data, reduce=(mode == "binned"))
    doc = {"verdict": result.verdict.verdict, "effects": list(result.selected_effects),
           "cells": result.cells.size, "steps": [[s.action, s.effect, s.wall_time] for s in result.steps]}
doc.update(rows=data.points, time=time.perf_counter() - started,
           data_mb=before / 1024, peak_mb=resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024)
print(json.dumps(doc))
"""


def child(size: str, mode: str) -> dict:
    env = {**os.environ, "OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1", "MKL_NUM_THREADS": "1"}
    cycles, points, radial = SIZES[size]
    out = subprocess.run([sys.executable, "-c", CHILD, str(cycles), str(points), str(radial), mode,
                          str(ROOT / "problems" / "pams" / "paper-radial-pam.yaml")],
                         capture_output=True, text=True, env=env, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def example() -> None:
    from pampipe.diagnosis.workflow import diagnose
    from pampipe.identification import identify, parse_fit_options
    from pampipe.io.csvfile import load_experiment_data
    from pampipe.io.experiment_schema import load_experiment
    from pampipe.views.tables import table

    data = load_experiment_data(load_experiment(EXAMPLE))
    started = time.perf_counter()
    identify(data, parse_fit_options(data.fit).with_overrides(mode="shared"))
    baseline = time.perf_counter() - started
    started = time.perf_counter()
    result = diagnose(data)
    total = time.perf_counter() - started
    print(f"{EXAMPLE.name}: {data.points} rows, {result.cells.size} cells; verdict {result.verdict.verdict}, "
          f"named {' + '.join(result.selected_effects) or 'none'}")
    rows = [(s.number, s.action, s.effect or "-", len(s.trials), s.wall_time) for s in result.steps]
    print(table(["step", "action", "effect", "refits tried", "time [s]"], rows))
    print(table(["what", "time [s]"], [("identify (shared), the baseline alone", baseline),
                                       ("diagnose, every step", total),
                                       ("ratio diagnose / identify", total / baseline)]))
    print(f"goal: < 60 s on 2 cores -> {'met' if total < 60 else 'NOT met'} ({total:.1f} s)")


def scaling(sizes: list[str]) -> None:
    from pampipe.views.tables import table

    rows = []
    for size in sizes:
        ident = child(size, "identify")
        binned = child(size, "binned")
        exact = child(size, "exact") if size != "3e5" else None
        rows.append((binned["rows"], binned["cells"], binned["time"], binned["peak_mb"],
                     binned["peak_mb"] - binned["data_mb"],
                     "-" if exact is None else exact["cells"], "-" if exact is None else exact["time"],
                     "-" if exact is None else f"{exact['time'] / binned['time']:.1f}",
                     ident["time"], binned["time"] / ident["time"], binned["verdict"]))
        steps = ", ".join(f"{a} {e or ''} {t:.1f} s" for a, e, t in binned["steps"])
        print(f"{size}: steps {steps}", flush=True)
    print(table(["rows", "cells", "diagnose [s]", "peak RSS [MB]", "added by diagnose [MB]", "unbinned cells",
                 "unbinned [s]",
                 "unbinned / binned", "identify [s]", "diagnose / identify", "verdict"], rows))
    at = next((r for r in rows if 0.9e5 <= r[0] <= 1.1e5), None)
    if at is not None:
        print(f"goal: 10^5 rows < 15 s -> {'met' if at[2] < 15 else 'NOT met'} ({at[2]:.1f} s)")


if __name__ == "__main__":
    example()
    scaling(["1e4", "1e5"] if "--quick" in sys.argv else ["1e4", "1e5", "3e5"])
