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
from collections.abc import Callable
from dataclasses import replace
from functools import cache, partial
from typing import NamedTuple

import casadi as ca
import numpy as np

from pampipe._version import __version__
from pampipe.errors import InputError, SolverError
from pampipe.identification import drucker, envelope, exact, problem, quality, written
from pampipe.identification import geometry as geo
from pampipe.identification import model_error as model_errors
from pampipe.identification.covariance import analyse
from pampipe.identification.fit_setup import Setup, set_up, updater_for
from pampipe.identification.fit_warnings import fit_warnings
from pampipe.identification.held_out import refit as refit_from_full
from pampipe.identification.options import FitOptions, parse_fit_options
from pampipe.identification.predict import evaluate_tests, predict
from pampipe.identification.result import MPA, Calibration, IdentifyResult, SolverInfo
from pampipe.identification.solve import fixed_geometry_fit, solve_fit
from pampipe.identification.statistics import Memo, without
from pampipe.model import bladder, braid
from pampipe.model.domain import check_length, check_pipe_diameter
from pampipe.model.muscle import Muscle
from pampipe.model.pam import Pam
from pampipe.specs.experiment import ExperimentData

#: The names of the four moduli laws in the order of θ (:data:`.problem.LAW_NAMES`).
LAW_NAMES = problem.LAW_NAMES


def identify(data: ExperimentData, options: FitOptions | None = None, *, progress=None,
             refits: str = "active_set") -> IdentifyResult:
    """Fit the moduli (and the calibrated geometry) of ``data.pam`` to the experiment's tests (§6).

    The slack hinge (docs/physics.md §6.2): measured axial rows where the fitted model predicts no
    tension are scored by max(0, F) = 0, like the report and the plots score them. They are found
    after a fit, moved to cells whose hinge the fit updates, and the fit is repeated from its
    solution until no measured row outside the cells predicts ≤ 0 (at most :data:`HINGE_ROUNDS`).

    ``refits``: how the model error's held-out fits are solved (:func:`_refit`): "active_set" (from the full
    fit, where least squares allows) or "ipopt" (each an IPOPT fit, the reference the tests check it by).
    """
    options = options or parse_fit_options(data.fit, source=data.source)
    say = progress or (lambda _text: None)
    if not data.tests:  # slip tests only: μ and κ from the stated PAM's moduli
        from pampipe.identification.grip import identify_grip

        return identify_grip(data, options)
    _check(data, options)
    hinge: dict[int, np.ndarray] = {}
    fitted, warm, centred, wall_time, iterations, builds, notes = None, None, None, 0.0, 0, [], []
    memo = Memo()  # what the hinge's refits reuse of the first reduction
    for round_ in range(HINGE_ROUNDS):
        try:
            fitted = _fit(data, options, say, hinge, warm, memo, round_, centred)
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
        warm, centred = fitted.x, fitted.hessian()
    else:
        notes.append(f"after {HINGE_ROUNDS} fits {sum(r.size for r in more.values())} measured row(s) still "
                     "predict a negative force and are scored by it (the slack hinge did not settle).")
    result, finish = fitted.report()  # only for the fit reported
    _check_fitted(data, result.geometry)
    model_error, joint, fit_quality, predictions, warnings = finish(refits=refits)
    warnings = (*warnings, *quality.warnings(fit_quality, result.calibration, options.calibrate), *notes)
    result = replace(result, model_error=model_error, parameter_uncertainty=joint, quality=fit_quality,
                     predictions=predictions, warnings=warnings)
    built = [b for b in builds if b[0] > 0] or builds[-1:]  # the rounds that built or loaded an NLP
    slip = None
    if data.slip:
        from pampipe.slip.workflow import fit_slip

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
    fit: Fit  # the round's geometry and moduli (a refit of the model error needs no report)
    hessian: Callable  # () -> the Hessian of the round's problem at x


def _fit(data: ExperimentData, options: FitOptions, say, hinge, warm, memo: Memo,
         round_: int = 0, centred=None, setup: Setup | None = None) -> Round:
    """One fit with the ``hinge`` rows in cells, from ``warm`` (a previous solution, ``centred`` the Hessian
    of its problem there: see :func:`.solve.solve_fit`) if given. Its
    report gives the IdentifyResult and ``finish``; ``finish()`` gives its (model error, written joint
    uncertainty, fit quality, predictions the data determine, warnings), which the result leaves out
    (None, no warnings). Both are computed only for the fit reported, not for every round of the hinge,
    which needs only the axial model to find the rows it moves.
    ``memo``: what the rounds of the hinge share of the reduction
    (:class:`~pampipe.identification.statistics.Memo`); ``round_``: which round (0: the first), named in
    the progress line of every later one; ``setup``: :func:`.fit_setup.set_up` of these arguments if the
    caller made it (this fit changes its parameter values).

    Steps: :func:`.fit_setup.set_up` (reduce, build, start), :func:`_calibrated` or one solve, :func:`_solved`
    (polish, moduli), and :func:`_report` when asked for.
    """
    setup = setup or set_up(data, options, say, hinge, warm, memo)
    if options.calibrate:
        solve = _calibrated(data, options, say, setup)
    else:
        which = f", round {round_ + 1} of at most {HINGE_ROUNDS} (slack rows as max(0, F))" if round_ else ""
        say(f"solving the {setup.x0.size}-parameter NLP with IPOPT ({options.mode}, {options.objective})"
            + which)
        solution, info = solve_fit(setup.nlp, setup.values, setup.x0, setup.lbx, setup.ubx, setup.stats,
                                   setup.structure, updater_for(setup.values, data, options, setup),
                                   centred if warm is not None and warm.size == setup.x0.size else None)
        solve = Solve(solution, info, setup.values, 0.0, 0, None, None)
    fit = _solved(data, options, setup, solve)
    return Round(fit.x, fit.solver, cache(lambda: _report(data, options, setup, solve, fit)), fit.axial, fit,
                 lambda: np.asarray(setup.nlp.hessian(fit.x, fit.p), dtype=float))


class Solve(NamedTuple):
    """What the solve gives: IPOPT's solution and statistics and the parameter values it used; with
    calibration also the earlier fit at the stated geometry and the multistart search."""

    solution: dict
    info: SolverInfo
    values: dict
    wall_time: float  # [s] of the solves before ``info``'s (the stated geometry's fit)
    iterations: int  # and their iterations
    stated_fit: float | None  # SSE at the stated geometry
    search: object | None  # multistart.Search


class Fit(NamedTuple):
    """The solution of one round (:func:`_solved`): x polished, the geometry and moduli it gives."""

    x: np.ndarray
    p: object  # the packed parameter values of the solve
    geometry: object
    moduli: object
    pipe_moduli: object
    blocks: dict
    axial: dict[int, np.ndarray]  # test index -> F_ax of every row [N], before the hinge
    solver: SolverInfo


def _calibrated(data: ExperimentData, options: FitOptions, say, setup: Setup) -> Solve:
    """(4) with calibration: the fit at the stated geometry, then IPOPT from several starting geometries
    (:mod:`.multistart`), the best kept."""
    from pampipe.identification import multistart, seeds  # imported here: only a calibration uses them

    nlp, structure, stats, stated = setup.nlp, setup.structure, setup.stats, data.pam.geometry
    lbx, ubx, fixed, values = setup.lbx, setup.ubx, setup.fixed, setup.values
    say("fitting at the stated geometry")
    held = _copied(values)
    x_held, info = fixed_geometry_fit(nlp, held, setup.x0, lbx, ubx, stats, structure,
                                      updater_for(held, data, options, setup))
    wall_time, iterations = info.wall_time, info.iterations
    stated_fit = float(nlp.sse(x_held, nlp.layout.pack(held)))
    seed = seeds.seed(data, stated, None if "initial_length" not in options.calibrate
                      else tuple(v * 1e-3 for v in setup.geometry_bounds["initial_length"]))
    reference, p0 = problem.reference_theta(data, stats.n_theta), nlp.layout.pack(values)

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

    def run(start, x0=None):
        own, x0 = _copied(values), guess_at(start) if x0 is None else x0
        update = updater_for(own, data, options, setup)
        update(x0, set())  # the Drucker rows and slack cells of the start's geometry, not the stated one's
        free, second = solve_fit(nlp, own, x0, lbx, ubx, stats, structure, update)
        totals[0] += second.wall_time
        totals[1] += second.iterations
        x_free = np.asarray(free["x"], dtype=float).ravel()
        return (free, second, own), float(nlp.sse(x_free, nlp.layout.pack(own))), x_free[fixed]

    held_start = np.asarray(x_held, dtype=float).ravel()
    search, (solution, info, values) = multistart.search(
        run, starts, structure.calibrate, stats.points, seed, screened,
        fallback=(multistart.FALLBACK, held_start[fixed], lambda: run(held_start[fixed], held_start)))
    info = replace(info, wall_time=totals[0], iterations=totals[1])
    return Solve(solution, info, values, wall_time, iterations, stated_fit, search)


def _solved(data: ExperimentData, options: FitOptions, setup: Setup, solve: Solve) -> Fit:
    """The round's solution: x at the exact optimum of its active set where that applies (IPOPT stops at its
    tolerance), the geometry and moduli it gives, and every axial row's model force."""
    nlp, structure = setup.nlp, setup.structure
    x = np.asarray(solve.solution["x"], dtype=float).ravel()
    wall_time, iterations = solve.wall_time + solve.info.wall_time, solve.iterations + solve.info.iterations
    p = nlp.layout.pack(solve.values)
    if exact.applies(structure):
        x = exact.polish(nlp, p, x, setup.lbx, setup.ubx)
    geometry = geo.from_x(data.pam.geometry, structure.calibrate, x[setup.fixed]) if options.calibrate \
        else data.pam.geometry
    moduli, pipe_moduli, blocks = problem.moduli_of(structure, setup.stats, x)
    axial = {i: predict(Pam(data.pam.name, geometry, moduli), t) for i, t in enumerate(data.tests)
             if t.kind == "axial"}
    solver = SolverInfo(solve.info.status, True, iterations, wall_time, setup.build_time, setup.reduce_time,
                        float(solve.solution["f"]), nlp.origin)
    return Fit(x, p, geometry, moduli, pipe_moduli, blocks, axial, solver)


def _report(data: ExperimentData, options: FitOptions, setup: Setup, solve: Solve, fit: Fit):
    """(5)-(7) of the reported round: (IdentifyResult, finish) with the uncertainty from the Hessian, each
    test's scores, the exact Drucker minimum and the geometry checks; ``finish`` (:func:`_finish`) gives the
    rest."""
    nlp, structure, stated, names, x = setup.nlp, setup.structure, data.pam.geometry, setup.names, fit.x
    sse_model = float(nlp.sse(x, fit.p))
    hessian = np.asarray(nlp.hessian(x, fit.p), dtype=float)
    uncertainty = analyse(x, hessian, sse_model, setup.stats.points, setup.lbx, setup.ubx, names)
    tests, sse, sum_rmse, models, _ = evaluate_tests(data, fit.geometry, fit.moduli, fit.pipe_moduli,
                                                             fit.blocks, slack=options.slack,
                                                             evaluated=fit.axial)
    minimum = _drucker_minimum(fit.geometry, fit.blocks, fit.moduli, setup.pressures, setup.lengths,
                               setup.stats, options)
    blocked = geo.blocked_force(data, fit.geometry)
    calibration = replace(
        _calibration(stated, fit.geometry, structure, uncertainty, names, solve.stated_fit,
                     setup.stats.points, blocked,
                     geo.blocked_force(data, stated) if options.calibrate else blocked),
        blocked_force_skipped=geo.blocked_force_skipped(data, fit.geometry), search=solve.search)
    prior_hessian = problem.prior_hessian(structure, solve.values, x.size)
    data_only = None if not prior_hessian.any() else analyse(x, hessian - prior_hessian, sse_model,
                                                             setup.stats.points, setup.lbx, setup.ubx, names)
    finish = partial(_finish, data, options, setup, fit, hessian, uncertainty, data_only, models, minimum,
                     calibration)
    return IdentifyResult(
        success=True, status=fit.solver.status, options=options, moduli=fit.moduli,
        pipe_moduli=fit.pipe_moduli, x=x, names=tuple(names), tests=tests, sse=sse, sum_rmse=sum_rmse,
        points=data.points, solver=fit.solver, uncertainty=uncertainty, drucker_minimum=minimum,
        drucker_grid={"pressures": setup.pressures.tolist(), "lengths": setup.lengths.tolist(),
                      "form": options.drucker},
        warnings=(), provenance=_provenance(data, structure, nlp), geometry=fit.geometry,
        calibration=calibration, predictions=None, slack_rows=setup.stats.slack_rows,
        excluded_rows=setup.stats.excluded, parameter_uncertainty=None, model_error=None,
        quality=None), finish


def _finish(data, options, setup: Setup, fit: Fit, hessian, uncertainty, data_only, models, minimum,
            calibration, refits: str = "active_set"):
    """(model error, written joint uncertainty, fit quality, predictions the data determine, warnings) of the
    reported round (:func:`_report`); ``refits``: how the model error's held-out fits are solved
    (:func:`_refit`)."""
    structure, stats, names, x = setup.structure, setup.stats, setup.names, fit.x
    lbx, ubx = setup.lbx, setup.ubx

    def muscles_at(xv):
        return problem.muscles_of(structure, stats, data.pam.geometry, xv)

    fit_quality = quality.assess(data, models, names, uncertainty.at_bound)
    model_error = model_errors.estimate(data, muscles_at, x, partial(_refit, options, fit, hessian, refits),
                                        slack=options.slack, noise=fit_quality.noise_floor)
    top = max(float(t.pressure.max()) for t in data.tests)
    joint = written.parameter_uncertainty(uncertainty, x, names, structure, hessian, lbx, ubx,
                                          model_error, lambda xv: muscles_at(xv)[0],
                                          written.bores(data, options, fit.geometry), top, data_only)
    predictions = envelope.predictions(data, structure, x, uncertainty, fit.geometry, data.pam.geometry,
                                       options, stats)
    warnings = fit_warnings(fit.solver.status, uncertainty, names, minimum, options, structure, calibration,
                            stats, data, predictions)
    few = model_errors.few_blocks_warning(model_error)
    return model_error, joint, fit_quality, predictions, tuple(warnings) + ((few,) if few else ())


#: A Drucker row C·θ ≥ 0 (unit max-norm, MPa) at most this far from zero is active at the solution.
ACTIVE = 1e-5


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
    seeded = {"braid_angle", "initial_length"} & set(options.calibrate)
    for test in data.tests:
        where = f"{test.spec.data}"
        if test.kind == "axial" and not seeded:  # calibrated: checked on the fitted geometry (_check_fitted)
            check_length(geometry, test.length, where=f"{where}: length")
        elif "braid_angle" not in options.calibrate:
            check_pipe_diameter(geometry, test.spec.pipe_diameter, where=f"test {test.name}: pipe_diameter")


def _refit(options: FitOptions, fit: Fit, hessian: np.ndarray, refits: str, data: ExperimentData):
    """(muscle, {pipe: muscle}) of the fit to ``data`` (the experiment with a block of the protocol withheld,
    :mod:`.model_error`), a calibrated geometry held at the full fit's, the slack hinge not repeated
    (``hessian``: the full fit's Hessian at its solution).
    ``refits`` "active_set": solved from the full fit by :func:`.held_out.refit` where that applies (least
    squares), else, and always with "ipopt", by one fit of the same NLP structure (cached) from the linear
    screen: IPOPT, then the rounds of the slack cells as the full fit's, :func:`.solve.solve_fit`); only the
    round's geometry and moduli, not its report (the Hessian, the uncertainty, each test's scores, the
    Drucker minimum)."""
    x, moduli = fit.x, slice(0, fit.x.size - len(options.calibrate))  # the geometry is x's last block
    if options.calibrate:
        data = replace(data, pam=replace(data.pam, geometry=fit.geometry))
        options = replace(options, calibrate=())
    setup = set_up(data, options, lambda _text: None, {}, None, Memo())  # for both solves: reduced once
    if refits == "active_set":
        found = refit_from_full(data, options, x[moduli], hessian[moduli, moduli], setup)
        if found is not None:
            return found
    fitted = _fit(data, options, lambda _text: None, {}, None, Memo(), setup=setup).fit
    return problem.muscles(fitted.geometry, fitted.moduli, fitted.pipe_moduli)


def _check_fitted(data: ExperimentData, geometry) -> None:
    """The tested lengths inside the braid's range B/√3 < L < B of the fitted geometry. A calibrated braid
    angle or rest length is checked here, not as stated: the stated value only seeds the calibration,
    whose bounds (:func:`.geometry.bounds`) keep every tested length inside, so this is a guard."""
    for test in data.tests:
        if test.kind == "axial":
            check_length(geometry, test.length, where=f"{test.spec.data}: length (fitted geometry)")


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


def _provenance(data, structure, nlp) -> dict:
    return {"pampipe": __version__, "casadi": ca.__version__, "numpy": np.__version__,
            "experiment": str(data.source), "parameters": nlp.n_x, "constraints": nlp.n_g,
            "nlp_nodes": nlp.n_nodes}
