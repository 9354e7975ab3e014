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
#: The last step of a converged solve is at most this, relative to max(1, |x|) (a quadratic objective's
#: second step is rounding; a Newton step on a smooth one this small has converged).
SETTLED = 1e-7
#: Active-set steps at most of :func:`resolved`: from a neighbouring minimum the answer may slide along a
#: chain of Drucker rows (one added, the previous dropped, per step): up to ~70 on the paper protocol.
RESOLVE_STEPS = 200
#: The reduced Hessian of a unique minimum has no eigenvalue below this times its largest.
UNIQUE = 1e-9


def applies(structure) -> bool:
    """Least squares at a fixed geometry (the moduli enter linearly)."""
    return structure.objective == "least_squares" and not structure.calibrate


def polish(nlp, p: np.ndarray, x: np.ndarray, lbx: np.ndarray, ubx: np.ndarray) -> np.ndarray:
    """The minimum of (SSE + prior)/2 over the bounds and the Drucker rows, from IPOPT's ``x``."""
    return minimum(nlp, p, x, lbx, ubx)[0]


def minimum(nlp, p: np.ndarray, x: np.ndarray, lbx: np.ndarray, ubx: np.ndarray, *, steps: int = STEPS,
            refine: int = 2, model: bool = False) -> tuple[np.ndarray, np.ndarray | None]:
    """(x*, free): at most ``steps`` active-set steps of the module docstring from ``x`` (which may lie off
    the constraints: those it violates start in the working set), ending after ``refine`` steps that
    neither add nor drop a constraint, or from the second of them on at one below :data:`SETTLED`; x* is
    the start if they end infeasible or above it. ``free`` is None unless the steps ended at a point with
    no blocking constraint and no negative multiplier, their last step below :data:`SETTLED` (relative to
    x), feasible and not above the start; then it holds (columns) the directions along which the minimum
    is not unique: Z·V, Z the null space of the constraints with a positive multiplier, V the eigenvectors
    of ZᵀHZ below :data:`UNIQUE` times its largest eigenvalue (none: x* is the one minimum, which any
    solver reaches). ``model``: between the steps that add or drop a constraint the quadratic model is
    moved (g + H·Δx, H kept) instead of evaluated; it is evaluated afresh before every other step."""
    a, b = _constraints(nlp, p, x, lbx, ubx)
    size = np.maximum(np.abs(a).max(axis=1), 1e-300) * (1.0 + np.abs(x).max())
    working = list(np.flatnonzero(a @ x - b <= ACTIVE * size))
    start, best = x, _objective(nlp, x, p)
    refined, free = 0, None
    fresh = True
    for _ in range(steps):
        if fresh or not model:
            gradient = np.asarray(nlp.gradient(x, p)[1], dtype=float).ravel()
            hessian = np.asarray(nlp.hessian(x, p), dtype=float)
        fresh = False
        step, multipliers = _equality_step(hessian, gradient, a[working], b[working] - a[working] @ x)
        slack, rate = a @ x - b, a @ step
        outside = np.ones(b.size, dtype=bool)  # the constraints not in the working set, in order
        outside[working] = False
        blocking = np.flatnonzero(outside & (rate < 0) & (slack + rate < 0))
        if blocking.size:
            fractions = np.maximum(slack[blocking], 0.0) / -rate[blocking]
            k = int(np.argmin(fractions))
            x = x + min(fractions[k], 1.0) * step
            gradient = gradient + min(fractions[k], 1.0) * (hessian @ step)
            working.append(int(blocking[k]))
            continue
        x = x + step
        gradient = gradient + hessian @ step
        if multipliers.size and multipliers.min() < -TOLERANCE * max(np.abs(multipliers).max(), 1.0):
            working.pop(int(np.argmin(multipliers)))
            continue
        refined, fresh = refined + 1, True
        settled = float(np.abs(step).max()) <= SETTLED * (1.0 + float(np.abs(x).max()))
        if refined == refine or not np.any(step) or (settled and refined >= 2):  # from the second on: once
            # more from the new point, the residual's rounding
            if settled:
                binding = multipliers > TOLERANCE * max(float(np.abs(multipliers).max(initial=0.0)), 1.0)
                free = undetermined(hessian, a[working][binding])
            break
    x = np.clip(x, lbx, ubx)
    feasible = np.all(a @ x - b >= -ACTIVE * size)
    if feasible and _objective(nlp, x, p) <= best:
        return x, free
    return start, None


def resolved(nlp, values: dict, x: np.ndarray, lbx: np.ndarray, ubx: np.ndarray, centred: np.ndarray,
             *, steps: int = RESOLVE_STEPS) -> np.ndarray | None:
    """The minimum of the problem of parameter values ``values`` by at most ``steps`` active-set steps from
    ``x`` (:func:`minimum`, the quadratic model moved between them), where it is the one an IPOPT solve
    would give: None where the steps do not settle, or the minimum is not unique along a direction that
    ``centred`` sees (the Hessian of the problem an IPOPT solve reached ``x`` in: along a direction flat for
    both, the steps leave x where that solve's barrier put it; along one it saw, the place the minimum is
    taken at would be the steps' choice, not IPOPT's)."""
    x, free = minimum(nlp, nlp.layout.pack(values), np.clip(x, lbx, ubx), lbx, ubx, steps=steps,
                      refine=steps, model=True)
    return x if free is not None and unseen(free, centred) else None


def unseen(directions: np.ndarray, hessian: np.ndarray) -> bool:
    """Whether the objective of Hessian ``hessian`` is flat along every column of ``directions`` (dᵀHd at most
    :data:`UNIQUE` times H's largest entry)."""
    if directions.shape[1] == 0:
        return True
    seen = np.abs(np.diag(directions.T @ hessian @ directions)).max()
    return bool(seen <= UNIQUE * max(float(np.abs(hessian).max()), 1e-300))


def undetermined(hessian: np.ndarray, rows: np.ndarray) -> np.ndarray:
    """Z·V (columns): Z the null space of ``rows`` (all of x without rows), V the eigenvectors of ZᵀHZ whose
    eigenvalue is below :data:`UNIQUE` times the largest |eigenvalue|."""
    basis = _null_space(rows) if rows.size else np.eye(hessian.shape[0])
    if basis.shape[1] == 0:
        return basis
    values, vectors = np.linalg.eigh(basis.T @ hessian @ basis)
    return basis @ vectors[:, values <= UNIQUE * max(float(np.abs(values).max()), 1e-300)]


def _null_space(rows: np.ndarray) -> np.ndarray:
    """An orthonormal basis of {d: rows·d = 0} (columns)."""
    _, singular, vt = np.linalg.svd(rows)
    rank = int(np.sum(singular > singular.max() * max(rows.shape) * np.finfo(float).eps))
    return vt[rank:].T


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
        basis = _null_space(rows)
    else:
        d0, basis = np.zeros(n), np.eye(n)
    y = np.linalg.lstsq(basis.T @ hessian @ basis, -basis.T @ (gradient + hessian @ d0), rcond=None)[0]
    step = d0 + basis @ y
    multipliers = np.linalg.lstsq(rows.T, hessian @ step + gradient, rcond=None)[0] if gaps.size \
        else np.zeros(0)
    return step, multipliers
