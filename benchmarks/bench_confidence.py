"""Benchmark: `pampipe plan --confidence 0.95` at network scale, whole processes, serial and 2 workers.

The mission (``bench_network.write_mission``) is the riser mission's robot (three segments carrying the fit
covariance of ``problems/pams/paper-radial-pam-uncertain.yaml``) on a synthetic route: varied lengths, five
bores (a fifth with a tolerance), 90 inclines and four frictions, each known to ±0.03 (sd). Its sections
are of 180 kinds (bore, incline, friction); the sampling evaluates each kind once
(docs/physics.md §15). A second route gives every section its own incline: every section is its own kind,
the worst case.

Each command runs as a fresh process with one BLAS thread; printed per command: the CPU time (user +
system of the process and its workers, ``getrusage`` of the children), the wall time and the peak resident
memory (``wait4`` of a small launcher's child: the largest single process, the workers included).

Goal (issue 25): ``plan --confidence 0.95`` with 10⁴ draws on 10⁵ sections in ≤ 60 s, peak ≤ 1 GB.

    .venv/bin/python benchmarks/bench_confidence.py [--sections 1000,100000] [--samples 10000]
        [--distinct 2000]
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_big_mission import THREADS, measured, peak_kb
from bench_network import MISSIONS, write_mission

ROBOT = MISSIONS / "riser-uncertain-friction.yaml"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sections", default="1000,100000", help="route sizes, comma-separated")
    parser.add_argument("--samples", type=int, default=10_000, help="draws (--samples of plan)")
    parser.add_argument("--distinct", type=int, default=2000,
                        help="sections of the route whose every section is its own kind (0: none)")
    args = parser.parse_args()
    env = {**os.environ, **THREADS}
    routes = [(int(s), False) for s in args.sections.split(",")] + ([(args.distinct, True)] if args.distinct
                                                                    else [])
    print(f"plan --confidence 0.95 --samples {args.samples}; load average {os.getloadavg()[0]:.2f}; "
          "one BLAS thread; whole processes")
    print(f"{'sections':>9} {'kinds':>7} {'run':<12} {'CPU s':>7} {'wall s':>7} {'peak MB':>8}")
    with tempfile.TemporaryDirectory(prefix="bench-confidence-") as tmp:
        for sections, distinct in routes:
            path = write_mission(Path(tmp), sections, robot=ROBOT, friction_sd=0.03, distinct=distinct)
            mission = str(path)
            kinds = sections if distinct else min(sections, 180)
            if distinct:
                print("every section its own kind:")
            for name, extra in (("serial", []), ("--workers 2", ["--workers", "2"])):
                command = [sys.executable, "-m", "pampipe", "plan", mission, "--confidence", "0.95",
                           "--samples", str(args.samples), "--quiet", *extra]
                cpu, wall = measured(command, env)
                peak = peak_kb(command, env) / 1024
                print(f"{sections:>9} {kinds:>7} {name:<12} {cpu:>7.2f} {wall:>7.2f} {peak:>8.0f}")
    print("kinds: distinct (bore, incline, friction) sections, each sampled once; CPU includes the workers; "
          "peak: the largest single process")


if __name__ == "__main__":
    main()
