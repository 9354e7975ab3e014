"""Benchmark of start-up: `pampipe plan` on the demo mission as a whole process (issue 17, item 1).

Every command is run ``--repeat`` times in a fresh interpreter; the table shows the fastest and the
median wall time, and the median CPU time (user + system: close to the wall time of a quiet machine, and far
less disturbed when other processes share the cores), measured in the same run as the baselines:

* ``python -c pass``: the interpreter alone;
* ``import numpy``: the least any numpy tool pays (the yardstick of issue 25: plan ≤ 2× it);
* ``import numpy, casadi``: the two libraries plan cannot do without;
* ``import numpy, casadi, pydantic, yaml`` and one pydantic model: every third-party import of plan.

The demo plan is timed twice: as a mission read before (its validated mission is in the cache, so it
imports neither pydantic nor CasADi: the row the issue's goal is about) and with the cache off (every run
validates the files with pydantic, as the first run of a new or edited mission does). The cache is a
temporary folder, warmed by one untimed run. Then ``python -X importtime`` of the plan run (cache warm)
lists the imports that take longest (cumulative).

Goal: the demo plan starts and finishes in under 0.35 s.

    .venv/bin/python benchmarks/bench_startup.py [--repeat 15]
"""

from __future__ import annotations

import argparse
import compileall
import os
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
DEMO = ROOT / "problems" / "missions" / "vertical-climb-3in.yaml"
GOAL = 0.35  # [s]
DEPENDENCIES = ("import numpy, casadi, pydantic, yaml\n"
                "class A(pydantic.BaseModel):\n    x: float = 1.0\n")  # pydantic builds lazily: one model


def run_times(command: list[str], repeat: int, cache: str) -> tuple[list[float], list[float]]:
    """(wall times, CPU times) [s] of ``repeat`` runs of ``command`` (each must exit 0) with the cache
    folder ``cache`` (or ``off``)."""
    walls, cpus = [], []
    env = {**os.environ, "PAMPIPE_NLP_CACHE": cache}
    for _ in range(repeat):
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        started = time.perf_counter()
        subprocess.run(command, check=True, capture_output=True, cwd=ROOT, env=env)
        walls.append(time.perf_counter() - started)
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        cpus.append(after.ru_utime - before.ru_utime + after.ru_stime - before.ru_stime)
    return walls, cpus


def slowest_imports(cache: str, count: int = 10) -> list[tuple[float, str]]:
    """(cumulative import time [s], module) of the plan run's top-level imports, slowest first."""
    out = subprocess.run([sys.executable, "-X", "importtime", "-m", "pampipe", "plan", str(DEMO)],
                         capture_output=True, text=True, cwd=ROOT,
                         env={**os.environ, "PAMPIPE_NLP_CACHE": cache})
    rows = []
    for line in out.stderr.splitlines():
        if not line.startswith("import time:") or "|" not in line:
            continue
        _, cumulative, name = line.split("|")
        if cumulative.strip().isdigit() and len(name) - len(name.lstrip()) <= 3:  # top level only
            rows.append((int(cumulative) / 1e6, name.strip()))
    return sorted(rows, reverse=True)[:count]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=15)
    args = parser.parse_args()
    compileall.compile_dir(ROOT / "pampipe", quiet=1)  # bytecode, as installed (PYTHONDONTWRITEBYTECODE)
    python = sys.executable
    runs = {
        "python -c pass": [python, "-c", "pass"],
        "import numpy": [python, "-c", "import numpy"],
        "import numpy, casadi": [python, "-c", "import numpy, casadi"],
        "+ pydantic, yaml (all deps)": [python, "-c", DEPENDENCIES],
        "import pampipe plan command": [python, "-c", "import pampipe.cli as c; c.build_parser(('plan',))"],
        "pampipe plan (demo)": [python, "-m", "pampipe", "plan", str(DEMO)],
        "pampipe plan (demo, cache off)": [python, "-m", "pampipe", "plan", str(DEMO)],
    }
    cache = tempfile.mkdtemp(prefix="pampipe-bench-cache-")
    run_times(runs["pampipe plan (demo)"], 1, cache)  # warm: the demo mission is validated and kept
    print(f"{'process':<30}{'fastest [s]':>12}{'median [s]':>12}{'CPU [s]':>10}{'x numpy+casadi':>16}")
    base = None
    results = {}
    for label, command in runs.items():
        walls, cpus = run_times(command, args.repeat, "off" if "cache off" in label else cache)
        fastest, median, cpu = min(walls), statistics.median(walls), statistics.median(cpus)
        base = median if label == "import numpy, casadi" else base
        results[label] = (median, cpu)
        ratio = f"{median / base:>16.2f}" if base else f"{'':>16}"
        print(f"{label:<30}{fastest:>12.3f}{median:>12.3f}{cpu:>10.3f}{ratio}")
    (plan, plan_cpu), (deps, deps_cpu) = (results["pampipe plan (demo)"],
                                          results["+ pydantic, yaml (all deps)"])
    cold, cold_cpu = results["pampipe plan (demo, cache off)"]
    print(f"\nplan with the cache off beyond all its dependencies: {cold - deps:.3f} s wall, "
          f"{cold_cpu - deps_cpu:.3f} s CPU (pampipe's own imports and the run); "
          f"goal {GOAL} s for the plan read before: {'met' if plan < GOAL else 'NOT met'} "
          f"(median wall {plan:.3f} s, CPU {plan_cpu:.3f} s; load average {os.getloadavg()[0]:.1f})")
    numpy_wall, numpy_cpu = results["import numpy"]
    print(f"pampipe plan (demo) / import numpy: {plan / numpy_wall:.2f}x median wall, "
          f"{plan_cpu / numpy_cpu:.2f}x CPU (issue 25 goal: 2x)")
    print(f"pampipe plan (demo, cache off) / import numpy: {cold / numpy_wall:.2f}x median wall, "
          f"{cold_cpu / numpy_cpu:.2f}x CPU (a new or edited mission: validated with pydantic)")
    print("\nslowest top-level imports of the plan run (cumulative, python -X importtime):")
    for seconds, name in slowest_imports(cache):
        print(f"  {seconds:8.3f} s  {name}")
    shutil.rmtree(cache, ignore_errors=True)


if __name__ == "__main__":
    main()
