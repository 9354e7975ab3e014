"""Independent cross-check of the planning NLP's solution (the plan issue, item 2).

A bracketing search on the model: the least P with μπF_r(P, D, κW) ≥ SF·W and F_ax(P, L_p) ≥ κW (the muscle
touches the wall), from :meth:`Muscle.holding_capacity` and :meth:`Muscle.axial_force`: a different
algorithm from the closed form (and from IPOPT) that the solution must agree with.

On long routes the check covers a seeded random sample of :data:`SAMPLE` elements plus every element
whose pressure exceeds the supply (those are the ones the infeasibility report rests on), so that
plan with checks stays within a small factor of plan without them.
"""

from __future__ import annotations

from functools import partial

import numpy as np

from pampipe.model.muscle import Muscle
from pampipe.planning.problem import Elements
from pampipe.runtime.alike import per_distinct

PRESSURE_FLOOR = 1e3  # [Pa] floor of the relative difference, so P ≈ 0 cannot blow it up
SAMPLE = 4096  # elements checked per segment on long routes
STEPS = 64  # bits of the search on [0, 2P + 1 kPa]: relative resolution 2⁻⁶⁴
POINTS = 1 << 16  # pressures tested per element and pass, summed over the elements: sets k


def checked_rows(pressure: np.ndarray, supply: float, *, seed: int = 0) -> np.ndarray:
    """Section indices the check covers: all of them, or a sample plus those beyond the supply."""
    n = pressure.shape[0]
    if n <= SAMPLE:
        return np.arange(n)
    sample = np.random.default_rng(seed).choice(n, SAMPLE, replace=False)
    beyond = np.flatnonzero((pressure > supply).any(axis=1))
    return np.union1d(sample, beyond)


def bisection_pressure(muscles: tuple[Muscle, ...], elements: Elements, upper: np.ndarray, rows: np.ndarray):
    """Least holding pressure by bracketing on [0, upper] of the full model (NaN where not bracketed).

    Each pass tests k − 1 evenly spaced pressures inside every element's bracket at once and keeps
    the sub-interval where the model starts to hold: k = 2 is bisection; small samples take up to
    k = 256 (8 bits per pass), so that few passes of whole arrays replace 64 calls on tiny ones. Alike
    elements (a long route's repeated sections) are searched once
    (:func:`~pampipe.runtime.alike.per_distinct`).
    """
    e = elements
    out = np.full((rows.size, len(muscles)), np.nan)
    for i, muscle in enumerate(muscles):
        col = rows[e.valid[rows, i] & np.isfinite(upper[rows, i])]
        bits = int(np.clip(np.log2(POINTS / max(col.size, 1)), 1, 8))
        least = per_distinct(partial(_bracketed, muscle, e.kappa, e.safety_factor, bits),
                             e.diameter[col, i], e.load[col, i], e.friction[col, i], upper[col, i])
        out[np.searchsorted(rows, col), i] = least
    return out


def _bracketed(muscle: Muscle, kappa: float, safety_factor: float, bits: int, d, w, mu, upper) -> np.ndarray:
    """The bracketing search of :func:`bisection_pressure` for elements (d, w, μ) on [0, upper], ``bits``
    bits per pass: the least P that holds (NaN where [0, upper] does not bracket it), element by element."""
    length = muscle.anchored_length(d)
    fractions = np.arange(1, 2**bits) / 2**bits

    def holds(p):
        shape = (-1,) + (1,) * (np.ndim(p) - 1)
        d_, w_, mu_, length_ = (np.reshape(v, shape) for v in (d, w, mu, length))
        capacity = muscle.holding_capacity(p, d_, w_, kappa=kappa, friction=mu_)
        touching = muscle.axial_force(p, length_) >= kappa * w_
        return (capacity >= safety_factor * w_) & touching

    low, high = np.zeros_like(d), upper.copy()
    bracketed = holds(high) & ~holds(low)
    for _ in range(-(-STEPS // bits)):
        grid = low[:, None] + (high - low)[:, None] * fractions
        ok = holds(grid)
        first = np.argmax(ok, axis=1)  # the first tested pressure that holds (monotone in P)
        rows_ = np.arange(grid.shape[0])
        found = ok[rows_, first]
        high = np.where(found, grid[rows_, first], high)
        low = np.where(found, np.where(first > 0, grid[rows_, first - 1], low), grid[:, -1])
    return np.where(bracketed, high, np.nan)


def largest_difference(reference: np.ndarray, pressure: np.ndarray) -> float | None:
    """max |P − P_ref| / max(P_ref, 1 kPa) over the finite entries of both; None if there are none."""
    both = np.isfinite(reference) & np.isfinite(pressure)
    if not both.any():
        return None
    diff = np.abs(pressure[both] - reference[both]) / np.maximum(np.abs(reference[both]), PRESSURE_FLOOR)
    return float(diff.max())


def cross_check(muscles: tuple[Muscle, ...], elements: Elements, pressure: np.ndarray, supply: float) -> dict:
    """{'bisection_max_rel_diff': …, 'checked_elements': …} for the solved pressures."""
    rows = checked_rows(pressure, supply)
    upper = np.where(np.isfinite(pressure), 2 * pressure + PRESSURE_FLOOR, np.nan)
    reference = bisection_pressure(muscles, elements, upper, rows)
    return {"bisection_max_rel_diff": largest_difference(reference, pressure[rows]),
            "checked_elements": int(np.isfinite(reference).sum())}
