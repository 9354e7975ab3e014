"""Rows → cells: the data every refit sees, of bounded size whatever the row count.

A *cell* gathers the rows of one test that share a direction, a cycle group and a small (P, L) bin;
it keeps the count n, the means (P̄, L̄, t̄, F̄, rate) and the within-cell sum of squares. For a model
f evaluated at the cell means,

  Σ_rows (f − F)² = Σ_cells n (f(P̄, L̄) − F̄)² + Σ_cells SS_within,

which is exact when the rows of a cell share (P, L) (repeated set points: the test protocols of
pampipe's own tests) and close otherwise (the bins below are ≤ 1/64 of a path, and the model is
evaluated at two points per binned cell, see below). The second term does not depend on the model.

How rows are grouped (per test; nothing here depends on the row order or on pressure *levels*):

* **order in time**: the ``time`` column where it is given, else the recorded order;
* **path**: the protocol of :mod:`pampipe.specs.protocol` (``test.protocol``): isobaric and mixed axial
  tests sweep L, isometric axial tests and radial tests sweep P. The other coordinate, *held*, is
  binned into ≤ :data:`HELD_BINS` groups (exact values when few);
* **directions and cycles** as the experiment found them (:mod:`pampipe.specs.protocol`: in time order, or
  from a direction column; 0 where unknown): the model's legs (signs of dL/dt and dP/dt), the
  direction of the swept variable, and the first cycle (``test.cycle == 0``); the rows of a cell
  share all of them, and the slack flag (an axial reading of exactly 0 N, where the model is
  max(0, F), :func:`slack_rows`);
* **sweep bin**: exact values when a held group has ≤ :data:`MAX_EXACT` distinct ones, else
  :data:`SWEEP_BINS` equal-width bins over the group's span (the same edges for every direction and
  cycle, so cells of different cycles at one set point line up as *repeats*).

A binned cell also keeps the spread s of its swept coordinate x; the refit evaluates it at the two
points x̄ ± s (the unscented transform), ½[f(x̄ − s) + f(x̄ + s)] = mean f + O(f⁗s⁴), instead of
f(x̄) = mean f − ½f''s² + …, so the binning error is fourth order in the bin width.

Within each cell, SS_within is taken after a local linear fit on the swept and the held coordinate
(where they vary in the cell), so a bin's own slope is not counted as scatter; its degrees of
freedom are n − 1 − (coordinates that vary).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

#: A held group with at most this many distinct sweep values keeps them exact (one cell each).
MAX_EXACT = 128
#: Otherwise: equal-width sweep bins per held group.
SWEEP_BINS = 64
#: Bins of the held coordinate over a test when it has more distinct values than this.
HELD_BINS = 128
#: Values within this fraction of a test's range count as the same (float round-off of set points).
TIE = 1e-9


@dataclass(frozen=True)
class Cells:
    """Cells of an experiment, in test order (arrays over cells; SI).

    ``row_cell[i]`` maps the rows of test i (recorded order) to their cell; ``sequence`` numbers the
    paths (test, held group, direction, cycle group) along which ``sweep`` increases; ``repeat``
    numbers the set points (test, held group, direction, legs, slack flag, sweep bin) shared across
    cycle groups (cells whose model values coincide).
    """

    test: np.ndarray  # test index
    axial: np.ndarray  # bool: axial test
    count: np.ndarray  # rows n
    pressure: np.ndarray  # P̄ [Pa]
    length: np.ndarray  # L̄ [m] (axial; NaN for radial)
    diameter: np.ndarray  # D_p [m] (radial; NaN for axial)
    load: np.ndarray  # F_a [N] (radial)
    leg: np.ndarray  # the model's sign of dL/dt (axial tests), mean over the cell
    pressure_leg: np.ndarray  # the model's sign of dP/dt (axial tests)
    slack: np.ndarray  # bool: slack rows (recorded exactly 0 N, axial), where the model is max(0, F)
    direction: np.ndarray  # sign of the sweep rate (−1, 0, +1)
    first: np.ndarray  # bool: first cycle of its held group
    force: np.ndarray  # F̄ [N]
    time: np.ndarray  # t̄ [s] (row index where a test has no time column)
    rate: np.ndarray  # mean d(sweep)/dt [m/s or Pa/s] (0 without a time column)
    sweep: np.ndarray  # position along the path, 0…1 over the held group's span
    spread: np.ndarray  # standard deviation of the swept coordinate within the cell [m or Pa]
    swept_length: np.ndarray  # bool: the swept coordinate is L (isobaric axial), else P
    sequence: np.ndarray
    repeat: np.ndarray
    quantile: np.ndarray  # dense rank of P̄ in its test, 0 ≤ q < 1 (cross-validation bands)
    within_ss: np.ndarray  # [N²]
    within_dof: np.ndarray
    row_cell: tuple[np.ndarray, ...] = field(repr=False)
    swept: tuple[str, ...] = ()  # per test: "length" (isobaric) or "pressure"
    timed: tuple[bool, ...] = ()  # per test: has a usable time column
    moving: tuple[float, ...] = ()  # per test: share of rows read while the swept coordinate moves
    serial_within: tuple[tuple[float, float, int], ...] = ()  # per test: (ρ, ρ under white noise, pairs)

    @property
    def size(self) -> int:
        return int(self.count.size)

    @property
    def rows(self) -> int:
        return int(self.count.sum())

    @property
    def within_fitted(self) -> np.ndarray:
        """Per cell, the coefficients of the within-cell line beyond the mean (0 for exact cells).

        SS_within is taken about that line, so it reads low by σ² per coefficient: a test's RMSE
        √((Σ n r̄² + Σ SS_within)/(rows − Σ within_fitted)) is the row RMSE, not ≈ 25 % below it on a
        ramp of distinct set points binned ~2 rows per cell.
        """
        return np.where(self.count >= 2, self.count - 1 - self.within_dof, 0.0)

    def test_rmse(self, test_ss: np.ndarray, tests: int) -> np.ndarray:
        """RMSE [N] per test from Σ n r̄² per test (``test_ss``), the within-cell scatter corrected for
        the within-cell lines (:attr:`within_fitted`)."""
        within = np.bincount(self.test, weights=self.within_ss, minlength=tests)
        rows = np.bincount(self.test, weights=self.count - self.within_fitted, minlength=tests)
        return np.sqrt((test_ss + within) / np.maximum(rows, 1))

    def of_test(self, index: int) -> np.ndarray:
        return np.flatnonzero(self.test == index)


def reduce_rows(data, *, reduce: bool = True) -> Cells:
    """Cells of an :class:`pampipe.specs.experiment.ExperimentData` (see the module docstring).

    ``reduce=False`` keeps every distinct (P, L) its own cell (no bins): the reference the binned
    cells are checked against.
    """
    limits = (MAX_EXACT, HELD_BINS) if reduce else (np.inf, np.inf)
    parts, offset, sequence_offset, repeat_offset = [], 0, 0, 0
    for index, test in enumerate(data.tests):
        part = _test_cells(index, test, *limits)
        part["row_cell"] = part["row_cell"] + offset
        part["sequence"] = part["sequence"] + sequence_offset
        part["repeat"] = part["repeat"] + repeat_offset
        offset += part["count"].size
        sequence_offset = int(part["sequence"].max()) + 1 if part["count"].size else sequence_offset
        repeat_offset = int(part["repeat"].max()) + 1 if part["count"].size else repeat_offset
        parts.append(part)
    per_test = ("row_cell", "swept", "timed", "moving", "serial_within")
    names = [f for f in Cells.__dataclass_fields__ if f not in per_test]
    arrays = {name: np.concatenate([p[name] for p in parts]) for name in names}
    return Cells(**arrays, **{name: tuple(p[name] for p in parts) for name in per_test})


def time_order(test) -> tuple[np.ndarray, np.ndarray, bool]:
    """(order, time, timed): rows sorted by the time column if it is usable, else recorded order."""
    n = test.points
    t = None if test.time is None else np.asarray(test.time, dtype=float)
    if t is not None and t.size == n and np.all(np.isfinite(t)) and np.ptp(t) > 0:
        return np.argsort(t, kind="stable"), t, True
    return np.arange(n), np.arange(n, dtype=float), False


def _keys(values: np.ndarray, limit: float, bins: int) -> np.ndarray:
    """Exact keys (dense rank of distinct values, ties within TIE of the range) if at most ``limit``
    distinct values, else equal-width bin indices."""
    if values.size == 0:
        return np.zeros(0, dtype=np.int64)
    span = float(np.ptp(values))
    if span == 0:
        return np.zeros(values.size, dtype=np.int64)
    rounded = np.round((values - values.min()) / (span * TIE))
    unique, inverse = np.unique(rounded, return_inverse=True)
    if unique.size <= limit:
        return inverse.astype(np.int64)
    return np.minimum(((values - values.min()) / span * bins).astype(np.int64), bins - 1)


def _rates(sweep: np.ndarray, t: np.ndarray, order: np.ndarray, group: np.ndarray, timed: bool) -> np.ndarray:
    """d(sweep)/dt per row [unit/s] by central differences in time within held groups (0 untimed)."""
    rate = np.zeros(sweep.size)
    if not timed:
        return rate
    still = TIE * (float(np.ptp(sweep)) or 1.0) / max(float(np.ptp(t)), 1e-300)  # below: held still
    ordered_group = group[order]
    for g in np.unique(group):
        rows = order[ordered_group == g]
        if rows.size < 2:
            continue
        dt = np.gradient(t[rows])
        ok = dt > 0
        rate[rows[ok]] = np.gradient(sweep[rows])[ok] / dt[ok]
    return np.where(np.abs(rate) > still, rate, 0.0)


def _test_cells(index: int, test, max_exact: float, held_limit: float) -> dict:
    n = test.points
    order, t, timed = time_order(test)
    pressure = np.asarray(test.pressure, dtype=float)
    axial = test.kind == "axial"
    length = np.asarray(test.length, dtype=float) if axial else np.full(n, np.nan)
    if axial and test.protocol in ("isobaric", "mixed"):
        swept, held, sweep = "length", pressure, length
    else:
        swept, held, sweep = "pressure", (length if axial else np.zeros(n)), pressure
    held_key = _keys(held, held_limit, HELD_BINS)
    # the model's directions (sign of dL/dt, of dP/dt) as the experiment found them (time order,
    # a direction column, or 0 where unknown); the swept variable's one groups the rows
    leg = np.asarray(test.leg, dtype=float) if axial else np.zeros(n)
    pressure_leg = (np.zeros(n) if test.pressure_leg is None or not axial
                    else np.asarray(test.pressure_leg, dtype=float))
    swept_sign = leg if swept == "length" else np.asarray(
        test.pressure_leg if test.pressure_leg is not None else np.zeros(n), dtype=float)
    direction = np.sign(swept_sign).astype(np.int64)
    first = np.asarray(test.cycle) == 0
    slack = slack_rows(test)
    rate = _rates(sweep, t, order, held_key, timed)

    # sweep bins per held group (shared by all directions and cycles of the group)
    sweep_key = np.zeros(n, dtype=np.int64)
    position = np.zeros(n)
    for g in np.unique(held_key):
        rows = held_key == g
        values = sweep[rows]
        sweep_key[rows] = _keys(values, max_exact, SWEEP_BINS)
        span = float(np.ptp(values))
        position[rows] = (values - values.min()) / span if span > 0 else 0.0

    dir_code = direction + 1  # 0, 1, 2
    cyc = (~first).astype(np.int64)
    big = int(sweep_key.max(initial=0)) + 1
    # rows of a cell share every input of the model: legs, slack flag (and the swept direction)
    model_code = ((np.sign(leg) + 1) * 3 + np.sign(pressure_leg) + 1).astype(np.int64) * 2 + slack
    key = (((held_key * 3 + dir_code) * 2 + cyc) * 18 + model_code) * big + sweep_key
    _, row_cell, count = np.unique(key, return_inverse=True, return_counts=True)
    row_cell = row_cell.astype(np.int64)
    m = count.size

    def mean(values):
        return np.bincount(row_cell, weights=values, minlength=m) / count

    force = np.asarray(test.force, dtype=float)
    f_ref = float(np.mean(force)) if n else 0.0
    within_ss, within_dof, used = _within(row_cell, m, count, force - f_ref, _scaled(sweep), _scaled(held))
    serial_within = _serial_within(row_cell, order, count, used, force - f_ref)
    cell_first = np.bincount(row_cell, weights=first.astype(float), minlength=m) / count > 0.5
    cell_dir = np.sign(mean(direction.astype(float))).astype(np.int64)
    cell_held = np.zeros(m, dtype=np.int64)
    cell_held[row_cell] = held_key
    cell_sweep_key = np.zeros(m, dtype=np.int64)
    cell_sweep_key[row_cell] = sweep_key
    sequence = _dense((cell_held * 3 + cell_dir + 1) * 2 + (~cell_first).astype(np.int64))
    cell_model = np.zeros(m, dtype=np.int64)
    cell_model[row_cell] = model_code
    repeat = _dense(((cell_held * 3 + cell_dir + 1) * 18 + cell_model) * big + cell_sweep_key)
    p_mean = mean(pressure)
    span_p = float(np.ptp(p_mean)) if m else 0.0
    rounded = np.round((p_mean - p_mean.min()) / (span_p * 1e-3)) if span_p > 0 else np.zeros(m)
    unique, rank = np.unique(rounded, return_inverse=True)
    spec = test.spec
    return {
        "test": np.full(m, index, dtype=np.int64), "axial": np.full(m, axial), "count": count.astype(float),
        "pressure": p_mean, "length": mean(length) if axial else np.full(m, np.nan),
        "diameter": np.full(m, np.nan if axial else float(spec.pipe_diameter)),
        "load": np.full(m, 0.0 if axial else float(spec.axial_load)), "leg": mean(leg),
        "pressure_leg": mean(pressure_leg), "slack": mean(slack.astype(float)) > 0.5,
        "direction": cell_dir, "first": cell_first, "force": mean(force), "time": mean(t),
        "rate": mean(rate), "sweep": mean(position), "spread": _spread(row_cell, m, count, sweep),
        "swept_length": np.full(m, swept == "length"), "sequence": sequence, "repeat": repeat,
        "quantile": rank / max(unique.size, 1), "within_ss": within_ss, "within_dof": within_dof,
        "row_cell": row_cell, "swept": swept, "timed": timed, "serial_within": serial_within,
        "moving": float(np.mean(rate != 0)) if n else 0.0,
    }


def slack_rows(test) -> np.ndarray:
    """Rows of an axial test that recorded exactly 0 N (a slack muscle, docs/commands.md §3.3).

    Only exact zeros: a noisy reading below zero near F = 0 is noise, and splitting cells by its
    sign would bias both halves' means.
    """
    force = np.asarray(test.force)
    return force == 0 if test.kind == "axial" else np.zeros(force.size, dtype=bool)


def _spread(cell: np.ndarray, m: int, count: np.ndarray, values: np.ndarray) -> np.ndarray:
    """Within-cell standard deviation of ``values`` (0 for cells whose values coincide)."""
    shifted = values - values.min() if values.size else values
    mean = np.bincount(cell, weights=shifted, minlength=m) / count
    var = np.bincount(cell, weights=(shifted - mean[cell]) ** 2, minlength=m) / count
    span = float(np.ptp(values)) if values.size else 0.0
    return np.where(var > (TIE * span) ** 2, np.sqrt(np.maximum(var, 0.0)), 0.0)


def _dense(keys: np.ndarray) -> np.ndarray:
    return np.unique(keys, return_inverse=True)[1].astype(np.int64)


def _scaled(values: np.ndarray) -> np.ndarray:
    span = float(np.ptp(values)) if values.size else 0.0
    return (values - values.min()) / span if span > 0 else np.zeros(values.size)


def _within(cell: np.ndarray, m: int, count: np.ndarray, y: np.ndarray, u: np.ndarray, v: np.ndarray):
    """(SS, dof) per cell of y after a least-squares fit on [1, u, v] within the cell (u, v in [0, 1];
    a coordinate whose within-cell variance is below 1e-14 is left out)."""

    def centred(a, b):
        sab = np.bincount(cell, weights=a * b, minlength=m)
        sa = np.bincount(cell, weights=a, minlength=m)
        sb = np.bincount(cell, weights=b, minlength=m)
        return sab - sa * sb / count

    syy, suu, svv = centred(y, y), centred(u, u), centred(v, v)
    suv, suy, svy = centred(u, v), centred(u, y), centred(v, y)
    use_u, use_v = suu > 1e-14 * count, svv > 1e-14 * count
    ss = syy.copy()
    only_u = use_u & ~use_v
    ss[only_u] -= suy[only_u] ** 2 / suu[only_u]
    only_v = use_v & ~use_u
    ss[only_v] -= svy[only_v] ** 2 / svv[only_v]
    both = use_u & use_v
    det = suu * svv - suv**2
    ok = both & (det > 1e-12 * suu * svv)
    ss[ok] -= (svv[ok] * suy[ok] ** 2 - 2 * suv[ok] * suy[ok] * svy[ok] + suu[ok] * svy[ok] ** 2) / det[ok]
    degenerate = both & ~ok  # u and v move together: one regressor
    ss[degenerate] -= suy[degenerate] ** 2 / suu[degenerate]
    used = use_u.astype(int) + use_v.astype(int) - degenerate.astype(int)
    dof = np.maximum(count - 1 - used, 0)
    return np.where(dof > 0, np.maximum(ss, 0.0), 0.0), dof.astype(float), used


def _serial_within(cell, order, count, used, y) -> tuple[float, float, int]:
    """Lag-1 autocorrelation of the readings within exact cells (rows sharing (P, L)), in time order:
    (ρ = Σ d_i d_{i+1} / Σ d², its white-noise expectation Σ_pairs −1/(n_c − 1) / pairs, pairs), with
    d the deviation from the cell mean. Model-free: repeated readings that drift or oscillate show here."""
    exact = (used == 0) & (count >= 2)
    if not np.any(exact):
        return 0.0, 0.0, 0
    mean = np.bincount(cell, weights=y) / count
    d = y - mean[cell]
    c, dd = cell[order], d[order]
    pair = (c[1:] == c[:-1]) & exact[c[1:]]
    pairs = int(pair.sum())
    inside = exact[cell]
    denominator = float(np.sum(d[inside] ** 2))
    if pairs == 0 or denominator <= 0:
        return 0.0, 0.0, pairs
    rho = float(np.sum(dd[1:][pair] * dd[:-1][pair]) / denominator)
    # E[d_i d_{i+1}] = −σ²/n and E[Σd²] = σ²Σ(n − 1): ρ₀ = −Σ_pairs(1/n)/Σ(n − 1)
    rho0 = float(-np.sum(1 / count[c[1:][pair]]) / np.sum(count[exact] - 1))
    return rho, rho0, pairs
