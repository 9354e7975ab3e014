"""The anchoring-pressure NLP (docs/physics.md §8) and its two solvers.

    minimise   Σ_e V_e·P_e                       (the air used; V_e = πD²L/4 at the anchored length)
    subject to μπF_r(P_e, D_e, κW_e) ≥ SF·W_e     (no slip)
               max(P_a,e(κW), 0) ≤ P_e ≤ P_up,e  (contact under the load; supply pressure)

The NLP is separable and each capacity increases with P_e above anchoring, so its KKT point is
P_e* = max(P_lb, least P with no slip), with multiplier λ_e = V_e/∂_P(capacity) ≥ 0 where no slip
binds. ``"kkt"`` (the default) takes that point from :meth:`Muscle.least_holding_pressure` (closed
form without diagnosed effects, bisection with them); ``"ipopt"`` hands the same NLP, built once per
muscle structure from the symbolic :class:`~pampipe.model.muscle.Muscle` as a block of fixed size
whose parameters are the muscle and the elements, to IPOPT (general, ~10³× slower on long routes,
benchmarks/bench_plan.py).

The upper bound is the supply pressure where the supply suffices; elsewhere it is the model's limit
(100 MPa), so the solution is the pressure the element *would need*, for the infeasibility report.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cache

import numpy as np

from pampipe.model.muscle import PRESSURE_LIMIT, Muscle, Structure
from pampipe.planning.problem import Elements, chunks

PRESSURE_SCALE = 1e5  # [Pa] scale of the IPOPT decision variable
METHODS = ("kkt", "ipopt")
_ELEMENT = 6  # per-element parameters of the IPOPT block: D, W, κ, μ, SF, objective weight


@dataclass(frozen=True)
class Solution:
    """Minimum pressure per element, (S, segments) arrays [Pa]; ``inf`` where no pressure ≤ 100 MPa holds."""

    pressure: np.ndarray
    slip_active: np.ndarray  # True where no slip (not contact) sets the pressure
    method: str
    iterations: int


def slip_binds(pressure: np.ndarray, elements: Elements) -> np.ndarray:
    """True where no slip, not contact, sets the pressure: P > max(P_a(κW), 0) beyond round-off."""
    out = np.empty(pressure.shape[::-1], dtype=bool)
    for part in chunks(pressure.shape[0]):
        p = pressure[part].T
        out[:, part] = np.isfinite(p) & (p > np.maximum(elements.anchoring[part].T, 0.0) * (1 + 1e-12) + 1e-9)
    return out.T


def solve(muscles: tuple[Muscle, ...], elements: Elements, supply: float, *, method: str = "kkt") -> Solution:
    """Solve the planning NLP for every element with the chosen method."""
    if method not in METHODS:
        raise ValueError(f"unknown method {method!r}; choose one of {METHODS}")
    pressure = elements.least_pressure
    iterations = 0
    if method == "ipopt":
        pressure, iterations = _solve_ipopt(muscles, elements, supply, pressure)
    slip_active = slip_binds(pressure, elements)
    return Solution(pressure, slip_active, method, iterations)


def _element_function(structure: Structure):
    """Scaled no-slip margin and objective of one element (x = P/P_scale), for the IPOPT block."""
    import casadi as ca

    sym = Muscle.symbolic(structure)
    x = ca.SX.sym("x")
    q = ca.SX.sym("q", _ELEMENT)
    diameter, load, kappa, friction, safety_factor, weight = (q[i] for i in range(_ELEMENT))
    holding = friction * math.pi * sym.muscle.radial_force(PRESSURE_SCALE * x, diameter, kappa * load,
                                                           clip=False)
    margin = (holding - safety_factor * load) / ca.fmax(safety_factor * load, 1.0)
    return ca.Function("plan_element", [x, sym.p, q], [weight * x, margin])


@cache
def block_solver(structure: Structure, size: int):
    """IPOPT on a block of ``size`` elements of one muscle; built once per (structure, size)."""
    import casadi as ca

    from pampipe.runtime import ipopt as nlp

    element = _element_function(structure)
    x = ca.MX.sym("x", size)
    p_muscle = ca.MX.sym("muscle", structure.size)
    q = ca.MX.sym("q", _ELEMENT, size)
    objective, margin = element.map(size)(x.T, p_muscle, q)
    problem = {"x": x, "p": ca.vertcat(p_muscle, ca.vec(q)), "f": ca.sum2(objective), "g": margin.T}
    return nlp.nlpsol("plan_block", problem, ipopt={"tol": 1e-11, "constr_viol_tol": 1e-11,
                                                   "mu_oracle": "probing"})


def _solve_ipopt(muscles, e: Elements, supply: float, least: np.ndarray, *, block: int | None = None):
    """Solve the NLP with IPOPT in fixed-size blocks per segment (elements no pressure holds are left out).

    The box is [max(P_a(κW), 0), supply] where the supply holds the load, else [.., 100 MPa].
    """
    from pampipe.runtime import ipopt as nlp

    pressure = np.full(least.shape, np.inf)
    iterations = 0
    lower = e.lower_bound / PRESSURE_SCALE
    upper = np.where(least <= supply, supply, PRESSURE_LIMIT) / PRESSURE_SCALE
    for i, muscle in enumerate(muscles):
        index = np.flatnonzero(np.isfinite(least[:, i]))
        if index.size == 0:
            continue
        size = block or (16 if index.size <= 16 else 512)
        solver = block_solver(muscle.structure, size)
        weight = e.volume[:, i] / e.volume[index, i].max()
        params = np.stack([e.diameter[:, i], e.load[:, i], np.full(e.load.shape[0], e.kappa),
                           e.friction[:, i], np.full(e.load.shape[0], e.safety_factor), weight])
        for start in range(0, index.size, size):
            part = index[start:start + size]
            take = np.concatenate([part, np.full(size - part.size, part[0])])  # pad with a copy
            result, stats = nlp.solve(
                solver, what="IPOPT on the planning NLP",
                x0=np.minimum(upper[take, i], lower[take, i] + 1.0),
                p=np.concatenate([muscle.parameter_vector(), params[:, take].T.ravel()]),
                lbx=lower[take, i], ubx=upper[take, i], lbg=0.0, ubg=np.inf)
            iterations += stats.iterations
            pressure[part, i] = np.asarray(result["x"]).ravel()[:part.size] * PRESSURE_SCALE
    return pressure, iterations
