"""Exact order statistics of a family whose only drawn input is the friction (docs/physics.md §15, *Convex in
μ*): the breakdown's "friction alone", and any plan whose muscle, κ, model error and bore are certain.

With the terms k, r, f of every bore the same in every draw (:mod:`pampipe.planning.family`), member c's raw
P* in draw d is a function of the drawn friction μ(d) > 0 alone,

    g_c(μ) = max over the bores b of  s_c·k_b·μ + b_c·r_b/μ + (s_c·r_b + b_c·k_b − f_b),   b_c = z_c (+ t_c),

convex in μ wherever b_c·r_b ≥ 0 (a line plus b_c·r_b/μ, and the max of convex functions). Over the draws
sorted by μ (positions 0 … n−1), then:

* **high ranks:** every draw between positions K−1 and n−K lies at or below the larger of the two (a convex
  function's chord): the K lowest and K highest μ are the candidates (where the coarse grid below shows g
  falling or rising throughout, the K of that end and the other end's last draw), and a member's statistics
  among them are its statistics among all n where its lowest high statistic lies above that larger value + 2E
  (K: the high tail and ``family.MARGIN`` draws);
* **low ranks:** around the member's least value on a coarse grid of positions (every :data:`STRIDE`-th), a
  window [L, R] of positions; where g falls from L to L+1 (μ_L < μ_{L+1}), every draw left of L lies at or
  above g(μ_L) (convexity), and likewise right of R where g rises from R−1 to R: its statistics among the
  window are its statistics among all n where its highest low statistic lies below both edges − 2E.

E is the rounding of one computed value against its terms' size (``family.SLACK``). The values are computed
by the operations of :func:`family.raw_values` (the same bits as the whole row), every member of the family
in one numpy pass per block of :data:`BLOCK` members, no reference member, no bound between members; a member
that does not clear its test is evaluated over all n draws. Either way the numbers equal those of the whole
row's partition bit for bit.
"""

from __future__ import annotations

import numpy as np

from pampipe.planning.family import (
    MARGIN,
    SLACK,
    Family,
    Statistics,
    exact,
    extremes,
    family_statistics,
    raw_values,
    select,
    whole,
)

#: Positions between the points of the coarse grid that finds a member's least value (a window reaches
#: STRIDE beyond its tail; 64 against 32: 157 fewer grid values, 32 or 64 more in the window).
STRIDE = 64
#: Members per numpy pass (arrays of BLOCK × about 1.3·10³ values at 10⁴ draws: within the L2 cache's reach).
BLOCK = 128


def chunk_statistics(found: list[Family], ranks: list[int], n: int, count: int, share: bool):
    """(settled statistics (len(ranks), count), shares (count,) or None) of every class of the families
    ``found``: convex in μ (:func:`applies`) by :func:`convex_statistics`, else from a reference member's
    candidates (:func:`family.family_statistics`); None where candidates do not pay."""
    stats, shares = np.empty((len(ranks), count)), np.empty(count) if share else None
    for family in found:
        fill = convex_statistics if applies(family) else None
        result = family_statistics(family, ranks, n, share, fill)
        if result is None:
            return None
        stats[:, family.rows] = result[0]
        if share:
            shares[family.rows] = result[1]
    return stats, shares


def applies(family: Family) -> bool:
    """True where μ is drawn, every bore's terms are one number and b_c·r_b ≥ 0 (g_c convex in μ)."""
    if not family.drawn or any(np.size(v) > 1 for t in family.terms for v in vars(t).values()):
        return False
    b = family.at_zero + (0.0 if family.drag is None else family.drag)
    return all(np.all(b * float(t.r[0]) >= 0) for t in family.terms)


def convex_statistics(family: Family, high: list[int], low: list[int], n: int, out: Statistics) -> None:
    """Fill ``out`` for every member of ``family`` (:func:`applies`) for the 0-based ranks ``high`` and
    ``low``. The candidates of each tail are its ranks and :data:`family.MARGIN` more: each member is tested
    on its own values, so the margin need only put the chord's (or the window edge's) draws MARGIN
    positions away from the nearest statistic, not cover a reference's spread (family.MARGIN_SHARE)."""
    top = n - min(high) + MARGIN if high else 0
    bottom = max(low) + 1 + MARGIN if low else 0
    order = np.argsort(family.mu, kind="stable") if family.order is None else family.order
    mu = family.mu[order]
    size = extremes(family).size
    grid = np.unique(np.append(np.arange(0, n, STRIDE), n - 1))
    for start in range(0, family.rows.size, BLOCK):
        members = np.arange(start, min(start + BLOCK, family.rows.size))
        slack = 2 * SLACK * size[members]
        coarse = raw_values(family, members, mu[grid][None, :])
        good = np.all(np.isfinite(coarse), axis=1)
        found = []
        if high:
            found.append(_high(family, members, mu, coarse, grid, high, top, n, slack, good,
                               out.shares is not None))
        if low:
            found.append(_low(family, members, mu, coarse, grid, low, bottom, n, slack, good))
        settled = exact(np.concatenate([raw for raw, _ in found]), None, 0, 0, n, False)[0]
        out.stats[:, members[good]] = settled[out.slots][:, good]
        if out.shares is not None:
            out.shares[members[good]] = found[0][1][good]
        if not good.all():
            whole(family, members[~good], high + low, n, out)


def _high(family: Family, members, mu, coarse, grid, high, top, n, slack, good, share: bool):
    """(raw high statistics (len(high), m), the share of n values ≤ the first or None): the candidates
    are the ``top`` lowest and highest μ, or those of one end and the other end's last draw where the
    coarse grid shows g falling (rising) to below its value ``top`` positions in; clears ``good`` where the
    lowest statistic is not above the chord between the candidates around the other draws + 2E."""
    k = min(top, n // 2)
    inner_left = coarse[:, np.searchsorted(grid, k)]  # g on the grid k positions in from either end
    inner_right = coarse[:, np.searchsorted(grid, n - 1 - k) - 1]
    left = (coarse[:, -1] < inner_left) & (coarse[:, 0] >= inner_left)  # the top k all on the left
    right = ~left & (coarse[:, 0] < inner_right) & (coarse[:, -1] >= inner_right)
    raw, held = np.empty((len(high), members.size)), np.empty(members.size) if share else None
    ends = np.arange(n - k, n)
    for rows, positions, chord in ((left, np.append(np.arange(k), n - 1), k - 1),
                                   (right, np.insert(ends, 0, 0), 0),
                                   (~left & ~right, np.concatenate([np.arange(k), ends]), k - 1)):
        if not rows.any():
            continue
        part = raw_values(family, members[rows], mu[positions][None, :])
        ceiling = np.maximum(part[:, chord], part[:, chord + 1]) + slack[rows]  # the draws between them
        below = n - positions.size
        raw[:, rows] = select(part, high, below)
        good[rows] &= np.all(np.isfinite(part), axis=1) & (raw[:, rows].min(axis=0) > ceiling + 4 * SLACK
                                                           * np.abs(ceiling))
        if share:
            held[rows] = exact(raw[:, rows], part, high[0], below, n, True)[1]
    return raw, held


def _low(family: Family, members, mu, coarse, grid, low, bottom, n, slack, good):
    """(raw low statistics (len(low), m), None): a window of positions around each member's least value on
    the coarse grid (one-sided at an end of the draws); clears ``good`` where an edge does not bound the
    draws beyond it."""
    least = grid[np.argmin(coarse, axis=1)]
    at_end = (least == 0) | (least == n - 1)
    raw = np.empty((len(low), members.size))
    for rows, width in ((at_end, min(n, bottom + STRIDE + 1)), (~at_end, min(n, 2 * (bottom + STRIDE) + 1))):
        if not rows.any():
            continue
        left = window_start(least[rows], bottom, n, width)
        if np.all(left == left[0]):  # one window for all (commonly: g monotone over the draws), one row of μ
            window = mu[left[0]:left[0] + width][None, :]
        else:
            window = mu[left[:, None] + np.arange(width)]
        part = raw_values(family, members[rows], window)
        edges = [(left > 0, part[:, 0].copy(), part[:, 1].copy(), window[:, 0] < window[:, 1]),
                 (left + width < n, part[:, -1].copy(), part[:, -2].copy(), window[:, -2] < window[:, -1])]
        ok = np.all(np.isfinite(part), axis=1)
        raw[:, rows] = select(part, low, 0)
        for beyond, edge, inner, apart in edges:
            ok &= ~beyond | bounds_beyond(edge, inner, apart, raw[:, rows].max(axis=0), slack[rows])
        good[rows] &= ok
    return raw, None


def window_start(least: np.ndarray, bottom: int, n: int, width: int) -> np.ndarray:
    """The first position of each member's window of ``width`` positions: ``bottom`` + STRIDE before the least
    value on the coarse grid (at position ``least``), within 0 … n − width (at an end of the draws the
    window reaches ``bottom`` + STRIDE from it). For an exact convex g its
    ``bottom`` least values lie within ``bottom`` positions of its least value, itself within STRIDE of
    the grid's."""
    return np.clip(least - bottom - STRIDE, 0, n - width)


def bounds_beyond(edge, inner, apart, most, slack) -> np.ndarray:
    """True where a window's ``edge`` value bounds every draw beyond it from below, above ``most`` (the
    highest low statistic): between two distinct μ (``apart``) g rises outwards from ``inner`` to ``edge``
    by more than the rounding 2E = ``slack``, so beyond the edge g ≥ g(edge) (convexity), and
    edge − 2E > most."""
    floor = edge - slack
    return apart & (inner + slack <= edge) & (floor > most + 4 * SLACK * np.abs(most))
