"""Benchmark: `identify` vs scipy SLSQP (finite differences, the fmincon analogue) vs scipy least_squares.

Same data (the paper protocol generated from the demo moduli, 2 N force noise, scaled to 3·10³ …
3·10⁶ rows), same model (the exact Eq. 9 / F_r = max(0, A(F_ax − F_a)) on every row), same start
(pampipe's bounded linear least-squares guess), same bounds; SLSQP gets the same Drucker rows on the
same grid as linear inequality constraints (their Jacobian by finite differences too, as fmincon
would). least_squares has bounds only (no Drucker constraint): a speed reference.

Times: pampipe "build" is the NLP construction (cache cleared before each size), "solve" is
everything else of `identify` (data reduction, IPOPT, uncertainty, exact per-row report). The
baselines have no build; "solve" is the optimiser call. The objective is the exact sum of squared
residuals over all rows (lower is better). Two ratios: baseline time / pampipe total time (build
included: a single fit in a fresh process) and baseline time / pampipe solve time (the NLP is
cached: every further fit of data with the same structure, e.g. refits, seeds, diagnose).
The shared start is already close to the optimum, which favours the baselines.

SLSQP and least_squares evaluate the model on every row at every finite-difference step; above
``BASELINE_CAP`` rows they would run for many minutes, so they are skipped there (printed as such).
Run: ``.venv/bin/python benchmarks/bench_identify.py [--sizes 3000 30000 ...] [--cap N]``.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np
from scipy.optimize import LinearConstraint, least_squares, minimize

from pampipe.experiment import ExperimentData, make_test_data
from pampipe.identify import FitOptions, identify, predict
from pampipe.identify.fit import _decision_names_and_bounds, _initial_guess, _reference_theta
from pampipe.identify.nlp import Structure, build_problem
from pampipe.identify.statistics import drucker_rows, reduce_experiment
from pampipe.io.config import load_pam
from pampipe.model.pam import Moduli, Pam
from pampipe.synth import Protocol, generate

ROOT = Path(__file__).resolve().parent.parent
BASELINE_CAP = 300_000


def make_data(pam: Pam, scale: int) -> ExperimentData:
    """≈ 2988·scale rows: 1800·scale axial (30·scale points per leg) and 1188·scale radial."""
    protocol = Protocol(points_per_leg=30 * scale, radial_points=27 * scale)
    tests = [make_test_data(spec, cols) for spec, cols in generate(pam, protocol, seed=scale)]
    return ExperimentData(ROOT / "bench", Pam(pam.name, pam.geometry, pam.moduli), tuple(tests), {})


def sse_of(data: ExperimentData, theta_mpa: np.ndarray) -> float:
    pam = Pam(data.pam.name, data.pam.geometry, Moduli.from_vector(theta_mpa * 1e6))
    return float(sum(np.sum((predict(pam, t) - t.force) ** 2) for t in data.tests))


def residual_vector(data: ExperimentData, theta_mpa: np.ndarray) -> np.ndarray:
    pam = Pam(data.pam.name, data.pam.geometry, Moduli.from_vector(theta_mpa * 1e6))
    return np.concatenate([predict(pam, t) - t.force for t in data.tests])


def baseline_setup(data: ExperimentData, result):
    """Start, bounds and Drucker rows identical to pampipe's."""
    options = result.options
    stats = reduce_experiment(data, degree=options.degree)
    structure = Structure("shared", "least_squares", stats.n_theta, 1,
                          tuple((r.levels, r.pipe) for r in stats.radial), len(stats.pipes), 0, 0,
                          "constant", "none", 1, 1.0)
    _, lower, upper = _decision_names_and_bounds(structure, stats, options)
    x0 = np.clip(_initial_guess(structure, stats, stats.axial.combined(),
                                _reference_theta(data, stats.n_theta), lower, upper),
                 lower + 1e-6 * (upper - lower), upper - 1e-6 * (upper - lower))
    grid = drucker_rows(data.pam.geometry, options.degree, result.drucker_grid["pressures"],
                        result.drucker_grid["lengths"], form="tangent")
    return x0, lower, upper, grid


def run_slsqp(data, x0, lower, upper, grid):
    scale = sse_of(data, x0)
    started = time.perf_counter()
    fit = minimize(lambda th: sse_of(data, th) / scale, x0, method="SLSQP",
                   bounds=list(zip(lower, upper, strict=True)),
                   constraints=[LinearConstraint(grid, 0, np.inf)],
                   options={"maxiter": 500, "ftol": 1e-12})
    return time.perf_counter() - started, sse_of(data, fit.x), f"{fit.message[:28]}"


def run_least_squares(data, x0, lower, upper):
    started = time.perf_counter()
    fit = least_squares(lambda th: residual_vector(data, th), x0, bounds=(lower, upper), x_scale="jac")
    return time.perf_counter() - started, sse_of(data, fit.x), f"{fit.message[:28]}"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[1, 10, 100, 1000],
                        help="multiples of ≈ 2988 rows (default 1 10 100 1000: 3e3 … 3e6)")
    parser.add_argument("--cap", type=int, default=BASELINE_CAP, help="largest row count for the baselines")
    args = parser.parse_args()
    pam = load_pam(ROOT / "problems" / "pams" / "paper-radial-pam.yaml")
    rows = []
    header = (f"{'rows':>9}  {'method':<26}{'build s':>9}{'solve s':>10}{'total s':>10}"
              f"{'SSE [N^2]':>14}{'vs total':>10}{'vs solve':>10}  status")
    identify(make_data(pam, 1), FitOptions(degree=1))  # warm-up: load CasADi's IPOPT plugin once
    print(header)
    print("-" * len(header))
    for scale in args.sizes:
        data = make_data(pam, scale)
        build_problem.cache_clear()
        started = time.perf_counter()
        result = identify(data, FitOptions())
        total = time.perf_counter() - started
        build = result.solver.build_time
        solve = total - build
        rows.append((data.points, "pampipe (IPOPT, exact)", build, solve, total, result.sse, 1.0, 1.0,
                     result.status))
        print(_line(rows[-1]), flush=True)
        if data.points > args.cap:
            print(f"{data.points:>9}  {'scipy SLSQP / least_squares':<26}  skipped: above the "
                  f"{args.cap:,}-row cap (each finite-difference step evaluates every row)", flush=True)
            continue
        x0, lower, upper, grid = baseline_setup(data, result)
        seconds, sse, status = run_slsqp(data, x0, lower, upper, grid)
        rows.append((data.points, "scipy SLSQP (FD, Drucker)", 0.0, seconds, seconds, sse, seconds / total,
                     seconds / solve, status))
        print(_line(rows[-1]), flush=True)
        seconds, sse, status = run_least_squares(data, x0, lower, upper)
        rows.append((data.points, "scipy least_squares (FD)", 0.0, seconds, seconds, sse, seconds / total,
                     seconds / solve, status + " (no Drucker)"))
        print(_line(rows[-1]), flush=True)


def _line(row) -> str:
    points, method, build, solve, total, sse, ratio_total, ratio_solve, status = row
    return (f"{points:>9}  {method:<26}{build:>9.3f}{solve:>10.3f}{total:>10.3f}{sse:>14.6g}"
            f"{ratio_total:>9.1f}x{ratio_solve:>9.1f}x  {status}")


if __name__ == "__main__":
    main()
