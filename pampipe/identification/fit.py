"""`identify(data, options)`: reduce, build (cached), initialise, solve (:mod:`.solve`), check, report.

Steps: (1) one pass over the rows → sufficient statistics and cells; (2) the NLP for this problem
structure (built once, cached in memory and on disk); (3) initial guess = bounded linear least
squares at the stated geometry; (4) IPOPT with the Drucker rows on a (P, L) grid covering the
tested pressures and L ∈ [min(L_data, L_pipes, L_free(P_max)), L₀] plus the pipes' lengths; with
calibration, first with the geometry held at its stated values (the stated geometry's fit), then
with it free; (5) the exact Drucker minimum between grid points, re-solving with that point added
while it is negative (:mod:`.drucker`); (6) uncertainty from the Hessian at the solution;
(7) fit quality from the exact model on every row, the blocked-force geometry check
(:mod:`.geometry`) and which predictions the data determine (:mod:`.envelope`).
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import replace
from functools import cache
from typing import NamedTuple

import casadi as ca
import numpy as np

from pampipe._version import __version__
from pampipe.errors import InputError, SolverError
from pampipe.identification import drucker, envelope, exact, multistart, problem, quality, seeds, written
from pampipe.identification import geometry as geo
from pampipe.identification import model_error as model_errors
from pampipe.identification.covariance import analyse
from pampipe.identification.fit_nlp import build_problem
from pampipe.identification.grip import identify_grip
from pampipe.identification.options import FitOptions, parse_fit_options
from pampipe.identification.predict import evaluate_tests, predict
from pampipe.identification.result import MPA, Calibration, IdentifyResult, SolverInfo
from pampipe.identification.solve import fixed_geometry_fit, geometry_mask, solve_fit, updater
from pampipe.identification.statistics import Memo, Statistics, drucker_rows, reduce_experiment, without
from pampipe.model import bladder, braid
from pampipe.model.domain import check_length, check_pipe_diameter
from pampipe.model.muscle import Muscle
from pampipe.model.pam import Pam
from pampipe.specs.experiment import ExperimentData

#: What an IPOPT failure means for this fit (the generic words are in
#: :data:`pampipe.runtime.ipopt.IPOPT_STATUS`).
LAW_NAMES = problem.LAW_NAMES
def identify(data: ExperimentData, options: FitOptions | None = None, *, progress=None) -> IdentifyResult:
    """Fit the moduli (and the calibrated geometry) of ``data.pam`` to the experiment's tests (§6).

    The slack hinge (docs/physics.md §6.2): measured axial rows where the fitted model predicts no
    tension are scored by max(0, F) = 0, like the report and the plots score them. They are found
    after a fit, moved to cells whose hinge the fit updates, and the fit is repeated from its
    solution until no measured row outside the cells predicts ≤ 0 (at most :data:`HINGE_ROUNDS`).
    """
    options = options or parse_fit_options(data.fit, source=data.source)
    say = progress or (lambda _text: None)
    if not data.tests:  # slip tests only: μ and κ from the stated PAM's moduli
        return identify_grip(data, options)
    _check(data, options)
    hinge: dict[int, np.ndarray] = {}
    fitted, warm, wall_time, iterations, builds, notes = None, None, 0.0, 0, [], []
    memo = Memo()  # what the hinge's refits reuse of the first reduction
    for round_ in range(HINGE_ROUNDS):
        try:
            fitted = _fit(data, options, say, hinge, warm, memo)
        except SolverError as error:
            if round_ == 0:
                raise
            notes.append(f"the refit that scores {sum(r.size for r in hinge.values())} measured row(s) by "
                         f"max(0, F) failed ({error}); the fit reported scores them by the negative model "
                         "force.")  # the previous round's fit is reported
            break
        wall_time, iterations = wall_time + fitted.solver.wall_time, iterations + fitted.solver.iterations
        builds.append((fitted.solver.build_time, fitted.solver.origin))
        more = {} if options.calibrate else _negative_rows(data, fitted.axial_model, hinge)
        if not more:
            break
        say(f"{sum(r.size for r in more.values())} measured row(s) where the model predicts no tension: "
            "refitting them as max(0, F)")
        hinge = {i: np.union1d(hinge.get(i, np.zeros(0, dtype=np.int64)), more.get(i, ()))
                 for i in set(hinge) | set(more)}
        warm = fitted.x
    else:
        notes.append(f"after {HINGE_ROUNDS} fits {sum(r.size for r in more.values())} measured row(s) still "
                     "predict a negative force and are scored by it (the slack hinge did not settle).")
    result, finish = fitted.report()  # only for the fit reported
    model_error, joint, fit_quality, predictions, warnings = finish()
    warnings = (*warnings, *quality.warnings(fit_quality, result.calibration, options.calibrate), *notes)
    result = replace(result, model_error=model_error, parameter_uncertainty=joint, quality=fit_quality,
                     predictions=predictions, warnings=warnings)
    built = [b for b in builds if b[0] > 0] or builds[-1:]  # the rounds that built or loaded an NLP
    slip = None
    if data.slip:
        from pampipe.slip import fit_slip

        say(f"fitting friction and load coupling to {len(data.slip)} slip test(s)")
        slip = fit_slip(data.slip, Muscle.from_pam(Pam(data.pam.name, result.geometry, result.moduli)))
    return replace(result, slip=slip, solver=replace(
        result.solver, wall_time=wall_time, iterations=iterations, build_time=sum(b[0] for b in builds),
        origin=built[0][1]))


#: Fits at most while measured rows turn out to predict no tension (the slack hinge).
HINGE_ROUNDS = 4
#: A measured row is hinged when the model predicts below −this × the test's largest |force|.
HINGE_TOLERANCE = 1e-6


def _negative_rows(data: ExperimentData, axial_model: dict[int, np.ndarray], hinge) -> dict[int, np.ndarray]:
    """Measured axial rows (force > 0), not yet hinged, where the fitted model (``axial_model``: test
    index → F_ax of every row [N], before the hinge) predicts a tension below zero by more than
    :data:`HINGE_TOLERANCE` of the test's largest force (at F ≈ 0 the hinge changes nothing)."""
    out = {}
    for index, model in axial_model.items():
        test = data.tests[index]
        below = model < -HINGE_TOLERANCE * max(float(np.max(np.abs(test.force))), 1e-300)
        rows = np.flatnonzero(without((test.force > 0) & below, hinge.get(index, ())))
        if rows.size:
            out[index] = rows
    return out


class Round(NamedTuple):
    """One fit of the slack hinge's rounds (see :func:`_fit`)."""

    x: np.ndarray  # the solution
    solver: SolverInfo  # this round's solve
    report: Callable  # () -> (IdentifyResult, finish), computed when asked for: only the reported round is
    axial_model: dict[int, np.ndarray]  # test index -> F_ax of every row [N], before the hinge


def _fit(data: ExperimentData, options: FitOptions, say, hinge, warm, memo: Memo) -> Round:
    """One fit with the ``hinge`` rows in cells, from ``warm`` (a previous solution) if given. Its
    report gives the IdentifyResult and ``finish``; ``finish()`` gives its (model error, written joint
    uncertainty, fit quality, predictions the data determine, warnings), which the result leaves out
    (None, no warnings). Both are computed only for the fit reported, not for every round of the hinge,
    which needs only the axial model to find the rows it moves.
    ``memo``: what the rounds of the hinge share of the reduction
    (:class:`~pampipe.identification.statistics.Memo`)."""
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
    structure = problem.structure_of(stats, options, grid.shape[0], contact_base.shape[0], stated.wall, prior)
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
    x0 = problem.initial_guess(structure, stats, problem.reference_theta(data, n), lbx, ubx, inside)
    if warm is not None and warm.size == x0.size:
        x0 = warm
    x0 = np.clip(x0, lbx + 1e-6 * (ubx - lbx), ubx - 1e-6 * (ubx - lbx))
    p = nlp.layout.pack(values)
    sse0 = float(nlp.sse(x0, p))
    points_fit = stats.points
    if prior == "gaussian":  # σ̂²(θ − θ_p)ᵀΣ_p⁻¹(θ − θ_p) in MPa, σ̂² from the start: a posterior
        values["prior_weight"] = sse0 / max(points_fit - x0.size, 1)
        values["prior_target"] = np.asarray(options.prior_mean) / MPA
        values["prior_precision"] = np.asarray(options.prior_precision) * MPA**2
    elif prior != "none":
        values["prior_weight"] = sse0 / max(points_fit - x0.size, 1) / (options.prior_sd / MPA) ** 2
        if prior == "fixed":
            values["prior_target"] = problem.prior_target(data, options, n)

    stated_fit, search = None, None
    wall_time, iterations = 0.0, 0
    if options.calibrate:
        say("fitting at the stated geometry")
        held = _copied(values)
        x_held, info = fixed_geometry_fit(nlp, held, x0, lbx, ubx, stats, structure,
                                          updater(held, stats, structure, stated, options, pressures, low))
        wall_time, iterations = info.wall_time, info.iterations
        stated_fit = float(nlp.sse(x_held, nlp.layout.pack(held)))
        seed = seeds.seed(data, stated, None if "initial_length" not in options.calibrate
                          else tuple(v * 1e-3 for v in geometry_bounds["initial_length"]))
        reference, p0 = problem.reference_theta(data, n), nlp.layout.pack(values)

        def guess_at(start):
            guess = problem.initial_guess(structure, stats, reference, lbx, ubx,
                                          geo.from_x(stated, structure.calibrate, start))
            guess[fixed] = start
            return np.clip(guess, lbx + 1e-6 * (ubx - lbx), ubx - 1e-6 * (ubx - lbx))

        starts, screened = multistart.start_points(
            structure.calibrate, lbx[fixed], ubx[fixed], geo.stated_x(stated, structure.calibrate),
            _seed_starts(data, stated, structure.calibrate, seed),
            lambda start: float(nlp.sse(guess_at(start), p0)))
        say(f"global calibration: IPOPT from {len(starts)} starting geometries ({options.mode}, "
            f"calibrating {', '.join(options.calibrate)})")
        totals = [0.0, 0]

        def run(start):
            own = _copied(values)
            update = updater(own, stats, structure, stated, options, pressures, low)
            free, second = solve_fit(nlp, own, guess_at(start), lbx, ubx, stats, structure, update)
            totals[0] += second.wall_time
            totals[1] += second.iterations
            x_free = np.asarray(free["x"], dtype=float).ravel()
            return (free, second, own), float(nlp.sse(x_free, nlp.layout.pack(own))), x_free[fixed]

        search, (solution, info, values) = multistart.search(run, starts, structure.calibrate, points_fit,
                                                             seed, screened)
        info = replace(info, wall_time=totals[0], iterations=totals[1])
    else:
        say(f"solving the {x0.size}-parameter NLP with IPOPT ({options.mode}, {options.objective})")
        solution, info = solve_fit(nlp, values, x0, lbx, ubx, stats, structure,
                                   updater(values, stats, structure, stated, options, pressures, low))
    x = np.asarray(solution["x"], dtype=float).ravel()
    wall_time, iterations = wall_time + info.wall_time, iterations + info.iterations
    p = nlp.layout.pack(values)
    if exact.applies(structure):  # IPOPT stops at its tolerance: the exact optimum at its active set
        x = exact.polish(nlp, p, x, lbx, ubx)
    geometry = geo.from_x(stated, structure.calibrate, x[fixed]) if options.calibrate else stated

    moduli, pipe_moduli, blocks = problem.moduli_of(structure, stats, x)
    axial = {i: predict(Pam(data.pam.name, geometry, moduli), t) for i, t in enumerate(data.tests)
             if t.kind == "axial"}
    solver = SolverInfo(info.status, True, iterations, wall_time, build_time, reduce_time,
                        float(solution["f"]), nlp.origin)

    @cache
    def report():
        """(IdentifyResult, finish) of this fit."""
        sse_model = float(nlp.sse(x, p))
        hessian = np.asarray(nlp.hessian(x, p), dtype=float)
        uncertainty = analyse(x, hessian, sse_model, points_fit, lbx, ubx, names)
        tests, sse, sum_rmse, models, unclipped = evaluate_tests(data, geometry, moduli, pipe_moduli, blocks,
                                                                 slack=options.slack, evaluated=axial)
        minimum = _drucker_minimum(geometry, blocks, moduli, pressures, lengths, stats, options)
        blocked = geo.blocked_force(data, geometry)
        calibration = replace(
            _calibration(stated, geometry, structure, uncertainty, names, stated_fit, points_fit, blocked,
                         geo.blocked_force(data, stated) if options.calibrate else blocked),
            blocked_force_skipped=geo.blocked_force_skipped(data, geometry), search=search)

        def muscles_at(xv):
            return problem.muscles_of(structure, stats, stated, xv)

        prior_hessian = problem.prior_hessian(structure, values, x.size)
        data_only = None if prior == "none" else analyse(x, hessian - prior_hessian, sse_model, points_fit,
                                                         lbx, ubx, names)

        def finish():
            model_error = model_errors.estimate(data, x, prior_hessian, muscles_at,
                                                slack=options.slack, half_range=0.5 * (ubx - lbx),
                                                constraints=_constraints(structure, grid, x, lbx, ubx,
                                                                         uncertainty.at_bound),
                                                model=unclipped)
            top = max(float(t.pressure.max()) for t in data.tests)
            joint = written.parameter_uncertainty(uncertainty, x, names, structure, hessian, lbx, ubx,
                                                  model_error.value, lambda xv: muscles_at(xv)[0],
                                                  written.bores(data, options, geometry), top, data_only)
            predictions = envelope.predictions(data, structure, x, uncertainty, geometry, stated, options,
                                               stats)
            warnings = _warnings(solver.status, uncertainty, names, minimum, options, structure, calibration,
                                 stats, data, predictions)
            return (model_error, joint, quality.assess(data, models, names, uncertainty.at_bound),
                    predictions, tuple(warnings))

        return IdentifyResult(
            success=True, status=solver.status, options=options, moduli=moduli, pipe_moduli=pipe_moduli, x=x,
            names=tuple(names), tests=tests, sse=sse, sum_rmse=sum_rmse, points=data.points, solver=solver,
            uncertainty=uncertainty, drucker_minimum=minimum,
            drucker_grid={"pressures": pressures.tolist(), "lengths": lengths.tolist(),
                          "form": options.drucker},
            warnings=(), provenance=_provenance(data, structure, nlp), geometry=geometry,
            calibration=calibration, predictions=None, slack_rows=stats.slack_rows,
            excluded_rows=stats.excluded, parameter_uncertainty=None, model_error=None, quality=None), finish

    return Round(x, solver, report, axial)


#: A Drucker row C·θ ≥ 0 (unit max-norm, MPa) at most this far from zero is active at the solution.
ACTIVE = 1e-5


def _constraints(structure, grid, x, lower, upper, at_bound):
    """(rows, lower, active) of the fit's linear constraints rows·x ≥ lower: the bounds and the Drucker
    rows of every moduli block; ``active``: reached at ``x`` (bounds as the uncertainty says)."""
    n = x.size
    rows, low, active = [np.eye(n), -np.eye(n)], [lower, -upper], [at_bound & (x - lower <= upper - x),
                                                                     at_bound & (x - lower > upper - x)]
    at = 0
    for name, size in structure.blocks():
        if name not in ("contact", "geometry") and grid.shape[0]:
            block = np.zeros((grid.shape[0], n))
            block[:, at:at + size] = grid
            rows.append(block)
            low.append(np.zeros(grid.shape[0]))
            active.append(grid @ x[at:at + size] <= ACTIVE)
        at += size
    return np.vstack(rows), np.concatenate(low), np.concatenate(active)


def _copied(values: dict) -> dict:
    """A copy of the parameter values that a solve may change (slack flags, Drucker rows)."""
    return {key: np.array(value, copy=True) for key, value in values.items()}


def _seed_starts(data, stated, calibrate, seed) -> list[tuple[str, np.ndarray | None]]:
    """Starts from the data: the stated geometry, the blocked-force angle at the stated L₀, and the
    (α₀, L₀) of the force slopes (:mod:`.seeds`), in x units (None where the data give none)."""
    out = [("stated geometry", geo.stated_x(stated, calibrate))]
    blocked = geo.blocked_force(data, stated)
    if "braid_angle" in calibrate and blocked is not None and blocked.fitting_angle is not None:
        out.append(("blocked-force slope", geo.stated_x(replace(stated, braid_angle=blocked.fitting_angle),
                                                        calibrate)))
    if seed is not None and "braid_angle" in calibrate:
        at = replace(stated, braid_angle=seed.braid_angle,
                     initial_length=seed.initial_length if "initial_length" in calibrate
                     else stated.initial_length)
        out.append(("force slopes", geo.stated_x(at, calibrate)))
    return out


def _constraint_rows(stated, options: FitOptions, pressures, lengths, n: int) -> np.ndarray:
    """Drucker rows: Bernstein bounds between the grid's lengths (tangent) or grid points (sum)."""
    if options.drucker == "none":
        return np.zeros((0, n))
    if options.drucker == "sum":
        return drucker_rows(stated, options.degree, pressures, lengths, form="sum")
    return drucker.bernstein_rows([stated], options.degree, pressures, lengths, reference_pressure=MPA)


def _check(data: ExperimentData, options: FitOptions) -> None:
    geometry = data.pam.geometry
    kinds = {t.kind for t in data.tests}
    if options.mode in ("per_pipe", "contact_increment") and "radial" not in kinds:
        raise InputError(f"{data.source}: fit.mode '{options.mode}' needs radial tests; use mode: shared "
                         "for axial tests only.")
    if options.prior_toward == "axial" and options.prior_sd is not None and options.mode == "shared":
        raise InputError(f"{data.source}: fit.prior.toward 'axial' applies to the per_pipe and "
                         "contact_increment modes; use 'input' or 'zero' with mode: shared.")
    if options.prior_toward == "axial" and options.mode == "per_pipe" and "axial" not in kinds \
            and options.prior_sd is not None:
        raise InputError(f"{data.source}: fit.prior.toward 'axial' needs an axial test.")
    ramps = [t.name for t in data.tests if not t.has_levels]
    if ramps and options.objective == "sum_rmse":
        raise InputError(f"{data.source}: fit.objective 'sum_rmse' sums the RMSE over pressure levels, and "
                         f"test(s) {', '.join(ramps)} have none (pressure ramps); use least_squares.")
    if options.average_legs and any(t.kind == "axial" and t.protocol != "isobaric" for t in data.tests):
        raise InputError(f"{data.source}: fit.average_legs averages the lengthening and shortening legs at "
                         "each pressure level; it needs isobaric axial tests (pressure held while the "
                         "length is cycled).")
    if options.calibrate and options.objective != "least_squares":
        raise InputError(f"{data.source}: fit.calibrate fits the geometry by least squares; use "
                         "objective: least_squares (the report still gives the sum of RMSE per level).")
    if options.calibrate and options.average_legs:
        raise InputError(f"{data.source}: fit.calibrate and fit.average_legs cannot be combined; the "
                         "calibrated fit uses every row.")
    for test in data.tests:
        where = f"{test.spec.data}"
        if test.kind == "axial":
            check_length(geometry, test.length, where=f"{where}: length")
        elif "braid_angle" not in options.calibrate:
            check_pipe_diameter(geometry, test.spec.pipe_diameter, where=f"test {test.name}: pipe_diameter")


def _grid(data: ExperimentData, stats: Statistics, options: FitOptions):
    """(pressures, lengths, low): the Drucker grid over the tested pressures and L ∈ [low, L₀] plus the
    pipes' anchored lengths, low = min(tested lengths, pipe lengths, L_free(P_max) of the input moduli)."""
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
    low = max(low, geometry.shortest_length * 1.001)
    with np.errstate(invalid="ignore"):
        lengths = drucker.grid_lengths(geometry, stats.pipes, low, options)
    return pressures, lengths, low


def _drucker_minimum(geometry, blocks, moduli, pressures, lengths, stats, options) -> drucker.Minimum | None:
    """The exact minimum over the box for every moduli set; contact mode adds the anchored state."""
    if options.drucker == "none":
        return None
    found = [drucker.minimum(m.as_vector(), MPA, geometry, pressures, lengths, options.drucker)
             for m in blocks.values()]
    if options.mode == "contact_increment":
        theta, delta = moduli.as_vector(), moduli.contact_vector()
        fine = np.linspace(np.min(pressures), np.max(pressures), 200)
        for d in stats.pipes:
            length = float(braid.length_at_diameter(d, geometry))
            for pressure in fine:
                engaged = theta + pressure / MPA * delta
                e1, e2 = bladder.drucker_tangent_moduli(pressure, length, d, geometry, engaged, MPA)
                for value, direction in ((float(e1), "axial"), (float(e2), "hoop")):
                    found.append(drucker.Minimum(value, float(pressure), length, f"{direction} (anchored)"))
    return min(found, key=lambda m: m.value)


def _calibration(stated, geometry, structure, uncertainty, names, stated_sse, rows, blocked,
                 stated_blocked) -> Calibration:
    intervals = {}
    for name in structure.calibrate:
        i = names.index(problem.GEOMETRY_NAMES[name])
        low, high = uncertainty.lower[i], uncertainty.upper[i]
        intervals[name] = (float(low), float(high)) if np.isfinite(low) else None
    stated_rmse = None if stated_sse is None else math.sqrt(stated_sse / max(rows, 1))
    return Calibration(stated, geometry, tuple(structure.calibrate), intervals, stated_rmse, blocked,
                       stated_blocked)


def _warnings(status, u, names, minimum, options, structure, calibration, stats, data,
              predictions) -> list[str]:
    out = []
    if status != "Solve_Succeeded":
        out.append(f"IPOPT stopped with {status}: the solution is acceptable but not fully converged.")
    if u.rank_deficient:
        out.append(f"the data determine only {u.rank} of {len(names)} parameter combinations; individual "
                   "coefficients without an interval are not identifiable from these tests "
                   "(docs/physics.md §6); see which predictions are determined, or add a prior (fit.prior).")
    bound = [name for name, flag in zip(names, u.at_bound, strict=True) if flag]
    if bound:
        out.append(f"at a bound: {', '.join(bound)} (intervals ignore the bound; consider fit.bounds"
                   + (" or fit.calibration_bounds" if any(b.startswith("geometry.") for b in bound) else "")
                   + ").")
    if minimum is not None and not minimum.stable:
        out.append(f"Drucker stability fails between the grid points: {minimum.direction} tangent modulus "
                   f"{minimum.value / 1e6:.4g} MPa at P = {minimum.pressure / 1e3:.4g} kPa, L = "
                   f"{minimum.length * 1e3:.5g} mm; refine fit.drucker_grid.")
    if options.mode == "per_pipe" and not (structure.qr or structure.cells):
        out.append("per_pipe without an axial test: the PAM file gets the first pipe's moduli; each pipe's "
                   "moduli are valid only in that pipe (see per_pipe in the JSON).")
    out += _geometry_warnings(calibration, options)
    if calibration.search is not None and calibration.search.runner_ups():
        best, other = calibration.search.best, calibration.search.runner_ups()[0]
        shown = ", ".join(f"{name} {value:.4g} {multistart.UNITS[name]}"
                          for name, value in zip(calibration.calibrated, other.geometry, strict=True))
        out.append(f"another local minimum fits almost as well (RMSE {other.rmse:.4g} N against "
                   f"{best.rmse:.4g} N) at {shown}: the data barely tell these geometries apart; a test that "
                   "separates them (a pressure ramp at the rest length, lengths closer to full contraction) "
                   "would, or state the geometry you trust and narrow fit.calibration_bounds.")
    unused = [name for name, *_ in options.calibration_bounds if name not in options.calibrate]
    if unused:
        out.append(f"fit.calibration_bounds for {', '.join(unused)} is not used: only calibrated entries "
                   "have bounds (add them to fit.calibrate or --calibrate).")
    judged = {pipe.pipe_diameter for pipe in predictions.pipes}
    outside = [d for d in options.pipe_diameters if d not in judged]
    if outside:
        g = calibration.geometry
        shown = ", ".join(f"{d * 1e3:.4g} mm" for d in outside)
        out.append(f"pipe diameter(s) {shown} of fit.pipe_diameters cannot be judged: the muscle touches "
                   f"only bores between its rest diameter "
                   f"{g.initial_diameter * 1e3:.4g} mm and {g.largest_diameter * 1e3:.4g} mm.")
    if stats.excluded:
        out.append(f"{stats.excluded} slack row(s) (force <= 0) were excluded from the fit (fit.slack: "
                   "exclude).")
    unknown = [t.name for t in data.tests if t.direction_source == "unknown"]
    if unknown:
        out.append(f"test(s) {', '.join(unknown)}: the rows are not in time order and there is no time or "
                   "direction column, so the loading/unloading legs are unknown (hysteresis effects cannot "
                   "be fitted).")
    return out


def _geometry_warnings(calibration: Calibration, options: FitOptions) -> list[str]:
    out = []
    undetermined = [name for name, band in calibration.intervals.items() if band is None]
    if undetermined:
        out.append(f"the data do not determine the calibrated {' and '.join(undetermined)} (no 95 % "
                   "interval): the moduli can absorb the geometry; add a test at the rest length (a pressure "
                   "ramp at L0, where the force depends on the geometry alone) or calibrate less.")
    blocked = calibration.blocked_force
    if blocked is None:
        return out
    g = calibration.geometry
    if not blocked.consistent:
        words = (f"the blocked-force slope dF/dP at L = {blocked.length * 1e3:.5g} mm is "
                 f"{blocked.slope * 1e3:.4g} N/kPa in the data but {blocked.geometry_slope * 1e3:.4g} N/kPa "
                 f"for the {'calibrated' if options.calibrate else 'stated'} geometry (braid angle "
                 f"{math.degrees(g.braid_angle):.4g} deg from the axis, L0 = "
                 f"{g.initial_length * 1e3:.5g} mm)")
        if blocked.fitting_angle is not None:
            words += (f"; a braid angle of {math.degrees(blocked.fitting_angle):.4g} deg from the axis would "
                      "fit it (at this L0)")
        if not options.calibrate:
            words += "; calibrate it: --calibrate braid_angle --calibrate initial_length"
        out.append(words + ".")
    if blocked.has_threshold and "initial_length" not in options.calibrate:
        out.append(f"the muscle needs about {blocked.threshold / 1e3:.3g} kPa before it pulls at its longest "
                   f"tested length ({blocked.length * 1e3:.5g} mm), which the model cannot show at the "
                   "stated rest length: calibrate it (--calibrate initial_length) or diagnose prestrain.")
    return out


def _provenance(data, structure, nlp) -> dict:
    return {"pampipe": __version__, "casadi": ca.__version__, "numpy": np.__version__,
            "experiment": str(data.source), "parameters": nlp.n_x, "constraints": nlp.n_g,
            "nlp_nodes": nlp.n_nodes}
