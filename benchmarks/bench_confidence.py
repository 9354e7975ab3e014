"""Benchmark: `pampipe plan --confidence 0.95` at network scale, whole processes, serial and 2 workers,
against the plain numpy Monte Carlo of the same closed form (``baseline_confidence.py``).

The mission (``bench_network.write_mission``) is the riser mission's robot (three segments carrying the fit
covariance of ``problems/pams/paper-radial-pam-uncertain.yaml``) on a synthetic route: varied lengths, five
bores (a fifth with a tolerance), 90 inclines and four frictions, each known to ±0.03 (sd). Its sections
are of 180 kinds (bore, incline, friction); the sampling evaluates each kind once
(docs/physics.md §15). A second route (``--distinct``) gives every section its own incline: every section is
its own kind, the worst case.

Each command runs as a fresh process with one BLAS thread; printed per command: the CPU time (user + system of
the process and its workers, ``getrusage`` of the children), the wall time (median and spread, fastest-
slowest, of ``--repeat`` alternated rounds) and the peak resident memory (``wait4`` of a small launcher's
child: the largest single process, the workers included), then pampipe's serial CPU ÷ the baseline's (the
median of the rounds' ratios and their spread), and the load average before and after. The mission is read
once before the rounds (``pampipe.load_mission``): every command, the baseline included, reads it from
pampipe's cache of a file read before. The baseline plans the worst bores as pampipe does, then samples each
section's C-quantile (``baseline_confidence.py``: it times only the quantiles, no holding share, band, other
levels or per-source breakdown, which pampipe reports too).

Goals (issues 25, 39): ``plan --confidence 0.95`` with 10⁴ draws on 10⁵ sections, every section its own kind,
in ≤ 60 s CPU serial and at most the baseline's CPU, peak ≤ 1 GB; 2 workers faster (wall) than 1 on a free
machine.

    .venv/bin/python benchmarks/bench_confidence.py [--sections 1000,100000] [--samples 10000]
        [--distinct 2000] [--repeat 1]
"""

from __future__ import annotations

import argparse
import compileall
import os
import statistics
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_big_mission import THREADS, measured, peak_kb
from bench_network import MISSIONS, ROOT, write_mission

ROBOT = MISSIONS / "riser-uncertain-friction.yaml"
BASELINE = Path(__file__).resolve().parent / "baseline_confidence.py"
WARM = "import sys, pampipe; pampipe.load_mission(sys.argv[1])"


def spread(values: list[float]) -> str:
    """``median (fastest-slowest)``, or the one value."""
    if len(values) == 1:
        return f"{values[0]:.2f}"
    return f"{statistics.median(values):.2f} ({min(values):.2f}-{max(values):.2f})"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sections", default="1000,100000", help="route sizes, comma-separated ('' none)")
    parser.add_argument("--samples", type=int, default=10_000, help="draws (--samples of plan)")
    parser.add_argument("--distinct", type=int, default=2000,
                        help="sections of the route whose every section is its own kind (0: none)")
    parser.add_argument("--repeat", type=int, default=1, help="alternated rounds of every command")
    parser.add_argument("--no-workers", action="store_true", help="skip the --workers 2 runs")
    args = parser.parse_args()
    compileall.compile_dir(ROOT / "pampipe", quiet=1)  # bytecode, as installed (PYTHONDONTWRITEBYTECODE)
    env = {**os.environ, **THREADS}
    routes = [(int(s), False) for s in args.sections.split(",") if s] + ([(args.distinct, True)]
                                                                       if args.distinct else [])
    print(f"plan --confidence 0.95 --samples {args.samples}; load average {os.getloadavg()[0]:.2f}; "
          f"one BLAS thread; whole processes; median (spread) of {args.repeat} alternated round(s)")
    print(f"{'sections':>9} {'kinds':>7} {'run':<24} {'CPU s':>22} {'wall s':>22} {'peak MB':>8}")
    with tempfile.TemporaryDirectory(prefix="bench-confidence-") as tmp:
        for sections, distinct in routes:
            path = write_mission(Path(tmp), sections, robot=ROBOT, friction_sd=0.03, distinct=distinct)
            mission = str(path)
            measured([sys.executable, "-c", WARM, mission], env)  # read once: every command finds it cached
            kinds = sections if distinct else min(sections, 180)
            if distinct:
                print("every section its own kind:")
            plan = [sys.executable, "-m", "pampipe", "plan", mission, "--confidence", "0.95",
                    "--samples", str(args.samples), "--quiet"]
            commands = {"serial": plan}
            if not args.no_workers:
                commands["--workers 2"] = [*plan, "--workers", "2"]
            commands["baseline (plain numpy)"] = [sys.executable, str(BASELINE), mission, "--samples",
                                                  str(args.samples)]
            runs: dict[str, list[tuple[float, float]]] = {name: [] for name in commands}
            for _ in range(args.repeat):
                for name, command in commands.items():
                    runs[name].append(measured(command, env))
            for name, command in commands.items():
                peak = peak_kb(command, env) / 1024
                print(f"{sections:>9} {kinds:>7} {name:<24} {spread([c for c, _ in runs[name]]):>22} "
                      f"{spread([w for _, w in runs[name]]):>22} {peak:>8.0f}")
            ratios = [s / b for (s, _), (b, _) in zip(runs["serial"], runs["baseline (plain numpy)"],
                                                      strict=True)]
            print(f"{sections:>9} {kinds:>7} serial CPU / baseline CPU: {spread(ratios)}")
    print(f"load average after: {os.getloadavg()[0]:.2f}")
    print("kinds: distinct (bore, incline, friction) sections, each sampled once; CPU includes the workers; "
          "peak: the largest single process")


if __name__ == "__main__":
    main()
