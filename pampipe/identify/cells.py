"""Axial rows → cells of raw (P, L, F) moments, for the parts of the fit that are not linear in θ.

Two parts of the axial fit cannot use the exact QR reduction of :mod:`pampipe.identify.statistics`:

* **slack rows** (recorded force ≤ 0, ``fit.slack: unilateral``): the model there is max(0, F_ax),
  a hinge (docs/commands.md §7.1);
* **geometry calibration**: L₀, α₀ (and t₀) enter F_ax nonlinearly, so the regressors cannot be
  computed before the fit.

Both use cells: the rows of one (test, pressure level, slack flag) are binned on a (P, L) grid
(each row its own cell when the test has at most :data:`CELL_BUDGET` rows) and every cell keeps
n, the means x̄ = P̄/P_ref, L̄, ȳ and the centred sums Σd_x², Σd_L², Σd_x d_L, Σd_x e, Σd_L e, Σe²
(d = deviation from the mean, e = y − ȳ). With the model linearised about the cell mean,
u ≈ u₀ + u_x d_x + u_L d_L, the cell's sum of squares is

  SSE = n(w·u₀ − ȳ)² + w·[u_x²Σd_x² + u_L²Σd_L² + 2u_x u_L Σd_x d_L − 2u_x Σd_x e − 2u_L Σd_L e] + Σe²

with w = 1 for measured rows and for slack rows where the model is positive, and w = 0 (the
prediction max(0, F) = 0) for slack rows where it is not: w = 1 − ``clipped``, a flag that starts
at 1 for every slack cell and is updated by the fit (:mod:`pampipe.identify.fit`). It is exact when
each row is its own cell and, for binned data, exact to first order in the cell size: F_ax is
affine in P at fixed L (§7), so only the curvature in L over a bin is neglected.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from pampipe.experiment import TestData

#: Rows of the moments matrix.
FIELDS = ("n", "x", "l", "y", "sxx", "sll", "sxl", "sxe", "sle", "see", "clipped")
#: Cells at most per test; a test with fewer rows keeps one cell per row (exact).
CELL_BUDGET = 2048
#: Finest grid tried per axis (then halved until the occupied cells fit the budget).
FINEST = 256


@dataclass(frozen=True)
class Cells:
    """Cells of all axial tests: ``moments`` (len(FIELDS) × C), the (test, level) group of each;
    ``slack`` marks the cells of slack rows (their ``clipped`` flag may change during the fit)."""

    moments: np.ndarray
    group: np.ndarray  # (C,) index into ``groups``
    groups: tuple[tuple[int, int], ...]  # (test index, level) of every group

    @property
    def slack(self) -> np.ndarray:
        return self.moments[FIELDS.index("clipped")] > 0

    @property
    def count(self) -> int:
        return int(self.moments.shape[1])

    def padded(self, capacity: int) -> np.ndarray:
        """The moments padded to ``capacity`` columns with empty cells (n = 0) at a real cell's mean,
        so that the model is evaluated only inside the data's domain."""
        out = np.zeros((len(FIELDS), capacity))
        out[:, :self.count] = self.moments
        if self.count:
            out[1:3, self.count:] = self.moments[1:3, :1]
        return out


def capacity(count: int) -> int:
    """The NLP's cell capacity for ``count`` cells: the next power of four ≥ max(count, 64), so that
    data sets of one protocol share one NLP whatever their row counts."""
    size = 64
    while size < count:
        size *= 4
    return size


def reduce_cells(tests, rows_of, *, pref: float) -> Cells:
    """Cells of every (test index, TestData) in ``tests``; ``rows_of(test)`` picks the rows used."""
    blocks, groups, group_of = [], [], []
    for index, test in tests:
        rows = rows_of(test)
        if rows.size == 0:
            continue
        moments, level = _test_cells(test, rows, pref)
        levels = np.unique(level)
        group_of.append(len(groups) + np.searchsorted(levels, level))
        groups.extend((index, int(lev)) for lev in levels)
        blocks.append(moments)
    if not blocks:
        return Cells(np.zeros((len(FIELDS), 0)), np.zeros(0, dtype=np.int64), ())
    return Cells(np.hstack(blocks), np.concatenate(group_of), tuple(groups))


def _test_cells(test: TestData, rows: np.ndarray, pref: float):
    x = test.pressure[rows] / pref
    length = test.length[rows]
    y = test.force[rows]
    slack = (y <= 0).astype(np.int64)
    level = test.level[rows]
    key = np.arange(rows.size) if rows.size <= CELL_BUDGET else _binned_key(x, length, level, slack)
    cell_keys, cell = np.unique(key, return_inverse=True)
    cell = cell.ravel()
    count = np.bincount(cell).astype(float)

    def total(values):
        return np.bincount(cell, weights=values, minlength=cell_keys.size)

    xbar, lbar, ybar = total(x) / count, total(length) / count, total(y) / count
    dx, dl, e = x - xbar[cell], length - lbar[cell], y - ybar[cell]
    first = np.zeros(cell_keys.size, dtype=np.int64)
    first[cell[::-1]] = np.arange(rows.size)[::-1]  # a row of each cell: its level and slack flag
    moments = np.array([count, xbar, lbar, ybar, total(dx * dx), total(dl * dl), total(dx * dl),
                        total(dx * e), total(dl * e), total(e * e), slack[first].astype(float)])
    return moments, level[first]


def _binned_key(x, length, level, slack) -> np.ndarray:
    """A cell key per row on the finest (P, L) grid whose occupied cells fit :data:`CELL_BUDGET`."""
    bins = FINEST
    span_x, span_l = max(np.ptp(x), 1e-300), max(np.ptp(length), 1e-300)
    while True:
        bx = np.minimum(((x - x.min()) / span_x * bins).astype(np.int64), bins - 1)
        bl = np.minimum(((length - length.min()) / span_l * bins).astype(np.int64), bins - 1)
        key = ((level * 2 + slack) * bins + bx) * bins + bl
        if bins == 1 or np.unique(key).size <= CELL_BUDGET:
            return key
        bins //= 2
