"""Scoring and choosing candidates: BIC, cross-validated RMSE, parameter intervals, the decision.

* BIC = n ln(SSE/n) + k ln n, k = the number of fitted parameters (moduli + effect).
* Cross-validation: K folds across pressure levels (fold = level mod K in every test); each fold
  is refitted without its rows (weights 0, same NLP) from the full fit, and predicts them.
  cv_rmse = √(Σ held-out r²/n).
* Intervals: Gauss-Newton covariance σ̂²(JᵀJ)⁻¹ at the fit, σ̂² = SSE/(n − k); 95 % = ±1.96 sd,
  clipped to the parameter's bounds.
* Decision: ``none`` when every test's baseline RMSE is within :data:`NOISE_RATIO` of its noise
  floor; otherwise the lowest-BIC candidate that beats the baseline by ΔBIC ≤ −:data:`BIC_MARGIN`
  and by :data:`CV_MARGIN` in cross-validated RMSE; ``none`` if no candidate does. A runner-up
  within :data:`BIC_MARGIN` of the winner is reported as confounded with it.
"""

from __future__ import annotations

import numpy as np

from pampipe.diagnose.refit import Fit, Refitter, Rows
from pampipe.model.effects import get_effect

#: Baseline "fits to the noise" when every test's RMSE ≤ NOISE_RATIO × its noise floor.
NOISE_RATIO = 1.1
#: A candidate must lower BIC by at least this (Kass & Raftery: > 10 is "very strong").
BIC_MARGIN = 10.0
#: ... and lower the cross-validated RMSE by at least this fraction.
CV_MARGIN = 0.02
FOLDS = 5


def sse(fit: Fit) -> float:
    return float(np.sum(fit.residual_axial**2) + np.sum(fit.residual_radial**2))


def bic(fit: Fit, n: int) -> float:
    """n ln(SSE/n) + k ln n."""
    return float(n * np.log(max(sse(fit), 1e-300) / n) + fit.x.size * np.log(n))


def folds_of(rows: Rows, k: int = FOLDS) -> tuple[np.ndarray, np.ndarray]:
    """Fold index of every axial and radial row: pressure level mod k."""
    return rows.axial_level % k, rows.radial_level % k


def cross_validate(refitter: Refitter, full: Fit, *, k: int = FOLDS) -> float:
    """Cross-validated RMSE [N] of ``full``'s model over k folds of pressure levels."""
    rows = refitter.rows
    fold_a, fold_r = folds_of(rows, k)
    total, count = 0.0, 0
    params = get_effect(full.effect).parameters if full.effect else ()
    n_theta = full.x.size - len(params)
    for fold in range(k):
        held_a, held_r = fold_a == fold, fold_r == fold
        if not (held_a.any() or held_r.any()):
            continue
        train = rows.weighted((~held_a).astype(float), (~held_r).astype(float))
        fit = refitter.fit(full.effect, full.x[:n_theta], eta0=full.x[n_theta:], rows=train)
        total += float(np.sum(fit.residual_axial[held_a] ** 2) + np.sum(fit.residual_radial[held_r] ** 2))
        count += int(held_a.sum() + held_r.sum())
    return float(np.sqrt(total / max(count, 1)))


def intervals(fit: Fit, n: int) -> dict[str, tuple[float, float, float]]:
    """{parameter: (value, low, high)} in SI for the effect's parameters (95 %, clipped to bounds)."""
    if not fit.effect:
        return {}
    params = get_effect(fit.effect).parameters
    jac = fit.jacobian
    k = fit.x.size
    sigma2 = sse(fit) / max(n - k, 1)
    jtj = jac.T @ jac
    col = np.sqrt(np.maximum(np.diag(jtj), 1e-300))
    scaled = jtj / np.outer(col, col)  # column scaling before the inverse (θ and η differ a lot)
    cov = np.linalg.pinv(scaled, rcond=1e-13) / np.outer(col, col) * sigma2
    out = {}
    for i, p in enumerate(params):
        j = k - len(params) + i
        value = fit.x[j] * p.scale
        sd = float(np.sqrt(max(cov[j, j], 0.0))) * p.scale
        out[p.name] = (float(value), float(max(p.lower, value - 1.96 * sd)),
                       float(min(p.upper, value + 1.96 * sd)))
    return out


def decide(baseline_ratio: float, candidates: list[dict]) -> tuple[str, str, str | None]:
    """(selected effect or 'none', reason in words, confounded runner-up or None).

    ``baseline_ratio`` is the largest RMSE / noise floor over the tests; each candidate dict has
    ``effect``, ``delta_bic`` and ``cv_ratio`` (cv_rmse / baseline cv_rmse, or None if not run).
    """
    if baseline_ratio <= NOISE_RATIO:
        return "none", (f"the baseline already fits to the noise (every test's RMSE is within "
                        f"{NOISE_RATIO:.2f}x its noise floor; worst {baseline_ratio:.2f}x)"), None
    eligible = [c for c in candidates if c["delta_bic"] <= -BIC_MARGIN and c["cv_ratio"] is not None
                and c["cv_ratio"] <= 1 - CV_MARGIN]
    if not eligible:
        return "none", (f"no candidate beats the baseline by a clear margin (ΔBIC ≤ −{BIC_MARGIN:g} and "
                        f"{CV_MARGIN:.0%} lower cross-validated RMSE); the residual (worst test "
                        f"{baseline_ratio:.2f}x its noise floor) is not explained by the library"), None
    eligible.sort(key=lambda c: c["delta_bic"])
    best = eligible[0]
    runner = eligible[1] if len(eligible) > 1 else None
    confounded = runner["effect"] if runner and runner["delta_bic"] - best["delta_bic"] < BIC_MARGIN else None
    reason = (f"{best['effect']} lowers BIC by {-best['delta_bic']:.1f} and the cross-validated RMSE by "
              f"{1 - best['cv_ratio']:.1%}")
    if runner is not None:
        gap = runner["delta_bic"] - best["delta_bic"]
        reason += f"; next best {runner['effect']} is {gap:.1f} BIC behind"
    return best["effect"], reason, confounded
