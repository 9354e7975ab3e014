"""Benchmark of start-up: `pampipe --help`, `--version` and `pampipe plan` on the demo mission as whole
processes (issue 17 item 1, issue 25, issue 39 item 1).

Each round runs every command once in a fresh interpreter, in turn (pampipe alternates with its baselines,
so a change of the machine's load falls on all of them); ``--repeat`` rounds. The table shows the median CPU
time (user + system: far less disturbed than the wall time when other processes share the cores), its
spread (fastest-slowest) and the median wall time, with the load average before and after. Baselines:

* ``python -c pass``: the interpreter alone;
* ``import numpy``: the least any numpy tool pays (the yardstick: --help ≤ 1.5× it, the demo plan ≤ 2× it);
* ``import numpy, casadi``: the two libraries plan cannot do without;
* ``import numpy, casadi, pydantic, yaml`` and one pydantic model: every third-party import of plan.

The demo plan is timed twice: as a mission read before (its validated mission is in the cache, so it
reads no YAML and imports neither pydantic nor CasADi) and with the cache off (every run reads the files
and validates them, as the first run of a new or edited mission does: by the quick check of
pampipe.io.quick_schemas, without pydantic, since the demo is well-formed). The cache is a temporary
folder, warmed by one untimed run. Then ``python -X importtime`` of the plan run (cache warm) lists the
imports that take longest.

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
DEPENDENCIES = ("import numpy, casadi, pydantic, yaml\n"
                "class A(pydantic.BaseModel):\n    x: float = 1.0\n")  # pydantic builds lazily: one model


def run_once(command: list[str], cache: str) -> tuple[float, float]:
    """(wall time, CPU time) [s] of one run of ``command`` (it must exit 0) with the cache folder ``cache``
    (or ``off``)."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    started = time.perf_counter()
    subprocess.run(command, check=True, capture_output=True, cwd=ROOT,
                   env={**os.environ, "PAMPIPE_NLP_CACHE": cache})
    wall = time.perf_counter() - started
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return wall, after.ru_utime - before.ru_utime + after.ru_stime - before.ru_stime


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
    parser.add_argument("--repeat", type=int, default=15, help="rounds (at least 5)")
    args = parser.parse_args()
    compileall.compile_dir(ROOT / "pampipe", quiet=1)  # bytecode, as installed (PYTHONDONTWRITEBYTECODE)
    python = sys.executable
    runs = {
        "python -c pass": [python, "-c", "pass"],
        "import numpy": [python, "-c", "import numpy"],
        "pampipe --help": [python, "-m", "pampipe", "--help"],
        "pampipe --version": [python, "-m", "pampipe", "--version"],
        "pampipe plan --help": [python, "-m", "pampipe", "plan", "--help"],
        "import numpy, casadi": [python, "-c", "import numpy, casadi"],
        "+ pydantic, yaml (all deps)": [python, "-c", DEPENDENCIES],
        "pampipe plan (demo)": [python, "-m", "pampipe", "plan", str(DEMO)],
        "pampipe plan (demo, cache off)": [python, "-m", "pampipe", "plan", str(DEMO)],
    }
    cache = tempfile.mkdtemp(prefix="pampipe-bench-cache-")
    run_once(runs["pampipe plan (demo)"], cache)  # warm: the demo mission is validated and kept
    times = {label: ([], []) for label in runs}
    load_before = os.getloadavg()[0]
    for _ in range(max(args.repeat, 5)):
        for label, command in runs.items():
            wall, cpu = run_once(command, "off" if "cache off" in label else cache)
            times[label][0].append(wall)
            times[label][1].append(cpu)
    load = f"load {load_before:.2f}-{os.getloadavg()[0]:.2f}"
    rounds = max(args.repeat, 5)
    print(f"{rounds} alternated rounds, {load}")
    print(f"{'process':<32}{'CPU median [s]':>15}{'CPU spread [s]':>17}{'wall median [s]':>16}")
    cpu = {label: statistics.median(c) for label, (_, c) in times.items()}
    for label, (walls, cpus) in times.items():
        print(f"{label:<32}{cpu[label]:>15.3f}{f'{min(cpus):.3f}-{max(cpus):.3f}':>17}"
              f"{statistics.median(walls):>16.3f}")

    def ratio(label: str, goal: float, note: str) -> None:
        each = sorted(c / n for c, n in zip(times[label][1], times["import numpy"][1], strict=True))
        value = cpu[label] / cpu["import numpy"]
        print(f"{label} / import numpy: {value:.2f}x CPU (round by round {each[0]:.2f}-{each[-1]:.2f}x; goal "
              f"{goal}x: {'met' if value <= goal else 'NOT met'}; {load}){note}")

    print()
    ratio("pampipe --help", 1.5, "")
    ratio("pampipe --version", 1.5, "")
    ratio("pampipe plan (demo)", 2.0, " (a mission read before)")
    ratio("pampipe plan (demo, cache off)", 2.0, " (a new or edited mission: read and validated)")
    print(f"plan with the cache off beyond all its dependencies: "
          f"{cpu['pampipe plan (demo, cache off)'] - cpu['+ pydantic, yaml (all deps)']:.3f} s CPU "
          "(pampipe's own imports and the run)")
    print("\nslowest top-level imports of the plan run (cumulative, python -X importtime):")
    for seconds, name in slowest_imports(cache):
        print(f"  {seconds:8.3f} s  {name}")
    shutil.rmtree(cache, ignore_errors=True)


if __name__ == "__main__":
    main()
