"""The solve loop of `identify`: IPOPT through :func:`pampipe.runtime.ipopt.solve`, rescaled at every start
and
repeated while the data the problem is fed follow the solution (slack cells changing side, Drucker
intervals following a calibrated geometry).
"""

from __future__ import annotations

import math
from dataclasses import replace

import casadi as ca
import numpy as np

from pampipe.errors import SolverError
from pampipe.identification import drucker, exact
from pampipe.identification import geometry as geo
from pampipe.identification.fit_nlp import Structure
from pampipe.identification.moment_cells import FIELDS
from pampipe.identification.options import FitOptions
from pampipe.identification.statistics import MPA, Statistics
from pampipe.model import forces
from pampipe.runtime.ipopt import SolverStats, ipopt_version, solve

#: What an IPOPT failure means for this fit (the generic words are in
#: :data:`pampipe.runtime.ipopt.IPOPT_STATUS`).
FIT_HINTS = {
    "Maximum_Iterations_Exceeded": "IPOPT stopped at the iteration limit (raise fit.max_iterations)",
    "Infeasible_Problem_Detected": "no moduli satisfy the bounds and the Drucker constraints together "
                                   "(widen fit.bounds or check the data)",
}
#: IPOPT statuses after which the solve is restarted once from its last point: the scale set at an
#: infeasible start can leave the converged objective hundreds of times larger, where IPOPT's
#: absolute tolerance can no longer be met; rescaled at the stopping point it converges. So does a
#: calibrated fit whose objective is flat to 10⁻⁸ when IPOPT can no longer compute a step (the coverage
#: benchmark's seed 2, trial 13: every start stopped so, and the fit was refused).
STALLED = ("Search_Direction_Becomes_Too_Small", "Error_In_Step_Computation")
#: Solves at most while the problem's data follow the solution (slack cells changing side, Drucker
#: intervals following a calibrated geometry); each re-solve starts from the last solution.
UPDATE_ROUNDS = 8
#: The objective's scale is at least this RMS residual [N] per row (a near-exact start would make it
#: vanish and IPOPT's steps degenerate).
SCALE_FLOOR = 1e-3
#: Drucker rows (unit max-norm) that moved less than this are kept.
ROWS_MOVED = 1e-3


def solve_fit(nlp, values, x0, lbx, ubx, stats: Statistics, structure: Structure, update, centred=None):
    """IPOPT, re-solved from its last point while ``update(x, seen)`` changes the data of the problem.

    ``update`` (see :func:`_updater`) moves slack cells between clipped and live and, with a
    calibrated geometry, puts the Drucker intervals where the fitted geometry's strains are.
    A re-solve of least squares at a fixed geometry (:func:`.exact.applies`) is the active-set solve of
    :func:`.exact.resolved` from the last point instead, where that finds the one minimum IPOPT would
    (IPOPT for the rest); so is the first solve when ``x0`` is an IPOPT solution and ``centred`` the
    Hessian of its problem there (the slack hinge's next round, :func:`.fit.identify`). Along a direction
    the data leave flat the steps do not move x: it stays where the first IPOPT solve put it (a held-out
    refit of the model error, whose withheld rows may see such a direction, keeps that solve's choice).
    Returns (solution, statistics summed over the solves).
    """
    iterations, wall = 0, 0.0
    x, last, seen = x0, None, set()
    for round_ in range(UPDATE_ROUNDS):
        if centred is not None and exact.applies(structure):
            scale(nlp, values, x, stats, structure)  # as IPOPT's solve from x would be
            found = exact.resolved(nlp, values, x, lbx, ubx, centred)
            if found is not None:
                x, solution = found, {"x": found, "f": _objective(nlp, values, found)}
                last = (solution, last[1] if last else _no_solve(), _kept(values))
                if not update(x, seen):
                    break
                continue
        try:
            for attempt in range(2):  # a stalled solve is restarted once from where it stopped, rescaled
                scale(nlp, values, x, stats, structure)
                solution, info = solve(nlp.solver, what="the moduli fit (no result was written)",
                                       hints=FIT_HINTS, also_accept=() if attempt else STALLED, x0=x,
                                       p=nlp.layout.pack(values), lbx=lbx, ubx=ubx, lbg=0, ubg=ca.inf)
                iterations, wall = iterations + info.iterations, wall + info.wall_time
                x = np.asarray(solution["x"], dtype=float).ravel()
                if info.status not in STALLED:
                    break
        except SolverError:
            if round_ == 0:
                raise
            values.update(last[2])  # a refinement failed: keep the previous solve and its data
            break
        last = (solution, info, _kept(values))
        if exact.applies(structure):
            centred = np.asarray(nlp.hessian(x, nlp.layout.pack(values)), dtype=float)
        if not update(x, seen):
            break
    return last[0], replace(last[1], iterations=iterations, wall_time=wall)


def _kept(values: dict) -> dict:
    """A copy of the problem's parameter values, to restore if a later round fails."""
    return {k: np.array(v, copy=True) for k, v in values.items()}


def _objective(nlp, values, x) -> float:
    """IPOPT's objective (SSE + prior)/scale at ``x`` (least squares; the scale of :func:`scale`)."""
    return float(nlp.gradient(x, nlp.layout.pack(values))[0]) * 2 / float(values["scale"])


def _no_solve() -> SolverStats:
    """The statistics of a fit no IPOPT solve was needed for (the hinge's round finished by active-set steps
    from the previous round's IPOPT solution, whose status it keeps)."""
    return SolverStats("ipopt", "Solve_Succeeded", True, 0, 0.0, ca.__version__, ipopt_version())


def updater(values, stats: Statistics, structure: Structure, stated, options: FitOptions, pressures, low):
    """``update(x, seen) -> changed`` for :func:`solve_fit`, changing ``values`` in place.

    Cells (slack rows, and measured rows where the model may predict no tension): clipped
    (max(0, F) = 0) where the model at the cell mean is ≤ 0, live otherwise (the slack hinge,
    docs/physics.md §6.2); a set of sides already solved in this :func:`solve_fit` (``seen``) is not
    solved again (a cell whose model sits at F ≈ 0 would flip back and forth).
    Calibrated geometry (tangent form): the Bernstein rows over the strains of the fitted geometry
    for the grid's lengths, so that the constraint covers the range the model is used in.
    """
    row = FIELDS.index("clipped")
    rows_follow = bool(structure.calibrate) and structure.grid_rows and options.drucker == "tangent"

    def update(x, seen: set) -> bool:
        geometry = geo.from_x(stated, structure.calibrate, x[geometry_mask(structure, x.size)]) \
            if structure.calibrate else stated
        changed = False
        if stats.cells is not None and stats.cells.count:
            moments, count = values["cells"], stats.cells.count
            seen.add(moments[row, :count].tobytes())
            model = forces.axial_force(moments[1, :count] * MPA, moments[2, :count], geometry,
                                       x[:stats.n_theta] * MPA, MPA)
            clipped = (np.asarray(model) <= 0).astype(float)
            if clipped.tobytes() not in seen:  # a side already tried would only cycle (a cell at F ≈ 0)
                changed = True
                moments[row, :count] = clipped
        if rows_follow:
            lengths = drucker.grid_lengths(geometry, stats.pipes, drucker.grid_low(geometry, low), options)
            rows = drucker.bernstein_rows([geometry], options.degree, pressures, lengths,
                                          reference_pressure=MPA)
            if np.max(np.abs(rows - values["grid"])) > ROWS_MOVED:
                values["grid"] = rows
                changed = True
        return changed

    return update


def scale(nlp, values, x, stats: Statistics, structure: Structure) -> None:
    """Scales that make IPOPT's objective 1 at the start ``x`` (a warm start from a good point would
    otherwise have an objective far below the barrier terms, which then pull the iterates away)."""
    values["scale"] = values["scale_sse"] = 1.0
    sse = max(float(nlp.sse(x, nlp.layout.pack(values))), SCALE_FLOOR**2 * max(stats.points, 1))
    values["scale_sse"] = sse
    if structure.objective == "least_squares":
        values["scale"] = sse
    else:
        groups = structure.axial_groups + sum(levels for levels, _ in structure.radial)
        values["scale"] = max(groups * math.sqrt(sse / max(stats.points, 1)), 1e-9)


def fixed_geometry_fit(nlp, values, x0, lbx, ubx, stats, structure, update):
    """The moduli fit with the calibrated entries held at their values in ``x0``."""
    fixed = geometry_mask(structure, x0.size)
    solution, info = solve_fit(nlp, values, x0, np.where(fixed, x0, lbx), np.where(fixed, x0, ubx), stats,
                            structure, update)
    return np.asarray(solution["x"], dtype=float).ravel(), info


def geometry_mask(structure: Structure, size: int) -> np.ndarray:
    """True at the calibrated geometry entries (the last block of x)."""
    mask = np.zeros(size, dtype=bool)
    if structure.calibrate:
        mask[size - len(structure.calibrate):] = True
    return mask


