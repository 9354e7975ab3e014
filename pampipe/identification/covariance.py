"""Parameter uncertainty of a fit: covariance, 95 % intervals, correlation, identifiable combinations.

Let H = ∇²[(SSE + prior)/2] at the solution (MPa units). For the parts of the model that are
linear in θ (axial data, radial data above anchoring) H = JᵀJ exactly, J being the Jacobian of
the residual vector, so H comes from the sufficient statistics; the smoothed contact switch and
the contact increments add their (small) curvature, i.e. H is the observed information.
σ² = SSE/(n − k) with k free parameters, and Cov = σ² H⁺.

Identifiability (docs/physics.md §6): with D = diag(√H_jj), the scaled matrix D⁻¹HD⁻¹ = VΛVᵀ is the
Gram matrix of the column-scaled Jacobian, whose singular values are √λ_i. The combination
c_i = Σ_j V_ji D_j θ_j (weights ``V_ji D_j`` [N/MPa], value [N]) has standard error σ/√λ_i. It is
called *identifiable* if its 95 % half-width is below ``IDENTIFIABLE`` (10 %) of the half-range
the bounds alone allow it; otherwise the data say (next to) nothing about it, the fit is reported
as rank-deficient, and coefficients that load on such combinations get no interval (instead of a
meaningless ±). The covariance is the pseudo-inverse restricted to identifiable combinations.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

Z95 = 1.959963984540054
#: An identifiable combination's 95 % half-width is below this fraction of its bound-implied half-range.
IDENTIFIABLE = 0.1
#: A coefficient is determined if at most this fraction of it lies in unidentifiable directions.
DETERMINED = 1e-4


@dataclass(frozen=True)
class Combination:
    """c = weights·x [N] with x in MPa: one direction of the scaled Jacobian's SVD."""

    weights: np.ndarray  # [N/MPa]
    value: float  # [N]
    std: float  # [N]
    singular_value: float  # of the column-scaled Jacobian [-]
    identifiable: bool

    @property
    def interval(self) -> tuple[float, float]:
        return self.value - Z95 * self.std, self.value + Z95 * self.std


@dataclass(frozen=True)
class Uncertainty:
    """Uncertainty of the decision vector x (MPa); ``names`` label its entries."""

    names: tuple[str, ...]
    sigma: float  # residual standard deviation σ [N]
    dof: int
    covariance: np.ndarray  # [MPa²]
    std: np.ndarray  # [MPa], NaN where undetermined
    lower: np.ndarray  # 95 % interval [MPa], NaN where undetermined
    upper: np.ndarray
    correlation: np.ndarray  # NaN where undetermined
    at_bound: np.ndarray  # bool
    determined: np.ndarray  # bool
    combinations: tuple[Combination, ...]  # by decreasing singular value
    rank: int  # number of identifiable combinations
    scales: np.ndarray  # D = √diag(H) [N/unit]
    directions: np.ndarray  # V (columns, scaled space), in the order of ``combinations``

    def undetermined_share(self, gradient) -> float:
        """How much of a prediction depends on combinations the data do not fix: ‖V_uᵀg̃‖/‖g̃‖ with
        g̃ = gradient/D (0: determined by the identifiable combinations alone)."""
        scaled = np.asarray(gradient, float) / self.scales
        norm = float(np.linalg.norm(scaled))
        if norm == 0:
            return 0.0
        free = np.array([not c.identifiable for c in self.combinations])
        return float(np.linalg.norm(self.directions[:, free].T @ scaled)) / norm

    @property
    def rank_deficient(self) -> bool:
        return self.rank < len(self.names)


def identifiable(lam: np.ndarray, weights: np.ndarray, half_range, sigma: float) -> np.ndarray:
    """Which combinations c_i = weights_i·x (eigenvalue λ_i of the scaled Hessian) the data identify:
    λ_i > 10⁻¹⁴·max λ and 95 % half-width Z95·σ/√λ_i below IDENTIFIABLE of the range the bounds allow,
    |weights_i|·half_range."""
    lam = np.clip(np.asarray(lam, float), 0, None)
    allowed = np.abs(weights) @ np.asarray(half_range, float)
    with np.errstate(divide="ignore", invalid="ignore"):  # σ is NaN with no residual degree of freedom
        std = np.where(lam > 0, sigma / np.sqrt(lam), np.inf)
    return (lam > 1e-14 * max(lam.max(initial=0.0), 1e-300)) & (Z95 * std < IDENTIFIABLE * allowed)


def analyse(x, hessian, sse: float, points: int, lower_bounds, upper_bounds, names) -> Uncertainty:
    """Uncertainty of the solution ``x`` (see the module docstring)."""
    x = np.asarray(x, dtype=float)
    k = x.size
    dof = max(points - k, 1)
    sigma = float(np.sqrt(max(sse, 0.0) / dof))
    h = 0.5 * (np.asarray(hessian, dtype=float) + np.asarray(hessian, dtype=float).T)
    d = np.sqrt(np.clip(np.diag(h), 0, None))
    d[d == 0] = 1.0
    lam, vec = np.linalg.eigh(h / np.outer(d, d))
    order = np.argsort(lam)[::-1]
    lam, vec = np.clip(lam[order], 0, None), vec[:, order]
    lb, ub = np.asarray(lower_bounds, float), np.asarray(upper_bounds, float)
    half_range = 0.5 * (ub - lb)
    keep = identifiable(lam, (vec * d[:, None]).T, half_range, sigma)
    combos = []
    for i in range(k):
        weights = vec[:, i] * d
        std = sigma / np.sqrt(lam[i]) if lam[i] > 0 else np.inf
        if weights[np.argmax(np.abs(weights))] < 0:  # sign convention: largest weight positive
            weights = -weights
        combos.append(Combination(weights, float(weights @ x), float(std), float(np.sqrt(lam[i])),
                                  bool(keep[i])))
    v_keep = vec[:, keep]
    cov = sigma**2 * (v_keep / lam[keep]) @ v_keep.T / np.outer(d, d)
    determined = np.sum(vec[:, ~keep] ** 2, axis=1) < DETERMINED
    std = np.where(determined, np.sqrt(np.clip(np.diag(cov), 0, None)), np.nan)
    with np.errstate(invalid="ignore", divide="ignore"):
        corr = cov / np.outer(std, std)
    corr[~determined, :] = np.nan
    corr[:, ~determined] = np.nan
    tol = 1e-6 * (ub - lb)
    at_bound = (x - lb < tol) | (ub - x < tol)
    return Uncertainty(tuple(names), sigma, dof, cov, std, x - Z95 * std, x + Z95 * std, corr, at_bound,
                       determined, tuple(combos), int(keep.sum()), d, vec)
