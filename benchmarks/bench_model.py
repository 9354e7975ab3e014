"""Radial force at 10⁶ (pressure, diameter, axial load) points, three ways (issue 2 benchmark).

1. pampipe's vectorized path: the model's pure functions evaluated on numpy arrays (and, for
   reference, the prebuilt CasADi Function called on whole rows);
2. a plain per-point Python loop over the scalar formula (math module);
3. a hand-vectorized numpy version written here, independently of pampipe.

Goals: pampipe within 2x of hand-vectorized numpy, and at least 100x faster than the loop.
Usage: python benchmarks/bench_model.py [--points N] [--loop-points M]
"""

from __future__ import annotations

import argparse
import math
import time
from pathlib import Path

import casadi as ca
import numpy as np

from pampipe.io.config import load_pam
from pampipe.model import forces
from pampipe.model.muscle import Muscle, Structure

PAM = Path(__file__).resolve().parent.parent / "problems" / "pams" / "paper-radial-pam.yaml"


def scalar_radial_force(p, d, fa, l0, d0, alpha0, t0, theta, pref):
    """Thick-wall F_r = max(0, A(F_ax − F_a)) for one point, written out with the math module."""
    b = l0 / math.cos(alpha0)
    n = l0 * math.tan(alpha0) / (math.pi * d0)
    r0 = d0 / 2
    vb = math.pi * (r0**2 - (r0 - t0) ** 2) * l0
    length = math.sqrt(b * b - (n * math.pi * d) ** 2)
    ro = d / 2
    ri = math.sqrt(ro * ro - vb / (math.pi * length))
    t = ro - ri
    e1, e2 = (length - l0) / l0, (d - d0) / d0
    k = len(theta) // 4
    s1 = sum((theta[j] + theta[k + j] * p / pref) * e1 ** (j + 1) for j in range(k))
    s2 = sum((theta[2 * k + j] + theta[3 * k + j] * p / pref) * e2 ** (j + 1) for j in range(k))
    fax = (p * (ri * length**2 / (2 * math.pi * n * n * ro) - math.pi * ri * ri) + s1 * vb / length
           - s2 * t * length**2 / (2 * math.pi * n * n * ro))
    amp = 2 * math.pi * n * n * d / length
    return max(0.0, amp * (fax - fa))


def numpy_radial_force(p, d, fa, l0, d0, alpha0, t0, theta, pref):
    """The same formula, hand-vectorized with numpy."""
    b = l0 / np.cos(alpha0)
    n = l0 * np.tan(alpha0) / (np.pi * d0)
    r0 = d0 / 2
    vb = np.pi * (r0**2 - (r0 - t0) ** 2) * l0
    length = np.sqrt(b * b - (n * np.pi * d) ** 2)
    ro = d / 2
    ri = np.sqrt(ro * ro - vb / (np.pi * length))
    t = ro - ri
    e1, e2 = (length - l0) / l0, (d - d0) / d0
    k = len(theta) // 4
    scaled = p / pref
    s1 = np.zeros_like(p)
    s2 = np.zeros_like(p)
    for j in range(k):
        s1 += (theta[j] + theta[k + j] * scaled) * e1 ** (j + 1)
        s2 += (theta[2 * k + j] + theta[3 * k + j] * scaled) * e2 ** (j + 1)
    lever = length**2 / (2 * np.pi * n * n * ro)
    fax = p * (ri * lever - np.pi * ri * ri) + s1 * vb / length - s2 * t * lever
    return np.maximum(0.0, 2 * np.pi * n * n * d / length * (fax - fa))


def best_of(repeats, fn):
    times, result = [], None
    for _ in range(repeats):
        start = time.perf_counter()
        result = fn()
        times.append(time.perf_counter() - start)
    return min(times), result


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--points", type=int, default=10**6)
    parser.add_argument("--loop-points", type=int, default=10**6,
                        help="points for the Python loop (its time is scaled to --points)")
    args = parser.parse_args()
    pam = load_pam(PAM)
    g, theta, pref = pam.geometry, pam.moduli.as_vector(), pam.moduli.reference_pressure
    rng = np.random.default_rng(0)
    n = args.points
    p, d, fa = rng.uniform(0, 7e5, n), rng.uniform(0.06, 0.095, n), rng.uniform(0, 1500, n)
    geo = (g.initial_length, g.initial_diameter, g.braid_angle, g.bladder_thickness)

    t_pampipe, f_pampipe = best_of(3, lambda: forces.radial_force(p, d, g, theta, pref, fa))
    sym = Muscle.symbolic(Structure("thick", pam.moduli.degree))
    ps, ds, fs = ca.SX.sym("p"), ca.SX.sym("d"), ca.SX.sym("f")
    function = ca.Function("radial", [ps, ds, fs, sym.p], [sym.muscle.radial_force(ps, ds, fs)])
    packed = sym.pack(Muscle.from_pam(pam))
    t_casadi, f_casadi = best_of(1, lambda: np.asarray(
        function(p[None, :], d[None, :], fa[None, :], packed)).ravel())
    t_numpy, f_numpy = best_of(3, lambda: numpy_radial_force(p, d, fa, *geo, theta, pref))
    m = min(args.loop_points, n)
    t_loop, f_loop = best_of(1, lambda: np.array([scalar_radial_force(p[i], d[i], fa[i], *geo, theta, pref)
                                                   for i in range(m)]))
    t_loop_scaled = t_loop * n / m

    worst = max(np.max(np.abs(f_pampipe - f_numpy)), np.max(np.abs(f_pampipe[:m] - f_loop)),
                np.max(np.abs(f_pampipe - f_casadi)))
    print(f"radial force at {n:,} points (thick wall, cubic moduli); largest disagreement {worst:.2e} N")
    print(f"{'method':<34}{'time [s]':>10}{'pampipe speed-up':>18}")
    rows = [("pampipe vectorized (numpy)", t_pampipe), ("pampipe CasADi Function (rows)", t_casadi),
            ("hand-vectorized numpy", t_numpy),
            (f"Python loop ({m:,} pts, scaled)" if m < n else "Python loop", t_loop_scaled)]
    for name, t in rows:
        print(f"{name:<34}{t:>10.3f}{t / t_pampipe:>17.1f}x")
    print(f"goal: pampipe / numpy <= 2   -> {t_pampipe / t_numpy:.2f} "
          f"({'met' if t_pampipe <= 2 * t_numpy else 'MISSED'})")
    print(f"goal: loop / pampipe >= 100  -> {t_loop_scaled / t_pampipe:.0f} "
          f"({'met' if t_loop_scaled >= 100 * t_pampipe else 'MISSED'})")


if __name__ == "__main__":
    main()
