"""The identification NLP (docs/physics.md §6), built once per problem structure and cached.

Everything that depends on the data enters through the parameter vector p (the sufficient
statistics of :mod:`pampipe.identify.statistics`, the Drucker grid rows, scales); the symbolic
graph depends only on the :class:`Structure` (mode, objective, degree, number of axial groups,
pressure levels per radial test, pipes, grid size), never on the number of rows.

Decision vector x (MPa): the blocks named by :meth:`Structure.blocks`: ``theta`` (the muscle's
moduli [a₁, b₁, a₂, b₂]), ``pipe<k>`` (``per_pipe``: separate moduli for the k-th pipe diameter),
``contact`` (``contact_increment``: Δθ, either the two constant terms Δa₁₀, Δa₂₀ or all of them).

Sum of squares:
* axial group g: ‖R_g θ − z_g‖² + rest_g (exact);
* radial bin b with u(x) = u₀ + u₁d + u₂d² about x̄ (d = x − x̄): with m = s·softplus(u₀/s) and
  w = sigmoid(u₀/s) (the smoothed contact switch, width s = ``contact_smoothing``)
  SSE_b = n(m − ȳ)² + w[2(m − ȳ)u₂Σd² + u₁²Σd² + u₂²Σd⁴ + 2u₁u₂Σd³ − 2u₁Σde − 2u₂Σd²e] + Σe²,
  exact (= Σ(u(x_i) − y_i)²) in a bin wholly above anchoring (w = 1) and (= Σy_i²) wholly below
  (w = 0); only a bin that straddles the anchoring pressure is smoothed.
  Above anchoring u = c₀ + c₁x, plus, with contact increments (docs/physics.md §9d),
  (x − x_a)₊(e₀ + e₁x) where x_a = −c₀/c₁ is the anchoring pressure; (·)₊ is a softplus of width
  ``SMOOTH_X`` (1 kPa).

Objective: ``least_squares`` Σ SSE / scale; ``sum_rmse`` Σ over (test, pressure level) of
√(SSE/n + ε_s) / scale (the paper's metric). An optional Gaussian prior adds λ‖θ − θ₀‖² to the sum
of squares. The scale (the value at the initial guess) keeps IPOPT's objective of order one.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from functools import lru_cache

import casadi as ca
import numpy as np

from pampipe.identify.statistics import SUB_BINS
from pampipe.model.ops import softplus
from pampipe.nlp import nlpsol

#: Width of the softplus in (x − x_a)₊, in units of P_ref (1e-3 → 1 kPa at P_ref = 1 MPa).
SMOOTH_X = 1e-3


@dataclass(frozen=True)
class Structure:
    """Everything the symbolic NLP depends on (the cache key)."""

    mode: str  # shared | per_pipe | contact_increment
    objective: str  # least_squares | sum_rmse
    n_theta: int  # 4(degree + 1)
    axial_groups: int  # 0 without axial tests
    radial: tuple[tuple[int, int], ...]  # (pressure levels, pipe index) per radial test
    pipes: int
    grid_rows: int  # Drucker rows per moduli block (0: no constraint)
    contact_rows: int  # Drucker rows of the anchored (contact) state
    contact_terms: str  # constant | full
    prior: str  # none | fixed | axial
    max_iterations: int
    tolerance: float

    @property
    def n_contact(self) -> int:
        return 2 if self.contact_terms == "constant" else self.n_theta

    def blocks(self) -> list[tuple[str, int]]:
        """Decision-vector blocks (name, size) in order."""
        out = []
        if self.axial_groups or self.mode != "per_pipe":
            out.append(("theta", self.n_theta))
        if self.mode == "per_pipe":
            out += [(f"pipe{k}", self.n_theta) for k in range(self.pipes)]
        if self.mode == "contact_increment":
            out.append(("contact", self.n_contact))
        return out

    def radial_block(self, pipe: int) -> str:
        return f"pipe{pipe}" if self.mode == "per_pipe" else "theta"

    def contact_selection(self) -> np.ndarray:
        """S (n_theta × n_contact) with Δθ = S·x_contact."""
        if self.contact_terms == "full":
            return np.eye(self.n_theta)
        k = self.n_theta // 4
        s = np.zeros((self.n_theta, 2))
        s[0, 0] = s[2 * k, 1] = 1.0  # Δa₁₀ and Δa₂₀
        return s

    def parameters(self) -> list[tuple[str, tuple[int, int]]]:
        """Parameter-vector entries (name, (rows, cols)), stored column-major."""
        p, g = self.n_theta, self.axial_groups
        out = [("scale", (1, 1)), ("scale_sse", (1, 1)), ("smooth", (1, 1)), ("eps", (1, 1))]
        if g:
            out += [("ax_r", (p, p * g)), ("ax_z", (p, g)), ("ax_rest", (1, g)), ("ax_n", (1, g))]
        for j, (levels, _) in enumerate(self.radial):
            out += [(f"rad{j}_coef", (2 * p + 2, 1)), (f"rad{j}_mom", (9, levels * SUB_BINS))]
        if self.grid_rows:
            out.append(("grid", (self.grid_rows, p)))
        if self.contact_rows:
            out += [("cgrid_base", (self.contact_rows, p)), ("cgrid_incr", (self.contact_rows, p))]
        if self.prior != "none":
            out.append(("prior_weight", (1, 1)))
        if self.prior == "fixed":
            out.append(("prior_target", (p, 1)))
        return out


class Layout:
    """Packs named numpy arrays into p and slices the symbol p back into named matrices."""

    def __init__(self, entries):
        self.entries = entries
        self.size = sum(r * c for _, (r, c) in entries)

    def symbols(self, p):
        out, at = {}, 0
        for name, (r, c) in self.entries:
            out[name] = ca.reshape(p[at:at + r * c], r, c)
            at += r * c
        return out

    def pack(self, values: dict) -> np.ndarray:
        parts = []
        for name, (r, c) in self.entries:
            value = np.asarray(values[name], dtype=float)
            if value.size != r * c:
                raise ValueError(f"parameter {name}: expected {r}x{c} values, got {value.shape}")
            parts.append(value.reshape(r, c).ravel(order="F"))
        return np.concatenate(parts)


@dataclass(frozen=True)
class Problem:
    """A built NLP: the IPOPT solver and helper functions, all taking (x, p)."""

    structure: Structure
    layout: Layout
    solver: ca.Function
    sse: ca.Function  # (x, p) -> Σ SSE [N²]
    hessian: ca.Function  # (x, p) -> ∇²[(SSE + prior)/2] [N²/MPa²]
    constraints: ca.Function  # (x, p) -> g (normalised Drucker rows, ≥ 0)
    build_time: float  # [s]
    n_x: int
    n_g: int
    n_nodes: int  # symbolic size of the objective (independent of the row count)


def sigmoid(t):
    return 0.5 * (1 + ca.tanh(t / 2))


@lru_cache(maxsize=32)
def build_problem(structure: Structure) -> Problem:
    """Build (once per structure) the IPOPT solver of the identification NLP."""
    started = time.perf_counter()
    layout = Layout(structure.parameters())
    p = ca.SX.sym("p", layout.size)
    par = layout.symbols(p)
    blocks = structure.blocks()
    x = ca.SX.sym("x", sum(size for _, size in blocks))
    var, at = {}, 0
    for name, size in blocks:
        var[name] = x[at:at + size]
        at += size
    n = structure.n_theta

    group_sse, group_n = [], []
    if structure.axial_groups:
        theta = var["theta"]
        for g in range(structure.axial_groups):
            residual = ca.mtimes(par["ax_r"][:, g * n:(g + 1) * n], theta) - par["ax_z"][:, g]
            group_sse.append(ca.sumsqr(residual) + par["ax_rest"][g])
            group_n.append(par["ax_n"][g])
    contact = None
    if structure.mode == "contact_increment":
        contact = ca.mtimes(ca.DM(structure.contact_selection()), var["contact"])
    for j, (levels, pipe) in enumerate(structure.radial):
        bins = _radial_bins(par[f"rad{j}_coef"], par[f"rad{j}_mom"], var[structure.radial_block(pipe)],
                            contact, par["smooth"], n)
        per_level = ca.sum1(ca.reshape(bins, SUB_BINS, levels))
        counts = ca.sum1(ca.reshape(par[f"rad{j}_mom"][0, :], SUB_BINS, levels))
        group_sse += [per_level[k] for k in range(levels)]
        group_n += [counts[k] for k in range(levels)]

    sse = ca.sum1(ca.vertcat(*group_sse)) if group_sse else ca.SX(0)
    prior = _prior(structure, var, par)
    if structure.objective == "sum_rmse":
        rmse = [ca.sqrt(ca.fmax(s, 0) / ca.fmax(k, 1) + par["eps"]) for s, k in zip(group_sse, group_n,
                                                                                       strict=True)]
        f = ca.sum1(ca.vertcat(*rmse)) / par["scale"] + prior / par["scale_sse"]
    else:
        f = (sse + prior) / par["scale"]
    g = _drucker(structure, var, par, contact)

    solver = nlpsol("identify", {"x": x, "p": p, "f": f, "g": g},
                    ipopt={"max_iter": structure.max_iterations, "tol": structure.tolerance,
                           "mu_strategy": "monotone"})
    sse_fn = ca.Function("sse", [x, p], [sse])
    hess, _ = ca.hessian((sse + prior) / 2, x)
    hess_fn = ca.Function("hessian", [x, p], [hess])
    g_fn = ca.Function("drucker", [x, p], [g])
    nodes = ca.Function("objective", [x, p], [f]).n_nodes()
    return Problem(structure, layout, solver, sse_fn, hess_fn, g_fn, time.perf_counter() - started,
                   x.shape[0], g.shape[0], nodes)


def _radial_bins(coef, mom, theta, contact, smooth, n):
    """SSE of every pressure bin of one radial test (1 × bins), see the module docstring."""
    a0, a1, area, load = coef[:n], coef[n:2 * n], coef[2 * n], coef[2 * n + 1]
    c0 = ca.dot(a0, theta) - load
    c1 = area + ca.dot(a1, theta)
    count, xbar, ybar = mom[0, :], mom[1, :], mom[2, :]
    sdd, sddd, sdddd, sde, sdde, see = (mom[k, :] for k in range(3, 9))
    u0 = c0 + c1 * xbar
    u1 = c1 * ca.DM.ones(1, xbar.shape[1])
    u2 = ca.DM.zeros(1, xbar.shape[1])
    if contact is not None:
        e0, e1 = ca.dot(a0, contact), ca.dot(a1, contact)
        x_anchor = -c0 / ca.fmax(c1, 1e-3 * area)
        t = (xbar - x_anchor) / SMOOTH_X
        engaged, slope = SMOOTH_X * softplus(t), sigmoid(t)
        increment = e0 + e1 * xbar
        u0 = u0 + engaged * increment
        u1 = u1 + slope * increment + engaged * e1
        u2 = slope * e1
    t = u0 / smooth
    m, w = smooth * softplus(t), sigmoid(t)
    gap = m - ybar
    inner = (2 * gap * u2 * sdd + u1**2 * sdd + u2**2 * sdddd + 2 * u1 * u2 * sddd - 2 * u1 * sde
             - 2 * u2 * sdde)
    return count * gap**2 + w * inner + see


def _prior(structure: Structure, var, par):
    if structure.prior == "none":
        return ca.SX(0)
    weight = par["prior_weight"]
    if structure.prior == "fixed":
        names = [name for name, _ in structure.blocks() if name != "contact"]
        return weight * sum(ca.sumsqr(var[name] - par["prior_target"]) for name in names)
    if structure.mode == "per_pipe":  # toward the axial moduli
        return weight * sum(ca.sumsqr(var[f"pipe{k}"] - var["theta"]) for k in range(structure.pipes))
    return weight * ca.sumsqr(var["contact"])  # contact increments toward zero


def _drucker(structure: Structure, var, par, contact):
    rows = []
    if structure.grid_rows:
        for name, _ in structure.blocks():
            if name != "contact":
                rows.append(ca.mtimes(par["grid"], var[name]))
    if structure.contact_rows:
        rows.append(ca.mtimes(par["cgrid_base"], var["theta"]) + ca.mtimes(par["cgrid_incr"], contact))
    return ca.vertcat(*rows) if rows else ca.SX(0, 1)
