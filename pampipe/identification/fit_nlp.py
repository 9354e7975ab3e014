"""The identification NLP (docs/physics.md §6), built once per problem structure and cached (memory, disk).

Everything that depends on the data enters through the parameter vector p (the statistics of
:mod:`pampipe.identification.statistics` and :mod:`pampipe.identification.moment_cells`, the stated geometry,
the
Drucker grid rows, scales); the graph depends only on the :class:`Structure`, never on the number
of rows. Cells are evaluated by one CasADi function mapped over a fixed capacity, so the graph does
not grow with the number of cells either. The built functions are saved on disk
(:func:`pampipe.runtime.ipopt.cached_functions`), so a new process loads them instead of building.

Decision vector x: the blocks named by :meth:`Structure.blocks`: ``theta`` (the muscle's moduli
[a₁, b₁, a₂, b₂], MPa), ``pipe<k>`` (``per_pipe``), ``contact`` (``contact_increment``) and
``geometry`` (calibrated geometry: α₀ in deg, L₀ and t₀ in mm, in :data:`GEOMETRY` order).

Sum of squares:
* axial group g (QR, measured rows at the stated geometry): ‖R_g θ − z_g‖² + rest_g (exact);
* axial cell (slack rows; every axial row when calibrating): see :mod:`pampipe.identification.moment_cells`; a
  slack cell is either live (the model F applies) or clipped (max(0, F) = 0), a flag in p that the
  fit updates between solves until no cell changes side (an exact hinge, no smoothing); at
  the stated geometry the model at a cell's mean and its derivatives are linear rows in θ computed
  before the fit; with the geometry free one SX function of (cell, θ, geometry) gives the cell's
  sum of squares and its Gauss-Newton Hessian, mapped over the cells (IPOPT gets that Hessian);
* radial bin b with u(x) = u₀ + u₁d + u₂d² about x̄ (d = x − x̄): with m = s·softplus(u₀/s) and
  w = sigmoid(u₀/s) (the smoothed contact switch, width s = ``contact_smoothing``)
  SSE_b = n(m − ȳ)² + w[2(m − ȳ)u₂Σd² + u₁²Σd² + u₂²Σd⁴ + 2u₁u₂Σd³ − 2u₁Σde − 2u₂Σd²e] + Σe²,
  exact (= Σ(u(x_i) − y_i)²) in a bin wholly above anchoring (w = 1) and (= Σy_i²) wholly below
  (w = 0); only a bin that straddles the anchoring pressure is smoothed.
  Above anchoring u = c₀ + c₁x with c₀ = A(φ₀·θ − F_a), c₁ = A(area·P_ref + φ₁·θ) at the pipe's
  length L(D_p), computed here from the (possibly calibrated) geometry, plus, with contact
  increments (docs/physics.md §9d), (x − x_a)₊(e₀ + e₁x) where x_a = −c₀/c₁ is the anchoring
  pressure; (·)₊ is a softplus of width ``SMOOTH_X`` (1 kPa).

Objective: ``least_squares`` Σ SSE / scale; ``sum_rmse`` Σ over (test, pressure level) of
√(SSE/n + ε_s) / scale (the paper's metric). An optional Gaussian prior adds λ‖θ − θ₀‖² to the sum
of squares. The scale (the value at the initial guess) keeps IPOPT's objective of order one.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, replace
from functools import lru_cache

import casadi as ca
import numpy as np

from pampipe.identification.moment_cells import FIELDS, gram
from pampipe.identification.statistics import SUB_BINS
from pampipe.model import braid, forces
from pampipe.model.ops import softplus
from pampipe.model.pam import Geometry
from pampipe.runtime.ipopt import cached_functions, nlpsol

MPA = 1e6
#: Width of the softplus in (x − x_a)₊, in units of P_ref (1e-3 → 1 kPa at P_ref = 1 MPa).
SMOOTH_X = 1e-3
#: Derivatives of the model at a cell mean, rows of the linear cells (:func:`_linear_cells`).
DERIVATIVES = ("u", "ux", "ul", "ull", "uxl")
#: Calibratable geometry: name → (index in Geometry.as_vector(), SI value of one unit of x).
GEOMETRY = {"braid_angle": (2, np.pi / 180), "initial_length": (0, 1e-3), "bladder_thickness": (3, 1e-3)}


@dataclass(frozen=True)
class Structure:
    """Everything the symbolic NLP depends on (the cache key)."""

    mode: str  # shared | per_pipe | contact_increment
    objective: str  # least_squares | sum_rmse
    n_theta: int  # 4(degree + 1)
    axial_groups: int  # axial groups in the objective (least_squares: 1 or 0)
    qr: bool  # exact QR statistics of measured axial rows (stated geometry)
    cells: int  # cell capacity (0: no cells)
    radial: tuple[tuple[int, int], ...]  # (pressure levels, pipe index) per radial test
    pipes: int
    grid_rows: int  # Drucker rows per moduli block (0: no constraint)
    contact_rows: int  # Drucker rows of the anchored (contact) state
    contact_terms: str  # constant | full
    prior: str  # none | fixed | axial | gaussian
    calibrate: tuple[str, ...]  # calibrated geometry, in GEOMETRY order
    wall: str  # thick | thin
    max_iterations: int
    tolerance: float

    @property
    def n_contact(self) -> int:
        return 2 if self.contact_terms == "constant" else self.n_theta

    def blocks(self) -> list[tuple[str, int]]:
        """Decision-vector blocks (name, size) in order."""
        out = []
        if self.axial_groups or self.qr or self.cells or self.mode != "per_pipe":
            out.append(("theta", self.n_theta))
        if self.mode == "per_pipe":
            out += [(f"pipe{k}", self.n_theta) for k in range(self.pipes)]
        if self.mode == "contact_increment":
            out.append(("contact", self.n_contact))
        if self.calibrate:
            out.append(("geometry", len(self.calibrate)))
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
        out = [("scale", (1, 1)), ("scale_sse", (1, 1)), ("smooth", (1, 1)), ("eps", (1, 1)),
               ("geometry", (4, 1))]
        if self.qr:
            out += [("ax_r", (p, p * g)), ("ax_z", (p, g)), ("ax_rest", (1, g))]
        if g:
            out.append(("ax_n", (1, g)))
        if self.cells:
            out.append(("cells", (len(FIELDS), self.cells)))
            if not self.calibrate:
                out += [(f"cell_{k}", (self.cells, p + 1)) for k in DERIVATIVES]
            if self.objective == "sum_rmse":
                out.append(("cell_groups", (g, self.cells)))
        for j, (levels, _) in enumerate(self.radial):
            out += [(f"rad{j}_test", (2, 1)), (f"rad{j}_mom", (9, levels * SUB_BINS))]
        if self.grid_rows:
            out.append(("grid", (self.grid_rows, p)))
        if self.contact_rows:
            out += [("cgrid_base", (self.contact_rows, p)), ("cgrid_incr", (self.contact_rows, p))]
        if self.prior != "none":
            out.append(("prior_weight", (1, 1)))
        if self.calibrate:  # the stated geometry as the calibration's prior: (weight, stated) per entry
            out.append(("geometry_prior", (len(self.calibrate), 2)))
        if self.prior in ("fixed", "gaussian"):
            out.append(("prior_target", (p, 1)))
        if self.prior == "gaussian":
            out.append(("prior_precision", (p, p)))
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

    def pack(self, values: dict) -> ca.DM:
        """p as a CasADi column: converted once, not at every call (a numpy p of 1.6·10⁴ entries costs
        1.6 ms a call to convert, three times the Hessian's evaluation); from a list of floats, which
        CasADi converts 3× faster than the numpy array (0.9 ms against 2.9 ms), to the same numbers."""
        parts = []
        for name, (r, c) in self.entries:
            value = np.asarray(values[name], dtype=float)
            if value.size != r * c:
                raise ValueError(f"parameter {name}: expected {r}x{c} values, got {value.shape}")
            parts.append(value.reshape(r, c).ravel(order="F"))
        return ca.DM(np.concatenate(parts).tolist())


@dataclass(frozen=True)
class Problem:
    """A built NLP: the IPOPT solver and helper functions, all taking (x, p)."""

    structure: Structure
    layout: Layout
    solver: ca.Function
    sse: ca.Function  # (x, p) -> Σ SSE [N²]
    hessian: ca.Function  # (x, p) -> ∇²[(SSE + prior)/2] [N²/unit²]
    gradient: ca.Function  # (x, p) -> ((SSE + prior)/2, its gradient)
    constraints: ca.Function  # (x, p) -> (g ≥ 0, ∂g/∂x): the Drucker rows, linear in x
    build_time: float  # [s] to build, or to load from the disk cache
    origin: str  # "built" or "disk"
    n_x: int
    n_g: int
    n_nodes: int  # symbolic size of the sum of squares (independent of the row count)


def sigmoid(t):
    return 0.5 * (1 + ca.tanh(t / 2))


def with_held_room(structure: Structure) -> Structure:
    """``structure``, or the NLP this process already holds (:func:`build_problem`) that differs from it only
    by a larger cell capacity, the smallest such. Empty cells add exact zeros to the sums of squares and
    their derivatives (:func:`.moment_cells.capacity`), so the fit is the same, and no second NLP is loaded
    (0.05-0.1 s): the model error's refits on a subset of a large experiment hold fewer slack cells than its
    fit."""
    if not structure.cells:
        return structure
    roomier = [held for held in _HELD if held.cells >= structure.cells
               and replace(held, cells=structure.cells) == structure]
    return min(roomier, key=lambda held: held.cells, default=structure)


#: The structures :func:`build_problem` has built or loaded in this process.
_HELD: list[Structure] = []


@lru_cache(maxsize=32)
def build_problem(structure: Structure) -> Problem:
    """The IPOPT solver of the identification NLP: from memory, the disk cache, or built."""
    started = time.perf_counter()
    _HELD.append(structure)
    functions, origin = cached_functions("identify", repr(structure), lambda: _build(structure))
    layout = Layout(structure.parameters())
    solver = functions["solver"]
    return Problem(structure, layout, solver, functions["sse"], functions["hessian"], functions["gradient"],
                   functions["constraints"],
                   time.perf_counter() - started, origin, int(solver.size1_in("x0")),
                   int(solver.size1_in("lbg")), int(functions["sse"].n_nodes()))


def _build(structure: Structure) -> dict[str, ca.Function]:
    layout = Layout(structure.parameters())
    p = ca.MX.sym("p", layout.size)
    par = layout.symbols(p)
    blocks = structure.blocks()
    x = ca.MX.sym("x", sum(size for _, size in blocks))
    var, at = {}, 0
    for name, size in blocks:
        var[name] = x[at:at + size]
        at += size
    geometry = _geometry(structure, par["geometry"], var.get("geometry"))
    n = structure.n_theta

    axial_sse = ca.MX(0)
    group_sse = []
    cell_hessian = None
    if structure.qr:
        theta = var["theta"]
        for g in range(structure.axial_groups):
            residual = ca.mtimes(par["ax_r"][:, g * n:(g + 1) * n], theta) - par["ax_z"][:, g]
            group_sse.append(ca.sumsqr(residual) + par["ax_rest"][g])
    if structure.cells and structure.calibrate:
        axial_sse, cell_hessian = _calibration_cells(structure, par, var, geometry, x)
    elif structure.cells:
        cell_sse = _linear_cells(par, var["theta"])
        if structure.objective == "sum_rmse":
            by_group = ca.mtimes(par["cell_groups"], cell_sse)
            group_sse = [by_group[g] + (group_sse[g] if group_sse else 0)
                         for g in range(structure.axial_groups)]
        else:
            axial_sse = ca.sum1(cell_sse)
    group_n = [par["ax_n"][g] for g in range(structure.axial_groups)]
    contact = None
    if structure.mode == "contact_increment":
        contact = ca.mtimes(ca.DM(structure.contact_selection()), var["contact"])
    for j, (levels, pipe) in enumerate(structure.radial):
        coef = _radial_coefficients(par[f"rad{j}_test"], geometry, n)
        bins = _radial_bins(coef, par[f"rad{j}_mom"], var[structure.radial_block(pipe)], contact,
                            par["smooth"], n)
        per_level = ca.sum1(ca.reshape(bins, SUB_BINS, levels))
        counts = ca.sum1(ca.reshape(par[f"rad{j}_mom"][0, :], SUB_BINS, levels))
        group_sse += [per_level[k] for k in range(levels)]
        group_n += [counts[k] for k in range(levels)]

    sse = axial_sse + (ca.sum1(ca.vertcat(*group_sse)) if group_sse else 0)
    prior = _prior(structure, var, par)
    if structure.objective == "sum_rmse":
        rmse = [ca.sqrt(ca.fmax(s, 0) / ca.fmax(k, 1) + par["eps"]) for s, k in zip(group_sse, group_n,
                                                                                       strict=True)]
        f = ca.sum1(ca.vertcat(*rmse)) / par["scale"] + prior / par["scale_sse"]
    else:
        f = (sse + prior) / par["scale"]
    g = _drucker(structure, var, par, contact)

    options = {}
    if cell_hessian is None:
        hess = ca.hessian((sse + prior) / 2, x)[0]
    else:  # the cells' Hessian comes from inside the mapped function (MX AD through map is slow)
        rest = ca.hessian(sse - axial_sse + prior, x)[0]
        hess = (rest + cell_hessian) / 2
        lam_f, lam_g = ca.MX.sym("lam_f"), ca.MX.sym("lam_g", g.shape[0])
        options["hess_lag"] = ca.Function("nlp_hess_l", [x, p, lam_f, lam_g],
                                          [ca.triu(lam_f * 2 * hess / par["scale"])],
                                          ["x", "p", "lam_f", "lam_g"], ["triu_hess_gamma_x_x"])
    solver = nlpsol("identify", {"x": x, "p": p, "f": f, "g": g},
                    ipopt={"max_iter": structure.max_iterations, "tol": structure.tolerance,
                           "mu_strategy": "monotone"}, **options)
    half = (sse + prior) / 2
    gradient = [half, ca.gradient(half, x)] if not structure.calibrate else [half, ca.MX.nan(x.shape[0])]
    return {"solver": solver, "sse": ca.Function("sse", [x, p], [sse]),
            "hessian": ca.Function("hessian", [x, p], [hess]),
            "gradient": ca.Function("gradient", [x, p], gradient),
            "constraints": ca.Function("constraints", [x, p], [g, ca.jacobian(g, x)])}


def _linear_cells(par, theta):
    """SSE of every cell (C × 1) at the stated geometry, where F_ax is linear in θ: the model at the
    cell mean and its derivatives (u, u_x, u_L, u_LL, u_xL) are rows ``off + Φθ`` computed before the fit."""
    c = par["cells"].T  # C × fields
    derivatives = [par[f"cell_{k}"][:, 0] + ca.mtimes(par[f"cell_{k}"][:, 1:], theta) for k in DERIVATIVES]
    return _cell_sse([c[:, k] for k in range(len(FIELDS))], *derivatives)


def _cell_sse(moments, u, u_x, u_l, u_ll, u_xl):
    """wᵀGw of :mod:`pampipe.identification.moment_cells` (elementwise over cells); a clipped cell predicts
    0."""
    live = 1 - moments[FIELDS.index("clipped")]
    ybar = moments[FIELDS.index("y")]
    w = [live * u - ybar, live * u_x, live * u_l, live * u_ll / 2, live * u_xl, -1]
    g = gram(moments)
    total = 0
    for i in range(len(w)):
        for j in range(len(w)):
            total = total + w[i] * g[i][j] * w[j]
    return total


def _calibration_cells(structure: Structure, par, var, geometry, x):
    """(Σ cell SSE, its Gauss-Newton Hessian in x) with the geometry free.

    One SX function per cell, mapped over the cell capacity: the SSE wᵀGw and 2JᵀGJ with
    J = ∂w/∂(θ, geometry) (exact in θ, where w is linear; it drops the curvature of w in the geometry
    times the residual, the usual least-squares approximation, at half the cost of the exact
    Hessian); the Hessian in x by the chain rule.
    """
    n = structure.n_theta
    moments = ca.SX.sym("cell", len(FIELDS))
    theta = ca.SX.sym("theta", n)
    g = ca.SX.sym("geometry", 4)
    shape = Geometry(g[0], g[1], g[2], g[3], structure.wall)
    xbar, length = moments[FIELDS.index("x")], moments[FIELDS.index("l")]
    u = forces.axial_force(xbar * MPA, length, shape, theta * MPA, MPA)
    u_x, u_l = ca.jacobian(u, xbar), ca.jacobian(u, length)
    u_ll, u_xl = ca.jacobian(u_l, length), ca.jacobian(u_x, length)
    column = [moments[k] for k in range(len(FIELDS))]
    sse = _cell_sse(column, u, u_x, u_l, u_ll, u_xl)
    live = 1 - moments[FIELDS.index("clipped")]
    w = live * ca.vertcat(u, u_x, u_l, u_ll / 2, u_xl)
    jac = ca.jacobian(w, ca.vertcat(theta, g))
    gram_ = gram(column)
    block = ca.vertcat(*[ca.horzcat(*gram_[i][:5]) for i in range(5)])
    hess = 2 * ca.mtimes([jac.T, block, jac])
    inputs = [moments, theta, g]
    arguments = (par["cells"], var["theta"], _vector(geometry))
    values = ca.Function("cell", inputs, [sse]).map(structure.cells)(*arguments)
    hessians = ca.Function("cell_hessian", inputs, [ca.reshape(hess, -1, 1)])
    hessians = hessians.map(structure.cells)(*arguments)
    size = n + 4
    z_of_x = ca.jacobian(ca.vertcat(var["theta"], _vector(geometry)), x)
    return ca.sum2(values), ca.mtimes([z_of_x.T, ca.reshape(ca.sum2(hessians), size, size), z_of_x])


def _geometry(structure: Structure, stated, calibrated) -> Geometry:
    """The geometry as symbols: the stated values (p) with the calibrated entries from x."""
    entries = [stated[i] for i in range(4)]
    for k, name in enumerate(structure.calibrate):
        index, unit = GEOMETRY[name]
        entries[index] = calibrated[k] * unit
    return Geometry(*entries, structure.wall)


def _vector(geometry: Geometry):
    return ca.vertcat(geometry.initial_length, geometry.initial_diameter, geometry.braid_angle,
                      geometry.bladder_thickness)


def _radial_coefficients(test, geometry: Geometry, n: int):
    """(A·φ₀, A·φ₁, A·area·P_ref, A·F_a) of u(x) = c₀ + c₁x at the pipe [N/MPa, N], symbolic."""
    diameter, load = test[0], test[1]
    length = braid.length_at_diameter(diameter, geometry)
    amp = braid.amplification_factor(diameter, geometry, length)
    degree = n // 4 - 1
    off0, row0 = forces.axial_force_regressors(0.0, length, geometry, degree, MPA)
    off1, row1 = forces.axial_force_regressors(MPA, length, geometry, degree, MPA)
    phi0 = ca.vertcat(*row0) * MPA
    phi1 = ca.vertcat(*row1) * MPA - phi0
    return amp * phi0, amp * phi1, amp * (off1 - off0), amp * load


def _radial_bins(coef, mom, theta, contact, smooth, n):
    """SSE of every pressure bin of one radial test (1 × bins), see the module docstring."""
    a0, a1, area, load = coef
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
    """The moduli's prior (``fit.prior``) plus the calibrated geometry's: Σ_k w_k (x_k − stated_k)², w_k =
    σ̂²/sd_k² for an entry whose stated sd is sd_k (x units), 0 without one (issue 35)."""
    if not structure.calibrate:
        return _moduli_prior(structure, var, par)
    weight, stated = par["geometry_prior"][:, 0], par["geometry_prior"][:, 1]
    return _moduli_prior(structure, var, par) + ca.dot(weight, (var["geometry"] - stated) ** 2)


def _moduli_prior(structure: Structure, var, par):
    if structure.prior == "none":
        return ca.MX(0)
    weight = par["prior_weight"]
    if structure.prior in ("fixed", "gaussian"):
        names = [name for name, _ in structure.blocks() if name not in ("contact", "geometry")]
        if structure.prior == "fixed":
            return weight * sum(ca.sumsqr(var[name] - par["prior_target"]) for name in names)
        gaps = [var[name] - par["prior_target"] for name in names]
        return weight * sum(ca.dot(gap, ca.mtimes(par["prior_precision"], gap)) for gap in gaps)
    if structure.mode == "per_pipe":  # toward the axial moduli
        return weight * sum(ca.sumsqr(var[f"pipe{k}"] - var["theta"]) for k in range(structure.pipes))
    return weight * ca.sumsqr(var["contact"])  # contact increments toward zero


def _drucker(structure: Structure, var, par, contact):
    rows = []
    if structure.grid_rows:
        for name, _ in structure.blocks():
            if name not in ("contact", "geometry"):
                rows.append(ca.mtimes(par["grid"], var[name]))
    if structure.contact_rows:
        rows.append(ca.mtimes(par["cgrid_base"], var["theta"]) + ca.mtimes(par["cgrid_incr"], contact))
    return ca.vertcat(*rows) if rows else ca.MX(0, 1)
