"""Exact order statistics of a family whose only drawn input is the friction (docs/physics.md §15, *Convex in
μ*): the breakdown's "friction alone", and any plan whose muscle, κ, model error and bore are certain.

With the terms k, r, f of every bore the same in every draw (:mod:`pampipe.planning.family`), member c's raw
P* in draw d is a function of the drawn friction μ(d) > 0 alone,

    g_c(μ) = max over the bores b of  s_c·k_b·μ + b_c·r_b/μ + (s_c·r_b + b_c·k_b − f_b),   b_c = z_c (+ t_c),

convex in μ wherever b_c·r_b ≥ 0 (a line plus b_c·r_b/μ, and the max of convex functions). Over the draws
sorted by μ (positions 0 … n−1), then:

* **high ranks:** every draw between positions K−1 and n−K lies at or below the larger of the two (a convex
  function's chord): the K lowest and K highest μ are the candidates, and a member's statistics among them are
  its statistics among all n where its lowest high statistic lies above that larger value + 2E;
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

#: Positions between the points of the coarse grid that finds a member's least value.
STRIDE = 32
#: Members per numpy pass (arrays of BLOCK × about 2.5·10³ values: within the L2 cache's reach).
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


def convex_statistics(family: Family, high: list[int], low: list[int], top: int, bottom: int, n: int,
                      out: Statistics) -> None:
    """Fill ``out`` for every member of ``family`` (:func:`applies`), ``top`` / ``bottom`` the candidates
    of each tail (margins included)."""
    order = np.argsort(family.mu, kind="stable")
    mu = family.mu[order]
    size = extremes(family).size
    for start in range(0, family.rows.size, BLOCK):
        members = np.arange(start, min(start + BLOCK, family.rows.size))
        slack = 2 * SLACK * size[members]
        good = np.ones(members.size, dtype=bool)
        found = []
        if high:
            found.append(_high(family, members, mu, high, top, n, slack, good))
        if low:
            found.append(_low(family, members, mu, low, bottom, n, slack, good))
        settled = exact(np.concatenate([raw for raw, _, _ in found]), None, 0, 0, n, False)[0]
        out.stats[:, members[good]] = settled[out.slots][:, good]
        if out.shares is not None:
            raw, part, below = found[0]
            out.shares[members[good]] = exact(raw[:, good], part[good], high[0], below, n, True)[1]
        if not good.all():
            whole(family, members[~good], high + low, n, out)


def _high(family: Family, members, mu, high, top, n, slack, good):
    """(raw high statistics, the candidates partitioned, how many lie below): the ``top`` lowest and
    highest μ; clears ``good`` where the lowest statistic is not above the chord between them + 2E."""
    k = min(top, n // 2)
    columns = np.concatenate([mu[:k], mu[n - k:]])[None, :]
    part = raw_values(family, members, columns)
    ceiling = np.maximum(part[:, k - 1], part[:, k]) + slack
    below = n - 2 * k
    raw = select(part, high, below)
    good &= np.all(np.isfinite(part), axis=1) & (raw.min(axis=0) > ceiling + 4 * SLACK * np.abs(ceiling))
    return raw, part, below


def _low(family: Family, members, mu, low, bottom, n, slack, good):
    """(raw low statistics, the window partitioned, 0): a window of positions around each member's least value
    on the coarse grid; clears ``good`` where an edge does not bound the draws beyond it."""
    grid = np.unique(np.append(np.arange(0, n, STRIDE), n - 1))
    coarse = raw_values(family, members, mu[grid][None, :])
    width = min(n, 2 * (bottom + STRIDE) + 1)
    left = window_start(grid[np.argmin(coarse, axis=1)], bottom, n, width)
    if np.all(left == left[0]):  # one window for all (commonly: g monotone over the draws), one row of μ
        window = mu[left[0]:left[0] + width][None, :]
    else:
        window = mu[left[:, None] + np.arange(width)]
    part = raw_values(family, members, window)
    edges = [(left > 0, part[:, 0].copy(), part[:, 1].copy(), window[:, 0] < window[:, 1]),
             (left + width < n, part[:, -1].copy(), part[:, -2].copy(), window[:, -2] < window[:, -1])]
    good &= np.all(np.isfinite(part), axis=1)
    raw = select(part, low, 0)
    for beyond, edge, inner, apart in edges:
        good &= ~beyond | bounds_beyond(edge, inner, apart, raw.max(axis=0), slack)
    return raw, part, 0


def window_start(least: np.ndarray, bottom: int, n: int, width: int) -> np.ndarray:
    """The first position of each member's window of ``width`` positions: ``bottom`` + STRIDE before the least
    value on the coarse grid (at position ``least``), within 0 … n − width. For an exact convex g its
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
