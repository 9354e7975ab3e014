"""The exact optimum after IPOPT: an active-set solve of the least-squares problem on the reduced statistics.

At a fixed geometry and fixed slack sides the model is linear in the moduli (docs/physics.md §4.3), so
the objective f(x) = (SSE + prior)/2 is quadratic, f(x + d) = f(x) + gᵀd + ½dᵀHd, and the constraints
(bounds, Drucker rows C·x ≥ 0) are linear: A·x ≥ b. IPOPT's interior point stops a little inside
the constraints and at its tolerance, a few 10⁻⁶ above the optimum SSE. Starting from the constraints
IPOPT left (nearly) active, each step solves the equality-constrained problem on the working set W

    [ H   −A_Wᵀ ] [d]   [ −g          ]
    [ A_W   0   ] [λ] = [ b_W − A_W·x ]

(least-squares solution: a direction the data do not determine gets no step), then, as a primal
active-set method does, stops at the first constraint the step would cross (adding it to W) or drops
the constraint of the most negative multiplier λ. Where the objective is not exactly quadratic
(straddling radial bins, contact increments) the same steps are Newton steps, kept only if they
lower f and stay feasible.
"""

from __future__ import annotations

import numpy as np

#: A constraint within this distance (relative to its row's size and x) counts as active at IPOPT's point.
ACTIVE = 1e-6
#: Steps at most (each adds or drops one constraint, or refines a converged point once more).
STEPS = 40
#: Multipliers above −TOLERANCE·max|λ| are taken as non-negative.
TOLERANCE = 1e-10


def applies(structure) -> bool:
    """Least squares at a fixed geometry (the moduli enter linearly)."""
    return structure.objective == "least_squares" and not structure.calibrate


def polish(nlp, p: np.ndarray, x: np.ndarray, lbx: np.ndarray, ubx: np.ndarray) -> np.ndarray:
    """The minimum of (SSE + prior)/2 over the bounds and the Drucker rows, from IPOPT's ``x``."""
    a, b = _constraints(nlp, p, x, lbx, ubx)
    size = np.maximum(np.abs(a).max(axis=1), 1e-300) * (1.0 + np.abs(x).max())
    working = list(np.flatnonzero(a @ x - b <= ACTIVE * size))
    start, best = x, _objective(nlp, x, p)
    refined = 0
    for _ in range(STEPS):
        gradient = np.asarray(nlp.gradient(x, p)[1], dtype=float).ravel()
        hessian = np.asarray(nlp.hessian(x, p), dtype=float)
        step, multipliers = _equality_step(hessian, gradient, a[working], b[working] - a[working] @ x)
        slack, rate = a @ x - b, a @ step
        others = np.setdiff1d(np.arange(b.size), working)
        blocking = others[(rate[others] < 0) & (slack[others] + rate[others] < 0)]
        if blocking.size:
            fractions = np.maximum(slack[blocking], 0.0) / -rate[blocking]
            k = int(np.argmin(fractions))
            x = x + min(fractions[k], 1.0) * step
            working.append(int(blocking[k]))
            continue
        x = x + step
        if multipliers.size and multipliers.min() < -TOLERANCE * max(np.abs(multipliers).max(), 1.0):
            working.pop(int(np.argmin(multipliers)))
            continue
        refined += 1
        if refined == 2 or not np.any(step):  # once more from the new point: the residual's rounding
            break
    x = np.clip(x, lbx, ubx)
    feasible = np.all(a @ x - b >= -ACTIVE * size)
    return x if feasible and _objective(nlp, x, p) <= best else start


def _objective(nlp, x, p) -> float:
    return float(nlp.gradient(x, p)[0])


def _constraints(nlp, p, x, lbx, ubx):
    """(A, b) of A·x ≥ b: the finite bounds, then the Drucker rows (g(x) = g(x₀) + J(x − x₀), exact)."""
    n = x.size
    eye = np.eye(n)
    low, high = np.isfinite(lbx), np.isfinite(ubx)
    g, jacobian = (np.asarray(v, dtype=float) for v in nlp.constraints(x, p))
    jacobian = jacobian.reshape(g.size, n)
    a = np.vstack([eye[low], -eye[high], jacobian])
    b = np.concatenate([lbx[low], -ubx[high], jacobian @ x - g.ravel()])
    return a, b


def _equality_step(hessian, gradient, rows, gaps):
    """(d, λ) of the KKT system on the working set, by the null-space method: d = d₀ + Z·y with
    A_W·d₀ = gaps, Z spanning the null space of A_W and (ZᵀHZ)y = −Zᵀ(g + H·d₀) (least-squares
    solution: a direction the data do not determine gets no step); then A_Wᵀλ = H·d + g."""
    n = gradient.size
    if gaps.size:
        d0 = np.linalg.lstsq(rows, gaps, rcond=None)[0]
        _, singular, vt = np.linalg.svd(rows)
        rank = int(np.sum(singular > singular.max() * max(rows.shape) * np.finfo(float).eps))
        basis = vt[rank:].T
    else:
        d0, basis = np.zeros(n), np.eye(n)
    y = np.linalg.lstsq(basis.T @ hessian @ basis, -basis.T @ (gradient + hessian @ d0), rcond=None)[0]
    step = d0 + basis @ y
    multipliers = np.linalg.lstsq(rows.T, hessian @ step + gradient, rcond=None)[0] if gaps.size \
        else np.zeros(0)
    return step, multipliers
