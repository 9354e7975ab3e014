"""Scores of one fit: SSE, BIC, cross-validated RMSE and joint parameter intervals (on cells).

* SSE = Σ_c n_c r̄_c² + Σ_c SS_within,c [N²]: the row sum of squares (:mod:`.cells`).
* BIC = n ln(SSE/n) + k ln n, n = rows, k = fitted parameters (moduli + effects).
* Cross-validation: K folds across pressure bands: within each test the cells' distinct pressures
  are ranked, cut into 2K bands and fold = band mod K (with stepped pressures a band is a pressure
  level; a ramp is cut by pressure all the same). Each fold is refitted without its cells (weights
  0, same NLP) from the full fit (warm-started from its primal-dual solution; solved again from its
  point with a cold barrier when the warm start does not converge; both stop when the objective stalls,
  :data:`.refit.STALL`), and predicts them:
  cv_rmse = √(Σ held-out (n r̄² + SS_within) / (rows − m)).
* Intervals: Gauss-Newton covariance σ̂²(JᵀJ)⁻¹ of all fitted parameters jointly at the fit,
  σ̂² = SSE/(n − k − m), m the within-cell line coefficients of binned cells (:mod:`.cells`);
  95 % = ±1.96 sd, clipped to the parameter's bounds.
"""

from __future__ import annotations

import numpy as np

from pampipe.diagnosis.candidates import FOLDS
from pampipe.diagnosis.refit import Fit, Refitter, effect_parameters
from pampipe.errors import SolverError


def sse(fit: Fit, cells) -> float:
    return float(np.sum(cells.count * fit.residual**2) + np.sum(cells.within_ss))


def bic(fit: Fit, cells) -> float:
    """n ln(SSE/n) + k ln n."""
    n = cells.rows
    return float(n * np.log(max(sse(fit, cells), 1e-300) / n) + fit.x.size * np.log(n))


def folds_of(cells, k: int = FOLDS) -> np.ndarray:
    """Fold index of every cell: (pressure band of its test) mod k, with 2k bands per test."""
    return np.floor(cells.quantile * 2 * k).astype(np.int64) % k


def cross_validate(refitter: Refitter, full: Fit, *, k: int = FOLDS) -> float:
    """Cross-validated RMSE [N] of ``full``'s model over k folds of pressure bands (NaN if no fold
    could be refitted)."""
    cells = refitter.cells
    fold = folds_of(cells, k)
    total, count = 0.0, 0.0
    known = full.eta()
    for f in range(k):
        held = fold == f
        if not held.any() or held.all():
            continue
        weight = np.where(held, 0.0, cells.count)
        try:
            fit = refitter.fit(full.effects, full.theta, known=known, weight=weight, warm=full)
        except SolverError:
            try:
                fit = refitter.fit(full.effects, full.theta, known=known, weight=weight, fold=True)
            except SolverError:
                continue
        total += float(np.sum(cells.count[held] * fit.residual[held] ** 2) + np.sum(cells.within_ss[held]))
        count += float(cells.count[held].sum() - cells.within_fitted[held].sum())
    return float(np.sqrt(total / count)) if count else float("nan")


def intervals(fit: Fit, cells, refitter: Refitter) -> dict[str, dict[str, tuple[float, float, float]]]:
    """{effect: {parameter: (value, low, high)}} in SI, 95 %, from the joint covariance."""
    if not fit.effects or fit.jacobian is None:
        return {}
    jac = fit.jacobian
    k = fit.x.size
    sigma2 = sse(fit, cells) / max(cells.rows - k - float(cells.within_fitted.sum()), 1)
    jtj = jac.T @ jac
    col = np.sqrt(np.maximum(np.diag(jtj), 1e-300))
    scaled = jtj / np.outer(col, col)  # column scaling before the inverse (θ and η differ a lot)
    cov = np.linalg.pinv(scaled, rcond=1e-13) / np.outer(col, col) * sigma2
    out: dict[str, dict[str, tuple[float, float, float]]] = {}
    start = k - fit.n_eta
    for j, (name, p) in enumerate(effect_parameters(fit.effects)):
        value = fit.x[start + j] * p.scale
        sd = float(np.sqrt(max(cov[start + j, start + j], 0.0))) * p.scale
        low, high = p.fit_bounds  # the interval stays within the physics' sign
        out.setdefault(name, {})[p.name] = (float(value), float(max(low, value - 1.96 * sd)),
                                            float(min(high, value + 1.96 * sd)))
    return out
