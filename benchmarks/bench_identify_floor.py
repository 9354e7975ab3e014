"""Benchmark: `pampipe identify` against its floor and the least_squares peer, whole processes, CPU time.

The floor (``floor_identify.py``): pandas' C reader, one fused reduction of the normal equations per test,
bvls on the 16 moduli: what any identify of these files pays at least. The peer
(``baseline_identify.py``): scipy's least_squares (trf) with the analytic Jacobian and its ``exact``
(SVD) subproblem solver (``--peer-solver lsmr`` for the other): at 3·10⁵ rows exact took 6.0 s CPU and
stopped 2.4·10⁻⁵ (relative SSE) above pampipe's constrained optimum, lsmr 6.3 s and 1.2·10⁻³ above it
(its inner iterations stop early on these ill-conditioned regressors), so exact is the stronger. Data:
the paper protocol of ``bench_identify.py`` (demo moduli, 2 N noise) at ≈ 2988·scale rows. Each
command runs as a fresh process with one BLAS thread, alternating; CPU time (user + system, from
``getrusage`` of the children) and wall time are the medians of ``--repeat`` runs; pampipe's cache is
warm (filled by a first run: the NLPs and the validated experiment, :mod:`pampipe.io.validated`).
Printed per size: the load average, the three CPU times, pampipe ÷ floor and peer ÷ pampipe (goals,
issue 25: ≤ 1.1× the floor at 3·10⁵–3·10⁶ rows, ≥ 5× faster than the peer at 3·10⁶).

    .venv/bin/python benchmarks/bench_identify_floor.py [--scales 100 1000] [--repeat 3] [--no-peer]
        [--peer-solver exact|lsmr]
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_big_mission import THREADS, measured
from bench_identify import ROOT, paper_protocol

from pampipe.io.pam_schema import load_pam


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scales", type=int, nargs="+", default=[100, 1000],
                        help="multiples of ≈ 2988 rows (default 100 1000: 3·10⁵ and 3·10⁶)")
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--no-peer", action="store_true", help="skip least_squares (minutes at 3·10⁶)")
    parser.add_argument("--peer-solver", choices=("exact", "lsmr"), default="exact",
                        help="least_squares' trust-region subproblem solver (default exact: the stronger)")
    args = parser.parse_args()
    pam = load_pam(ROOT / "problems" / "pams" / "paper-radial-pam.yaml")
    here = Path(__file__).resolve().parent
    with tempfile.TemporaryDirectory(prefix="bench-identify-floor-") as tmp:
        tmp = Path(tmp)
        env = {**os.environ, **THREADS, "PAMPIPE_NLP_CACHE": str(tmp / "cache")}
        print(f"{'rows':>9} {'load':>5} {'pampipe s':>10} {'floor s':>8} {'peer s':>8} {'pampipe÷floor':>13} "
              f"{'peer÷pampipe':>12}   (CPU, median of {args.repeat} whole processes, one BLAS thread)")
        for scale in args.scales:
            experiment, job, rows = paper_protocol(pam, scale, tmp / f"scale{scale}")
            commands = {"pampipe": [sys.executable, "-m", "pampipe", "identify", str(experiment), "--json"],
                        "floor": [sys.executable, str(here / "floor_identify.py"), str(job)]}
            if not args.no_peer:
                commands["peer"] = [sys.executable, str(here / "baseline_identify.py"), str(job),
                                    args.peer_solver]
            measured(commands["pampipe"], env)  # fills the NLP cache
            cpu: dict[str, list[float]] = {name: [] for name in commands}
            for _ in range(args.repeat):
                for name, command in commands.items():
                    cpu[name].append(measured(command, env)[0])
            t = {name: statistics.median(values) for name, values in cpu.items()}
            peer = f"{t['peer']:>8.3f}" if "peer" in t else f"{'-':>8}"
            lead = f"{t['peer'] / t['pampipe']:>11.2f}x" if "peer" in t else f"{'-':>12}"
            print(f"{rows:>9} {os.getloadavg()[0]:>5.2f} {t['pampipe']:>10.3f} {t['floor']:>8.3f} {peer} "
                  f"{t['pampipe'] / t['floor']:>12.2f}x {lead}", flush=True)


if __name__ == "__main__":
    main()
