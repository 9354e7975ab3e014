"""The least holding pressure of a muscle without contact increments or effects, affine in the load
(docs/physics.md §15, *Affine form*): the costly part of a confidence plan, four passes over classes × draws.

  P* = (κW − F₀ − e)/F₁ + SF·W/(μπAF₁) = W·k + (W/μ)·r − f,   k = κ/F₁, r = SF/(πAF₁), f = (F₀ + e)/F₁

with k, r [Pa/N] and f [Pa] per draw (the muscle, κ, e) and W, W/μ [N] per class and draw. The raw
value may lie below 0 or beyond 100 MPa, and is NaN where the law does not hold (F₁ ≤ 0, μ ≤ 0);
:func:`settle` maps it onto P* [Pa] (0 below, inf beyond 100 MPa or NaN), as
:meth:`Muscle.closed_form_pressure` does. ``settle`` is non-decreasing, so the max over a range's bores and
the order statistics may be taken of the raw values and settled after.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from pampipe.model.muscle import PRESSURE_LIMIT, Anchored


@dataclass(frozen=True)
class Terms:
    """The per-draw terms of the affine form."""

    k: np.ndarray  # κ/F₁ [Pa/N], NaN where F₁ ≤ 0 (the law does not hold)
    r: np.ndarray  # SF/(πAF₁) [Pa/N]
    f: np.ndarray  # (F₀ + e)/F₁ [Pa]; −f is P_a(D, 0), the pressure of first contact


def per_draw(c: Anchored, kappa, error, sf: float) -> Terms:
    """The :class:`Terms` of the coefficients ``c`` (F₀ without the model error ``error`` [N]), broadcast
    against ``kappa`` and ``error``."""
    with np.errstate(all="ignore"):
        slope = np.asarray(c.slope, dtype=float)
        k = np.divide(kappa, slope)
        holds = slope > 0
        if not np.all(holds):
            k = np.where(holds, k, np.nan)
        r = sf / (math.pi * c.amplification * slope)
        f = (c.at_zero + error) / slope
    return Terms(k, r, f)


def per_class(load: np.ndarray, mu: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(W [N], W/μ [N], NaN where μ ≤ 0: no grip) of the loads ``load`` at frictions ``mu`` (same shape)."""
    with np.errstate(all="ignore"):
        per_mu = np.divide(load, mu)
        if not np.min(mu) > 0:  # one reduction in the common case
            per_mu = np.where(mu > 0, per_mu, np.nan)
    return load, per_mu


def raw_least(w, per_mu, t: Terms, out: np.ndarray, spare: np.ndarray) -> np.ndarray:
    """W·k + (W/μ)·r − f into ``out`` (``spare``: a buffer of its shape): four passes, no floor, no limit."""
    with np.errstate(all="ignore"):
        np.multiply(w, t.k, out=out)
        np.multiply(per_mu, t.r, out=spare)
        out += spare
        out -= t.f
    return out


def settle(raw) -> np.ndarray:
    """P* [Pa] from the raw value: max(raw, 0) where raw ≤ 100 MPa, else inf (NaN too); non-decreasing."""
    with np.errstate(invalid="ignore"):
        return np.where(np.less_equal(raw, PRESSURE_LIMIT), np.maximum(raw, 0.0), np.inf)
