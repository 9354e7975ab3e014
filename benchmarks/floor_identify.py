"""The floor of an identify: pandas' C reader, one fused reduction per test, bounded least squares (bvls).

Standalone (numpy, pandas, scipy only; no pampipe import), like ``baseline_identify.py``, whose job file
and regressors it uses. It is not a full identify: no slack hinge, no radial contact switch, no Drucker
constraint, no uncertainty, no report. It reads each CSV, forms the normal equations G = ΦᵀΦ,
h = Φᵀ(F − offset) and FᵀF of the rows in tension or contact (F above 1 % of the test's largest) in one
pass per test, and solves the 16 bounded moduli from them (``scipy.optimize.lsq_linear``, bvls, on a square
root R of G, RᵀR = G, from the eigen-decomposition of the equilibrated G). What pampipe does beyond this is
the price of its model, checks and report: ``bench_identify_floor.py`` prints pampipe ÷ floor.

Usage: ``python floor_identify.py JOB.json``; prints one JSON line {"sse_N2", "rows"} (the SSE of the rows
kept, so not comparable with an identify's).
"""

from __future__ import annotations

import json
import sys

import numpy as np
from baseline_identify import test_rows
from scipy.optimize import lsq_linear


def main() -> None:
    job = json.loads(open(sys.argv[1]).read())
    g, degree = job["geometry"], job["degree"]
    k = 4 * (degree + 1)
    gram, rhs, yy, rows = np.zeros((k, k)), np.zeros(k), 0.0, 0
    for test in job["tests"]:
        force, offset, phi = test_rows(test, g, degree)
        held = force > 0.01 * force.max()  # in tension / in contact (not noise about 0): the linear part
        phi, target = phi[held], (force - offset)[held]
        gram += phi.T @ phi
        rhs += phi.T @ target
        yy += float(target @ target)
        rows += force.size
    lower, upper = np.full(k, -50.0), np.full(k, 50.0)
    lower[0] = lower[k // 2] = 0.0
    scale = 1 / np.sqrt(np.diag(gram))  # G is ill-conditioned in these units: equilibrate, then G = RᵀR
    values, vectors = np.linalg.eigh(gram * np.outer(scale, scale))
    kept = values > values.max() * 1e-15
    factor = np.sqrt(values[kept])[:, None] * vectors[:, kept].T / scale[None, :]  # R = Λ^½VᵀD⁻¹
    target = (vectors[:, kept].T @ (scale * rhs)) / np.sqrt(values[kept])
    fit = lsq_linear(factor, target, bounds=(lower, upper), method="bvls")
    theta = fit.x
    sse = yy - 2 * theta @ rhs + theta @ gram @ theta
    print(json.dumps({"sse_N2": float(sse), "rows": rows}))


if __name__ == "__main__":
    main()
