"""`identify(data, options)`: reduce, build (cached), initialise, solve, analyse, report.

Steps: (1) one pass over the rows → sufficient statistics; (2) the NLP for this problem structure
(built once, cached); (3) initial guess = unconstrained linear least squares on the axial groups
and the clearly anchored radial bins (minimum-norm, column-scaled), clipped into the bounds;
(4) IPOPT with the Drucker rows on a (P, L) grid covering the tested pressures and
L ∈ [min(L_data, L_pipes, L_free(P_max)), L₀] plus the pipes' lengths; (5) uncertainty from the
Hessian at the solution; (6) fit quality from the exact model on every row.
"""

from __future__ import annotations

import math
import time
from importlib.metadata import PackageNotFoundError, version

import casadi as ca
import numpy as np
from scipy.optimize import lsq_linear

from pampipe.errors import InputError, SolverError
from pampipe.experiment import ExperimentData
from pampipe.identify.nlp import Structure, build_problem
from pampipe.identify.options import FitOptions, parse_fit_options
from pampipe.identify.predict import evaluate_tests
from pampipe.identify.result import MPA, IdentifyResult, SolverInfo
from pampipe.identify.statistics import Statistics, drucker_rows, reduce_experiment, tangent_rows
from pampipe.identify.uncertainty import analyse
from pampipe.model import bladder, braid
from pampipe.model.domain import check_length, check_pipe_diameter
from pampipe.model.muscle import Muscle
from pampipe.model.pam import Moduli
from pampipe.nlp import solve

#: What an IPOPT failure means for this fit (the generic words are in :data:`pampipe.nlp.IPOPT_STATUS`).
FIT_HINTS = {
    "Maximum_Iterations_Exceeded": "IPOPT stopped at the iteration limit (raise fit.max_iterations)",
    "Infeasible_Problem_Detected": "no moduli satisfy the bounds and the Drucker constraints together "
                                   "(widen fit.bounds or check the data)",
}
LAW_NAMES = ("axial.a", "axial.b", "hoop.a", "hoop.b")


def identify(data: ExperimentData, options: FitOptions | None = None, *, progress=None) -> IdentifyResult:
    """Fit the moduli of ``data.pam`` to the experiment's tests (docs/physics.md §6)."""
    options = options or parse_fit_options(data.fit, source=data.source)
    say = progress or (lambda _text: None)
    _check(data, options)
    geometry = data.pam.geometry
    pref = MPA
    started = time.perf_counter()
    say(f"reducing {data.points:,} rows to sufficient statistics")
    stats = reduce_experiment(data, degree=options.degree, reference_pressure=pref,
                              average_legs=options.average_legs, average_bins=options.average_bins)
    axial = stats.axial
    if axial is not None and options.objective == "least_squares":
        axial = axial.combined()
    reduce_time = time.perf_counter() - started

    n = stats.n_theta
    pressures, lengths = _grid(data, stats, options)
    grid = drucker_rows(geometry, options.degree, pressures, lengths, form=options.drucker) \
        if options.drucker != "none" else np.zeros((0, n))
    contact_base, contact_incr = _contact_rows(stats, options, pressures, geometry)
    prior = _prior_kind(options)
    structure = Structure(options.mode, options.objective, n, 0 if axial is None else axial.test.size,
                          tuple((r.levels, r.pipe) for r in stats.radial), len(stats.pipes),
                          grid.shape[0], contact_base.shape[0], options.contact_terms, prior,
                          options.max_iterations, options.tolerance)
    before = build_problem.cache_info().misses
    problem = build_problem(structure)
    build_time = problem.build_time if build_problem.cache_info().misses > before else 0.0

    names, lbx, ubx = _decision_names_and_bounds(structure, stats, options)
    values = _parameters(structure, stats, axial, grid, contact_base, contact_incr, options)
    x0 = _initial_guess(structure, stats, axial, _reference_theta(data, n), lbx, ubx)
    x0 = np.clip(x0, lbx + 1e-6 * (ubx - lbx), ubx - 1e-6 * (ubx - lbx))
    p = problem.layout.pack(values)
    sse0 = float(problem.sse(x0, p))
    points_fit = int((0 if axial is None else axial.points.sum())
                     + sum(r.moments[0].sum() for r in stats.radial))
    if prior != "none":
        noise = sse0 / max(points_fit - x0.size, 1)
        values["prior_weight"] = noise / (options.prior_sd / MPA) ** 2
        if prior == "fixed":
            values["prior_target"] = _prior_target(data, options, n)
    values["scale_sse"] = max(sse0, 1e-12)
    groups = structure.axial_groups + sum(levels for levels, _ in structure.radial)
    values["scale"] = (max(sse0, 1e-12) if options.objective == "least_squares"
                       else max(groups * math.sqrt(sse0 / max(points_fit, 1)), 1e-9))
    p = problem.layout.pack(values)

    say(f"solving the {x0.size}-parameter NLP with IPOPT ({options.mode}, {options.objective})")
    solution, stats_ipopt = solve(problem.solver, what="the moduli fit (no result was written)",
                                  hints=FIT_HINTS, x0=x0, p=p, lbx=lbx, ubx=ubx, lbg=0, ubg=ca.inf)
    status = stats_ipopt.status
    x = np.asarray(solution["x"], dtype=float).ravel()

    moduli, pipe_moduli, blocks = _moduli(structure, stats, x, pref)
    sse_model = float(problem.sse(x, p))
    hessian = np.asarray(problem.hessian(x, p), dtype=float)
    uncertainty = analyse(x, hessian, sse_model, points_fit, lbx, ubx, names)
    tests, sse, sum_rmse = evaluate_tests(data, moduli, pipe_moduli, blocks)
    margin = _drucker_margin(geometry, blocks, moduli, pressures, lengths, stats, options, pref)
    warnings = _warnings(status, uncertainty, names, margin, options, structure)
    return IdentifyResult(
        success=True, status=status, options=options, moduli=moduli, pipe_moduli=pipe_moduli, x=x,
        names=tuple(names), tests=tests, sse=sse, sum_rmse=sum_rmse, points=data.points,
        solver=SolverInfo(status, True, stats_ipopt.iterations, stats_ipopt.wall_time, build_time,
                          reduce_time, float(solution["f"])),
        uncertainty=uncertainty, drucker_margin=margin,
        drucker_grid={"pressures": pressures.tolist(), "lengths": lengths.tolist(), "form": options.drucker},
        warnings=tuple(warnings), provenance=_provenance(data, structure, problem))


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
    for test in data.tests:
        where = f"{test.spec.data}"
        if test.kind == "axial":
            check_length(geometry, test.length, where=f"{where}: length")
        else:
            check_pipe_diameter(geometry, test.spec.pipe_diameter, where=f"test {test.name}: pipe_diameter")


def _grid(data: ExperimentData, stats: Statistics, options: FitOptions):
    geometry = data.pam.geometry
    tested = np.concatenate([t.level_pressure for t in data.tests])
    p_max = max(float(tested.max()), 1.0)
    pressures = np.linspace(max(0.0, float(tested.min())), p_max, options.grid_pressures)
    pipe_lengths = [float(braid.length_at_diameter(d, geometry)) for d in stats.pipes]
    low = min([geometry.initial_length, *pipe_lengths,
               *(float(t.length.min()) for t in data.tests if t.kind == "axial")])
    if data.pam.moduli is not None:
        try:
            low = min(low, float(Muscle.from_pam(data.pam).free_length(p_max)[0]))
        except SolverError:
            pass
    low = max(low, geometry.shortest_length * 1.001)
    lengths = np.unique(np.concatenate([np.linspace(low, geometry.initial_length, options.grid_lengths),
                                        pipe_lengths]))
    return pressures, lengths


def _contact_rows(stats: Statistics, options: FitOptions, pressures, geometry):
    n = stats.n_theta
    if options.mode != "contact_increment" or options.drucker == "none":
        return np.zeros((0, n)), np.zeros((0, n))
    base, incr = [], []
    for d in stats.pipes:
        length = braid.length_at_diameter(d, geometry)
        eps1, eps2 = bladder.strains(length, d, geometry)
        for x in pressures / stats.reference_pressure:
            for eps, first in ((eps1, 0), (eps2, 2)):
                row = tangent_rows(eps, x, stats.degree, first)[0]
                scale = max(np.abs(row).max(), np.abs(x * row).max())
                base.append(row / scale)
                incr.append(x * row / scale)
    return np.array(base), np.array(incr)


def _reference_theta(data: ExperimentData, n: int) -> np.ndarray:
    """The input moduli in MPa (b at P_ref = 1 MPa) if the PAM has them at this degree, else zeros."""
    moduli = data.pam.moduli
    if moduli is None or moduli.degree + 1 != n // 4:
        return np.zeros(n)
    theta = moduli.as_vector() / MPA
    k = n // 4
    for block in (1, 3):  # b coefficients scale with P_ref: E = a + b P/P_ref
        theta[block * k:(block + 1) * k] *= MPA / moduli.reference_pressure
    return theta


def _prior_kind(options: FitOptions) -> str:
    if options.prior_sd is None:
        return "none"
    return "axial" if options.prior_toward == "axial" else "fixed"


def _prior_target(data: ExperimentData, options: FitOptions, n: int) -> np.ndarray:
    if options.prior_toward == "zero":
        return np.zeros(n)
    if data.pam.moduli is None:
        raise InputError(f"{data.source}: fit.prior.toward 'input' needs a moduli: block in the PAM; "
                         "add one or use toward: zero.")
    if data.pam.moduli.degree + 1 != n // 4:
        raise InputError(f"{data.source}: fit.prior: the PAM's moduli have degree {data.pam.moduli.degree}, "
                         f"the fit has degree {options.degree}.")
    return _reference_theta(data, n)


def _decision_names_and_bounds(structure: Structure, stats: Statistics, options: FitOptions):
    k = structure.n_theta // 4
    law = [f"{name}{j}" for name in LAW_NAMES for j in range(k)]
    names, lower, upper = [], [], []
    for block, size in structure.blocks():
        if block == "contact":
            picked = np.flatnonzero(structure.contact_selection().any(axis=1))
            names += [f"contact.{law[i]}" for i in picked]
            lower += [options.bounds_contact[0]] * size
            upper += [options.bounds_contact[1]] * size
            continue
        label = "theta" if block == "theta" else f"pipe_{stats.pipes[int(block[4:])] * 1e3:.1f}mm"
        names += [f"{label}.{item}" for item in law]
        for i in range(size):
            low, high = options.bounds_constant if i in (0, 2 * k) else options.bounds_other
            lower.append(low)
            upper.append(high)
    return names, np.array(lower) / MPA, np.array(upper) / MPA


def _parameters(structure, stats, axial, grid, contact_base, contact_incr, options) -> dict:
    values = {"scale": 1.0, "scale_sse": 1.0, "smooth": options.contact_smoothing,
              "eps": options.rmse_smoothing}
    if structure.axial_groups:
        values.update(ax_r=np.concatenate(list(axial.r), axis=1), ax_z=axial.z.T, ax_rest=axial.rest,
                      ax_n=axial.points.astype(float))
    for j, r in enumerate(stats.radial):
        values[f"rad{j}_coef"] = np.concatenate([r.amp_phi0, r.amp_phi1, [r.amp_area, r.amp_load]])
        values[f"rad{j}_mom"] = r.moments
    if structure.grid_rows:
        values["grid"] = grid
    if structure.contact_rows:
        values.update(cgrid_base=contact_base, cgrid_incr=contact_incr)
    if structure.prior != "none":
        values["prior_weight"] = 0.0
    if structure.prior == "fixed":
        values["prior_target"] = np.zeros(structure.n_theta)
    return values


def _initial_guess(structure: Structure, stats: Statistics, axial, reference_theta, lower, upper
                   ) -> np.ndarray:
    """Linear least squares per moduli block with the bounds only (no Drucker), contact increments 0.

    Rows: the axial groups' R, z and the clearly anchored radial bins (ȳ > 20 % of the test's
    largest). Columns are scaled to unit norm and a tiny ridge (1e-6) toward a reference picks
    values for the combinations the data do not fix: the input moduli (or zero) for the muscle's
    block, the muscle's block for a per-pipe block (radial data fix two combinations per pipe).
    """
    rows = {name: ([], []) for name, _ in structure.blocks()}
    if structure.axial_groups:
        for g in range(axial.test.size):
            rows["theta"][0].append(axial.r[g])
            rows["theta"][1].append(axial.z[g])
    for r in stats.radial:
        n, xbar, ybar = r.moments[0], r.moments[1], r.moments[2]
        anchored = (n > 0) & (ybar > 0.2 * max(ybar.max(), 1e-9))
        w = np.sqrt(n[anchored])[:, None]
        block = structure.radial_block(r.pipe)
        rows[block][0].append(w * (r.amp_phi0[None, :] + xbar[anchored, None] * r.amp_phi1[None, :]))
        rows[block][1].append(w[:, 0] * (ybar[anchored] + r.amp_load - r.amp_area * xbar[anchored]))
    solved, at = {}, {}
    offset = 0
    for name, size in structure.blocks():
        at[name] = slice(offset, offset + size)
        offset += size
    for name, _ in structure.blocks():  # the muscle's block first: the pipe blocks start from it
        a_rows, b_rows = rows[name]
        if name == "contact" or not a_rows:
            continue
        reference = solved.get("theta", reference_theta)
        solved[name] = _bounded_ls(np.vstack(a_rows), np.concatenate(b_rows), reference,
                                   lower[at[name]], upper[at[name]])
    return np.concatenate([solved.get(name, np.zeros(size)) for name, size in structure.blocks()])


def _bounded_ls(a, b, reference, lower, upper, ridge: float = 1e-6):
    """argmin ‖a·θ − b‖² + ridge‖S(θ − reference)‖² within bounds, S = column norms of a."""
    norms = np.linalg.norm(a, axis=0)
    norms[norms == 0] = 1.0
    k = a.shape[1]
    scale = math.sqrt(ridge) * np.linalg.norm(a / norms, ord=2)
    matrix = np.vstack([a / norms, scale * np.eye(k)])
    target = np.concatenate([b, scale * np.clip(reference, lower, upper) * norms])
    fit = lsq_linear(matrix, target, bounds=(lower * norms, upper * norms), method="bvls")
    return fit.x / norms


def _moduli(structure: Structure, stats: Statistics, x, pref):
    """(muscle moduli, {pipe: moduli}, {block name: moduli}) from the solution (x in MPa)."""
    blocks, at = {}, 0
    contact = None
    for name, size in structure.blocks():
        part = x[at:at + size]
        at += size
        if name == "contact":
            contact = structure.contact_selection() @ part * MPA
        else:
            blocks[name] = part * MPA
    out = {name: Moduli.from_vector(theta, reference_pressure=pref, contact=contact)
           for name, theta in blocks.items()}
    main = out.get("theta", next(iter(out.values())))
    pipes = {d: out[structure.radial_block(k)] for k, d in enumerate(stats.pipes)}
    return main, pipes, out


def _drucker_margin(geometry, blocks, moduli, pressures, lengths, stats, options, pref) -> float:
    """Smallest Drucker quantity on the grid from the model's own functions [Pa]."""
    if options.drucker == "none":
        return float("nan")
    pp, ll = np.meshgrid(pressures, lengths, indexing="ij")
    dd = braid.diameter_at_length(ll, geometry)
    values = []
    for m in blocks.values():
        theta = m.as_vector()
        if options.drucker == "sum":
            work = bladder.drucker_second_order_work(pp, ll, dd, geometry, theta, pref)
            values.append(np.min(work) * geometry.initial_length**2)
        else:
            values.append(min(np.min(e) for e in bladder.drucker_tangent_moduli(pp, ll, dd, geometry, theta,
                                                                                 pref)))
    if options.mode == "contact_increment":
        theta, delta = moduli.as_vector(), moduli.contact_vector()
        for d in stats.pipes:
            length = braid.length_at_diameter(d, geometry)
            for pressure in pressures:
                engaged = theta + pressure / pref * delta
                moduli_now = bladder.drucker_tangent_moduli(pressure, length, d, geometry, engaged, pref)
                values.append(min(moduli_now))
    return float(min(values))


def _warnings(status, u, names, margin, options, structure) -> list[str]:
    out = []
    if status != "Solve_Succeeded":
        out.append(f"IPOPT stopped with {status}: the solution is acceptable but not fully converged.")
    if u.rank_deficient:
        out.append(f"the data determine only {u.rank} of {len(names)} parameter combinations; individual "
                   "coefficients without an interval are not identifiable from these tests "
                   "(docs/physics.md §6); "
                   "see the identifiable combinations, or add a prior (fit.prior).")
    bound = [name for name, flag in zip(names, u.at_bound, strict=True) if flag]
    if bound:
        out.append(f"at a bound: {', '.join(bound)} (intervals ignore the bound; consider fit.bounds).")
    if options.drucker != "none" and margin < 1e3:
        out.append("the Drucker stability constraint is active: it limits the fit somewhere on the grid.")
    if options.mode == "per_pipe" and not structure.axial_groups:
        out.append("per_pipe without an axial test: the PAM file gets the first pipe's moduli; each pipe's "
                   "moduli are valid only in that pipe (see per_pipe in the JSON).")
    return out


def _provenance(data, structure, problem) -> dict:
    try:
        pampipe_version = version("pampipe")
    except PackageNotFoundError:
        pampipe_version = "unknown"
    return {"pampipe": pampipe_version, "casadi": ca.__version__, "numpy": np.__version__,
            "experiment": str(data.source), "parameters": problem.n_x, "constraints": problem.n_g,
            "nlp_nodes": problem.n_nodes}
