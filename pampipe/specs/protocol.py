"""Test protocols: pressure levels, held lengths and the direction of every row (no I/O, numpy only).

A lab records an axial test in one of three ways, and the fit needs to know which:

* **isobaric** cycles: the pressure is held at set points (levels) while the length is cycled;
* **isometric** ramps: the length is held while the pressure is ramped up and down;
* **mixed**: neither is held (a free trajectory through the (P, L) plane).

Levels come from set points when the file gives them, otherwise from :func:`cluster_levels`, a
clustering of the sorted values that accepts a partition only if every cluster is narrower than
the gaps that separate it from its neighbours (a ramp has no such partition, so it stays a ramp).

Directions come from the sign of the rate of the swept variable (dL/dt for isobaric and mixed
tests, dP/dt for isometric and radial tests) in time order, by :func:`rate_sign`: a lagged central
difference whose lag is chosen from the noise, so that noise never flips a leg. Rows are put in
time order by the ``time`` column when there is one; without it the recorded order is used, and a
test whose swept variable does not move consistently along that order (shuffled or sorted rows)
gets direction 0 ("unknown") instead of legs invented from row positions.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass

import numpy as np

#: More clusters than this is not a stepped protocol (sparse data): no levels.
MAX_LEVELS = 64
#: A single cluster is one level if its spread is below this fraction of the largest |value|.
TIGHT = 0.05
#: A partition is separated when every cluster is narrower than this fraction of the narrowest cut
#: gap (two merged neighbours of an evenly spaced, noise-free set have a ratio of exactly 1).
SEPARATION = 0.75
#: Levels hold at least this many rows on average (fewer: a sparsely sampled ramp).
MIN_ROWS = 3
#: Equal-count pressure bins used inside the fit when a test has no levels (ramps).
FALLBACK_BINS = 10
#: Gaussian noise: the MAD of second differences is 0.6745·√6·σ.
_MAD_D2 = 0.6745 * np.sqrt(6.0)


@dataclass(frozen=True)
class Levels:
    """Rows grouped into held values: ``index`` per row into ``values`` (sorted increasing).

    ``source``: ``set_points`` (from the file), ``clusters`` (found in the data) or ``none`` (no
    levels: ``index`` then holds :data:`FALLBACK_BINS` equal-count bins, for the fit's bookkeeping
    only, and ``values`` their medians).
    """

    index: np.ndarray
    values: np.ndarray
    source: str

    @property
    def exist(self) -> bool:
        return self.source != "none"


def cluster_levels(values: np.ndarray, *, max_levels: int = MAX_LEVELS) -> Levels | None:
    """Levels of ``values`` found by clustering, or None when the values form no levels (a ramp).

    Sorting the values, the partition into k clusters cut at the k − 1 widest gaps is *separated*
    when every cluster's spread is below :data:`SEPARATION` times the narrowest cut gap. The
    largest separated k ≤ ``max_levels`` is taken (a smaller one would merge neighbouring levels;
    a larger one cuts inside a level at a gap narrower than its spread), provided the clusters
    hold at least :data:`MIN_ROWS` rows on average (a level is held for several readings). With no
    separated k > 1, all values are one level if their spread is below :data:`TIGHT` of the
    largest |value|. Evenly spread values (a ramp) are never separated: their clusters are always
    much wider than the gaps between them.
    """
    values = np.asarray(values, dtype=float)
    n = values.size
    if n == 0:
        return None
    ordered, signed_zeros = _sorted(values)
    gaps = np.diff(ordered)
    widest = _widest(gaps, min(max_levels, n // MIN_ROWS) - 1)
    best = None
    for k in range(2, min(max_levels, n // MIN_ROWS) + 1):
        narrowest_cut = gaps[widest[k - 2]]
        if narrowest_cut <= 0:
            break
        cuts = np.sort(widest[:k - 1]) + 1
        starts = np.concatenate([[0], cuts])
        ends = np.concatenate([cuts, [n]]) - 1
        if np.max(ordered[ends] - ordered[starts]) < SEPARATION * narrowest_cut:
            best = (cuts, starts, ends)
    if best is None:
        scale = max(float(np.max(np.abs(ordered))), 1e-300)
        if ordered[-1] - ordered[0] > TIGHT * scale:
            return None
        best = (np.zeros(0, dtype=np.int64), np.array([0]), np.array([n - 1]))
    cuts, starts, ends = best
    # a row's level: the cuts at or below its value (every cut follows a gap > 0, so the values above
    # a cut are the rows after it in sorted order, as a stable sort's cumulative count would number them)
    index = np.searchsorted(ordered[cuts], values, side="right").astype(np.int64)
    medians = np.array([_sorted_median(ordered[a:b + 1], signed_zeros)
                        for a, b in zip(starts, ends, strict=True)])
    return Levels(index, medians, "clusters")


def _sorted(values: np.ndarray) -> tuple[np.ndarray, bool]:
    """(``values[np.argsort(values, kind="stable")]``, whether they hold a −0.0) by numpy's unstable sort
    (≈ 15x faster at 10⁶ rows): the same numbers in the same order, since equal floats differ only in the
    sign of a zero; the stable sort where the values hold a −0.0 (its place among the +0.0s is then the
    recorded one)."""
    ordered = np.sort(values)
    zeros = ordered[np.searchsorted(ordered, 0.0, side="left"):np.searchsorted(ordered, 0.0, side="right")]
    if np.signbit(zeros).any():
        return np.sort(values, kind="stable"), True
    return ordered, False


def _widest(gaps: np.ndarray, count: int) -> np.ndarray:
    """``np.argsort(gaps, kind="stable")[::-1][:count]`` (the widest gaps, ties the later first) without
    sorting every gap: the ones above the count-th widest sorted, then as many of the ones equal to it as
    are left, the later first."""
    if count <= 0:
        return np.zeros(0, dtype=np.int64)
    if count >= gaps.size or not np.all(np.isfinite(gaps)):
        return np.argsort(gaps, kind="stable")[::-1][:count]
    threshold = np.sort(gaps)[gaps.size - count]  # numpy's vectorised sort: faster than a partition here
    above = np.flatnonzero(gaps > threshold)
    above = above[np.lexsort((-above, -gaps[above]))]
    equal = np.flatnonzero(gaps == threshold)[::-1][:count - above.size]
    return np.concatenate([above, equal])


def _sorted_median(ordered: np.ndarray, signed_zeros: bool) -> float:
    """``np.median`` of sorted values: the middle one, or the mean of the two, (x + y)/2 as numpy's; NaN
    where one is NaN (sorted last); numpy's own where the middle is a zero and the values hold a −0.0
    (which of ±0.0 its partition picks)."""
    middle, odd = ordered.size // 2, ordered.size % 2
    if np.isnan(ordered[-1]) or (signed_zeros and (ordered[middle] == 0 or ordered[middle - 1 + odd] == 0)):
        return np.median(ordered)
    if odd:
        return ordered[middle]
    return np.mean(ordered[middle - 1:middle + 1])


def set_point_levels(values: np.ndarray, set_points, *, per_row: bool) -> Levels:
    """Levels from set points: one per row (``per_row``, a ``set_pressure`` column) or a list for
    the whole test, each row then taking the nearest set point."""
    values = np.asarray(values, dtype=float)
    points = np.asarray(set_points, dtype=float).ravel()
    if per_row:
        unique, index = np.unique(points, return_inverse=True)
        return Levels(index.astype(np.int64).ravel(), unique, "set_points")
    unique = np.unique(points)
    edges = 0.5 * (unique[1:] + unique[:-1])
    index = np.searchsorted(edges, values).astype(np.int64)
    used = np.unique(index)
    remap = np.full(unique.size, -1, dtype=np.int64)
    remap[used] = np.arange(used.size)
    return Levels(remap[index], unique[used], "set_points")


def equal_count_bins(values: np.ndarray, bins: int = FALLBACK_BINS) -> Levels:
    """``bins`` groups of (nearly) equal row counts by increasing value: the grouping of a ramp."""
    values = np.asarray(values, dtype=float)
    n = values.size
    order = np.argsort(values, kind="stable")
    count = max(min(bins, n), 1)
    breaks = np.unique((np.arange(1, count) * n) // count)
    breaks = breaks[(breaks > 0) & (breaks < n)]
    sorted_index = np.zeros(n, dtype=np.int64)
    sorted_index[breaks] = 1
    index = np.empty(n, dtype=np.int64)
    index[order] = np.cumsum(sorted_index)
    bounds = np.concatenate([[0], breaks, [n]])
    medians = np.array([np.median(values[order[a:b]]) for a, b in itertools.pairwise(bounds)]) \
        if n else np.zeros(0)
    return Levels(index, medians, "none")


def find_levels(values: np.ndarray, set_points=None, *, per_row: bool = False) -> Levels:
    """Set points if given, else clusters, else equal-count bins (``source == "none"``)."""
    if set_points is not None and np.size(set_points):
        return set_point_levels(values, set_points, per_row=per_row)
    return cluster_levels(values) or equal_count_bins(values)


def rate_sign(x: np.ndarray) -> np.ndarray:
    """Sign of dx/dt (+1, −1, 0) of a series in time order, robust to noise.

    σ is estimated from the median absolute second difference (insensitive to ramps); the lag k
    (1, 2, 4, …) is the smallest whose central difference x[i+k] − x[i−k] has a median magnitude
    above 6σ, and a row gets the sign of that difference where it exceeds 3√2σ, the sign of the
    row 0 otherwise: a turning point or a dwell, where the direction (and any friction) is
    undetermined. Runs shorter than k between runs of the same sign are noise and take their
    neighbours' sign. Returns zeros when x does not move consistently along the series (held, or
    not in time order).
    """
    x = np.asarray(x, dtype=float)
    n = x.size
    signs = np.zeros(n, dtype=np.int8)
    if n < 3:
        return signs
    d2 = x[2:] - 2 * x[1:-1] + x[:-2]
    floor = 1e-9 * max(float(np.max(np.abs(x))), 1e-300)
    sigma = max(float(np.median(np.abs(d2 - np.median(d2)))) / _MAD_D2, floor)
    lag = 1
    while True:
        if 2 * lag >= n:
            return signs
        delta = x[2 * lag:] - x[:-2 * lag]
        if _median_above(np.abs(delta), 6 * sigma):
            break
        lag *= 2
    core = np.where(np.abs(delta) > 3 * np.sqrt(2) * sigma, np.sign(delta), 0).astype(np.int8)
    signs[lag:n - lag] = core
    signs[:lag], signs[n - lag:] = core[0], core[-1]
    return _drop_short_runs(signs, lag)


def _median_above(values: np.ndarray, threshold: float) -> bool:
    """``np.median(values) > threshold`` for values without NaN, by counting the values above: the
    median (the middle value, or the mean of the two) is above when more than half are, not when fewer
    than half are; only a tie between the two middle values needs the median itself."""
    above, half = int(np.count_nonzero(values > threshold)), values.size // 2
    if values.size % 2:
        return above > half
    if above != half:
        return above > half
    return bool(np.median(values) > threshold)


def _fill(signs: np.ndarray) -> np.ndarray:
    """Zeros take the previous nonzero sign (the first nonzero one at the start)."""
    nonzero = np.flatnonzero(signs)
    if nonzero.size == 0:
        return signs
    last = np.where(signs != 0, np.arange(signs.size), -1)  # the last nonzero row up to each row: a
    np.maximum.accumulate(last, out=last)  # running maximum, not a search per row
    last[last < 0] = nonzero[0]
    return signs[last]


def group_order(groups: np.ndarray) -> np.ndarray:
    """``np.argsort(groups, kind="stable")`` of non-negative group indices, as a radix sort (uint16)
    where they fit: O(n), where the merge sort of int64 is O(n log n)."""
    fits = groups.size and groups.min() >= 0 and groups.max() < 2**16
    return np.argsort(groups.astype(np.uint16) if fits else groups, kind="stable")


def _drop_short_runs(signs: np.ndarray, shortest: int) -> np.ndarray:
    """Interior runs shorter than ``shortest`` whose neighbours agree take the neighbours' sign."""
    if shortest <= 1 or signs.size == 0:
        return signs
    starts = np.concatenate([[0], np.flatnonzero(np.diff(signs)) + 1])
    ends = np.concatenate([starts[1:], [signs.size]])
    values = signs[starts].copy()
    short = (ends - starts < shortest)
    short[0] = short[-1] = False
    agree = np.zeros_like(short)
    agree[1:-1] = values[:-2] == values[2:]
    for i in np.flatnonzero(short & agree):
        values[i] = values[i - 1]
    return np.repeat(values, ends - starts)


def segments(groups: np.ndarray | None, order: np.ndarray | None, n: int) -> tuple[np.ndarray, np.ndarray]:
    """(rows in group-then-time order, bounds of each group in it) of ``n`` rows in ``groups`` (None:
    one group), in time ``order`` (None: recorded order); what :func:`directions` and :func:`cycles` take."""
    order = np.arange(n) if order is None else order
    if groups is None:
        return order, np.array([0, n])
    grouped = groups[order]
    by_group = group_order(grouped)
    rows = order[by_group]
    return rows, np.concatenate([[0], np.flatnonzero(np.diff(grouped[by_group])) + 1, [n]])


def directions(x: np.ndarray, grouped: tuple[np.ndarray, np.ndarray]) -> np.ndarray:
    """:func:`rate_sign` of ``x`` within each group of ``grouped`` (:func:`segments`), in time order."""
    out = np.zeros(x.size, dtype=np.int8)
    rows, bounds = grouped
    for a, b in itertools.pairwise(bounds):
        out[rows[a:b]] = rate_sign(x[rows[a:b]])
    return out


def cycles(signs: np.ndarray, grouped: tuple[np.ndarray, np.ndarray]) -> np.ndarray:
    """Cycle index per row: +1 at every switch from +1 to −1 within a group of ``grouped``
    (:func:`segments`), in time order (a turning point, direction 0, between + and − is one switch)."""
    out = np.zeros(signs.size, dtype=np.int64)
    rows, bounds = grouped
    for a, b in itertools.pairwise(bounds):
        s = _fill(signs[rows[a:b]]).astype(np.int64)
        out[rows[a:b]] = np.cumsum(np.concatenate([[0], (np.diff(s) < 0).astype(np.int64)]))
    return out


def classify(pressure_levels: Levels, length: np.ndarray,
             order: np.ndarray | None = None) -> tuple[str, Levels | None]:
    """(``isobaric`` | ``isometric`` | ``mixed``, held-length levels or None) of an axial test.

    Where both the pressure and the length form levels (a grid: held lengths with repeated pressure set
    points, or held pressures with stepped lengths), the held variable is the one that stays on one level
    longer: the longer mean run of consecutive rows, in time ``order`` (None: recorded order), on one level.
    """
    held = cluster_levels(length)
    if pressure_levels.exist:
        if held is not None and _mean_run(held.index, order) > _mean_run(pressure_levels.index, order):
            return "isometric", held
        return "isobaric", None
    return ("isometric", held) if held is not None else ("mixed", None)


def _mean_run(index: np.ndarray, order: np.ndarray | None) -> float:
    """The mean number of consecutive rows (in ``order``) on one level of ``index``."""
    ordered = index if order is None else index[order]
    switches = int(np.count_nonzero(np.diff(ordered)))
    return ordered.size / (switches + 1)
