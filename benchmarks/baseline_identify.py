"""The strongest identify a skilled scipy user would write: pandas + least_squares (trf) + analytic Jacobian.

Standalone on purpose (numpy, pandas, scipy only; no pampipe import), so that its process pays
only for what it uses. It fits the same 16 moduli coefficients (MPa, b per 1 MPa) of the thick-wall
force balance (docs/physics.md §4.3) to axial rows (max(0, F_ax) on the slack rows, recorded force
≤ 0: the muscle cannot push, as pampipe's default ``fit.slack: unilateral``; a peer fitting F_ax there
solves another problem, whose SSE is 5·10⁻⁵ lower on the paper protocol) and of
F_r = max(0, A(F_ax(P, L_p) − F_a))
(docs/physics.md §5.3) to radial rows, with pampipe's coefficient bounds (no Drucker constraint: scipy
has none). F_ax is linear in the moduli, so the Jacobian is the regressor matrix (times A on the
radial rows above anchoring, zero below). The start is the unconstrained linear least squares of
the axial rows, clipped into the bounds. Powers are written as products.

Usage: ``python baseline_identify.py JOB.json [exact|lsmr]`` (trf's trust-region solver) where the
job names the CSV files (columns
``pressure [kPa]``, ``length [mm]``, ``force [N]``, as pampipe writes them) and the geometry (SI);
prints one JSON line: {"sse_N2", "sse_plain_N2", "rmse_N", "rows", "status", "iterations"}
(``sse_plain_N2``: the slack axial rows scored by F instead of max(0, F)).
"""

from __future__ import annotations

import json
import sys

import numpy as np
import pandas as pd
from scipy.optimize import least_squares

MPA = 1e6


def regressors(pressure, length, g, degree):
    """(offset [N], Φ [N/MPa]) of F_ax = offset + Φθ, thick wall."""
    l0, d0, alpha, t0 = g["initial_length"], g["initial_diameter"], g["braid_angle"], g["bladder_thickness"]
    b = l0 / np.cos(alpha)
    n = l0 * np.tan(alpha) / (np.pi * d0)
    n2 = n * n
    d = np.sqrt(b * b - length * length) / (n * np.pi)
    r_o = d / 2
    r0 = d0 / 2
    v_b = np.pi * (r0 * r0 - (r0 - t0) ** 2) * l0
    r_i = np.sqrt(r_o * r_o - v_b / (np.pi * length))
    area = r_i * length * length / (2 * np.pi * n2 * r_o) - np.pi * r_i * r_i
    lever1 = v_b / length
    lever2 = (r_o - r_i) * length * length / (2 * np.pi * n2 * r_o)
    x = pressure / MPA
    e1, e2 = (length - l0) / l0, (d - d0) / d0
    k = degree + 1
    phi = np.empty((np.size(length * x), 4 * k))
    t1, t2 = e1 * lever1, -e2 * lever2
    for j in range(k):
        phi[:, j], phi[:, k + j] = t1, x * t1
        phi[:, 2 * k + j], phi[:, 3 * k + j] = t2, x * t2
        t1, t2 = t1 * e1, t2 * e2
    return pressure * area, phi * MPA


def test_rows(test: dict, g: dict, degree: int):
    """(F [N], offset [N], Φ) of one test's rows, read with pandas' C reader: the model is offset + Φθ;
    a radial test's rows are scaled by the amplification A = 2πN²D_p/L_p at its pipe, axial load taken off."""
    frame = pd.read_csv(test["csv"], engine="c", dtype=np.float64)
    pressure = frame["pressure [kPa]"].to_numpy() * 1e3
    force = frame["force [N]"].to_numpy()
    if test["kind"] == "axial":
        offset, phi = regressors(pressure, frame["length [mm]"].to_numpy() * 1e-3, g, degree)
        return force, offset, phi
    dp = test["pipe_diameter"]
    l0, alpha, d0 = g["initial_length"], g["braid_angle"], g["initial_diameter"]
    b, n = l0 / np.cos(alpha), l0 * np.tan(alpha) / (np.pi * d0)
    lp = np.sqrt(b * b - (n * np.pi * dp) ** 2)
    offset, phi = regressors(pressure, np.full(pressure.size, lp), g, degree)
    a = 2 * np.pi * n * n * dp / lp
    return force, a * (offset - test["axial_load"]), a * phi


def main() -> None:
    job = json.loads(open(sys.argv[1]).read())
    solver = sys.argv[2] if len(sys.argv) > 2 else "exact"  # trf's subproblem: "exact" (SVD) or "lsmr"
    g, degree = job["geometry"], job["degree"]
    offsets, phis, forces, amps = [], [], [], []
    for test in job["tests"]:
        force, offset, phi = test_rows(test, g, degree)
        offsets.append(offset)
        phis.append(phi)
        forces.append(force)
        amps.append(np.full(force.size, 1.0 if test["kind"] != "axial" else 0.0))
    offset, phi, force, radial = (np.concatenate(offsets), np.vstack(phis), np.concatenate(forces),
                                  np.concatenate(amps) > 0)
    hinged = radial | (force <= 0)  # slack axial rows read max(0, F), as pampipe's fit.slack: unilateral
    k = degree + 1
    lower = np.full(4 * k, -50.0)
    upper = np.full(4 * k, 50.0)
    lower[0] = lower[2 * k] = 0.0

    def residual(theta):
        u = offset + phi @ theta
        return np.where(hinged, np.maximum(u, 0.0), u) - force

    def jacobian(theta):
        u = offset + phi @ theta
        return phi * np.where(hinged & (u <= 0), 0.0, 1.0)[:, None]

    axial = ~radial
    start = np.linalg.lstsq(phi[axial], force[axial] - offset[axial], rcond=None)[0]
    start = np.clip(start, lower + 1e-6, upper - 1e-6)
    fit = least_squares(residual, start, jac=jacobian, bounds=(lower, upper), method="trf", x_scale="jac",
                        tr_solver=solver)
    sse = float(np.sum(residual(fit.x) ** 2))
    u = offset + phi @ fit.x
    plain = float(np.sum((np.where(radial, np.maximum(u, 0.0), u) - force) ** 2))  # slack rows scored by F
    print(json.dumps({"sse_N2": sse, "sse_plain_N2": plain, "rmse_N": float(np.sqrt(sse / force.size)),
                      "rows": int(force.size),
                      "status": fit.message, "iterations": int(fit.nfev)}))


if __name__ == "__main__":
    main()
