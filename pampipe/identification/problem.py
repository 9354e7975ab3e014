"""What one fit feeds the cached NLP: decision names and bounds, the parameter values, the start.

Units of the decision vector x: moduli in MPa (b per P_ref = 1 MPa), the braid angle in deg, the
rest length and the wall thickness in mm (:data:`pampipe.identification.fit_nlp.GEOMETRY`).
"""

from __future__ import annotations

import math

import numpy as np

from pampipe.errors import InputError
from pampipe.identification import geometry as geo
from pampipe.identification.fit_nlp import Structure
from pampipe.identification.moment_cells import capacity
from pampipe.identification.options import FitOptions
from pampipe.identification.statistics import MPA, Statistics, radial_coefficients, regressors, tangent_rows
from pampipe.model import bladder, braid
from pampipe.model.muscle import Muscle
from pampipe.model.pam import Moduli
from pampipe.specs.experiment import ExperimentData

LAW_NAMES = ("axial.a", "axial.b", "hoop.a", "hoop.b")
#: Display names of the calibrated geometry entries in x.
GEOMETRY_NAMES = {"braid_angle": "geometry.braid_angle_from_axis_deg",
                  "initial_length": "geometry.initial_length_mm",
                  "bladder_thickness": "geometry.bladder_thickness_mm"}


def structure_of(stats: Statistics, options: FitOptions, grid_rows: int, contact_rows: int, wall: str,
                 prior: str) -> Structure:
    """The cache key of this fit's NLP."""
    qr = stats.axial is not None
    if options.objective == "sum_rmse":
        groups = len(stats.groups)
    else:
        groups = 1 if qr else 0
    cells = 0 if stats.cells is None else capacity(stats.cells.count, headroom=not options.calibrate)
    return Structure(options.mode, options.objective, stats.n_theta, groups, qr, cells,
                     tuple((r.levels, r.pipe) for r in stats.radial), len(stats.pipes),
                     grid_rows, contact_rows, options.contact_terms, prior,
                     options.calibrate, wall, options.max_iterations, options.tolerance)


def names_and_bounds(structure: Structure, stats: Statistics, options: FitOptions, geometry_bounds):
    """(names, lower, upper) of the decision vector, in x units."""
    k = structure.n_theta // 4
    law = [f"{name}{j}" for name in LAW_NAMES for j in range(k)]
    names, lower, upper = [], [], []
    for block, size in structure.blocks():
        if block == "contact":
            picked = np.flatnonzero(structure.contact_selection().any(axis=1))
            names += [f"contact.{law[i]}" for i in picked]
            lower += [options.bounds_contact[0] / MPA] * size
            upper += [options.bounds_contact[1] / MPA] * size
        elif block == "geometry":
            for name in structure.calibrate:
                names.append(GEOMETRY_NAMES[name])
                lower.append(geometry_bounds[name][0])
                upper.append(geometry_bounds[name][1])
        else:
            label = "theta" if block == "theta" else f"pipe_{stats.pipes[int(block[4:])] * 1e3:.1f}mm"
            names += [f"{label}.{item}" for item in law]
            for i in range(size):
                low, high = options.bounds_constant if i in (0, 2 * k) else options.bounds_other
                lower.append(low / MPA)
                upper.append(high / MPA)
    return names, np.array(lower), np.array(upper)


def parameters(structure: Structure, stats: Statistics, grid, contact_base, contact_incr, options,
               geometry) -> dict:
    """Values of every parameter entry except the scales and the prior weight (set by the caller)."""
    values = {"scale": 1.0, "scale_sse": 1.0, "smooth": options.contact_smoothing,
              "eps": options.rmse_smoothing, "geometry": geometry.as_vector()}
    axial = stats.axial
    if structure.qr:
        if structure.objective == "least_squares":
            axial = axial.combined()
        values.update(ax_r=np.concatenate(list(axial.r), axis=1), ax_z=axial.z.T, ax_rest=axial.rest)
    if structure.axial_groups:
        values["ax_n"] = group_points(stats) if structure.objective == "sum_rmse" else \
            [float(stats.axial.points.sum()) if stats.axial is not None else 0.0]
    if structure.cells:
        values["cells"] = stats.cells.padded(structure.cells)
        if not structure.calibrate:
            values.update(linear_cells(stats, structure.cells, geometry))
        if structure.objective == "sum_rmse":
            agg = np.zeros((structure.axial_groups, structure.cells))
            agg[stats.cells.group, np.arange(stats.cells.count)] = 1.0
            values["cell_groups"] = agg
    for j, r in enumerate(stats.radial):
        values[f"rad{j}_test"] = [r.pipe_diameter, r.axial_load]
        values[f"rad{j}_mom"] = r.moments
    if structure.grid_rows:
        values["grid"] = grid
    if structure.contact_rows:
        values.update(cgrid_base=contact_base, cgrid_incr=contact_incr)
    if structure.prior != "none":
        values["prior_weight"] = 0.0
    if structure.calibrate:  # weights set by the caller (fit_setup), where a stated sd gives one
        values["geometry_prior"] = np.zeros((len(structure.calibrate), 2))
    if structure.prior in ("fixed", "gaussian"):
        values["prior_target"] = np.zeros(structure.n_theta)
    if structure.prior == "gaussian":
        values["prior_precision"] = np.zeros((structure.n_theta, structure.n_theta))
    return values


def linear_cells(stats: Statistics, capacity: int, geometry) -> dict:
    """Rows [offset, φ] (θ in MPa) of the model u and its derivatives u_x, u_L, u_LL, u_xL at every cell
    mean, at the stated geometry (x = P/P_ref). u is affine in x, so x-differences are exact; the
    L-derivatives are central differences with h = 10⁻⁵ m (truncation ~h² relative, round-off
    ~10⁻¹⁶·F/h², both far below what the cell sums resolve)."""
    c = stats.cells.moments
    x, length = c[1], c[2]

    def rows(xv, lv):
        offset, phi = regressors(xv * MPA, lv, geometry, stats.degree)
        return np.column_stack([offset, phi])

    h = 1e-5
    mid, up, down = rows(x, length), rows(x, length + h), rows(x, length - h)
    x_up = rows(x + 0.5, length + h) - rows(x - 0.5, length + h)
    x_down = rows(x + 0.5, length - h) - rows(x - 0.5, length - h)
    out = {"cell_u": mid, "cell_ux": rows(x + 0.5, length) - rows(x - 0.5, length),
           "cell_ul": (up - down) / (2 * h), "cell_ull": (up - 2 * mid + down) / h**2,
           "cell_uxl": (x_up - x_down) / (2 * h)}
    return {k: np.vstack([v, np.zeros((capacity - v.shape[0], v.shape[1]))]) for k, v in out.items()}


def group_points(stats: Statistics) -> np.ndarray:
    """Rows per axial group (QR rows and cell rows)."""
    points = np.zeros(len(stats.groups))
    if stats.axial is not None:
        points += stats.axial.points
    if stats.cells is not None:
        points += np.bincount(stats.cells.group, weights=stats.cells.moments[0], minlength=points.size)
    return points


def contact_rows(stats: Statistics, options: FitOptions, pressures, geometry):
    """Drucker rows of the anchored state in ``contact_increment`` mode (base, increment parts)."""
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


def reference_theta(data: ExperimentData, n: int) -> np.ndarray:
    """The input moduli in MPa (b at P_ref = 1 MPa) if the PAM has them at this degree, else zeros."""
    moduli = data.pam.moduli
    if moduli is None or moduli.degree + 1 != n // 4:
        return np.zeros(n)
    theta = moduli.as_vector() / MPA
    k = n // 4
    for block in (1, 3):  # b coefficients scale with P_ref: E = a + b P/P_ref
        theta[block * k:(block + 1) * k] *= MPA / moduli.reference_pressure
    return theta


def prior_kind(options: FitOptions) -> str:
    if options.prior_mean is not None:
        return "gaussian"
    if options.prior_sd is None:
        return "none"
    return "axial" if options.prior_toward == "axial" else "fixed"


def prior_target(data: ExperimentData, options: FitOptions, n: int) -> np.ndarray:
    if options.prior_toward == "zero":
        return np.zeros(n)
    if data.pam.moduli is None:
        raise InputError(f"{data.source}: fit.prior.toward 'input' needs a moduli: block in the PAM; "
                         "add one or use toward: zero.")
    if data.pam.moduli.degree + 1 != n // 4:
        raise InputError(f"{data.source}: fit.prior: the PAM's moduli have degree {data.pam.moduli.degree}, "
                         f"the fit has degree {options.degree}.")
    return reference_theta(data, n)


def initial_guess(structure: Structure, stats: Statistics, reference, lower, upper, geometry
                  ) -> np.ndarray:
    """Linear least squares per moduli block at the stated geometry with the bounds only (no
    Drucker), contact increments 0, calibrated geometry at its stated value.

    Rows: the axial QR groups' R, z, the measured cells' means (weight √n) and the clearly anchored
    radial bins (ȳ > 20 % of the test's largest). Columns are scaled to unit norm and a tiny ridge
    (1e-6) toward a reference picks values for the combinations the data do not fix: the input
    moduli (or zero) for the muscle's block, the muscle's block for a per-pipe block.
    """
    rows = {name: ([], []) for name, _ in structure.blocks()}
    if stats.axial is not None:
        rows["theta"][0].extend(stats.axial.r)
        rows["theta"][1].extend(stats.axial.z)
    if stats.cells is not None:
        c = stats.cells.moments
        measured = (c[0] > 0) & ~stats.cells.slack
        offset, phi = regressors(c[1, measured] * MPA, c[2, measured], geometry, stats.degree)
        w = np.sqrt(c[0, measured])
        rows["theta"][0].append(w[:, None] * phi)
        rows["theta"][1].append(w * (c[3, measured] - offset))
    for r in stats.radial:
        a0, a1, area, load = radial_coefficients(r.pipe_diameter, r.axial_load, geometry, stats.degree, MPA)
        n, xbar, ybar = r.moments[0], r.moments[1], r.moments[2]
        anchored = (n > 0) & (ybar > 0.2 * max(ybar.max(), 1e-9))
        w = np.sqrt(n[anchored])[:, None]
        block = structure.radial_block(r.pipe)
        rows[block][0].append(w * (a0[None, :] + xbar[anchored, None] * a1[None, :]))
        rows[block][1].append(w[:, 0] * (ybar[anchored] + load - area * xbar[anchored]))
    at, offset = {}, 0
    for name, size in structure.blocks():
        at[name] = slice(offset, offset + size)
        offset += size
    solved = {}
    for name, _ in structure.blocks():  # the muscle's block first: the pipe blocks start from it
        a_rows, b_rows = rows[name]
        if name in ("contact", "geometry") or not a_rows:
            continue
        start = solved.get("theta", reference)
        solved[name] = bounded_least_squares(np.vstack(a_rows), np.concatenate(b_rows), start,
                                             lower[at[name]], upper[at[name]])
    if "geometry" in at:
        solved["geometry"] = geo.stated_x(geometry, structure.calibrate)
    return np.concatenate([solved.get(name, np.zeros(size)) for name, size in structure.blocks()])


def bounded_least_squares(a, b, reference, lower, upper, ridge: float = 1e-6) -> np.ndarray:
    """argmin ‖a·θ − b‖² + ridge‖S(θ − reference)‖² within the box, S = column norms of a.

    Active-set iteration: solve on the free columns, fix the most violated one at its bound,
    repeat (at most one pass per column). A start for IPOPT, not a final answer.
    """
    norms = np.linalg.norm(a, axis=0)
    norms[norms == 0] = 1.0
    k = a.shape[1]
    scale = math.sqrt(ridge) * np.linalg.norm(a / norms, ord=2)
    matrix = np.vstack([a / norms, scale * np.eye(k)])
    target = np.concatenate([b, scale * np.clip(reference, lower, upper) * norms])
    low, high = lower * norms, upper * norms
    z = np.clip(reference * norms, low, high)
    free = np.ones(k, dtype=bool)
    for _ in range(k):
        rhs = target - matrix[:, ~free] @ z[~free]
        z[free] = np.linalg.lstsq(matrix[:, free], rhs, rcond=None)[0]
        excess = np.maximum(low - z, 0) + np.maximum(z - high, 0)
        if not np.any(excess > 0):
            break
        worst = int(np.argmax(excess))
        z[worst] = min(max(z[worst], low[worst]), high[worst])
        free[worst] = False
        if not free.any():
            break
    return np.clip(z, low, high) / norms


def moduli_of(structure: Structure, stats: Statistics, x):
    """(muscle moduli, {pipe: moduli}, {block name: moduli}) from a decision vector (MPa)."""
    blocks, at = {}, 0
    contact = None
    for name, size in structure.blocks():
        part = x[at:at + size]
        at += size
        if name == "contact":
            contact = structure.contact_selection() @ part * MPA
        elif name != "geometry":
            blocks[name] = part * MPA
    out = {name: Moduli.from_vector(theta, reference_pressure=MPA, contact=contact)
           for name, theta in blocks.items()}
    main = out.get("theta", next(iter(out.values())))
    pipes = {d: out[structure.radial_block(k)] for k, d in enumerate(stats.pipes)}
    return main, pipes, out


def muscles_of(structure: Structure, stats: Statistics, stated, x):
    """(the muscle, {pipe diameter: muscle of its radial tests}) of a decision vector ``x``."""
    geometry = geo.from_x(stated, structure.calibrate, x[x.size - len(structure.calibrate):]) \
        if structure.calibrate else stated
    main, pipes, _ = moduli_of(structure, stats, x)
    return muscles(geometry, main, pipes)


def muscles(geometry, main: Moduli, pipes: dict) -> tuple[Muscle, dict]:
    """(the muscle of ``main``, {pipe diameter: muscle of its moduli}) of one geometry."""
    def make(m: Moduli) -> Muscle:
        contact = m.contact_vector() if m.contact is not None else None
        return Muscle(geometry, m.as_vector(), m.reference_pressure, contact=contact)

    return make(main), {d: make(m) for d, m in pipes.items()}


def prior_hessian(structure: Structure, values: dict, size: int) -> np.ndarray:
    """∇²(prior/2) [N²/unit²] over the decision vector: the prior's share of the fit's Hessian."""
    out = np.zeros((size, size))
    at, offset = {}, 0
    for name, length in structure.blocks():
        at[name] = np.arange(offset, offset + length)
        offset += length
    if structure.calibrate:  # the stated geometry's prior: diagonal
        out[at["geometry"], at["geometry"]] += np.asarray(values["geometry_prior"], float)[:, 0]
    if structure.prior == "none":
        return out
    weight = float(values["prior_weight"])
    if structure.prior in ("fixed", "gaussian"):
        block = weight * (np.asarray(values["prior_precision"], float) if structure.prior == "gaussian"
                          else np.eye(structure.n_theta))
        for name in at:
            if name not in ("contact", "geometry"):
                out[np.ix_(at[name], at[name])] += block
    elif structure.mode == "per_pipe":  # toward the axial moduli
        for k in range(structure.pipes):
            pipe, theta = at[f"pipe{k}"], at["theta"]
            for a, b, sign in ((pipe, pipe, 1), (theta, theta, 1), (pipe, theta, -1), (theta, pipe, -1)):
                out[np.ix_(a, b)] += sign * weight * np.eye(structure.n_theta)
    else:  # contact increments toward zero
        out[np.ix_(at["contact"], at["contact"])] += weight * np.eye(len(at["contact"]))
    return out
