"""The anchoring-pressure NLP (docs/physics.md §8) and its two solvers.

    minimise   Σ_e V_e·P_e                       (the air used; V_e = πD²L/4 at the anchored length)
    subject to g_e(P_e) ≥ 0                      (no slip, :func:`pampipe.plan.problem.slip_margin`)
               max(P_a,e(κW), 0) ≤ P_e ≤ P_up,e  (contact under the load; supply pressure)

The NLP is separable and each g_e increases with P_e (F₁ > 0), so its KKT point is
P_e* = max(P_lb, g_e⁻¹(0)) with multiplier λ_e = V_e/g_e'(P_e*) ≥ 0 when the no-slip constraint is
active. ``"kkt"`` (the default) solves these conditions directly by safeguarded Newton on all elements
at once; ``"ipopt"`` hands the same NLP, built once as a CasADi block of fixed size whose parameters
are the element coefficients, to IPOPT (general, but ~100× slower on long routes: ~2·10⁴ vs
~10⁶ elements/s, benchmarks/bench_plan.py).

The upper bound is the supply pressure where the supply suffices; elsewhere it is the model's limit
(100 MPa), so the solution is the pressure the element *would need*, for the infeasibility report.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache

import casadi as ca
import numpy as np

from pampipe.errors import SolverError
from pampipe.plan.problem import PRESSURE_LIMIT, Elements, holding_force, slip_margin, slip_margin_slope

PRESSURE_SCALE = 1e5  # [Pa] scale of the IPOPT decision variable
METHODS = ("kkt", "ipopt")
_PARAMETERS = 10  # per-element parameters of the IPOPT block, see _element_function


@dataclass(frozen=True)
class Solution:
    """Minimum pressure per element, (S, 3) arrays [Pa]; ``inf`` where no pressure ≤ 100 MPa holds."""

    pressure: np.ndarray
    slip_active: np.ndarray  # True where no slip (not contact) sets the pressure
    method: str
    iterations: int


def pressure_bounds(elements: Elements, supply: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(lower, upper, reachable): bounds of each element and whether 100 MPa can hold its load."""
    e = elements
    usable = e.valid & (e.slope > 0)
    lower = np.where(usable, e.lower_bound, 0.0)
    at_supply = usable & (lower <= supply) & (slip_margin(supply, e) >= 0)
    upper = np.where(at_supply, supply, PRESSURE_LIMIT)
    reachable = usable & (lower <= PRESSURE_LIMIT) & (slip_margin(PRESSURE_LIMIT, e) >= 0)
    return lower, upper, reachable


def solve(elements: Elements, supply: float, *, method: str = "kkt") -> Solution:
    """Solve the planning NLP for every element with the chosen method."""
    if method not in METHODS:
        raise ValueError(f"unknown method {method!r}; choose one of {METHODS}")
    lower, upper, reachable = pressure_bounds(elements, supply)
    if method == "kkt":
        pressure, iterations = _solve_kkt(elements, lower, upper, reachable)
    else:
        pressure, iterations = _solve_ipopt(elements, lower, upper, reachable)
    slip_active = reachable & (pressure > lower) & np.isfinite(pressure)
    return Solution(pressure, slip_active, method, iterations)


def _solve_kkt(e: Elements, lower, upper, reachable, *, max_iterations: int = 100):
    """Safeguarded Newton on g(P) = 0 inside [lower, upper], all elements at once."""
    pressure = np.where(reachable, lower, np.inf)
    todo = reachable & (slip_margin(lower, e) < 0)
    low, high = lower.copy(), upper.copy()
    p = lower.copy()
    for iteration in range(1, max_iterations + 1):
        if not todo.any():
            return pressure, iteration - 1
        g, dg = slip_margin(p, e), slip_margin_slope(p, e)
        low = np.where(todo & (g < 0), p, low)
        high = np.where(todo & (g >= 0), p, high)
        with np.errstate(divide="ignore", invalid="ignore"):
            newton = p - g / dg
        inside = (newton >= low) & (newton <= high) & np.isfinite(newton)
        step = np.where(inside, newton, 0.5 * (low + high))
        done = todo & inside & (np.abs(newton - p) <= 1e-14 * np.abs(p) + 1e-10)
        p = np.where(todo, step, p)
        pressure = np.where(done, p, pressure)
        todo &= ~done
    raise SolverError(f"the Newton solve of the planning KKT conditions did not converge in "
                      f"{max_iterations} iterations", status="kkt_max_iterations")


def _element_function() -> ca.Function:
    """Scaled no-slip margin and objective of one element (x = P/P_scale), for the IPOPT block."""
    x = ca.SX.sym("x")
    q = ca.SX.sym("q", _PARAMETERS)
    (at_zero, slope, c0, c1, pref, anchoring, axial_load, grip, sf_load, weight) = (
        q[i] for i in range(_PARAMETERS))
    pressure = PRESSURE_SCALE * x
    hold = holding_force(pressure, at_zero, slope, c0, c1, pref, anchoring, axial_load)
    scale = grip * slope * PRESSURE_SCALE  # ∂g/∂x without contact increments: g is O(1) per unit x
    return ca.Function("plan_element", [x, q], [weight * x, (grip * hold - sf_load) / scale])


@cache
def block_solver(size: int) -> ca.Function:
    """IPOPT on a block of ``size`` elements; built once per size, parameters in ``p``."""
    element = _element_function()
    x = ca.MX.sym("x", size)
    q = ca.MX.sym("q", _PARAMETERS, size)
    objective, margin = element.map(size)(x.T, q)
    nlp = {"x": x, "p": ca.vec(q), "f": ca.sum2(objective), "g": margin.T}
    options = {"print_time": False, "error_on_fail": False,
               "ipopt": {"print_level": 0, "sb": "yes", "tol": 1e-11, "constr_viol_tol": 1e-11,
                         "bound_relax_factor": 0.0, "mu_strategy": "adaptive",
                         "mu_oracle": "probing"}}
    return ca.nlpsol("plan_block", "ipopt", nlp, options)


def _solve_ipopt(e: Elements, lower, upper, reachable, *, block: int | None = None):
    """Solve the NLP with IPOPT in fixed-size blocks (unreachable elements are left out)."""
    index = np.flatnonzero(reachable.ravel())
    pressure = np.full(reachable.size, np.inf)
    if index.size == 0:
        return pressure.reshape(reachable.shape), 0
    block = block or (16 if index.size <= 16 else 512)
    solver = block_solver(block)
    volume = e.volume.ravel()
    params = np.stack([e.at_zero.ravel(), e.slope.ravel(), e.contact_at_zero.ravel(),
                       e.contact_slope.ravel(), e.reference_pressure.ravel(), e.anchoring.ravel(),
                       e.kappa * e.load.ravel(), e.grip.ravel(), e.safety_factor * e.load.ravel(),
                       volume / volume[index].max()])
    lo, up = lower.ravel() / PRESSURE_SCALE, upper.ravel() / PRESSURE_SCALE
    iterations = 0
    for start in range(0, index.size, block):
        part = index[start:start + block]
        take = np.concatenate([part, np.full(block - part.size, part[0])])  # pad with a copy
        result = solver(x0=np.minimum(up[take], lo[take] + 1.0),
                        p=params[:, take].T.ravel(), lbx=lo[take], ubx=up[take], lbg=0.0, ubg=np.inf)
        stats = solver.stats()
        if not stats["success"]:
            raise SolverError(f"IPOPT could not solve the planning NLP: {stats['return_status']}",
                              status=stats["return_status"])
        iterations += stats["iter_count"]
        pressure[part] = np.asarray(result["x"]).ravel()[:part.size] * PRESSURE_SCALE
    return pressure.reshape(reachable.shape), iterations
