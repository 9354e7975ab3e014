"""Benchmark: `pampipe identify` against its floor and the least_squares peer, whole processes, CPU time.

The floor (``floor_identify.py``): pandas' C reader, one fused reduction of the normal equations per test,
bvls on the 16 moduli: what any identify of these files pays at least. The peer
(``baseline_identify.py``): scipy's least_squares (trf) with the analytic Jacobian and its ``exact``
(SVD) subproblem solver and with ``lsmr``, both run by default (the faster is the peer): at 3·10⁵
rows exact took 6.0 s CPU and stopped 2.4·10⁻⁵ (relative SSE) above pampipe's constrained optimum,
lsmr 6.3 s and 1.2·10⁻³ above it (its inner iterations stop early on these ill-conditioned
regressors) in an earlier round. Data:
the paper protocol of ``bench_identify.py`` (demo moduli, 2 N noise) at ≈ 2988·scale rows. Each
command runs as a fresh process with one BLAS thread, alternating; CPU time (user + system, from
``getrusage`` of the children) and wall time are the medians of ``--repeat`` runs; pampipe's cache is
warm (filled by a first run: the NLPs and the validated experiment, :mod:`pampipe.io.validated`) and its
bytecode compiled first, as an installed package's is (under PYTHONDONTWRITEBYTECODE a source tree without
it compiles every module in every run: 0.3 s of a 1.7 s run at 3·10⁴ rows).
Printed per size: the load average; per command its median CPU [min-max] over the runs, the peak
memory of one more run (started by a small launcher) and its SSE: pampipe's scores the slack rows as
max(0, F) (its objective, as the peer's ``sse_N2``); the peer's plain SSE scores them by F; then
pampipe ÷ floor and the faster of trf-exact and trf-lsmr ÷ pampipe, each the ratio of the medians with
the spread of the same ratio taken round by round (goals, issue 39: ≥ 1.5× / 2× / 5×
faster than the peer at 3·10⁴ / 3·10⁵ / 3·10⁶ rows, ≤ 1.2× the floor's CPU and memory at 3·10⁵–3·10⁶).

With ``--baseline TREE`` (a checkout of main) that tree's ``pampipe identify`` runs in the same rounds, with
a cache of its own, and pampipe ÷ baseline is printed (the median of the per-round ratios and their spread).

    .venv/bin/python benchmarks/bench_identify_floor.py [--scales 10 100 1000] [--repeat 5] [--no-peer]
        [--peer-solver exact lsmr] [--baseline TREE]
"""

from __future__ import annotations

import argparse
import compileall
import json
import os
import statistics
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_big_mission import THREADS, measured, peak_kb
from bench_identify import ROOT, paper_protocol

from pampipe.io.pam_schema import load_pam


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scales", type=int, nargs="+", default=[10, 100, 1000],
                        help="multiples of ≈ 2988 rows (default 10 100 1000: 3·10⁴, 3·10⁵ and 3·10⁶)")
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--no-peer", action="store_true", help="skip least_squares (minutes at 3·10⁶)")
    parser.add_argument("--peer-solver", choices=("exact", "lsmr"), nargs="+", default=["exact", "lsmr"],
                        help="least_squares' trust-region subproblem solvers run (default both; the faster "
                             "is the peer)")
    parser.add_argument("--baseline", type=Path, help="another pampipe source tree (a checkout of main): its "
                        "identify runs in the same rounds, as 'baseline'")
    args = parser.parse_args()
    compileall.compile_dir(ROOT / "pampipe", quiet=1)  # bytecode, as installed (PYTHONDONTWRITEBYTECODE)
    pam = load_pam(ROOT / "problems" / "pams" / "paper-radial-pam.yaml")
    here = Path(__file__).resolve().parent
    with tempfile.TemporaryDirectory(prefix="bench-identify-floor-") as tmp:
        tmp = Path(tmp)
        env = {**os.environ, **THREADS, "PAMPIPE_NLP_CACHE": str(tmp / "cache")}
        print(f"CPU s: median [min-max] of {args.repeat} whole processes, alternated, one BLAS thread; "
              "peak MB of one more run each")
        for scale in args.scales:
            experiment, job, rows = paper_protocol(pam, scale, tmp / f"scale{scale}")
            commands = {"pampipe": [sys.executable, "-m", "pampipe", "identify", str(experiment), "--json"],
                        "floor": [sys.executable, str(here / "floor_identify.py"), str(job)]}
            for solver in [] if args.no_peer else args.peer_solver:
                commands[f"trf-{solver}"] = [sys.executable, str(here / "baseline_identify.py"), str(job),
                                             solver]
            places = dict.fromkeys(commands, (env, ROOT))  # python -m imports the pampipe of its folder
            if args.baseline is not None:
                tree = args.baseline.resolve()
                compileall.compile_dir(tree / "pampipe", quiet=1)
                commands["baseline"] = commands["pampipe"]
                own = {**env, "PYTHONPATH": str(tree), "PAMPIPE_NLP_CACHE": str(tmp / "baseline-cache")}
                places["baseline"] = (own, tree)
            for name in [n for n in ("pampipe", "baseline") if n in commands]:
                measured(commands[name], *places[name])  # fills the NLP cache
            cpu: dict[str, list[float]] = {name: [] for name in commands}
            out: dict[str, list[bytes]] = {name: [] for name in commands}
            for _ in range(args.repeat):
                for name, command in commands.items():
                    cpu[name].append(measured(command, *places[name], out=out[name])[0])
            t = {name: statistics.median(values) for name, values in cpu.items()}
            print(f"\n{rows:,} rows, load average {os.getloadavg()[0]:.2f}")
            for name, values in cpu.items():
                doc = json.loads(out[name][0])
                if "fit" in doc:
                    sse = f"SSE {doc['fit']['sse_N2']:.10g} (slack rows as max(0, F))"
                else:
                    sse = f"SSE {doc['sse_N2']:.10g}" + (f", plain SSE {doc['sse_plain_N2']:.10g}"
                                                         if "sse_plain_N2" in doc else "")
                print(f"  {name:<11} {t[name]:7.3f} [{min(values):.3f}-{max(values):.3f}] s  "
                      f"{peak_kb(commands[name], *places[name]) / 1024:7.0f} MB  {sse}", flush=True)
            peers = [name for name in t if name.startswith("trf-")]
            line = (f"  pampipe / floor {t['pampipe'] / t['floor']:.2f}x "
                    f"{_spread(cpu['pampipe'], cpu['floor'])}")
            if peers:
                peer = min(peers, key=t.get)
                line += (f"; the faster peer {peer}: {t[peer] / t['pampipe']:.2f}x pampipe's CPU "
                         f"{_spread(cpu[peer], cpu['pampipe'])}")
            print(line, flush=True)
            if "baseline" in cpu:
                ratios = _per_round(cpu["pampipe"], cpu["baseline"])
                print(f"  pampipe / baseline {statistics.median(ratios):.3f} "
                      f"[{min(ratios):.3f}-{max(ratios):.3f}] (per round)", flush=True)


def _per_round(numerator: list[float], denominator: list[float]) -> list[float]:
    """The ratio of two commands' CPU round by round (they alternate within a round)."""
    return [a / b for a, b in zip(numerator, denominator, strict=True)]


def _spread(numerator: list[float], denominator: list[float]) -> str:
    """:func:`_per_round` as "[min-max per round]": the movement a ratio of medians has on this machine."""
    ratios = _per_round(numerator, denominator)
    return f"[{min(ratios):.2f}-{max(ratios):.2f} per round]"


if __name__ == "__main__":
    main()
