"""The model error of a fit: the residual spread beyond the noise floor, cross-validated over pressure bands.

**Noise floor** σ_n [N] (model-free): per test, from the second differences of the residuals in
recorded order, d_i = r_{i+1} − 2r_i + r_{i−1}, whose variance is 6σ² for white noise while any
smooth residual (a model error that varies with the swept variable) cancels; σ_t² = mean(d²)/6 over
the d within :data:`TRIM` robust (MAD) standard deviations, so the jumps between pressure levels
are left out. Rows read as exactly 0 N (slack) carry no noise and
are left out. The floor of the fit is the row-weighted pool √(Σ n_t σ_t² / Σ n_t).

**Cross-validation over pressure bands**: the rows are split into :data:`BANDS` bands of pressure
(quantiles of the tested pressures); each band is held out in turn and predicted by the fit to the
others. That refit is one Gauss-Newton step from the full fit x̂ (exact for the moduli, in which the
model is linear above the contact switch): Δx_g = A_g⁺ Σ_{i∈g} w_i J_iᵀ r_i with
A_g = Σ_{i∉g} w_i J_iᵀ J_i + P (P the prior's Hessian), and the held-out residual is r_i + J_iΔx_g.
J is the Jacobian of the model force of each row in x (central differences), over a uniform
subsample of at most :data:`SAMPLE` rows per test, each weighted by w = rows/sample (A_g is built
from the same sample: subtracting a sample from the full Hessian leaves noise where only the band
informs, whose inverse is meaningless).
The refit obeys the fit's constraints: parameters at a bound and Drucker rows at zero stay there
(the step is taken in the null space of those rows), the other bounds and Drucker rows bound the
step (a small QP, :func:`_refit`), and it moves only the combinations the remaining data identify by the
fit's own rule (:func:`pampipe.identification.covariance.identifiable`). Without that, a held-out
band is extrapolated along directions the constraints close (measured on data generated from the
model itself: 60 N held-out RMSE at the top pressure band instead of the 2 N noise).
Were the model right, a held-out residual would have variance σ_n²(1 + J_iS_gJ_iᵀ), noise plus the
refit's estimation error, S_g = A_g⁺(Σ_{i∉g} w_i² J_iᵀJ_i)A_g⁺. The model error is what exceeds that:

    s_e² = Σ w_i (r̃_i² − σ_n²(1 + J_iS_gJ_iᵀ)) / Σ w_i,   model_error = √max(0, s_e² − 2·SE(s_e²)),

SE being the standard error of that weighted mean: an excess within two standard errors of zero
is reported as 0 (the model fits to the noise). With fewer than two bands (one pressure) there is
nothing to hold out; the in-sample RMSE over the noise floor is used instead (``method = "in_sample"``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from pampipe.identification.covariance import identifiable

#: Pressure bands held out in turn.
BANDS = 4
#: Rows per test in the Jacobian sample.
SAMPLE = 2000
#: Second differences beyond this many robust (MAD) standard deviations are jumps, not noise.
TRIM = 5.0


@dataclass(frozen=True)
class ModelError:
    """The model-error term of a fit and how it was found (see the module docstring)."""

    value: float  # model_error [N], 0 when the model fits to the noise
    noise_floor: float  # pooled σ_n [N]
    cv_rmse: float  # RMS of the held-out residuals [N] (in-sample RMSE for "in_sample")
    expected_rmse: float  # what noise and estimation error alone would give [N]
    method: str  # "pressure_bands" or "in_sample"
    bands: tuple[tuple[float, float, int, float], ...]  # (P low [Pa], P high [Pa], rows, held-out RMSE [N])

    def as_document(self) -> dict:
        return {"model_error_N": self.value, "noise_floor_N": self.noise_floor,
                "cross_validated_rmse_N": self.cv_rmse, "expected_rmse_N": self.expected_rmse,
                "method": self.method,
                "bands": [{"pressure_range_Pa": [lo, hi], "rows": n, "held_out_rmse_N": rmse}
                          for lo, hi, n, rmse in self.bands]}


def noise_floor(residual: np.ndarray, measured: np.ndarray) -> tuple[float, int]:
    """(σ_n [N], rows used) of one test from the second differences of its residuals (module docstring)."""
    r = np.asarray(residual, float)[np.asarray(measured) != 0]
    if r.size < 5:
        return float("nan"), 0
    d2 = r[2:] - 2 * r[1:-1] + r[:-2]
    spread = np.abs(d2 - np.median(d2))
    robust = float(np.median(spread)) / 0.6745
    kept = d2[spread <= TRIM * robust] if robust > 0 else d2
    return float(np.sqrt(np.mean(kept**2) / 6.0)), int(r.size)


@dataclass(frozen=True)
class RowSample:
    """The rows used for cross-validation: their test, pressure, measured force and weight."""

    test: np.ndarray  # index into data.tests
    rows: np.ndarray  # row index within the test
    pressure: np.ndarray  # [Pa]
    force: np.ndarray  # [N]
    weight: np.ndarray  # rows each stands for


def sample_rows(data, slack: str, *, limit: int | None = SAMPLE) -> RowSample:
    """A uniform subsample of every test's fitted rows, in recorded order (at most ``limit`` per test)."""
    parts = []
    for t, test in enumerate(data.tests):
        used = np.arange(test.points)
        if slack == "exclude" and test.kind == "axial":
            used = used[~test.slack]
        if used.size == 0:
            continue
        if limit is None or used.size <= limit:  # every row (linspace(0, n − 1, n) is 0, 1, …, n − 1)
            pick = used
        else:
            pick = used[np.unique(np.linspace(0, used.size - 1, limit).astype(np.int64))]
        parts.append((np.full(pick.size, t), pick, test.pressure[pick], test.force[pick],
                      np.full(pick.size, used.size / pick.size)))
    return RowSample(*(np.concatenate([p[k] for p in parts]) for k in range(5)))


def _scored(test, model: np.ndarray, slack: str) -> tuple[np.ndarray, np.ndarray]:
    """(residual [N], measured force [N]) of the fitted rows of one test, as :func:`row_forces` scores
    them, from ``model``: the model force of every row before the hinge."""
    if slack == "exclude" and test.kind == "axial":
        used = ~test.slack
        force, model = test.force[used], model[used]
    else:  # every row (no copy)
        force = test.force
    if test.kind == "axial" and slack == "unilateral":
        model = np.where(test.slack, np.maximum(model, 0.0), model)
    return model - force, force


def row_forces(data, sample: RowSample, muscles, slack: str) -> np.ndarray:
    """Model force [N] at every sampled row for ``muscles`` = (muscle, {pipe: muscle})."""
    main, pipes = muscles
    out = np.empty(sample.rows.size)
    for t, test in enumerate(data.tests):
        mine = sample.test == t
        if not mine.any():
            continue
        rows = sample.rows[mine]
        if test.kind == "axial":
            pressure_leg = 0.0 if test.pressure_leg is None else test.pressure_leg[rows]
            force = main.axial_force(test.pressure[rows], test.length[rows], leg=test.leg[rows],
                                     pressure_leg=pressure_leg)
            if slack == "unilateral":
                force = np.where(test.slack_at(rows), np.maximum(force, 0.0), force)
        else:
            muscle = pipes.get(test.spec.pipe_diameter, main)
            force = muscle.radial_force(test.pressure[rows], test.spec.pipe_diameter, test.spec.axial_load)
        out[mine] = force
    return out


def estimate(data, x, prior_hessian, muscles_at, *, slack: str, half_range, constraints=None,
             model: dict[str, np.ndarray] | None = None) -> ModelError:
    """Model error of the fit ``x`` (module docstring); ``muscles_at(x)`` is (muscle, {pipe: muscle}).
    ``model``: test name → the model force of ``x`` at every row [N] (before the hinge max(0, F)), if
    already evaluated; else it is evaluated here."""
    if model is None:
        every = sample_rows(data, slack, limit=None)
        residual = row_forces(data, every, muscles_at(x), slack) - every.force
        floors = [noise_floor(residual[every.test == t], every.force[every.test == t])
                  for t in range(len(data.tests))]
    else:
        floors = [noise_floor(*_scored(test, model[test.name], slack)) for test in data.tests]
    pooled = [(s, n) for s, n in floors if n > 0 and np.isfinite(s)]
    sigma_n = float(np.sqrt(sum(n * s**2 for s, n in pooled) / sum(n for _, n in pooled))) if pooled else 0.0

    sample = sample_rows(data, slack)
    r = row_forces(data, sample, muscles_at(x), slack) - sample.force
    w = sample.weight
    edges = _band_edges(sample.pressure)
    if edges.size < 3:
        mse = float(np.sum(w * r**2) / np.sum(w))
        excess = mse - sigma_n**2
        return ModelError(float(np.sqrt(max(excess, 0.0))), sigma_n, float(np.sqrt(mse)), sigma_n,
                          "in_sample", ())
    jac = _jacobian(lambda xv: row_forces(data, sample, muscles_at(xv), slack), x)
    prior = np.asarray(prior_hessian, float)
    d = np.sqrt(np.clip(np.diag((jac * w[:, None]).T @ jac + prior), 0, None))
    d[d == 0] = 1.0
    # scaled coordinates y = D·x, restricted to the null space Z of the active constraints
    if constraints is None:
        constraints = (np.zeros((0, np.size(x))), np.zeros(0), np.zeros(0, dtype=bool))
    rows, lower, active = constraints
    z = _null_space(rows[active] / d, np.size(x))
    to_x = z / d[:, None]  # x change per unit of t
    jac = (jac / d) @ z
    weights = (d[:, None] * z).T  # row k: the x-weights of scaled coordinate k [N/unit]
    prior = z.T @ (prior / np.outer(d, d)) @ z
    free_rows, slack_left = rows[~active] @ to_x, lower[~active] - rows[~active] @ x
    band = np.clip(np.searchsorted(edges, sample.pressure, side="right") - 1, 0, edges.size - 2)
    held = np.empty_like(r)
    leverage = np.empty_like(r)
    bands = []
    for g in range(edges.size - 1):
        mine = band == g
        if not mine.any():
            continue
        jr, wr = jac[~mine], w[~mine]
        lam, vec = np.linalg.eigh((jr * wr[:, None]).T @ jr + prior)
        keep = identifiable(lam, vec.T @ weights, half_range, sigma_n)
        lam, vec = lam[keep], vec[:, keep]
        jg, rg, wg = jac[mine], r[mine], w[mine]
        step = vec @ _refit(lam, vec.T @ (jg.T @ (wg * rg)), free_rows @ vec, slack_left)
        held[mine] = rg + jg @ step
        inverse = (vec / lam) @ vec.T
        spread = inverse @ (jr * (wr**2)[:, None]).T @ jr @ inverse  # Cov of the refit / σ²
        leverage[mine] = np.einsum("ij,jk,ik->i", jg, spread, jg)
        bands.append((float(edges[g]), float(edges[g + 1]), round(float(wg.sum())),
                      float(np.sqrt(np.sum(wg * held[mine] ** 2) / wg.sum()))))
    expected = sigma_n**2 * (1 + np.clip(leverage, 0, None))
    excess = held**2 - expected
    mean = float(np.sum(w * excess) / np.sum(w))
    se = float(np.sqrt(np.sum(w**2 * (excess - mean) ** 2)) / np.sum(w))
    value = float(np.sqrt(max(mean - 2 * se, 0.0)))
    return ModelError(value, sigma_n, float(np.sqrt(np.sum(w * held**2) / np.sum(w))),
                      float(np.sqrt(np.sum(w * expected) / np.sum(w))), "pressure_bands", tuple(bands))


def _band_edges(pressure: np.ndarray) -> np.ndarray:
    """Edges of up to :data:`BANDS` pressure bands holding distinct tested pressures (quantiles)."""
    distinct = np.unique(np.round(pressure, -2))  # 100 Pa: a regulated level counts once
    if distinct.size < 2:
        return np.array([pressure.min(), pressure.max()])
    count = min(BANDS, distinct.size)
    cuts = np.quantile(distinct, np.linspace(0, 1, count + 1)[1:-1], method="nearest")
    middles = [0.5 * (distinct[max(np.searchsorted(distinct, c) - 1, 0)] + c) for c in cuts]
    return np.unique(np.concatenate([[pressure.min() - 1.0], middles, [pressure.max() + 1.0]]))


def _jacobian(function, x) -> np.ndarray:
    """∂f/∂x by central differences (step 10⁻⁵·max(1, |x_j|) in x units)."""
    x = np.asarray(x, float)
    columns = []
    for j in range(x.size):
        step = 1e-5 * max(1.0, abs(x[j]))
        up, down = x.copy(), x.copy()
        up[j] += step
        down[j] -= step
        columns.append((function(up) - function(down)) / (2 * step))
    return np.column_stack(columns)


def _null_space(rows: np.ndarray, size: int) -> np.ndarray:
    """Orthonormal basis (columns) of the directions that keep the active ``rows`` (m × size) at zero."""
    if rows.shape[0] == 0:
        return np.eye(size)
    _, singular, vt = np.linalg.svd(rows)
    rank = int(np.sum(singular > 1e-10 * singular.max()))
    return vt[rank:].T


def _refit(lam: np.ndarray, gradient: np.ndarray, rows: np.ndarray, lower: np.ndarray) -> np.ndarray:
    """argmin ½Σλ_k s_k² − gradient·s subject to rows·s ≥ lower (the constraints not active at x̂; s = 0
    is feasible), in u = √λ·s: the projection of c = gradient/√λ on the feasible set, by an active-set
    pass that walks toward the projection on the active rows and adds each row that blocks (no row is
    released, so the step can stop short of the optimum; it never leaves the feasible set)."""
    root = np.sqrt(lam)
    c, a = gradient / root, rows / root
    u = np.zeros_like(c)
    active = np.zeros(a.shape[0], dtype=bool)
    for _ in range(c.size + 1):
        target = c
        if active.any():
            aa = a[active]
            target = c - aa.T @ np.linalg.lstsq(aa @ aa.T, aa @ c - lower[active], rcond=None)[0]
        step = target - u
        rate = a @ step
        blocking = ~active & (rate < -1e-15)
        room = np.where(blocking, (lower - a @ u) / np.where(blocking, rate, 1.0), np.inf)
        k = int(np.argmin(room)) if room.size else 0
        if room.size == 0 or room[k] >= 1.0:
            return (u + step) / root
        u = u + max(room[k], 0.0) * step
        active[k] = True
    return u / root
