"""Radial force at 10⁶ (pressure, diameter, axial load) points: pampipe against hand-written numpy.

1. pampipe's vectorised path: :func:`pampipe.model.forces.radial_force` on numpy arrays (and, for
   reference, the CasADi Function of the symbolic :class:`~pampipe.model.muscle.Muscle` on whole rows);
2. the same formula written directly with numpy by a skilled user: the moduli sums by Horner
   (products, no powers ``ε**(j+1)``), each square root taken once.

Both give the same numbers (printed: the largest disagreement). Measured in one run, one BLAS
thread, best of ``--repeat``, in CPU seconds (wall in brackets). Goal: pampipe within 2× of the
hand-written numpy.

    .venv/bin/python benchmarks/bench_model.py [--points N] [--repeat 5]
"""

from __future__ import annotations

import argparse
import math
import time
from pathlib import Path

import casadi as ca
import numpy as np
from threadpoolctl import threadpool_limits

from pampipe.io.pam_schema import load_pam
from pampipe.model import forces
from pampipe.model.muscle import Muscle, Structure

PAM = Path(__file__).resolve().parent.parent / "problems" / "pams" / "paper-radial-pam.yaml"


def numpy_radial_force(p, d, fa, l0, d0, alpha0, t0, theta, pref):
    """Thick-wall F_r = max(0, A(F_ax − F_a)) written with numpy, moduli sums by Horner."""
    b = l0 / math.cos(alpha0)
    n = l0 * math.tan(alpha0) / (math.pi * d0)
    r0 = d0 / 2
    vb = math.pi * (r0 * r0 - (r0 - t0) ** 2) * l0
    c2 = 2 * math.pi * n * n
    length = np.sqrt(b * b - (n * math.pi * d) ** 2)
    ro = 0.5 * d
    ri = np.sqrt(ro * ro - vb / (math.pi * length))
    e1, e2 = (length - l0) / l0, (d - d0) / d0
    k = len(theta) // 4
    scaled = p / pref

    def sigma(a, bb, e):
        """Σ_j (a_j + b_j P/P_ref) e^{j+1} by Horner."""
        acc = a[k - 1] + bb[k - 1] * scaled
        for j in range(k - 2, -1, -1):
            acc = acc * e + (a[j] + bb[j] * scaled)
        return acc * e

    s1 = sigma(theta[:k], theta[k:2 * k], e1)
    s2 = sigma(theta[2 * k:3 * k], theta[3 * k:], e2)
    shared = length * length / (c2 * ro)
    fax = p * (ri * shared - math.pi * ri * ri) + s1 * vb / length - s2 * (ro - ri) * shared
    return np.maximum(0.0, c2 * d / length * (fax - fa))


def timed(fn):
    """(CPU time [s], wall time [s], result) of one call."""
    start, start_cpu = time.perf_counter(), time.process_time()
    result = fn()
    return time.process_time() - start_cpu, time.perf_counter() - start, result


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--points", type=int, default=10**6)
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args()
    pam = load_pam(PAM)
    g, theta, pref = pam.geometry, pam.moduli.as_vector(), pam.moduli.reference_pressure
    rng = np.random.default_rng(0)
    n = args.points
    p, d, fa = rng.uniform(0, 7e5, n), rng.uniform(0.06, 0.095, n), rng.uniform(0, 1500, n)
    geo = (g.initial_length, g.initial_diameter, g.braid_angle, g.bladder_thickness)

    sym = Muscle.symbolic(Structure("thick", pam.moduli.degree))
    ps, ds, fs = ca.SX.sym("p"), ca.SX.sym("d"), ca.SX.sym("f")
    function = ca.Function("radial", [ps, ds, fs, sym.p], [sym.muscle.radial_force(ps, ds, fs)])
    packed = sym.pack(Muscle.from_pam(pam))
    runs = {"pampipe": lambda: forces.radial_force(p, d, g, theta, pref, fa),
            "numpy": lambda: numpy_radial_force(p, d, fa, *geo, theta, pref),
            "casadi": lambda: np.asarray(function(p[None, :], d[None, :], fa[None, :], packed)).ravel()}
    best, values = {key: [float("inf"), float("inf")] for key in runs}, {}
    for repeat in range(args.repeat):  # alternate, so that both see the same machine
        for key, fn in runs.items():
            if key == "casadi" and repeat:
                continue  # a reference only, timed once
            cpu, wall, values[key] = timed(fn)
            best[key] = [min(best[key][0], cpu), min(best[key][1], wall)]
    f_pampipe, f_numpy, f_casadi = values["pampipe"], values["numpy"], values["casadi"]

    worst = max(np.max(np.abs(f_pampipe - f_numpy)), np.max(np.abs(f_pampipe - f_casadi)))
    print(f"radial force at {n:,} points (thick wall, cubic moduli), one BLAS thread, best of {args.repeat}; "
          f"largest disagreement {worst:.2e} N")
    print(f"{'method':<40}{'CPU [s]':>9}{'(wall)':>9}{'/ numpy':>9}")
    for name, key in (("pampipe vectorised (numpy)", "pampipe"), ("hand-written numpy (Horner)", "numpy"),
                      ("pampipe CasADi Function on rows", "casadi")):
        cpu, wall = best[key]
        print(f"{name:<40}{cpu:>9.3f} ({wall:>6.3f}){cpu / best['numpy'][0]:>8.2f}x")
    ratio = best["pampipe"][0] / best["numpy"][0]
    print(f"goal: pampipe within 2x of hand-written numpy -> {ratio:.2f} "
          f"({'met' if ratio <= 2 else 'MISSED'})")


if __name__ == "__main__":
    with threadpool_limits(limits=1):
        main()
