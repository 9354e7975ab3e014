"""Axial rows → cells of raw (P, L, F) moments, for the parts of the fit that are not linear in θ.

Two parts of the axial fit cannot use the exact QR reduction of :mod:`pampipe.identification.statistics`:

* **slack rows** (recorded force ≤ 0, ``fit.slack: unilateral``): the model there is max(0, F_ax),
  a hinge (docs/commands.md §3.3);
* **geometry calibration**: L₀, α₀ (and t₀) enter F_ax nonlinearly, so the regressors cannot be
  computed before the fit.

Both use cells: the rows of one (test, pressure level, slack flag) are binned in length (each row its
own cell when the test has at most :data:`CELL_BUDGET` rows). About the cell mean
(x̄ = P̄/P_ref, L̄) the model is expanded to second order; F_ax is affine in P at fixed L (§7), so
u_xx = 0 and

  u(x̄ + d_x, L̄ + d_L) = u₀ + u_x d_x + u_L d_L + ½u_LL d_L² + u_xL d_x d_L

holds to third order in d_L. With the basis v = [1, d_x, d_L, d_L², d_x d_L, e] (e = y − ȳ) each
cell keeps the Gram matrix G = Σ v vᵀ over its rows (21 entries), and its sum of squares is

  SSE = wᵀ G w,   w = [u₀ − ȳ, u_x, u_L, ½u_LL, u_xL, −1]

for a live cell, and w = [−ȳ, 0, 0, 0, 0, −1] (= Σy²) for a clipped one: a slack cell where the
model is ≤ 0 predicts max(0, F) = 0. The ``clipped`` flag starts at 1 for every slack cell and is
updated by the fit (:mod:`pampipe.identification.fit`). The sum is exact when each row is its own cell
and, for binned data, exact but for the third-order term u_LLL d_L³/6 (measured in the tests).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from pampipe.specs.experiment import TestData

#: The expansion basis of a cell (see the module docstring).
BASIS = ("1", "dx", "dl", "dl2", "dxdl", "e")
#: Index pairs (i ≤ j) of the Gram entries, in storage order.
PAIRS = tuple((i, j) for i in range(len(BASIS)) for j in range(i, len(BASIS)))
#: Rows of the moments matrix: count, means, the clipped flag, then the Gram entries.
FIELDS = ("n", "x", "l", "y", "clipped", *(f"g_{BASIS[i]}_{BASIS[j]}" for i, j in PAIRS))
#: Cells at most per test; a test with fewer rows keeps one cell per row (exact).
CELL_BUDGET = 512
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


def capacity(count: int, *, headroom: bool = False) -> int:
    """The NLP's cell capacity for ``count`` cells: the next power of two ≥ max(count, 64), so that
    data sets of one protocol share one NLP whatever their row counts (binned tests hold at most
    :data:`CELL_BUDGET` cells). With ``headroom``, for count + count/4: the slack hinge's refits add
    the few rows near the slack point as cells (2 to 12 in the benchmark and bundled sets), and a count
    crossing a power of two would load a second NLP (0.05-0.1 s). Empty cells add exact zeros to the
    sums of squares and their derivatives, so the fit is the same bit for bit."""
    size = 64
    while size < count + (count // 4 if headroom else 0):
        size *= 2
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
    basis = (np.ones(rows.size), dx, dl, dl * dl, dx * dl, e)
    first = np.zeros(cell_keys.size, dtype=np.int64)
    first[cell[::-1]] = np.arange(rows.size)[::-1]  # a row of each cell: its level and slack flag
    moments = np.array([count, xbar, lbar, ybar, slack[first].astype(float),
                        *(total(basis[i] * basis[j]) for i, j in PAIRS)])
    return moments, level[first]


def gram(moments) -> list[list]:
    """The 6 × 6 Gram matrix of a cell (or of every cell, entrywise) from its moments column(s)."""
    at = {pair: FIELDS.index(f"g_{BASIS[pair[0]]}_{BASIS[pair[1]]}") for pair in PAIRS}
    return [[moments[at[(min(i, j), max(i, j))]] for j in range(len(BASIS))] for i in range(len(BASIS))]


def _binned_key(x, length, level, slack) -> np.ndarray:
    """A cell key per row: (level, slack, length bin) with the finest length grid whose occupied cells
    fit :data:`CELL_BUDGET`. Pressure needs no bins of its own: F_ax is affine in P at fixed L, so the
    expansion is exact across a level in P (to the third-order term d_x·d_L² it neglects)."""
    bins = FINEST
    span = max(float(np.ptp(length)), 1e-300)
    while True:
        bl = np.minimum(((length - length.min()) / span * bins).astype(np.int64), bins - 1)
        key = (level * 2 + slack) * bins + bl
        if bins == 1 or np.unique(key).size <= CELL_BUDGET:
            return key
        bins //= 2
