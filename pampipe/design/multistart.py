"""Multi-start of the design NLP: Latin-hypercube starts, one plain-data task per start, the best kept.

A :class:`StartTask` holds numbers only (it pickles for any executor); :func:`solve_start` runs in
the worker, which builds its own solver (cached per process, :func:`pampipe.design.design_nlp.build`).
The starts are a Latin hypercube drawn from the inventory's seed, so start k is the same point on
every executor; the best start is the least objective, ties broken by the lower start index.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from pampipe.design import design_nlp
from pampipe.design.groups import Groups, block_size
from pampipe.errors import SolverError
from pampipe.model.muscle import Structure
from pampipe.runtime import ipopt
from pampipe.runtime.executors import run_all
from pampipe.specs.inventory import DesignSpace, Inventory, Objective

#: Starts whose objective is within this relative distance of the best "reached" it: IPOPT stops at
#: tol 1e-10 on the scaled problem, so starts converging to the same optimum agree far closer.
REACHED = 1e-6
#: Sampled starts keep this fraction inside the reach of the widest bore (so that L(D) is real there).
START_REACH = 0.98


@dataclass(frozen=True)
class StartTask:
    """Everything one start needs, as plain numbers."""

    index: int
    structure: Structure
    objective: Objective
    size: int
    x0: np.ndarray
    p: np.ndarray
    lbx: np.ndarray
    ubx: np.ndarray
    lbg: np.ndarray
    ubg: np.ndarray


@dataclass(frozen=True)
class StartResult:
    """What one start found (x in the NLP's scaled variables)."""

    index: int
    success: bool
    status: str
    objective: float  # the NLP's scaled objective f (inf if the start failed)
    x: np.ndarray
    iterations: int
    wall_time: float  # [s]
    lam_g: np.ndarray = field(repr=False)
    lam_x: np.ndarray = field(repr=False)


def solve_start(task: StartTask) -> StartResult:
    """Solve the design NLP from one start (in whatever process runs it)."""
    solver, _ = design_nlp.build(task.structure, task.objective, task.size)
    try:
        sol, stats = ipopt.solve(solver, what="the design NLP", x0=task.x0, p=task.p,
                               lbx=task.lbx, ubx=task.ubx, lbg=task.lbg, ubg=task.ubg)
    except SolverError as exc:
        raw = solver.stats()
        nan = np.full(task.x0.shape, np.nan)
        return StartResult(task.index, False, exc.status, math.inf, nan, int(raw.get("iter_count", -1)),
                           float(raw.get("t_wall_total", 0.0)), np.array([]), np.array([]))
    return StartResult(task.index, True, stats.status, float(sol["f"]), np.asarray(sol["x"]).ravel(),
                       stats.iterations, stats.wall_time, np.asarray(sol["lam_g"]).ravel(),
                       np.asarray(sol["lam_x"]).ravel())


@dataclass(frozen=True)
class Problem:
    """One design NLP instance: a material, a set of groups, the bounds and the objective."""

    structure: Structure
    objective: Objective
    size: int
    p: np.ndarray
    lbx: np.ndarray
    ubx: np.ndarray
    lbg: np.ndarray
    ubg: np.ndarray
    space: np.ndarray  # [L_lo, L_hi, D_lo, D_hi, α_lo, α_hi]
    groups: Groups
    scale: float  # the objective's unit per unit of the NLP's scaled objective f

    def physical(self, f: float) -> float:
        """The objective in its unit (Pa, J/m or 1/m) from the NLP's scaled f."""
        return f * self.scale

    def geometry(self, x) -> tuple[float, float, float]:
        """(L₀ [m], D₀ [m], α₀ [rad]) at the scaled variables x."""
        s = self.space
        return tuple(float(s[2 * k] + (s[2 * k + 1] - s[2 * k]) * x[k]) for k in range(3))

    def evaluate(self, x) -> tuple[float, np.ndarray]:
        """(f, g) of the NLP at x (numbers)."""
        _, fg = design_nlp.build(self.structure, self.objective, self.size)
        f, g = fg(x, self.p)
        return float(f), np.asarray(g).ravel()


def make_problem(inventory: Inventory, groups: Groups, *, objective: Objective | None = None,
                 relaxed: bool = False) -> Problem:
    """The NLP instance for ``groups``; ``relaxed`` drops the supply cap (t free) for max_pressure."""
    space = inventory.space
    objective = inventory.space.objective if objective is None else objective
    structure = design_nlp.material_structure(inventory.material)
    size = block_size(len(groups))
    bounds = np.array([*space.initial_length, *space.initial_diameter, *space.braid_angle])
    supply = inventory.supply_pressure
    total = float(groups.length.sum()) or 1.0
    mean_bore = float((groups.length * groups.diameter).sum() / total) if groups.length.sum() else \
        float(groups.diameter.mean())
    mid_length = 0.5 * sum(space.initial_length)
    # scales: air per metre ≈ n·P·(πD²/4)/0.1 and cycles per metre ≈ 1/(0.1 L₀) for a 10 % stride
    air_scale = len(inventory.segment_masses) * supply * math.pi * mean_bore**2 / 4 / 0.1
    speed_scale = 1 / (0.1 * mid_length)
    glob = [inventory.kappa, inventory.safety_factor, supply, space.contact_margin, space.min_stride,
            len(inventory.segment_masses), 1 / (total * air_scale), 1 / (total * speed_scale)]
    p = np.concatenate([bounds, design_nlp.material_vector(inventory.material), groups.block(size).T.ravel(),
                        glob])
    active = np.zeros(size, dtype=bool)
    active[:len(groups)] = groups.constrained
    lbg, ubg = design_nlp.constraint_bounds(active)
    lbx = np.zeros(4)
    ubx = np.array([1.0, clearance_fraction(space, groups.smallest_bore), 1.0, math.inf])
    if objective is not Objective.MAX_PRESSURE:
        lbx[3] = ubx[3] = 1.0  # every pressure ≤ supply
    elif not relaxed:
        ubx[3] = 1.0
    scales = {Objective.MAX_PRESSURE: supply, Objective.AIR: air_scale, Objective.SPEED: speed_scale}
    scale = scales[objective]
    return Problem(structure, objective, size, p, lbx, ubx, lbg, ubg, bounds, groups, scale)


def clearance_fraction(space: DesignSpace, smallest_bore: float) -> float:
    """The largest u_D that keeps D₀ ≤ smallest bore − clearance (may be < 0: no muscle passes)."""
    low, high = space.initial_diameter
    top = smallest_bore - space.clearance
    if high == low:
        return 1.0 if top >= low else -1.0
    return min(1.0, (top - low) / (high - low))


def latin_hypercube(n: int, seed: int) -> np.ndarray:
    """n points in [0, 1]³, one per stratum of each axis (a Latin hypercube), from ``seed``."""
    from scipy.stats import qmc

    return qmc.LatinHypercube(d=3, seed=np.random.default_rng(seed)).random(n)


def start_points(problem: Problem, n: int, seed: int) -> np.ndarray:
    """The (n, 4) starts: a Latin hypercube in the bounds, kept where the braid opens to the widest bore.

    The rest diameter is drawn from the part of its range where some allowed angle reaches the
    widest bore, and the angle from the part of its range that reaches it at that diameter, so
    that the model is defined at every start (L(D) real for every bore).
    """
    unit = latin_hypercube(n, seed)
    s, lbx, ubx = problem.space, problem.lbx, np.maximum(problem.ubx, problem.lbx)
    reach = START_REACH * (1 - _margin(problem)) * math.sqrt(2 / 3) / problem.groups.widest_bore
    u = np.empty((n, 3))
    u[:, 0] = lbx[0] + unit[:, 0] * (ubx[0] - lbx[0])
    d_low = lbx[1]
    if s[3] > s[2]:
        needed = math.sin(s[4]) / reach  # the least D₀ that opens to the widest bore at α_lo
        d_low = float(np.clip((needed - s[2]) / (s[3] - s[2]), lbx[1], ubx[1]))
    u[:, 1] = d_low + unit[:, 1] * (ubx[1] - d_low)
    d0 = s[2] + (s[3] - s[2]) * u[:, 1]
    top = np.arcsin(np.clip(reach * d0, 0.0, 1.0))  # the largest α that still opens to the widest bore
    a_high = np.clip((top - s[4]) / (s[5] - s[4]), lbx[2], ubx[2]) if s[5] > s[4] else np.full(n, ubx[2])
    u[:, 2] = lbx[2] + unit[:, 2] * (a_high - lbx[2])
    return np.array([with_epigraph(problem, point) for point in u])


def with_epigraph(problem: Problem, u: np.ndarray) -> np.ndarray:
    """The start (u, t): t fixed where the bounds fix it, else 1 % above the largest P*/P_s at u."""
    point = np.concatenate([np.asarray(u, dtype=float)[:3], [1.0]])
    if problem.lbx[3] == problem.ubx[3]:
        point[3] = problem.lbx[3]
        return point
    _, g = problem.evaluate(point)
    rows = g[:len(problem.groups)] + 1.0
    t = float(np.max(np.where(problem.groups.constrained & np.isfinite(rows), rows, -np.inf)))
    point[3] = 1.01 * t if math.isfinite(t) else 1.0
    return point


def _margin(problem: Problem) -> float:
    return float(problem.p[-len(design_nlp.GLOBALS) + design_nlp.GLOBALS.index("contact_margin")])


@dataclass(frozen=True)
class MultiStart:
    """Every start's result, the best one and how many starts reached it."""

    problem: Problem
    results: tuple[StartResult, ...]

    @property
    def best(self) -> StartResult | None:
        """The successful start of least objective (lowest index among equals); None if all failed."""
        ok = [r for r in self.results if r.success]
        return min(ok, key=lambda r: (r.objective, r.index)) if ok else None

    @property
    def reached(self) -> int:
        """How many starts ended within :data:`REACHED` (relative) of the best objective."""
        best = self.best
        if best is None:
            return 0
        tol = REACHED * max(abs(best.objective), 1e-12)
        return sum(r.success and abs(r.objective - best.objective) <= tol for r in self.results)


def multistart(problem: Problem, *, starts: int, seed: int, pool,
               extra: np.ndarray | None = None) -> MultiStart:
    """Solve ``problem`` from ``starts`` Latin-hypercube points (after the ``extra`` points) on ``pool``."""
    points = start_points(problem, starts, seed)
    if extra is not None:
        points = np.concatenate([with_epigraph(problem, extra)[None, :], points])
    tasks = [StartTask(k, problem.structure, problem.objective, problem.size, points[k], problem.p,
                       problem.lbx, problem.ubx, problem.lbg, problem.ubg) for k in range(len(points))]
    return MultiStart(problem, tuple(run_all(solve_start, tasks, pool, what="design starts")))
