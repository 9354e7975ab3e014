"""Benchmark: `pampipe plan` of a 10⁵-section mission, whole process: text report against --json (issue 25).

The mission is the demo robot on a synthetic route (``bench_network.write_mission``: varied lengths,
five bores, a fifth with a tolerance, inclines). Each command runs as a fresh process with one BLAS
thread; its CPU time (user + system, from ``getrusage`` of the children) and wall time are taken, the
median and the spread (fastest-slowest) of ``--repeat`` (at least 5) alternating runs, with the load
average before and after. The peer, in the same run: reading the same file with PyYAML's
C loader alone (``yaml.load(..., CSafeLoader)``), the least any YAML-reading tool pays before it plans.
Printed: the load average, then one line per command with CPU [s], wall [s], CPU ÷ peer and the peak
resident memory (a separate run, started by a small launcher process), also per section.

Goals (issues 25, 39): the text report of 10⁵ sections in ≤ 2.5 s CPU; --json ≤ 1.5× the text report.

    .venv/bin/python benchmarks/bench_big_mission.py [--sections 100000] [--repeat 5] [--baseline TREE]
        [--distinct]
"""

from __future__ import annotations

import argparse
import compileall
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_network import ROOT, write_mission

THREADS = {"OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1", "MKL_NUM_THREADS": "1"}
LAUNCHER = ("import os, subprocess, sys; p = subprocess.Popen(sys.argv[1:], stdout=subprocess.DEVNULL, "
            "stderr=subprocess.DEVNULL); _, s, u = os.wait4(p.pid, 0); print(u.ru_maxrss)")
PEER = "import sys, yaml; yaml.load(open(sys.argv[1], encoding='utf-8'), Loader=yaml.CSafeLoader)"


def measured(args: list[str], env: dict, cwd: Path = ROOT, *, out: list | None = None) -> tuple[float, float]:
    """(CPU [s], wall [s]) of one child process started in ``cwd``; its standard output is appended to ``out``
    if given."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    started = time.perf_counter()
    child = subprocess.run(args, capture_output=True, env=env, cwd=cwd)
    wall = time.perf_counter() - started
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if child.returncode:
        raise RuntimeError(f"{args[:5]} failed: {child.stderr.decode()[-2000:]}")
    if out is not None:
        out.append(child.stdout)
    return after.ru_utime - before.ru_utime + after.ru_stime - before.ru_stime, wall


def peak_kb(args: list[str], env: dict, cwd: Path = ROOT) -> int:
    """Peak resident memory [kB] of ``args``, started in ``cwd`` by a small launcher process."""
    out = subprocess.run([sys.executable, "-c", LAUNCHER, *args], capture_output=True, env=env, cwd=cwd)
    return int(out.stdout)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sections", type=int, default=100_000)
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--distinct", action="store_true", help="every section its own incline: no two "
                        "sections alike (by default the route repeats 1,260 distinct sections)")
    parser.add_argument("--baseline", type=Path, help="another pampipe source tree (a checkout of main): its "
                        "text report and --json run from there in the same rounds, as 'baseline: ...'")
    args = parser.parse_args()
    compileall.compile_dir(ROOT / "pampipe", quiet=1)  # bytecode, as installed (PYTHONDONTWRITEBYTECODE)
    env = {**os.environ, **THREADS}
    with tempfile.TemporaryDirectory(prefix="bench-big-mission-") as tmp:
        mission = str(write_mission(Path(tmp), args.sections, distinct=args.distinct))
        out = str(Path(tmp) / "plan.json")
        commands = {
            "peer: yaml.load (CSafeLoader)": [sys.executable, "-c", PEER, mission],
            "pampipe plan (text report)": [sys.executable, "-m", "pampipe", "plan", mission],
            "pampipe plan --json": [sys.executable, "-m", "pampipe", "plan", mission, "--json"],
            "pampipe plan -o plan.json": [sys.executable, "-m", "pampipe", "plan", mission, "-o", out],
        }
        places = dict.fromkeys(commands, (env, ROOT))  # python -m imports the pampipe of the folder it is in
        if args.baseline is not None:
            tree = args.baseline.resolve()
            compileall.compile_dir(tree / "pampipe", quiet=1)
            for name in ("pampipe plan (text report)", "pampipe plan --json"):
                commands[f"baseline: {name}"] = commands[name]
                places[f"baseline: {name}"] = ({**env, "PYTHONPATH": str(tree)}, tree)
        runs: dict[str, list[tuple[float, float]]] = {name: [] for name in commands}
        load_before = os.getloadavg()[0]
        repeat = max(args.repeat, 5)
        for _ in range(repeat):
            for name, command in commands.items():
                runs[name].append(measured(command, *places[name]))
        load = f"load {load_before:.2f}-{os.getloadavg()[0]:.2f}"
        print(f"{args.sections:,} sections{' (all distinct)' if args.distinct else ''}; {load}; one BLAS "
              f"thread; median and spread of {repeat} alternated whole processes")
        peer = statistics.median(cpu for cpu, _ in runs[next(iter(commands))])
        bare = peak_kb([sys.executable, "-c", "pass"], env)
        print(f"{'command':<38} {'CPU s':>7} {'CPU spread s':>13} {'wall s':>7} {'CPU / peer':>10} "
              f"{'peak MB':>8} {'kB/section':>10}")
        cpu = {name: statistics.median(c for c, _ in values) for name, values in runs.items()}
        for name, values in runs.items():
            cpus = [c for c, _ in values]
            wall = statistics.median(w for _, w in values)
            peak = peak_kb(commands[name], *places[name])
            print(f"{name:<38} {cpu[name]:>7.2f} {f'{min(cpus):.2f}-{max(cpus):.2f}':>13} {wall:>7.2f} "
                  f"{cpu[name] / peer:>9.2f}x {peak / 1024:>8.0f} {(peak - bare) / args.sections:>10.2f}")
        print("kB/section: the peak resident memory above a bare interpreter's, per section")
        text, json_cpu = cpu["pampipe plan (text report)"], cpu["pampipe plan --json"]
        ratios = sorted(j / t for (j, _), (t, _) in zip(runs["pampipe plan --json"],
                                                        runs["pampipe plan (text report)"], strict=True))
        verdict = ("met" if text <= 2.5 else "NOT met") if args.sections == 100_000 else "not judged"
        print(f"text report: {text:.2f} s CPU (goal 2.5 s at 10⁵ sections: {verdict}; {load})")
        if args.baseline is not None:
            for name in ("pampipe plan (text report)", "pampipe plan --json"):
                pairs = zip(runs[f"baseline: {name}"], runs[name], strict=True)
                each = sorted(b / c for (b, _), (c, _) in pairs)
                print(f"baseline / this tree, {name}: {cpu[f'baseline: {name}'] / cpu[name]:.2f}x CPU "
                      f"(round by round {each[0]:.2f}-{each[-1]:.2f}x; {load})")
        print(f"--json / text report: {json_cpu / text:.2f}x CPU (round by round "
              f"{ratios[0]:.2f}-{ratios[-1]:.2f}x; goal 1.5x: "
              f"{'met' if json_cpu / text <= 1.5 else 'NOT met'}; {load})")


if __name__ == "__main__":
    main()
