"""The baseline + effects NLP: shared moduli θ and the parameters η of a set of effects, fitted to cells.

Decision vector x = [θ (MPa; b at P_ref), η of each effect in registry order (display units, O(1))].
Objective: the weighted mean squared force residual over the cells (:mod:`.cells`),

  J(x) = Σ_c w_c (F_model(P̄_c, L̄_c; x) − F̄_c)² / Σ_c w_c,   w_c = n_c (0 for held-out cells),

which is Σ_rows (F_model − F)²/n up to a constant when each cell's rows share (P, L). F_model comes
from the one model door, :class:`pampipe.model.muscle.Muscle`, built by ``Muscle.symbolic`` for the
:class:`~pampipe.model.muscle.Structure` (wall, degree, effects): axial cells use
:meth:`~pampipe.model.muscle.Muscle.axial_force` with both legs (max(0, F) at slack cells, readings
of exactly 0 N, as `identify`'s ``fit.slack: unilateral``), radial cells
:meth:`~pampipe.model.muscle.Muscle.radial_force` (softplus contact switch of width ``SMOOTHING``).
Bounds as in docs/physics.md §6 (a_k0 ∈ [0, 50] MPa, others ±50 MPa) plus each effect parameter's
own bounds; Drucker stability E₁ᵗ ≥ 0, E₂ᵗ ≥ 0 on a fixed (P, L) grid (docs/physics.md §6).

Built once per (effects, wall, degree, padded cell counts): a per-cell residual ``casadi.Function``
(one evaluation for exact cells, the two-point mean of :mod:`.cells` for binned ones) is mapped over
the cells with ``.map(n)``, so the build does not grow with the data (the objective, which IPOPT's line
search evaluates several times per iteration, maps the same residual without its gradient: 11 ms instead of
19 ms at 1,360 cells, the same values bit for bit); cell counts are
padded up to a few fixed sizes (zero-weight cells) so that data sets of similar size share a build.
Every cell value, the weights, the geometry and the grid are NLP parameters; cross-validation only
changes the weights. Two more solvers of the same NLP are built on first use (:data:`VARIANTS`):

* ``warm``: cross-validation's fold refits start from the full fit's primal and dual solution
  (a barrier µ₀ of 1e-6 and no push off the bounds): from a cold barrier (µ₀ = 0.1) the start is
  first pushed off its bounds and IPOPT can wander hundreds of iterations in a flat valley;
* ``trial``: the search's candidate refits stop after :data:`TRIAL_ITERATIONS` iterations (a
  candidate that has not converged by then is a failed trial, as one that fails at 500 was: on six
  round-3 pairs the converged candidate refits took at most 140 iterations, and one failing candidate
  cost 26 s of a pair's 44 s of CPU).
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass
from functools import cache

import casadi as ca
import numpy as np

from pampipe.diagnosis.candidates import (
    CANDIDATES,
    candidate,
    corrected_geometry,
    corrected_vector,
    geometry_part,
    library_part,
    wall_of,
)
from pampipe.model.forces import contact_switch
from pampipe.model.muscle import Muscle, Structure
from pampipe.runtime.ipopt import nlpsol, solve

MPA = 1e6
#: Drucker grid size (pressures × lengths), fixed so that it never changes the build.
GRID = (6, 15)
#: Softplus width of the contact switch [N] (as `identify`'s default contact_smoothing).
SMOOTHING = 1.0
IPOPT_OPTIONS = {"tol": 1e-9, "acceptable_tol": 1e-8, "max_iter": 500, "bound_relax_factor": 1e-8}
#: Iteration limit of the search's candidate refits.
TRIAL_ITERATIONS = 300
#: The stagnation stop of the fold refits: IPOPT's acceptable termination once the objective has moved by
#: less than 1e-7 of itself (or of 1 N²) in each of 5 iterations in a row, with the scaled KKT error
#: below 1e-4. A fold in a flat valley (two effects' columns nearly collinear) otherwise crawls along it
#: to the iteration limit with 7-8 line-search evaluations per iteration; what it predicts for its
#: held-out cells has stopped changing (cross-validation compares RMSEs to :data:`.search.CV_MARGIN`).
STALL = {"acceptable_tol": 1e-4, "acceptable_iter": 5, "acceptable_obj_change_tol": 1e-7}
#: Options of the other solvers of each NLP over IPOPT_OPTIONS: ``warm`` (a fold refit from the full
#: fit's primal-dual solution; a fold that has not converged within 100 iterations is solved again
#: cold as ``fold``, within 100 more, see selection.cross_validate) and ``trial``. On seed 43509 the
#: stall stop took the CV of braid_extensibility + prestrain + geometry:initial_length from 241 s of CPU
#: (three folds at the limits, 100 warm + 500 cold, two of them dropped) to 46 s with the 300-iteration
#: cold limit; the folds that converged both ways agree to 1e-5 of their objective. The five slowest
#: round-3 pairs, CPU s before -> after (with the cheaper objective; same verdicts, names and tie groups):
#: 43509 270 -> 114, 43506 265 -> 201, 43518 156 -> 75, 43514 148 -> 113, 43511 115 -> 99 (load 4-13).
VARIANTS = {"warm": {"max_iter": 100, "warm_start_init_point": "yes", "mu_init": 1e-6,
                     "warm_start_bound_push": 1e-9, "warm_start_bound_frac": 1e-9,
                     "warm_start_slack_bound_push": 1e-9, "warm_start_slack_bound_frac": 1e-9,
                     "warm_start_mult_bound_push": 1e-9, **STALL},
            "fold": {"max_iter": 100, **STALL},
            "trial": {"max_iter": TRIAL_ITERATIONS}}


def canonical(effects) -> tuple[str, ...]:
    """A set of effect names in registry order (the key of every build and every report)."""
    names = set(effects or ())
    for name in names:
        candidate(name)  # unknown names fail here
    return tuple(name for name in CANDIDATES if name in names)


def effect_parameters(effects: tuple[str, ...]) -> list[tuple[str, object]]:
    """[(effect, Parameter)] in the order of η."""
    return [(name, p) for name in effects for p in candidate(name).parameters]


def padded(n: int) -> int:
    """The build size for n cells: the least of {2^j, 1.25·2^j, 1.5·2^j, 1.75·2^j} ≥ n (≥ 16)."""
    if n <= 16:
        return 16 if n else 0
    base = 2 ** (math.ceil(math.log2(n)) - 1)
    return next(int(base * f) for f in (1.25, 1.5, 1.75, 2.0) if base * f >= n)


#: The NLP's data blocks: (kind, binned). Each column is one cell: P̄, x, y, F̄, w, s_P, s_x, p_leg,
#: slack with x, y = L̄, leg (axial) or D_p, F_a (radial), s the within-cell spread of the swept
#: coordinate, p_leg the sign of dP/dt and slack 1 for slack cells (axial: the model is max(0, F)
#: there, as softplus of width SMOOTHING); a binned cell is evaluated at (P̄ ± s_P, x ± s_x) and
#: the two values averaged.
BLOCKS = (("axial", False), ("axial", True), ("radial", False), ("radial", True))
ROWS = 9


@dataclass(frozen=True)
class Blocks:
    """Cells as NLP data, one (7, N) array per entry of :data:`BLOCKS`, padded with zero-weight
    copies; ``index[b]`` gives the cell of each real column of block b."""

    data: tuple[np.ndarray, ...]
    index: tuple[np.ndarray, ...]

    @property
    def sizes(self) -> tuple[int, ...]:
        return tuple(d.shape[1] for d in self.data)

    def weighted(self, weight: np.ndarray) -> Blocks:
        """The same blocks with cell weights ``weight`` (padding stays at 0)."""
        data = []
        for block, index in zip(self.data, self.index, strict=True):
            block = block.copy()
            block[4, :index.size] = weight[index]
            data.append(block)
        return Blocks(tuple(data), self.index)

    def scatter(self, values: np.ndarray, size: int) -> np.ndarray:
        """Values given per column of the concatenated blocks (first axis) back in cell order."""
        out = np.zeros((size, *np.shape(values)[1:]))
        start = 0
        for block, index in zip(self.data, self.index, strict=True):
            out[index] = values[start:start + index.size]
            start += block.shape[1]
        return out


def blocks_of(cells) -> Blocks:
    """NLP data of :class:`.cells.Cells` (weights = counts)."""
    axial_x = np.where(cells.axial, cells.length, cells.diameter)
    axial_y = np.where(cells.axial, cells.leg, cells.load)
    spread_p = np.where(cells.swept_length, 0.0, cells.spread)
    spread_x = np.where(cells.swept_length, cells.spread, 0.0)
    binned = cells.spread > 0
    data, indices = [], []
    for kind, spread in BLOCKS:
        index = np.flatnonzero((cells.axial == (kind == "axial")) & (binned == spread))
        n = index.size
        out = np.zeros((ROWS, padded(n)))
        if n:
            out[:, :n] = np.vstack([cells.pressure[index], axial_x[index], axial_y[index], cells.force[index],
                                    cells.count[index], spread_p[index], spread_x[index],
                                    cells.pressure_leg[index], cells.slack[index].astype(float)])
            out[:4, n:] = out[:4, :1]  # padding: copies of the first cell, weight 0
        data.append(out)
        indices.append(index)
    return Blocks(tuple(data), tuple(indices))


@dataclass(frozen=True)
class Problem:
    """A built NLP and its helpers: residual and Jacobian of the mapped cells, Drucker moduli."""

    solver: ca.Function
    residuals: ca.Function  # (x, p) -> unweighted residuals of all columns (blocks in order)
    jacobian: ca.Function  # (x, p) -> ∂(√w·residual)/∂x
    variant: Callable[[str], ca.Function]  # the same NLP's solver with VARIANTS[kind] (built on first call)
    n_theta: int
    n_eta: int
    build_time: float


@cache
def build_problem(effects: tuple[str, ...], wall: str, degree: int, sizes: tuple[int, ...]) -> Problem:
    """The NLP for one set of effects (() : the baseline) and one padded data size (built once)."""
    started = time.perf_counter()
    wall = wall_of(wall, effects)
    structure = Structure(wall, degree, False, library_part(effects))
    sym = Muscle.symbolic(structure)
    params = effect_parameters(effects)
    n_library = len(effect_parameters(library_part(effects)))
    n_theta = structure.n_theta
    row, smooth = ca.SX.sym("row", ROWS), ca.SX.sym("smooth")
    muscle = sym.muscle
    axial = muscle.axial_force(row[0], row[1], leg=row[2], pressure_leg=row[7])
    unilateral = row[8] * contact_switch(axial, smooth) + (1 - row[8]) * axial  # slack cells: max(0, F)
    models = {"axial": ca.Function("axial_model", [row, sym.p, smooth], [unilateral]),
              "radial": ca.Function("radial_model", [row, sym.p, smooth],
                                    [muscle.radial_force(row[0], row[1], row[2], smoothing=smooth)])}
    # decision variables: θ in MPa (b at P_ref = 1 MPa in the fit) and η in display units
    xs = ca.SX.sym("x", n_theta + len(params))
    g, pref = ca.SX.sym("g", 4), ca.SX.sym("pref")
    scales = ca.DM([p.scale for _, p in params[:n_library]]) if n_library else ca.DM.zeros(0, 1)
    g_fit = ca.vertcat(*_geometry(g, xs, effects, n_theta))
    p_expr = ca.vertcat(g_fit, pref, xs[:n_theta] * MPA, xs[n_theta:n_theta + n_library] * scales)
    inputs = [row, xs, g, pref, smooth]
    shift = ca.vertcat(row[5], row[6], ca.DM.zeros(ROWS - 2, 1))
    cell_functions, value_functions = [], []
    for kind, binned in BLOCKS:
        model = models[kind]
        if binned:  # two-point (unscented) mean over the cell's spread
            value = (model(row + shift, p_expr, smooth) + model(row - shift, p_expr, smooth)) / 2
        else:
            value = model(row, p_expr, smooth)
        cell_functions.append(ca.Function(f"{kind}_cell", inputs, [value - row[3], ca.gradient(value, xs)]))
        value_functions.append(ca.Function(f"{kind}_value", inputs, [value - row[3]]))

    nx = n_theta + len(params)
    x = ca.MX.sym("x", nx)
    blocks = [ca.MX.sym(f"block{b}", ROWS, n) for b, n in enumerate(sizes)]
    g_p, pref_p, smooth_p = ca.MX.sym("g", 4), ca.MX.sym("pref"), ca.MX.sym("smooth")
    grid_p, grid_l = ca.MX.sym("grid_p", GRID[0] * GRID[1]), ca.MX.sym("grid_l", GRID[0] * GRID[1])
    res_parts, value_parts, jac_parts, w_parts = [], [], [], []
    for fun, value_fun, block, n in zip(cell_functions, value_functions, blocks, sizes, strict=True):
        if n:
            r, j = fun.map(n)(block, x, g_p, pref_p, smooth_p)
            res_parts.append(r)
            value_parts.append(value_fun.map(n)(block, x, g_p, pref_p, smooth_p))
            jac_parts.append(j)
            w_parts.append(block[4, :])
    res, jac_t, w = ca.horzcat(*res_parts), ca.horzcat(*jac_parts), ca.horzcat(*w_parts)  # 1×n, nx×n
    res_value = ca.horzcat(*value_parts)  # the same residuals without their gradient (objective, line search)
    total = ca.sum2(w)
    objective = ca.sum2(w * res_value**2) / total
    g_x = ca.vertcat(*_geometry(g_p, x, effects, n_theta))
    drucker = _drucker_function(wall, degree).map(GRID[0] * GRID[1])(grid_p.T, grid_l.T, x[:n_theta],
                                                                     g_x, pref_p)
    constraints = ca.vec(drucker.T)
    p = ca.vertcat(*(ca.vec(b) for b in blocks), g_p, pref_p, smooth_p, grid_p, grid_l)
    weighted_jac = jac_t * ca.repmat(w, nx, 1)
    gradient = 2 * ca.mtimes(weighted_jac, res.T) / total
    # Gauss-Newton Hessian of the Lagrangian: 2JᵀWJ/Σw (the Drucker constraints are linear in θ)
    lam_f, lam_g = ca.MX.sym("lam_f"), ca.MX.sym("lam_g", constraints.shape[0])
    hessian = ca.Function("hess_lag", [x, p, lam_f, lam_g],
                          [ca.triu(lam_f * 2 * ca.mtimes(weighted_jac, jac_t.T) / total)])
    grad_f = ca.Function("grad_f", [x, p], [ca.sum2(w * res**2) / total, gradient])
    nlp = {"x": x, "p": p, "f": objective, "g": constraints}
    label = "_".join(effects).replace(":", "_") or "baseline"
    solver = nlpsol(f"refit_{label}", nlp, ipopt=IPOPT_OPTIONS, hess_lag=hessian, grad_f=grad_f)
    residuals = ca.Function("residuals", [x, p], [res_value.T])
    jacobian = ca.Function("jacobian", [x, p], [(jac_t * ca.repmat(ca.sqrt(w), nx, 1)).T])

    @cache
    def variant(kind: str) -> ca.Function:
        return nlpsol(f"{kind}_{label}", nlp, ipopt={**IPOPT_OPTIONS, **VARIANTS[kind]}, hess_lag=hessian,
                      grad_f=grad_f)

    return Problem(solver, residuals, jacobian, variant, n_theta, len(params), time.perf_counter() - started)


def _geometry(g, x, effects: tuple[str, ...], n_theta: int) -> list:
    """[L₀, D₀, α₀, t₀] of the fit: the stated ``g`` with the geometry candidates' corrections, whose
    display values are the last entries of ``x`` (SX or MX)."""
    params = effect_parameters(effects)
    start = n_theta + len(params) - len(effect_parameters(geometry_part(effects)))
    values = {}
    for j, (name, p) in enumerate(effect_parameters(geometry_part(effects))):
        values.setdefault(name, {})[p.name] = x[start + j] * p.scale
    return corrected_vector(g, effects, values)


@cache
def _drucker_function(wall: str, degree: int) -> ca.Function:
    """(P, L, θ_MPa, g, P_ref) -> [E₁ᵗ, E₂ᵗ] [MPa] (per-direction Drucker, docs/physics.md §6)."""
    pressure, length = ca.SX.sym("P"), ca.SX.sym("L")
    theta = ca.SX.sym("theta", 4 * (degree + 1))
    sym = Muscle.symbolic(Structure(wall, degree))
    muscle = Muscle(sym.muscle.geometry, theta * MPA, sym.muscle.reference_pressure)
    e1, e2 = muscle.drucker_tangent_moduli(pressure, length)
    return ca.Function("drucker", [pressure, length, theta, sym.p[:4], sym.muscle.reference_pressure],
                       [ca.vertcat(e1, e2) / MPA])


@dataclass(frozen=True)
class Fit:
    """One solved refit: x, the residual of every cell (model − mean data [N]) and solver facts."""

    effects: tuple[str, ...]
    x: np.ndarray
    residual: np.ndarray  # per cell [N], cell order
    objective: float
    status: str
    iterations: int
    wall_time: float  # [s] build (when new) + solve
    jacobian: np.ndarray | None = None  # per cell, ∂(√n·r)/∂x
    multipliers: tuple[np.ndarray, np.ndarray] | None = None  # IPOPT's (λ_x, λ_g) at x

    @property
    def n_eta(self) -> int:
        return len(effect_parameters(self.effects))

    @property
    def theta(self) -> np.ndarray:
        return self.x[:self.x.size - self.n_eta]

    def eta(self) -> dict[str, np.ndarray]:
        """{effect: η (display units)}."""
        out, start = {}, self.x.size - self.n_eta
        for name in self.effects:
            k = len(candidate(name).parameters)
            out[name] = self.x[start:start + k]
            start += k
        return out

    def effect_values(self) -> dict[str, dict[str, float]]:
        """{effect: {parameter: SI value}}."""
        out = {}
        for name, eta in self.eta().items():
            params = candidate(name).parameters
            out[name] = {p.name: float(v * p.scale) for p, v in zip(params, eta, strict=True)}
        return out


class Refitter:
    """Fits the baseline and baseline + effects models to one experiment's cells (warm starts)."""

    def __init__(self, data, cells, *, degree: int = 3, reference_pressure: float = MPA):
        self.data, self.cells, self.degree, self.pref = data, cells, degree, reference_pressure
        self.geometry = data.pam.geometry
        self.blocks = blocks_of(cells)
        self.grid = _grid(data, cells)

    def bounds(self, effects: tuple[str, ...]):
        k = self.degree + 1
        low = np.full(4 * k, -50.0)
        high = np.full(4 * k, 50.0)
        low[[0, 2 * k]] = 0.0
        params = effect_parameters(effects)
        limits = [self._angle_limits() if name == "geometry:braid_angle" else p.fit_bounds
                  for name, p in params]
        low = np.concatenate([low, [lo / p.scale for (lo, _), (_, p) in zip(limits, params, strict=True)]])
        high = np.concatenate([high, [hi / p.scale for (_, hi), (_, p) in zip(limits, params, strict=True)]])
        return low, high

    def _angle_limits(self) -> tuple[float, float]:
        """Bounds [rad] of the braid-angle correction: ±10°, narrowed to the model's domain (every
        tested length below B = L₀/cos α₀ and above B/√3, every pipe below √(2/3)·D₀/sin α₀), 0.5 %
        from its edges."""
        p = candidate("geometry:braid_angle").parameters[0]
        g, cells, margin = self.geometry, self.cells, 1.005
        alpha, low, high = g.braid_angle, g.braid_angle + p.lower, g.braid_angle + p.upper
        if np.any(cells.axial):
            lengths = cells.length[cells.axial]
            low = max(low, math.acos(min(1.0, g.initial_length / (float(np.max(lengths)) * margin))))
            shortest = float(np.min(lengths))
            high = min(high, math.acos(min(1.0, g.initial_length * margin / (math.sqrt(3) * shortest))))
        if np.any(~cells.axial):
            widest = float(np.max(cells.diameter[~cells.axial])) * margin
            high = min(high, math.asin(min(1.0, math.sqrt(2 / 3) * g.initial_diameter / widest)))
        return min(low - alpha, 0.0), max(high - alpha, 0.0)

    def start(self, effects: tuple[str, ...], theta0: np.ndarray, known: dict[str, np.ndarray] | None = None
              ) -> np.ndarray:
        """x₀: θ₀ (MPa) and each effect's η from ``known`` or its null value."""
        parts = [np.asarray(theta0, dtype=float)]
        for name in effects:
            params = candidate(name).parameters
            parts.append(np.asarray(known[name]) if known and name in known
                         else np.array([p.null / p.scale for p in params]))
        return np.concatenate(parts)

    def parameters(self, blocks: Blocks | None = None) -> np.ndarray:
        blocks = blocks or self.blocks
        return np.concatenate([*(b.ravel(order="F") for b in blocks.data), self.geometry.as_vector(),
                               [self.pref, SMOOTHING], *self.grid])

    def problem(self, effects: tuple[str, ...]) -> Problem:
        return build_problem(effects, self.geometry.wall, self.degree, self.blocks.sizes)

    def fit(self, effects, theta0: np.ndarray, *, known: dict[str, np.ndarray] | None = None,
            weight: np.ndarray | None = None, jacobian: bool = False, warm: Fit | None = None,
            trial: bool = False, fold: bool = False) -> Fit:
        """Solve from θ₀ (MPa) and η₀ (``known`` or null); raise SolverError on failure.

        ``weight`` replaces the cell counts as weights (cross-validation: 0 for held-out cells);
        ``warm``, a solved fit of the same effects, is the primal-dual start of a warm-started solve
        (θ₀ and ``known`` are then not used); ``trial`` stops at :data:`TRIAL_ITERATIONS`; ``fold`` (a cold
        fold refit) at 100 iterations or when the objective stalls (:data:`STALL`).
        """
        effects = canonical(effects)
        started = time.perf_counter()
        problem = self.problem(effects)
        low, high = self.bounds(effects)
        blocks = self.blocks if weight is None else self.blocks.weighted(weight)
        p = self.parameters(blocks)
        label = " + ".join(effects) or "baseline"
        start = {"x0": np.clip(self.start(effects, theta0, known), low, high)}
        solver = problem.variant("fold") if fold else problem.variant("trial") if trial else problem.solver
        if warm is not None and warm.multipliers is not None and warm.effects == effects:
            start = {"x0": warm.x, "lam_x0": warm.multipliers[0], "lam_g0": warm.multipliers[1]}
            solver = problem.variant("warm")
        sol, stats = solve(solver, what=f"the {label} refit", accept_acceptable=True,
                           p=p, lbx=low, ubx=high, lbg=0, ubg=ca.inf, **start)
        x = np.clip(np.asarray(sol["x"], dtype=float).ravel(), low, high)  # IPOPT relaxes bounds by 1e-8
        res = np.asarray(problem.residuals(x, p), dtype=float).ravel()
        residual = self.blocks.scatter(res, self.cells.size)
        jac = None
        if jacobian:
            jac = self.blocks.scatter(np.asarray(problem.jacobian(x, self.parameters()), dtype=float),
                                      self.cells.size)
        multipliers = tuple(np.asarray(sol[key], dtype=float).ravel() for key in ("lam_x", "lam_g"))
        return Fit(effects, x, residual, float(sol["f"]), stats.status, stats.iterations,
                   time.perf_counter() - started, jac, multipliers)

    def moduli_si(self, x: np.ndarray) -> np.ndarray:
        """θ in Pa (b at P_ref = 1 MPa) from the NLP's MPa vector."""
        return np.asarray(x[:4 * (self.degree + 1)], dtype=float) * MPA

    def muscle(self, fit: Fit) -> Muscle:
        """The fitted model as a numeric :class:`Muscle` (for row residuals, anchoring and plots)."""
        values = fit.effect_values()
        effects = {name: values[name] for name in library_part(fit.effects)}
        return Muscle(self.fitted_geometry(fit), self.moduli_si(fit.x), MPA, effects=effects or None)

    def fitted_geometry(self, fit: Fit):
        """The stated geometry, corrected by the fit's geometry candidates."""
        return corrected_geometry(self.geometry, fit.effects, fit.effect_values())


def _grid(data, cells):
    """Drucker grid (pressures × lengths) flattened: tested pressures and L ∈ [L_min, L₀]."""
    geometry = data.pam.geometry
    pressures = np.concatenate([cells.pressure, [0.0]])
    lengths = [geometry.initial_length]
    if np.any(cells.axial):
        lengths.append(float(np.nanmin(cells.length[cells.axial])))
    for d in np.unique(cells.diameter[~cells.axial]):
        lengths.append(float(np.sqrt(geometry.braid_length**2 - (geometry.turns * np.pi * d) ** 2)))
    low = max(min(lengths), geometry.shortest_length * 1.001)
    pp, ll = np.meshgrid(np.linspace(max(pressures.min(), 0.0), pressures.max(), GRID[0]),
                         np.linspace(low, geometry.initial_length, GRID[1]), indexing="ij")
    return pp.ravel(), ll.ravel()
