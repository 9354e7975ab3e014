"""Order statistics of sampled pressures: the empirical quantiles of a confidence plan (docs/physics.md §15).

The q-quantile of n draws is the value of rank ⌈q·n⌉ − 1 among them sorted (the inverted CDF); the ranks
are found by numpy partitions, not a sort, and P(hold) at a pressure is the share of draws at or below it.
"""

from __future__ import annotations

import math
from decimal import Decimal

import numpy as np


def upper_rank(n: int, level: float) -> int:
    """0-based rank among n sorted values of the least x with a share ≥ level of them ≤ x (the empirical,
    inverted-CDF quantile)."""
    return max(math.ceil(level * n - 1e-9) - 1, 0)


def lower_rank(n: int, level: float) -> int:
    """0-based rank among n sorted values of the largest x with a share ≥ level of them ≥ x."""
    return min(math.floor((1 - level) * n + 1e-9), n - 1)


def order_statistics(values: np.ndarray, ranks, *, share: bool = False, overwrite: bool = False,
                     settle=None):
    """``np.sort(values, axis=0)[ranks]`` for ``values`` (n, C): (len(ranks), C), the same numbers without
    the full sort. One single-kth partition per distinct rank, each of what lies above the previous one
    (numpy's SIMD partition: half the sort's time at 10⁴ draws and a few ranks). With ``share``, also the
    share of the values ≤ the first rank's statistic (C,): after the partitions no value below a rank
    exceeds its statistic and none above is less, so only the ties above it are counted. ``overwrite``:
    ``values`` may be reordered in place where it allows (the evaluator's (n, C) are views of (C, n)).
    ``settle``: a non-decreasing map (NaN sorts last, as the largest): the statistics and the share of
    ``settle(values)``, mapped after the partitions (the ties it makes above the rank are counted)."""
    part = values.T
    if not (overwrite and part.flags.c_contiguous and part.flags.writeable):
        part = np.array(part, order="C")  # a copy, also of a broadcast (read-only) view
    start = 0
    for k in sorted(set(ranks)):
        part[:, start:].partition(k - start, axis=1)
        start = k + 1
    out = part[:, list(ranks)].T
    above = part[:, ranks[0] + 1:] if share else None
    if settle is not None:
        out = settle(out)
        above = None if above is None else settle(above)
    if not share:
        return out
    return out, (ranks[0] + 1 + np.count_nonzero(above == out[0][:, None], axis=1)) / values.shape[0]


def share_at_most(values: np.ndarray, limits: np.ndarray) -> np.ndarray:
    """The share of ``values`` (n, C) ≤ ``limits`` (C,), per column; values the same in every column (a
    broadcast (n, 1): every class of the chunk in one drawn bore) are sorted once and searched."""
    if values.shape[1] > 1 and values.strides[1] == 0:
        return np.searchsorted(np.sort(values[:, 0]), limits, side="right") / values.shape[0]
    return np.mean(values <= limits, axis=0)


def level_text(level: float) -> str:
    """C with every digit it was given (0.9999999999, not 1): 15 significant digits, trailing zeros cut."""
    return f"{level:.15g}"


def probability_places(level: float) -> int:
    """Decimal places that show a probability near C apart from 1: two significant digits of 1 − C, and at
    least 4 (0.95 → 4, 0.99999 → 6)."""
    return max(4, 1 - math.floor(math.log10(tail(level))))


def tail(level: float) -> float:
    """1 − C as C was written (:func:`level_text`): 1 − 0.95 is 0.05, not 0.050000000000000044."""
    return float(1 - Decimal(level_text(level)))
