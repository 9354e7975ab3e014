"""The set-up of one fit (:mod:`.fit`): reduce the rows, build the NLP, bound it and start it.

(1) one pass over the rows → sufficient statistics and cells; (2) the NLP for this problem structure (built
once, cached in memory and on disk); (3) bounds, parameter values, the Drucker rows on a (P, L) grid covering
the tested pressures and L ∈ [min(L_data, L_pipes, L_free(P_max)), L₀] plus the pipes' lengths, the initial
guess (bounded linear least squares at the stated geometry) and the prior's weight.
"""

from __future__ import annotations

import time
from typing import NamedTuple

import numpy as np

from pampipe.errors import SolverError
from pampipe.identification import drucker, problem
from pampipe.identification import geometry as geo
from pampipe.identification.fit_nlp import GEOMETRY, build_problem, with_held_room
from pampipe.identification.options import FitOptions
from pampipe.identification.result import MPA
from pampipe.identification.solve import geometry_mask, updater
from pampipe.identification.statistics import Memo, Statistics, drucker_rows, reduce_experiment
from pampipe.model import braid
from pampipe.model.muscle import Muscle
from pampipe.specs.experiment import ExperimentData


class Setup(NamedTuple):
    """One fit's problem as :func:`set_up` builds it: the reduction, the NLP, its bounds, values and start."""

    stats: Statistics
    structure: problem.Structure
    nlp: object  # the built (cached) NLP of fit_nlp.build_problem
    build_time: float  # [s], 0 when the NLP came from the cache
    reduce_time: float  # [s]
    pressures: np.ndarray  # the Drucker grid's pressures [Pa]
    lengths: np.ndarray  # and lengths [m]
    low: float  # the grid's shortest length [m]
    grid: np.ndarray  # the Drucker rows
    geometry_bounds: dict
    names: list[str]  # of the entries of x
    lbx: np.ndarray
    ubx: np.ndarray
    values: dict  # the NLP's parameter values (the prior's weight included)
    fixed: np.ndarray  # the geometry entries of x
    x0: np.ndarray
    prior: str  # problem.prior_kind


def set_up(data: ExperimentData, options: FitOptions, say, hinge, warm, memo: Memo) -> Setup:
    """(1) one pass over the rows → sufficient statistics; (2) the NLP of this structure (built once, cached);
    (3) bounds, parameter values, the start (bounded linear least squares at the stated geometry, or
    ``warm``) and the prior's weight."""
    stated = data.pam.geometry
    started = time.perf_counter()
    say(f"reducing {data.points:,} rows to sufficient statistics")
    stats = reduce_experiment(data, degree=options.degree, reference_pressure=MPA,
                              average_legs=options.average_legs, average_bins=options.average_bins,
                              slack=options.slack, calibrate=bool(options.calibrate), hinge=hinge,
                              memo=memo)
    reduce_time = time.perf_counter() - started

    n = stats.n_theta
    pressures, lengths, low = _grid(data, stats, options)
    grid = _constraint_rows(stated, options, pressures, lengths, n)
    contact_base, contact_incr = problem.contact_rows(stats, options, pressures, stated)
    prior = problem.prior_kind(options)
    structure = with_held_room(problem.structure_of(stats, options, grid.shape[0], contact_base.shape[0],
                                                    stated.wall, prior))
    before = build_problem.cache_info().misses
    nlp = build_problem(structure)
    build_time = nlp.build_time if build_problem.cache_info().misses > before else 0.0

    geometry_bounds = geo.bounds(data, options, stats.pipes)
    names, lbx, ubx = problem.names_and_bounds(structure, stats, options, geometry_bounds)
    values = problem.parameters(structure, stats, grid, contact_base, contact_incr, options, stated)
    fixed = geometry_mask(structure, lbx.size)
    inside = stated if not options.calibrate else geo.from_x(  # the stated geometry, within the bounds
        stated, structure.calibrate,
        np.clip(geo.stated_x(stated, structure.calibrate), lbx[fixed], ubx[fixed]))
    if warm is not None and warm.size == lbx.size:  # the slack hinge's next round: no linear screen
        x0 = warm
    else:
        x0 = problem.initial_guess(structure, stats, problem.reference_theta(data, n), lbx, ubx, inside)
    x0 = np.clip(x0, lbx + 1e-6 * (ubx - lbx), ubx - 1e-6 * (ubx - lbx))
    sse0 = float(nlp.sse(x0, nlp.layout.pack(values)))
    _weigh_prior(values, sse0, stats.points, x0.size, prior, data, options, n)
    if structure.calibrate:
        values["geometry_prior"] = geometry_prior(data.pam, structure.calibrate,
                                                  sse0 / max(stats.points - x0.size, 1))
    return Setup(stats, structure, nlp, build_time, reduce_time, pressures, lengths, low, grid,
                 geometry_bounds, names, lbx, ubx, values, fixed, x0, prior)


def _weigh_prior(values: dict, sse0: float, points: int, size: int, prior: str, data, options,
                 n: int) -> None:
    """The prior's weight and target in ``values``: σ̂²(θ − θ_p)ᵀΣ_p⁻¹(θ − θ_p) in MPa for a gaussian prior,
    σ̂²/σ_p² otherwise, with σ̂² = SSE/(points − size) at the start (a posterior)."""
    if prior == "gaussian":
        values["prior_weight"] = sse0 / max(points - size, 1)
        values["prior_target"] = np.asarray(options.prior_mean) / MPA
        values["prior_precision"] = np.asarray(options.prior_precision) * MPA**2
    elif prior != "none":
        values["prior_weight"] = sse0 / max(points - size, 1) / (options.prior_sd / MPA) ** 2
        if prior == "fixed":
            values["prior_target"] = problem.prior_target(data, options, n)


def geometry_prior(pam, calibrate, variance: float) -> np.ndarray:
    """(weight, stated value) per calibrated entry, x units: the stated sd as the calibration's prior,
    weight σ̂²/sd² (σ̂² = ``variance`` [N²], the fit's residual variance at the start: a posterior), 0 where
    no sd is stated. The posterior covariance of the fit then holds the stated sd once (issue 35)."""
    out = np.zeros((len(calibrate), 2))
    for k, name in enumerate(calibrate):
        index, unit = GEOMETRY[name]
        out[k, 1] = pam.geometry.as_vector()[index] / unit
        sd = pam.geometry_sd.get(name, 0.0) / unit
        out[k, 0] = variance / sd**2 if sd > 0 else 0.0
    return out


def updater_for(values: dict, data: ExperimentData, options: FitOptions, setup: Setup):
    """What the solve calls between its rounds to update ``values`` (:func:`.solve.updater`)."""
    return updater(values, setup.stats, setup.structure, data.pam.geometry, options, setup.pressures,
                   setup.low)


def _constraint_rows(stated, options: FitOptions, pressures, lengths, n: int) -> np.ndarray:
    """Drucker rows: Bernstein bounds between the grid's lengths (tangent) or grid points (sum)."""
    if options.drucker == "none":
        return np.zeros((0, n))
    if options.drucker == "sum":
        return drucker_rows(stated, options.degree, pressures, lengths, form="sum")
    return drucker.bernstein_rows([stated], options.degree, pressures, lengths, reference_pressure=MPA)


def _grid(data: ExperimentData, stats: Statistics, options: FitOptions):
    """(pressures, lengths, low): the Drucker grid over the tested pressures and L ∈ [low, L₀] plus the
    pipes' anchored lengths, low = min(tested lengths, pipe lengths, L_free(P_max) of the input moduli),
    before it is kept inside the braid's range of the geometry (:func:`.drucker.grid_low`: a calibrated
    geometry moves it)."""
    geometry = data.pam.geometry
    p_max = max(max(float(t.pressure.max()) for t in data.tests), 1.0)
    p_min = min(float(t.pressure.min()) for t in data.tests)
    pressures = np.linspace(max(0.0, p_min), p_max, options.grid_pressures)
    with np.errstate(invalid="ignore"):  # a pipe beyond the braid's reach: NaN, refused by the checks
        pipe_lengths = [float(braid.length_at_diameter(d, geometry)) for d in stats.pipes]
    low = min([geometry.initial_length, *pipe_lengths,
               *(float(t.length.min()) for t in data.tests if t.kind == "axial")])
    if data.pam.moduli is not None:
        try:
            low = min(low, float(Muscle.from_pam(data.pam).free_length(p_max)[0]))
        except SolverError:
            pass
    with np.errstate(invalid="ignore"):
        lengths = drucker.grid_lengths(geometry, stats.pipes, drucker.grid_low(geometry, low), options)
    return pressures, lengths, low
