"""What ``identify`` writes of its uncertainty: joint covariance, model error, undetermined directions.

The decision vector x of the fit is in MPa (moduli), deg (braid angle) and mm (lengths): exactly the
*scaled coordinates* of :mod:`pampipe.model.uncertainty`. The written names are the muscle's moduli
θ (the block written to the PAM file) and the calibrated geometry; the covariance is the fit's
(restricted to the identifiable combinations, :mod:`.uncertainty`) converted to SI.

**Undetermined directions.** Every combination that is not identifiable (its 95 % half-width is
not below :data:`pampipe.identification.covariance.IDENTIFIABLE` of the range the bounds allow, or
its eigenvalue is below 10⁻¹⁴ of the largest) has zero variance in that covariance; it is listed
instead. The combinations' directions δx = V_i/D (x units) are restricted to the written entries and
orthonormalised there (SVD; a direction with less than :data:`NEGLIGIBLE` of its length in the
written entries, e.g. one of contact increments only, is left out). Each unit vector q gets a
``scale``: the width that the data leave open along it, min(σ/√(qᵀHq), the largest step inside the
fit's bounds) [scaled units]; and ``moves``: the change of the radial force at the largest tested
pressure and of the anchoring pressure at each named bore for a step of ``scale`` along q
(directional central difference, i.e. linearised). The bores are the radial tests' and
``fit.pipe_diameters``; without either, the Sch 40 steel bores the muscle can anchor in. ``test``
names the bore where the radial force moves most: a radial test there (or a slip test in it)
determines the direction.
"""

from __future__ import annotations

import math

import numpy as np

from pampipe.identification import problem
from pampipe.model.uncertainty import ParameterUncertainty, UndeterminedDirection, moduli_names, scaled_unit

#: A direction with less than this share of its length in the written entries is not theirs.
NEGLIGIBLE = 1e-3
#: A move of the radial force [N] or of the anchoring pressure [Pa] per scale below these is none.
FORCE_MOVE = 0.5
PRESSURE_MOVE = 500.0
#: Step of the directional differences [scaled units].
STEP = 1e-3


def written_index(names, structure) -> tuple[list[int], tuple[str, ...]]:
    """(indices into x, written names): the muscle's moduli block, then the calibrated geometry."""
    prefix = "theta" if any(n.startswith("theta.") for n in names) else names[0].split(".")[0]
    moduli = [i for i, n in enumerate(names) if n.startswith(prefix + ".")]
    geometry = [names.index(problem.GEOMETRY_NAMES[g]) for g in structure.calibrate]
    return moduli + geometry, moduli_names(len(moduli) // 4 - 1) + tuple(structure.calibrate)


def bores(data, options, geometry) -> list[float]:
    """Bores [m] where the moves are given: the radial tests' and fit.pipe_diameters, else Sch 40 bores."""
    low, high = geometry.initial_diameter, geometry.largest_diameter
    named = sorted({t.spec.pipe_diameter for t in data.tests if t.kind == "radial"}
                   | set(options.pipe_diameters))
    named = [d for d in named if low < d < high]
    if named:
        return named
    from pampipe.specs.pipes import schedule_bores  # imported here: a fit with radial tests needs no schedule

    return [bore for _, bore in schedule_bores(low * 1.01, high * 0.99)]


def parameter_uncertainty(u, x, names, structure, hessian, lower, upper, model_error, muscle_at,
                          diameters, pressure: float, data_only=None) -> ParameterUncertainty:
    """The written :class:`ParameterUncertainty` (module docstring).

    ``u``: the fit's :class:`~pampipe.identification.covariance.Uncertainty`; ``model_error``: its
    :class:`~pampipe.identification.model_error.ModelError` (value [N], degrees of freedom);
    ``muscle_at(x)``: the
    muscle of a decision vector; ``pressure`` [Pa]: where the radial force is judged; ``data_only``:
    the uncertainty of the same fit without its prior (None: no prior), whose undetermined directions
    that the prior fixes are listed as ``prior_determined``.
    """
    index, written = written_index(list(names), structure)
    units = np.array([scaled_unit(n) for n in written])
    covariance = u.covariance[np.ix_(index, index)] * np.outer(units, units)
    def listed(q, scale) -> UndeterminedDirection:
        full = np.zeros(np.size(x))
        full[index] = q
        moves = _moves(muscle_at, np.asarray(x, float), full, scale, diameters, pressure)
        return UndeterminedDirection(q, scale, moves, _test(moves, diameters))

    free = _basis(u, index)
    directions = [listed(q, _scale(q, u.sigma, np.asarray(hessian)[np.ix_(index, index)],
                                   0.5 * (np.asarray(upper) - np.asarray(lower))[index])) for q in free]
    scaled = u.covariance[np.ix_(index, index)]  # x units = scaled units
    on_prior = [] if data_only is None else [listed(q, float(np.sqrt(max(q @ scaled @ q, 0.0))))
                                             for q in _beyond(_basis(data_only, index), free)]
    return ParameterUncertainty(written, 0.5 * (covariance + covariance.T), model_error.value,
                                tuple(directions), tuple(on_prior), model_error.dof)


def _beyond(candidates: list[np.ndarray], known: list[np.ndarray]) -> list[np.ndarray]:
    """Orthonormal basis of the part of span(``candidates``) orthogonal to span(``known``)."""
    if not candidates:
        return []
    m = np.array(candidates).T
    if known:
        q = np.array(known).T
        m = m - q @ (q.T @ m)
    left, singular, _ = np.linalg.svd(m, full_matrices=False)
    return [v if v[np.argmax(np.abs(v))] > 0 else -v
            for v in left[:, singular > NEGLIGIBLE * max(1.0, singular.max(initial=0.0))].T]


def _basis(u, index) -> list[np.ndarray]:
    """Orthonormal basis (scaled coordinates, over ``index``) of the undetermined combinations."""
    free = [i for i, c in enumerate(u.combinations) if not c.identifiable]
    if not free:
        return []
    columns = u.directions[:, free] / u.scales[:, None]
    columns /= np.linalg.norm(columns, axis=0)
    part = columns[index]
    left, singular, _ = np.linalg.svd(part, full_matrices=False)
    out = []
    for k in np.flatnonzero(singular > NEGLIGIBLE):
        q = left[:, k]
        out.append(q if q[np.argmax(np.abs(q))] > 0 else -q)
    return out


def _scale(q, sigma: float, hessian, half_range) -> float:
    """min(σ/√(qᵀHq), the largest step along q inside the bounds' half-ranges) [scaled units]."""
    curvature = float(q @ hessian @ q)
    data = sigma / math.sqrt(curvature) if curvature > 0 and sigma > 0 else math.inf
    moving = np.abs(q) > 1e-12
    box = float(np.min(half_range[moving] / np.abs(q[moving])))
    return float(min(data, box))


def _moves(muscle_at, x, direction, scale: float, diameters, pressure: float) -> dict[str, float]:
    """{prediction: change per ``scale`` along ``direction``} at every bore (finite changes only)."""
    up, down = muscle_at(x + STEP * direction), muscle_at(x - STEP * direction)
    out = {}
    for d in diameters:
        for key, value in ((f"radial_force_N@{d:.6g}m", lambda m, d=d: m.radial_force(pressure, d)),
                           (f"anchoring_pressure_Pa@{d:.6g}m", lambda m, d=d: m.anchoring_pressure(d))):
            change = (float(np.squeeze(value(up))) - float(np.squeeze(value(down)))) / (2 * STEP) * scale
            if math.isfinite(change):
                out[key] = change
    return out


def _test(moves: dict[str, float], diameters) -> str:
    """The test that would determine a direction: a radial (or slip) test at the bore it moves most."""
    force = {d: abs(moves.get(f"radial_force_N@{d:.6g}m", 0.0)) for d in diameters}
    anchoring = {d: abs(moves.get(f"anchoring_pressure_Pa@{d:.6g}m", 0.0)) for d in diameters}
    moving = [d for d in diameters if force[d] > FORCE_MOVE or anchoring[d] > PRESSURE_MOVE]
    if not moving:
        return "none needed at these bores (an axial test over wider pressures and lengths would fix it)"
    d = max(moving, key=lambda b: (force[b], anchoring[b]))
    return f"a radial test at {d * 1e3:.4g} mm ({d / 0.0254:.3g} in) bore, or a slip test in it"

