"""Data → sufficient statistics: one pass over the rows, after which the fit never sees them again.

Units inside the fit: θ in MPa, forces in N, pressures as x = P/P_ref (P_ref = 1 MPa by default).

**Axial tests** (docs/physics.md §4.3): F_ax = offset(P, L) + φ(P, L)·θ is linear in θ. For each group
(test × pressure level) the rows [Φ | y], y = F − offset, are reduced by a chunked QR (TSQR) to
R (p×p), z (p) and the residual ``rest`` with ‖Φθ − y‖² = ‖Rθ − z‖² + rest exactly; QR rather than
ΦᵀΦ keeps the conditioning of Φ, not its square. With ``average_legs`` each level's rows are first
averaged in ``average_bins`` length bins (regressors and forces alike: the mean model of a bin is
φ̄·θ exactly), the paper's averaged load line.

**Radial tests** (docs/physics.md §5.3): at the pipe the strains are frozen, so above anchoring
u(x) = A(F_ax(x, L_p) − F_a) = c₀ + c₁x with c₀ = A(φ₀·θ − F_a), c₁ = A(area·P_ref + φ₁·θ), and the
model is F_r = max(0, u). Each pressure level is split into ``SUB_BINS`` equal-count pressure bins,
and every bin keeps n, x̄, ȳ and the centred moments Σd², Σd³, Σd⁴, Σde, Σd²e, Σe² (d = x − x̄,
e = y − ȳ). With these the sum of squares of a bin is exact for any model quadratic in x on
the bin (see :mod:`pampipe.identification.fit_nlp`), whatever the number of rows.

**Drucker grid** (docs/physics.md §6): the tangent moduli are linear in θ, so the constraints are rows
C with C·θ ≥ 0 (MPa), one per direction and grid point, or one per point in the ``sum`` form.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass, field

import numpy as np
from threadpoolctl import threadpool_limits

from pampipe.identification.moment_cells import Cells, reduce_cells
from pampipe.model import braid, forces
from pampipe.model.bladder import strains
from pampipe.model.pam import Geometry
from pampipe.specs.experiment import ExperimentData, TestData

MPA = 1e6
#: Equal-count pressure sub-bins per radial pressure level.
SUB_BINS = 8
#: Rows per chunk of the one pass (bounds the regressor matrix: 2¹⁶ × 17 × 8 B ≈ 9 MB).
CHUNK = 1 << 16
RADIAL_MOMENTS = ("n", "x", "y", "sdd", "sddd", "sdddd", "sde", "sdde", "see")


@dataclass(frozen=True)
class AxialStats:
    """QR-reduced axial groups (test × pressure level); arrays over groups."""

    test: np.ndarray  # (G,) index into the experiment's tests
    pressure: np.ndarray  # (G,) level pressure [Pa]
    points: np.ndarray  # (G,) rows (bins when averaging legs)
    r: np.ndarray  # (G, p, p) [N/MPa]
    z: np.ndarray  # (G, p) [N]
    rest: np.ndarray  # (G,) [N²]

    def combined(self) -> AxialStats:
        """One group holding all axial rows (for the least-squares objective)."""
        if self.test.size <= 1:
            return self
        p = self.r.shape[1]
        stacked = np.concatenate([self.r, self.z[:, :, None]], axis=2).reshape(-1, p + 1)
        r_aug = _qr_r(stacked, p + 1)
        rest = self.rest.sum() + r_aug[p, p] ** 2
        return AxialStats(np.array([-1]), np.array([np.nan]), np.array([self.points.sum()]),
                          r_aug[None, :p, :p], r_aug[None, :p, p], np.array([rest]))


@dataclass(frozen=True)
class RadialStats:
    """One radial test reduced to pressure bins (see the module docstring)."""

    test: int
    pipe: int  # index into the experiment's distinct pipe diameters
    pipe_diameter: float  # [m]
    axial_load: float  # [N]
    amp_phi0: np.ndarray  # A·φ₀ (p,) [N/MPa]
    amp_phi1: np.ndarray  # A·φ₁ (p,) [N/MPa] per unit x
    amp_area: float  # A·area·P_ref [N] per unit x
    amp_load: float  # A·F_a [N]
    levels: int
    level_pressure: np.ndarray  # (levels,) [Pa]
    moments: np.ndarray  # (9, levels·SUB_BINS), rows named by RADIAL_MOMENTS


@dataclass(frozen=True)
class Statistics:
    """The whole experiment reduced: QR groups, cells, radial bins; ``groups`` lists the axial
    (test index, level) groups that ``axial`` (QR) and ``cells`` both index."""

    axial: AxialStats | None
    radial: tuple[RadialStats, ...]
    pipes: tuple[float, ...]  # distinct pipe diameters of the radial tests [m]
    degree: int
    reference_pressure: float  # [Pa]
    points: int  # rows used by the fit
    cells: Cells | None = None
    groups: tuple[tuple[int, int], ...] = ()
    slack_rows: tuple[int, ...] = ()  # per test: rows with recorded force ≤ 0 (axial tests)
    excluded: int = 0  # slack rows dropped (fit.slack: exclude)

    @property
    def n_theta(self) -> int:
        return 4 * (self.degree + 1)


def reduce_experiment(data: ExperimentData, *, degree: int, reference_pressure: float = MPA,
                      average_legs: bool = False, average_bins: int = 30, slack: str = "unilateral",
                      calibrate: bool = False, hinge: dict[int, np.ndarray] | None = None,
                      memo: Memo | None = None) -> Statistics:
    """Sufficient statistics of every test (one pass over the rows, chunked).

    Axial rows: measured rows (force > 0) go to the exact QR groups, slack rows (force ≤ 0) to
    cells (``slack: unilateral``) or nowhere (``exclude``); with ``calibrate`` every used axial row
    goes to cells, whose model is evaluated at the fitted geometry. ``hinge`` (test index → row
    indices): measured rows where the model predicts no tension, moved from the QR groups to cells so
    that the fit scores them by max(0, F) (docs/physics.md §6.2).

    BLAS runs single-threaded here: the QR blocks are tall and thin (17 columns), where
    OpenBLAS threads only add overhead, and on a busy machine they oversubscribe the cores
    (measured 10× slower with the default thread count at load 6 on 2 cores).

    ``memo``: shared by the reductions of one data set with one set of options that differ only in
    ``hinge`` (the refits of the slack hinge, which moves a few axial rows): each reuses what an
    earlier one computed of the same rows in the same order, so the numbers are the same.
    """
    memo = memo if memo is not None else Memo()
    with threadpool_limits(limits=1, user_api="blas"):
        return _reduce(data, degree, reference_pressure, average_legs, average_bins, slack, calibrate,
                       hinge or {}, memo)


@dataclass
class Memo:
    """What a reduction leaves for the next one of the same data (see :func:`reduce_experiment`):
    the radial bins (the hinge moves axial rows only) and, per axial test, the rows its QR groups
    reduced and the TSQR state (R of every level, row counts) after each chunk of :data:`CHUNK` rows.
    A later reduction restarts from the state after the last chunk whose rows are unchanged."""

    radial: tuple[RadialStats, ...] | None = None
    chunks: dict[int, tuple[np.ndarray, list[tuple[np.ndarray, np.ndarray]]]] = field(default_factory=dict)


def _reduce(data, degree, pref, average_legs, average_bins, slack, calibrate, hinge, memo) -> Statistics:
    geometry = data.pam.geometry
    pipes = tuple(sorted({t.spec.pipe_diameter for t in data.tests if t.kind == "radial"}))
    axial = [(i, t) for i, t in enumerate(data.tests) if t.kind == "axial"]

    def used(test):
        return np.flatnonzero(test.force > 0) if slack == "exclude" else np.arange(test.points)

    groups = tuple((i, int(lev)) for i, t in axial
                   for lev in np.flatnonzero(np.bincount(t.level[used(t)], minlength=t.level_pressure.size)))
    qr = None
    if axial and not calibrate:
        found = {}
        for index, test in axial:
            measured = np.flatnonzero(without(test.force > 0, hinge.get(index, ())))
            for item in _axial_groups(index, test, measured, geometry, degree, pref, average_legs,
                                      average_bins, memo):
                found[item[0]] = item[1:]
        p = 4 * (degree + 1)
        empty = (0.0, 0, np.zeros((p, p)), np.zeros(p), 0.0)
        rows = [found.get(g, empty) for g in groups]
        qr = AxialStats(np.array([g[0] for g in groups]),
                        np.array([data.tests[i].level_pressure[lev] for i, lev in groups]),
                        *(np.array([r[k] for r in rows]) for k in range(1, 5)))
    if calibrate:
        cells = reduce_cells(axial, used, pref=pref)
    else:
        index_of = {id(t): i for i, t in axial}
        cells = reduce_cells(axial, lambda t: np.union1d(
            np.flatnonzero(t.force <= 0) if slack == "unilateral" else np.zeros(0, dtype=np.int64),
            np.asarray(hinge.get(index_of[id(t)], ()), dtype=np.int64)), pref=pref)
    remap = {g: k for k, g in enumerate(groups)}
    cells = Cells(cells.moments, np.array([remap[cells.groups[c]] for c in cells.group], dtype=np.int64),
                  groups) if cells.count else None
    if memo.radial is None:
        memo.radial = tuple(_radial(index, test, geometry, degree, pref, pipes.index(test.spec.pipe_diameter))
                            for index, test in enumerate(data.tests) if test.kind == "radial")
    radial = memo.radial
    slack_rows = tuple(int(np.sum(t.force <= 0)) if t.kind == "axial" else 0 for t in data.tests)
    excluded = sum(slack_rows) if slack == "exclude" else 0
    return Statistics(qr, radial, pipes, degree, pref, data.points - excluded, cells, groups, slack_rows,
                      excluded)


def regressors(pressure, length, geometry, degree, pref=MPA):
    """(offset [N], Φ [N/MPa]) of F_ax = offset + Φ·θ_MPa, arrays over the rows."""
    block = _augmented(pressure, length, np.zeros(np.shape(length)), geometry, degree, pref)
    return -block[:, -1], block[:, :-1]


def _augmented(pressure, length, force, geometry, degree, pref, head: int = 0) -> np.ndarray:
    """[Φ | y] (rows × (p + 1)) with y = F − offset: one pass, written into one array, column-major
    (the layout LAPACK's QR reads: numpy copies a row-major block first, at the cost of the QR itself).
    ``head``: that many rows left unset above them (for the R a TSQR update stacks on its rows)."""
    offset, row = forces.axial_force_regressors(pressure, length, geometry, degree, pref)
    block = np.empty((head + np.size(length), len(row) + 1), order="F")
    for j, column in enumerate(row):
        np.multiply(column, MPA, out=block[head:, j])
    np.subtract(force, offset, out=block[head:, -1])
    return block


def _qr_r(block: np.ndarray, width: int) -> np.ndarray:
    """Upper-triangular R (width × width) of a tall block, zero-padded if it has fewer rows."""
    r = np.linalg.qr(block, mode="r")
    out = np.zeros((width, width))
    out[:r.shape[0], :] = r[:width]
    return out


def _axial_groups(index, test: TestData, rows, geometry, degree, pref, average, bins, memo: Memo):
    """((test, level), level pressure, rows, R, z, rest) of every level with rows among ``rows``.

    One pass over the rows in chunks: the regressors of a chunk are computed once and each level's
    R is updated by a QR of [R; its rows of the chunk] (TSQR). The chunks that ``memo`` holds for
    the same rows are not computed again.
    """
    p = 4 * (degree + 1)
    levels = test.level_pressure.size
    if average:
        level = test.level[rows]
        order = rows[np.argsort(level, kind="stable")]
        bounds = np.searchsorted(test.level[order], np.arange(levels + 1))
        for lev, (a, b) in enumerate(itertools.pairwise(bounds)):
            if b > a:
                block, count = _leg_average(test, order[a:b], geometry, degree, pref, bins)
                r_aug = _qr_r(block, p + 1)
                yield ((index, lev), test.level_pressure[lev], count, r_aug[:p, :p], r_aug[:p, p],
                       r_aug[p, p] ** 2)
        return
    r_aug = np.zeros((levels, p + 1, p + 1))
    count = np.zeros(levels, dtype=np.int64)
    before, states = memo.chunks.get(index, (np.zeros(0, dtype=np.int64), []))
    common = min(before.size, rows.size)
    differ = np.flatnonzero(before[:common] != rows[:common])
    kept = states[:(differ[0] if differ.size else common) // CHUNK]  # the chunks whose rows are unchanged
    if kept:
        r_aug, count = (a.copy() for a in kept[-1])
    memo.chunks[index] = (rows, kept)
    for start in range(len(kept) * CHUNK, rows.size, CHUNK):
        chunk = rows[start:start + CHUNK]
        block = _augmented(test.pressure[chunk], test.length[chunk], test.force[chunk], geometry, degree,
                           pref, p + 1)  # [R; the chunk's rows], R still to be written
        level = test.level[chunk]
        present = np.flatnonzero(np.bincount(level, minlength=levels))
        for lev in present:
            if present.size == 1:  # the chunk is one level's: its R goes on top (no copy of the rows)
                stacked = block
            else:
                mine = block[p + 1:][level == lev]
                stacked = np.empty((p + 1 + mine.shape[0], p + 1), order="F")  # [R; the level's rows]
                stacked[p + 1:] = mine
            stacked[:p + 1] = r_aug[lev]
            r_aug[lev] = _qr_r(stacked, p + 1)
            count[lev] += stacked.shape[0] - p - 1
        kept.append((r_aug.copy(), count.copy()))
    for lev in np.flatnonzero(count):
        yield ((index, lev), test.level_pressure[lev], count[lev], r_aug[lev, :p, :p], r_aug[lev, :p, p],
               r_aug[lev, p, p] ** 2)


def _leg_average(test: TestData, rows, geometry, degree, pref, bins):
    """Rows [φ̄ | ȳ] of the length-bin means of one level (both legs pooled), and their number."""
    length = test.length[rows]
    low, high = length.min(), length.max()
    which = np.minimum(((length - low) / max(high - low, 1e-12) * bins).astype(np.int64), bins - 1)
    sums = None
    for start in range(0, rows.size, CHUNK):
        chunk = rows[start:start + CHUNK]
        values = _augmented(test.pressure[chunk], test.length[chunk], test.force[chunk], geometry, degree,
                            pref)
        w = which[start:start + CHUNK]
        part = np.stack([np.bincount(w, weights=values[:, j], minlength=bins)
                         for j in range(values.shape[1])], 1)
        sums = part if sums is None else sums + part
    counts = np.bincount(which, minlength=bins)
    used = counts > 0
    return sums[used] / counts[used, None], int(used.sum())


def powers(d: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(d², d³, d⁴) by products: d²·d and d²·d² are within 2 ulp of d**3 and d**4 (numpy's ``**`` with
    these exponents calls pow(), 10× slower)."""
    d2 = d * d
    return d2, d2 * d, d2 * d2


def radial_coefficients(pipe_diameter, axial_load, geometry, degree, pref):
    """(A·φ₀, A·φ₁, A·area·P_ref, A·F_a) of u(x) = c₀ + c₁x at the pipe (N/MPa, N)."""
    with np.errstate(invalid="ignore"):  # NaN: a calibrated geometry that misses the pipe (refused later)
        length = braid.length_at_diameter(pipe_diameter, geometry)
        amp = float(braid.amplification_factor(pipe_diameter, geometry))
    off0, row0 = forces.axial_force_regressors(0.0, length, geometry, degree, pref)
    off1, row1 = forces.axial_force_regressors(pref, length, geometry, degree, pref)
    phi0 = np.array([float(v) for v in row0]) * MPA
    phi1 = np.array([float(v) for v in row1]) * MPA - phi0
    return amp * phi0, amp * phi1, amp * float(off1 - off0), amp * axial_load


def _radial(index, test: TestData, geometry: Geometry, degree, pref, pipe) -> RadialStats:
    x = test.pressure / pref
    y = test.force
    n_levels = test.level_pressure.size
    order = np.lexsort((x, test.level))
    level_sorted = test.level[order]
    start = np.searchsorted(level_sorted, np.arange(n_levels))
    count = np.bincount(test.level, minlength=n_levels)
    rank = np.arange(x.size) - start[level_sorted]
    sub = np.minimum((rank * SUB_BINS) // np.maximum(count[level_sorted], 1), SUB_BINS - 1)
    bin_of = np.empty(x.size, dtype=np.int64)
    bin_of[order] = level_sorted * SUB_BINS + sub
    nb = n_levels * SUB_BINS

    def total(w):
        return np.bincount(bin_of, weights=w, minlength=nb)

    n = np.bincount(bin_of, minlength=nb).astype(float)
    safe = np.maximum(n, 1)
    xbar = total(x) / safe
    ybar = total(y) / safe
    empty = n == 0
    xbar[empty] = np.repeat(test.level_pressure / pref, SUB_BINS)[empty]
    d, e = x - xbar[bin_of], y - ybar[bin_of]
    d2, d3, d4 = powers(d)
    moments = np.array([n, xbar, ybar, total(d2), total(d3), total(d4), total(d * e), total(d2 * e),
                        total(e * e)])
    a0, a1, area, load = radial_coefficients(test.spec.pipe_diameter, test.spec.axial_load, geometry,
                                             degree, pref)
    return RadialStats(index, pipe, test.spec.pipe_diameter, test.spec.axial_load, a0, a1, area, load,
                       n_levels, test.level_pressure, moments)


def drucker_rows(geometry: Geometry, degree: int, pressures, lengths, *, form: str, pref: float = MPA
                 ) -> np.ndarray:
    """Rows C [MPa per MPa of θ] with C·θ ≥ 0 ⇔ Drucker stability at every (P, L) of the grid.

    ``tangent``: E₁ᵗ(ε₁(L), P) ≥ 0 and E₂ᵗ(ε₂(D(L)), P) ≥ 0 separately (docs/physics.md §6 default);
    ``sum``: E₁ᵗ(∂ε₁/∂L)² + E₂ᵗ(∂ε₂/∂L)² ≥ 0, scaled by L₀². Each row is scaled to unit max-norm.
    """
    pp, ll = np.meshgrid(np.asarray(pressures, float), np.asarray(lengths, float), indexing="ij")
    pp, ll = pp.ravel(), ll.ravel()
    diameter = braid.diameter_at_length(ll, geometry)
    eps1, eps2 = strains(ll, diameter, geometry)
    rows1, rows2 = tangent_rows(eps1, pp / pref, degree, 0), tangent_rows(eps2, pp / pref, degree, 2)
    if form == "sum":
        n_pi = braid.turns(geometry) * np.pi
        de2 = ll * geometry.initial_length / (n_pi**2 * diameter * geometry.initial_diameter)
        rows = rows1 + rows2 * (de2**2)[:, None]
    else:
        rows = np.vstack([rows1, rows2])
    return rows / np.max(np.abs(rows), axis=1, keepdims=True)


def tangent_rows(eps, x, degree, first) -> np.ndarray:
    """Rows of Eᵗ = Σ_j (j+1)(a_j + b_j x) ε^j for the law starting at θ-block ``first`` (0 axial, 2 hoop)."""
    eps, x = np.atleast_1d(eps), np.atleast_1d(x)
    k = degree + 1
    rows = np.zeros((eps.size, 4 * k))
    for j in range(k):
        rows[:, first * k + j] = (j + 1) * eps**j
        rows[:, (first + 1) * k + j] = (j + 1) * eps**j * x
    return rows


def without(mask: np.ndarray, rows) -> np.ndarray:
    """``mask`` with ``rows`` (indices) cleared: flatnonzero of it is setdiff1d(flatnonzero(mask), rows),
    without sorting the rows."""
    mask = mask.copy()
    mask[np.asarray(rows, dtype=np.int64)] = False
    return mask
