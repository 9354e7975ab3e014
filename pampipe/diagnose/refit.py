"""The baseline + effect NLP: shared moduli θ and the effect's parameters η fitted to every row.

Decision vector x = [θ (MPa; b at P_ref), η (the effect's display units, O(1))]. Objective: the
mean squared force residual over the rows with non-zero weight,

  J(x) = Σ_i w_i (F_model,i(x) − F_i)² / Σ_i w_i,

with F_model from :meth:`pampipe.model.muscle.Muscle.axial_force` (axial rows) and
:meth:`~pampipe.model.muscle.Muscle.radial_force` (radial rows, softplus contact switch of
width ``smoothing``). Bounds as in docs/physics.md §6 (a_k0 ∈ [0, 50] MPa, others ±50 MPa) plus each
parameter's own bounds; Drucker stability E₁ᵗ ≥ 0, E₂ᵗ ≥ 0 on a (P, L) grid (docs/physics.md §6).

Built once per (effect, wall, degree, rows): a per-row residual ``casadi.Function`` is mapped over
the rows with ``.map(n)``, so the build size does not grow with n; every row value, the weights,
the geometry and the grid are NLP parameters. Cross-validation only changes the weights.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from functools import cache

import casadi as ca
import numpy as np

from pampipe.model.effects import get_effect
from pampipe.model.muscle import Muscle, Structure
from pampipe.nlp import nlpsol, solve

MPA = 1e6
#: Drucker grid size (pressures × lengths), fixed so that it never changes the build.
GRID = (6, 15)
#: Softplus width of the contact switch [N] (as `identify`'s default contact_smoothing).
SMOOTHING = 1.0
IPOPT_OPTIONS = {"tol": 1e-9, "acceptable_tol": 1e-8, "max_iter": 500, "bound_relax_factor": 1e-8}


@dataclass(frozen=True)
class Rows:
    """Every row of an experiment as NLP data (SI), in recorded order within each kind.

    ``axial`` is (5, n_a): P, L, leg, F, weight; ``radial`` is (5, n_r): P, D_p, F_a, F, weight.
    ``test``/``level`` give each row's test index and pressure level (for folds and reports).
    """

    axial: np.ndarray
    radial: np.ndarray
    axial_test: np.ndarray
    radial_test: np.ndarray
    axial_level: np.ndarray
    radial_level: np.ndarray
    axial_cycle: np.ndarray

    @property
    def n(self) -> int:
        return self.axial.shape[1] + self.radial.shape[1]

    def weighted(self, axial_weight: np.ndarray, radial_weight: np.ndarray) -> Rows:
        a, r = self.axial.copy(), self.radial.copy()
        a[4], r[4] = axial_weight, radial_weight
        return Rows(a, r, self.axial_test, self.radial_test, self.axial_level, self.radial_level,
                    self.axial_cycle)


def rows_of(data) -> Rows:
    """Rows of an :class:`pampipe.experiment.ExperimentData`."""
    a_parts, r_parts, a_test, r_test, a_lev, r_lev, a_cyc = [], [], [], [], [], [], []
    for index, t in enumerate(data.tests):
        ones = np.ones(t.points)
        if t.kind == "axial":
            a_parts.append(np.vstack([t.pressure, t.length, t.leg.astype(float), t.force, ones]))
            a_test.append(np.full(t.points, index))
            a_lev.append(t.level)
            a_cyc.append(t.cycle)
        else:
            r_parts.append(np.vstack([t.pressure, ones * t.spec.pipe_diameter, ones * t.spec.axial_load,
                                      t.force, ones]))
            r_test.append(np.full(t.points, index))
            r_lev.append(t.level)

    def cat(parts, rows=5):
        return np.hstack(parts) if parts else np.zeros((rows, 0))

    def flat(parts):
        return np.concatenate(parts).astype(np.int64) if parts else np.zeros(0, dtype=np.int64)

    return Rows(cat(a_parts), cat(r_parts), flat(a_test), flat(r_test), flat(a_lev), flat(r_lev),
                flat(a_cyc))


@dataclass(frozen=True)
class Problem:
    """A built NLP and its helpers: residual and Jacobian of the mapped rows."""

    solver: ca.Function
    residuals: ca.Function  # (x, p) -> unweighted residuals of all rows (axial then radial)
    jacobian: ca.Function  # (x, p) -> ∂(weighted residuals)/∂x
    n_theta: int
    n_eta: int
    build_time: float


@cache
def build_problem(effect: str | None, wall: str, degree: int, n_axial: int, n_radial: int) -> Problem:
    """The NLP for one effect (None: the baseline) and one data structure (built once, cached)."""
    started = time.perf_counter()
    n_theta = 4 * (degree + 1)
    params = get_effect(effect).parameters if effect else ()
    theta, eta = ca.SX.sym("theta", n_theta), ca.SX.sym("eta", len(params))
    row, smooth = ca.SX.sym("row", 5), ca.SX.sym("smooth")
    sym = Muscle.symbolic(Structure(wall, degree))
    geometry, pref, g = sym.muscle.geometry, sym.muscle.reference_pressure, sym.p[:4]
    values = {p.name: eta[i] * p.scale for i, p in enumerate(params)}
    # θ in MPa (b at P_ref, always 1 MPa in the fit) and η in display units are the decision variables
    muscle = Muscle(geometry, theta * MPA, pref, effects={effect: values} if effect else None)
    axial = muscle.axial_force(row[0], row[1], leg=row[2])
    radial = muscle.radial_force(row[0], row[1], row[2], smoothing=smooth)
    xs = ca.vertcat(theta, eta)
    inputs = [row, xs, g, pref, smooth]
    # per-row residual and its gradient, in SX (cheap), then mapped over the rows
    f_axial = ca.Function("axial_row", inputs, [axial - row[3], ca.gradient(axial, xs)])
    f_radial = ca.Function("radial_row", inputs, [radial - row[3], ca.gradient(radial, xs)])

    nx = n_theta + len(params)
    x = ca.MX.sym("x", nx)
    data_a, data_r = ca.MX.sym("axial", 5, n_axial), ca.MX.sym("radial", 5, n_radial)
    g_p, pref_p, smooth_p = ca.MX.sym("g", 4), ca.MX.sym("pref"), ca.MX.sym("smooth")
    grid_p, grid_l = ca.MX.sym("grid_p", GRID[0] * GRID[1]), ca.MX.sym("grid_l", GRID[0] * GRID[1])
    res_parts, jac_parts, w_parts = [], [], []
    for fun, block, n in ((f_axial, data_a, n_axial), (f_radial, data_r, n_radial)):
        if n:
            r, j = fun.map(n)(block, x, g_p, pref_p, smooth_p)
            res_parts.append(r)
            jac_parts.append(j)
            w_parts.append(block[4, :])
    res, jac_t, w = ca.horzcat(*res_parts), ca.horzcat(*jac_parts), ca.horzcat(*w_parts)  # 1×n, nx×n
    total = ca.sum2(w)
    objective = ca.sum2(w * res**2) / total
    drucker = _drucker_function(wall, degree).map(GRID[0] * GRID[1])(grid_p.T, grid_l.T, x[:n_theta],
                                                                     g_p, pref_p)
    constraints = ca.vec(drucker.T)
    p = ca.vertcat(ca.vec(data_a), ca.vec(data_r), g_p, pref_p, smooth_p, grid_p, grid_l)
    weighted_jac = jac_t * ca.repmat(w, nx, 1)
    gradient = 2 * ca.mtimes(weighted_jac, res.T) / total
    # Gauss-Newton Hessian of the Lagrangian: 2JᵀWJ/Σw (the Drucker constraints are linear in θ)
    lam_f, lam_g = ca.MX.sym("lam_f"), ca.MX.sym("lam_g", constraints.shape[0])
    hessian = ca.Function("hess_lag", [x, p, lam_f, lam_g],
                          [ca.triu(lam_f * 2 * ca.mtimes(weighted_jac, jac_t.T) / total)])
    grad_f = ca.Function("grad_f", [x, p], [objective, gradient])
    nlp = {"x": x, "p": p, "f": objective, "g": constraints}
    solver = nlpsol(f"refit_{effect or 'baseline'}", nlp, ipopt=IPOPT_OPTIONS, hess_lag=hessian,
                    grad_f=grad_f)
    residuals = ca.Function("residuals", [x, p], [res.T])
    jacobian = ca.Function("jacobian", [x, p], [(jac_t * ca.repmat(ca.sqrt(w), nx, 1)).T])
    return Problem(solver, residuals, jacobian, n_theta, len(params), time.perf_counter() - started)


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
    """One solved refit: x, the residual of every row, and solver facts."""

    effect: str | None
    x: np.ndarray
    residual_axial: np.ndarray  # model − data [N], unweighted
    residual_radial: np.ndarray
    objective: float
    status: str
    iterations: int
    wall_time: float
    jacobian: np.ndarray | None = None

    @property
    def eta(self) -> np.ndarray:
        params = get_effect(self.effect).parameters if self.effect else ()
        return self.x[self.x.size - len(params):]


class Refitter:
    """Fits the baseline and baseline + effect models to one experiment's rows (warm starts)."""

    def __init__(self, data, rows: Rows, *, degree: int = 3, reference_pressure: float = MPA):
        self.data, self.rows, self.degree, self.pref = data, rows, degree, reference_pressure
        self.geometry = data.pam.geometry
        self.grid = _grid(data, rows)

    def bounds(self, effect: str | None):
        k = self.degree + 1
        low = np.full(4 * k, -50.0)
        high = np.full(4 * k, 50.0)
        low[[0, 2 * k]] = 0.0
        params = get_effect(effect).parameters if effect else ()
        low = np.concatenate([low, [p.lower / p.scale for p in params]])
        high = np.concatenate([high, [p.upper / p.scale for p in params]])
        return low, high

    def null_eta(self, effect: str | None) -> np.ndarray:
        params = get_effect(effect).parameters if effect else ()
        return np.array([p.null / p.scale for p in params])

    def parameters(self, rows: Rows | None = None) -> np.ndarray:
        rows = rows or self.rows
        return np.concatenate([rows.axial.ravel(order="F"), rows.radial.ravel(order="F"),
                               self.geometry.as_vector(), [self.pref, SMOOTHING], *self.grid])

    def problem(self, effect: str | None) -> Problem:
        return build_problem(effect, self.geometry.wall, self.degree, self.rows.axial.shape[1],
                             self.rows.radial.shape[1])

    def fit(self, effect: str | None, theta0: np.ndarray, *, eta0=None, rows: Rows | None = None,
            jacobian: bool = False) -> Fit:
        """Solve from θ₀ (MPa) and η₀ (default: the null value); raise SolverError on failure."""
        problem = self.problem(effect)
        low, high = self.bounds(effect)
        eta0 = self.null_eta(effect) if eta0 is None else eta0
        x0 = np.clip(np.concatenate([theta0, eta0]), low, high)
        p = self.parameters(rows)
        sol, stats = solve(problem.solver, what=f"the {effect or 'baseline'} refit", accept_acceptable=True,
                           x0=x0, p=p, lbx=low, ubx=high, lbg=0, ubg=ca.inf)
        x = np.clip(np.asarray(sol["x"], dtype=float).ravel(), low, high)  # IPOPT relaxes bounds by 1e-8
        res = np.asarray(problem.residuals(x, p), dtype=float).ravel()
        n_a = self.rows.axial.shape[1]
        jac = np.asarray(problem.jacobian(x, p), dtype=float) if jacobian else None
        return Fit(effect, x, res[:n_a], res[n_a:], float(sol["f"]), stats.status, stats.iterations,
                   stats.wall_time, jac)

    def moduli_si(self, x: np.ndarray) -> np.ndarray:
        """θ in Pa (b at P_ref) from the NLP's MPa vector."""
        k = self.degree + 1
        theta = np.asarray(x[:4 * k], dtype=float) * MPA
        return theta


def _grid(data, rows: Rows):
    """Drucker grid (pressures × lengths) flattened: tested pressures and L ∈ [L_min, L₀]."""
    geometry = data.pam.geometry
    pressures = np.concatenate([rows.axial[0], rows.radial[0], [0.0]])
    lengths = [geometry.initial_length]
    if rows.axial.shape[1]:
        lengths.append(float(rows.axial[1].min()))
    for d in np.unique(rows.radial[1]):
        lengths.append(float(np.sqrt(geometry.braid_length**2 - (geometry.turns * np.pi * d) ** 2)))
    low = max(min(lengths), geometry.shortest_length * 1.001)
    pp, ll = np.meshgrid(np.linspace(max(pressures.min(), 0.0), pressures.max(), GRID[0]),
                         np.linspace(low, geometry.initial_length, GRID[1]), indexing="ij")
    return pp.ravel(), ll.ravel()
