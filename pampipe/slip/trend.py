"""Does the slip residual trend with pressure or load rate? (docs/physics.md §13.5)

A friction that grows with the holding pressure, or a rate-dependent (viscous) grip, would hide in μ.
Each residual (log(F/F̂) for relative noise, F − F̂ for absolute) of a slipped trial is regressed on the
trial's pressure and, separately, on its load rate; the slope's two-sided t-test p-value is reported, and a
trend is flagged when p < 0.05/2 (Bonferroni over the two tests).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

#: Family-wise level of the two trend tests.
LEVEL = 0.05


@dataclass(frozen=True)
class Trend:
    """A residual's linear trend against one variable: slope, its p-value and the verdict."""

    against: str  # pressure_Pa | load_rate_N_per_s
    slope: float  # residual per unit of ``against``
    p_value: float
    trials: int
    significant: bool

    def as_document(self) -> dict:
        return {"against": self.against, "slope_per_unit": self.slope, "p_value": self.p_value,
                "trials": self.trials, "significant": self.significant}


def trends(residual, pressure, load_rate) -> list[Trend]:
    """The trend tests of residuals (slipped trials only) against pressure and load rate."""
    out = []
    for name, x in (("pressure_Pa", pressure), ("load_rate_N_per_s", load_rate)):
        found = _trend(np.asarray(residual, float), np.asarray(x, float), name, tests=2)
        if found is not None:
            out.append(found)
    return out


def _trend(r: np.ndarray, x: np.ndarray, name: str, tests: int) -> Trend | None:
    from scipy.special import stdtr

    keep = np.isfinite(r) & np.isfinite(x)
    r, x = r[keep], x[keep]
    n = r.size
    if n < 4 or np.ptp(x) <= 1e-12 * max(abs(float(np.mean(x))), 1e-30):
        return None
    xc = x - x.mean()
    slope = float(np.dot(xc, r - r.mean()) / np.dot(xc, xc))
    fitted = r.mean() + slope * xc
    s2 = float(np.sum((r - fitted) ** 2)) / (n - 2)
    se = np.sqrt(s2 / float(np.dot(xc, xc)))
    t = slope / se if se > 0 else np.inf
    p = float(2 * stdtr(n - 2, -abs(t)))
    return Trend(name, slope, p, int(n), p < LEVEL / tests)
