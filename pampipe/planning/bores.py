"""The worst bore of a bore range: where the least holding pressure P*(D) is largest (docs/commands.md §4.3).

A plan that holds over [D_low, D_high] needs max P*(D) over the range: P* holds at every D ≤ P (the
capacity grows with P above contact), so the largest P* holds everywhere. P*(D) is not monotone in
general: the anchoring pressure P_a(D) grows with D while the slip term SF·W/(μπA(D)F₁(D)) first falls
as the amplification A grows (a U, e.g. heavy loads near D₀), and a softening hoop law can bend P_a(D)
itself into a hump. So the maximum is looked for properly, per element and vectorised:

1. P* on a grid of :data:`GRID` + 1 bores spanning the range (the ends included);
2. where the grid's largest value is at an end and dP*/dD there points out of the range (exact
   derivative of the closed form :meth:`Muscle.required_pressure`, through CasADi), that end is the
   maximum: P* cannot rise again inside the neighbouring cell without the derivative changing sign
   twice within a sixteenth of the range;
3. elsewhere (an interior grid maximum, an end whose slope points inwards, or a muscle with diagnosed
   effects that have no closed form, where P* comes from bisection), the two cells next to the grid
   maximum are scanned again on a grid of the same size, :data:`ZOOMS` times, each time around the
   new maximum (a k-ary search: the bracket shrinks 8-fold per pass, and each pass is one vectorised
   call, which matters where each P* is itself a bisection); the largest value seen wins.
"""

from __future__ import annotations

from functools import cache

import numpy as np

from pampipe.model.muscle import Muscle, Structure

GRID = 16  # cells of the scan over a bore range
#: Passes around the maximum: the bracket ends at (2/16)⁸ ≈ 6e-8 of the range, so P* at a smooth interior
#: maximum is within ½|P''|(6e-8·range)² of the true one: below 1e-9 Pa for a 10 mm range.
ZOOMS = 7


@cache
def slope_function(structure: Structure):
    """(D, W, κ, μ, SF, p_muscle) → dP*/dD [Pa/m] of the closed form, or None where effects refuse it."""
    import casadi as ca

    sym = Muscle.symbolic(structure)
    if sym.muscle.closed_form_refusals():
        return None
    d, w, kappa, mu, sf = (ca.SX.sym(n) for n in ("diameter", "load", "kappa", "friction", "safety_factor"))
    pressure = sym.muscle.required_pressure(d, w, kappa=kappa, friction=mu, safety_factor=sf)
    return ca.Function("bore_slope", [d, w, kappa, mu, sf, sym.p], [ca.jacobian(pressure, d)])


def slope(muscle: Muscle, diameter, load, *, kappa, friction, safety_factor) -> np.ndarray | None:
    """dP*/dD [Pa/m] at each element (exact, CasADi), or None for a muscle without a closed form."""
    function = slope_function(muscle.structure)
    if function is None:
        return None
    d, w, mu = np.broadcast_arrays(*(np.asarray(v, dtype=float).ravel() for v in (diameter, load, friction)))
    if d.size == 0:
        return np.empty(0)
    out = function.map(d.size)(d[None, :], w[None, :], kappa, mu[None, :], safety_factor,
                               muscle.parameter_vector())
    return np.asarray(out, dtype=float).ravel()


def worst_bores(muscle: Muscle, low, high, load, *, kappa: float, friction,
                safety_factor: float) -> np.ndarray:
    """The bore [m] in [low, high] where :meth:`Muscle.least_holding_pressure` is largest, per element.

    ``low``, ``high``, ``load`` [N] and ``friction`` are arrays of one length (low ≤ high, both inside the
    muscle's domain); where low = high the answer is low.
    """
    low, high, load, friction = (np.asarray(v, dtype=float)
                                 for v in np.broadcast_arrays(low, high, load, friction))
    out = low.copy()
    rows = np.flatnonzero(high > low)
    if rows.size == 0:
        return out
    a, b, w, mu = low[rows], high[rows], load[rows], friction[rows]

    def pressure(d, take=slice(None)):
        shape = (-1,) + (1,) * (np.ndim(d) - 1)
        return muscle.least_holding_pressure(d, np.reshape(w[take], shape), kappa=kappa,
                                             friction=np.reshape(mu[take], shape),
                                             safety_factor=safety_factor)

    grid = a[:, None] + (b - a)[:, None] * np.linspace(0.0, 1.0, GRID + 1)
    values = pressure(grid)
    best = np.argmax(values, axis=1)
    picked = np.arange(rows.size)
    best_d, best_p = grid[picked, best], values[picked, best]
    open_ = np.isfinite(best_p)  # an infinite P* somewhere: the element is infeasible there; done
    edge = open_ & ((best == 0) | (best == GRID))
    if edge.any():
        g = slope(muscle, best_d[edge], w[edge], kappa=kappa, friction=mu[edge], safety_factor=safety_factor)
        if g is not None:
            outward = np.where(best[edge] == 0, g <= 0, g >= 0)
            open_[np.flatnonzero(edge)[outward]] = False
    todo = np.flatnonzero(open_)
    for _ in range(ZOOMS if todo.size else 0):
        k = best[todo]
        left, right = grid[todo, np.maximum(k - 1, 0)], grid[todo, np.minimum(k + 1, GRID)]
        grid = np.empty_like(grid)
        grid[todo] = left[:, None] + (right - left)[:, None] * np.linspace(0.0, 1.0, GRID + 1)
        values = pressure(grid[todo], todo)
        best[todo] = np.argmax(values, axis=1)
        top = values[np.arange(todo.size), best[todo]]
        better = top > best_p[todo]
        best_d[todo] = np.where(better, grid[todo, best[todo]], best_d[todo])
        best_p[todo] = np.where(better, top, best_p[todo])
    out[rows] = best_d
    return out
