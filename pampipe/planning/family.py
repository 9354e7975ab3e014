"""Exact order statistics of alike classes from a few of their draws (docs/physics.md §15, *Families*).

The classes of a chunk that share every bore's drawn terms k, r, f (:class:`law.Terms`: the muscle, κ, e, the
drawn bore) and the friction statement (μ̂, sd) form a **family**: in draw d, class c's raw P* is

    v_c(d) = max over the bores b of  W_c(d)·k_b(d) + (W_c(d)/μ(d))·r_b(d) − f_b(d),
    W_c(d) = μ(d)·s_c + z_c (+ the tether's tension t_c),

the same features k, r, f, μ for every member, and the class's own load slope s_c [N] and load at μ = 0
z_c [N] (its incline). Two members differ in any draw by at most

    D = ΔW·max|k| + Δ(W/μ)·max|r|,   ΔW ≤ |Δs|·max μ + |Δz| + |Δt|,   Δ(W/μ) ≤ |Δs| + (|Δz| + |Δt|)·max 1/μ

(exactly |ΔW|, |Δ(W/μ)| where μ is not drawn), and each computed value is within E = 32u of its terms' size of
the exact one (u = 2⁻⁵³). A reference member's n values name the **candidates**: the K draws where it is
largest (for the high ranks, K = n − the lowest high rank + a margin) and the K' where it is smallest (the
low ranks); off the candidates it lies within [T_lo, T_hi]. Member c's values are computed on the candidates
only, by the operations of :func:`law.raw_least` (the same bits as the whole row), and its statistics among
them are its statistics among all n draws where they clear the bound: its lowest high statistic above
T_hi + D + E (every other draw lies below it), its highest low statistic below T_lo − D − E. A member that
does not clear it is evaluated over all n draws. Either way the numbers equal those of the whole row's
partition bit for bit; they cost about 2K/n of it where neighbours in the chunk (sorted by incline within a
family) are close.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np

from pampipe.model.muscle import PRESSURE_LIMIT
from pampipe.planning.law import Terms, per_class, raw_least, settle
from pampipe.planning.sources import keyed_normal
from pampipe.runtime.alike import unique_rows

#: Rounding allowance of one value against its terms' size (law.raw_least: five rounded operations after
#: the load's two or three; 32u is more than their sum).
SLACK = 32 * np.finfo(float).eps / 2
#: Candidates beyond a tail's ranks: MARGIN_SHARE of the tail, at least MARGIN.
MARGIN, MARGIN_SHARE = 32, 0.25
#: Members: how far the first reference lies ahead (half of it) and how many are evaluated in full where no
#: neighbour is sure to clear a reference's test; the most one reference serves.
FIRST_BLOCK, LARGEST_BLOCK = 8, 256
#: Values per block of rows of :func:`raw_values`: 2¹⁶ doubles, 512 kB, each of its seven to a dozen passes
#: within the L2 cache (the sampling of 10⁵ all-distinct sections at 10⁴ draws: 0.3–0.7 s CPU less than in
#: one block of up to 256 × 1,250 values; 2¹⁵: less gain, 2¹⁴: none).
BLOCK_VALUES = 1 << 16


@dataclass(frozen=True)
class Family:
    """Classes of a chunk with the same features: their rows, per bore their terms, μ, loads."""

    rows: np.ndarray  # (m,) the evaluator's classes, in chunk order
    terms: list[Terms]  # per bore of the ranges, the largest last; fields (n,) or (1,)
    mu: np.ndarray  # (n,) the drawn μ(d), or (m,) each member's μ̂ where friction is not drawn
    drawn: bool
    slope: np.ndarray  # (m,) ∂W/∂μ [N]
    at_zero: np.ndarray  # (m,) W at μ = 0 [N]
    drag: np.ndarray | None  # (m,) the tether's tension [N] (None: no tether)
    size: int  # n, the draws
    order: np.ndarray | None = None  # the draws by the drawn μ (stable argsort; None: not kept)


def families(ev, sources) -> list[Family] | None:
    """The families of evaluator ``ev``'s classes with only ``sources`` drawn; None where some draw does not
    hold (F₁ ≤ 0, μ ≤ 0, a non-finite term): the whole rows are evaluated then."""
    per_bore = ev.bore_terms(sources)
    slope, at_zero = ev.load_affine()
    friction = "friction" in sources
    keys = np.stack([*(group for group, _ in per_bore), ev.mu, ev.mu_sd if friction else 0 * ev.mu])
    inverse = unique_rows(keys.T)[2]
    out = []
    for f in range(int(inverse.max()) + 1 if inverse.size else 0):
        rows = np.flatnonzero(inverse == f)
        c = int(rows[0])
        terms = [all_terms[group[c]] for group, all_terms in per_bore]
        sd = float(ev.mu_sd[c]) if friction else 0.0
        order = None
        if sd > 0:
            mu, order = drawn_friction(ev.problem.seed, float(ev.mu[c]), sd, ev.problem.samples)
        else:
            mu = ev.mu[rows] + np.zeros(1)
        finite = all(np.all(np.isfinite(v)) for t in terms for v in vars(t).values())
        per_draw = sd > 0 or any(np.size(v) > 1 for t in terms for v in vars(t).values())
        if not (finite and per_draw and np.min(mu) > 0):
            return None
        drag = None if ev.drag is None else ev.drag[rows]
        out.append(Family(rows, terms, mu, sd > 0, slope[rows], at_zero[rows], drag, ev.problem.samples,
                          order))
    return out


@functools.lru_cache(maxsize=16)
def drawn_friction(seed: int, value: float, sd: float, n: int) -> tuple[np.ndarray, np.ndarray]:
    """(μ(d) = μ̂ + sd·ξ(d) (n,), as Evaluator.friction_load sums it, the draws in the order of μ (stable
    argsort)) of the friction statement (μ̂ = ``value``, ``sd``), read-only: once per process, not per
    family and chunk (every chunk's families of a statement share its draws)."""
    mu = value + keyed_normal(seed, "friction", (value, sd), n) * sd
    order = np.argsort(mu, kind="stable")
    mu.flags.writeable = order.flags.writeable = False
    return mu, order


def values(family: Family, members: np.ndarray, columns: np.ndarray | None) -> np.ndarray:
    """Raw P* (len(members), K) of ``members`` (positions in the family) in draws ``columns`` (None: all
    n)."""
    if family.drawn:
        mu = (family.mu if columns is None else family.mu[columns])[None, :]
    else:
        mu = family.mu[members, None]
    return raw_values(family, members, mu, columns)


def raw_values(family: Family, members: np.ndarray, mu: np.ndarray, columns: np.ndarray | None = None):
    """Raw P* of ``members`` at frictions ``mu`` (broadcast against (len(members), 1)), the terms in draws
    ``columns`` (None: all n, or one number each), by the operations of Evaluator.friction_load,
    law.per_class and law.raw_least (the same bits), in blocks of rows of at most :data:`BLOCK_VALUES`
    values whose every pass stays in the cache (elementwise: the same bits as one pass over all rows)."""
    terms = [t if columns is None else Terms(*(v if v.size == 1 else v[columns] for v in (t.k, t.r, t.f)))
             for t in family.terms]
    sizes = ((1, v.size) for t in terms for v in vars(t).values())
    shape = np.broadcast_shapes(np.shape(mu), (members.size, 1), *sizes)
    rows = max(1, BLOCK_VALUES // shape[1])
    out = np.empty(shape)
    for start in range(0, members.size, rows):
        block = slice(start, start + rows)
        _raw_block(family, members[block], mu if mu.shape[0] == 1 else mu[block], terms, out[block])
    return out


def _raw_block(family: Family, members: np.ndarray, mu: np.ndarray, terms: list[Terms], out: np.ndarray):
    """:func:`raw_values` of one block of rows, into ``out``: the first bore's values, then the max of each
    other bore's (NaN, where the law does not hold, stays NaN)."""
    load = np.multiply(mu, family.slope[members, None])
    load += family.at_zero[members, None]
    if family.drag is not None:
        load = load + family.drag[members, None]
    load, per_mu = per_class(load, mu)
    spare, other = np.empty(out.shape), None
    raw_least(load, per_mu, terms[0], out, spare)
    for t in terms[1:]:
        other = np.empty(out.shape) if other is None else other
        np.maximum(out, raw_least(load, per_mu, t, other, spare), out=out)


@dataclass(frozen=True)
class Extremes:
    """What bounds a member's values against the reference's (per bore of the family): the extremes of
    X and Y over the draws, their largest size, and each member's terms' size [Pa]."""

    a: np.ndarray  # (m,) the members' coefficient of X (before the reference's is taken off)
    b: np.ndarray  # (m,) of Y
    x: list[tuple[float, float]]  # per bore (min X, max X)
    y: list[tuple[float, float]]
    scale: float  # max |X| + max |Y| over the bores
    size: np.ndarray  # (m,) max over the bores of |W|·max|k| + |W/μ|·max|r| + max|f| [Pa]


def extremes(family: Family) -> Extremes:
    """v_c − v_ref = (a_c − a_ref)·X + (b_c − b_ref)·Y per bore in every draw (exact arithmetic): a = s,
    b = z + t, X = μk + r, Y = k + r/μ where μ is drawn (W = μs + z + t), a = W, b = W/μ, X = k, Y = r
    where it is not."""
    drag = np.zeros(family.slope.size) if family.drag is None else family.drag
    if family.drawn:
        mu = family.mu
        a, b = family.slope, family.at_zero + drag
        features = [(mu * t.k + t.r, t.k + t.r / mu) for t in family.terms]
        top, inverse = float(np.max(mu)), float(np.max(1.0 / mu))
        size_w = np.abs(family.slope) * top + np.abs(family.at_zero) + np.abs(drag)
        size_p = np.abs(family.slope) + (np.abs(family.at_zero) + np.abs(drag)) * inverse
    else:
        a = family.mu * family.slope + family.at_zero + drag
        b = a / family.mu
        features = [(t.k, t.r) for t in family.terms]
        size_w, size_p = np.abs(a), np.abs(b)
    x = [(float(np.min(u)), float(np.max(u))) for u, _ in features]
    y = [(float(np.min(v)), float(np.max(v))) for _, v in features]
    scale = max(max(abs(x0), abs(x1)) + max(abs(y0), abs(y1))
                for (x0, x1), (y0, y1) in zip(x, y, strict=True))
    size = np.max([size_w * np.max(np.abs(t.k)) + size_p * np.max(np.abs(t.r)) + np.max(np.abs(t.f))
                   for t in family.terms], axis=0)
    return Extremes(a, b, x, y, scale, size)


def _bound(e: Extremes, members: np.ndarray, reference: int) -> tuple[np.ndarray, np.ndarray]:
    """(lowest, highest) (len(members),) [Pa] that a member's value can lie from the reference's in any draw:
    each bore's a·X + b·Y at X's and Y's extremes, widened by the rounding of both values (SLACK of their
    terms' size and of the shift's)."""
    a, b = e.a[members] - e.a[reference], e.b[members] - e.b[reference]
    high = low = None
    for (x0, x1), (y0, y1) in zip(e.x, e.y, strict=True):
        up = np.maximum(a * x0, a * x1) + np.maximum(b * y0, b * y1)
        down = np.minimum(a * x0, a * x1) + np.minimum(b * y0, b * y1)
        high = up if high is None else np.maximum(high, up)
        low = down if low is None else np.minimum(low, down)
    slack = SLACK * (e.size[members] + e.size[reference] + (np.abs(a) + np.abs(b)) * e.scale)
    return low - slack, high + slack


def select(part: np.ndarray, ranks: list[int], below: int):
    """(raw statistics (len(ranks), m), ``part`` partitioned) of the full ranks ``ranks`` from candidates
    ``part`` (m, K), ``below`` values known to lie under them (partitioned in place)."""
    shifted = [k - below for k in ranks]
    start = 0
    for k in sorted(set(shifted)):
        part[:, start:].partition(k - start, axis=1)
        start = k + 1
    return part[:, shifted].T


def exact(stats: np.ndarray, part: np.ndarray, first: int, below: int, n: int, share: bool):
    """(settled statistics, the share of n values ≤ the first, or None) as quantiles.order_statistics
    gives them: the ties above the first rank after settle are counted. Where the first raw value v lies in
    (0, 100 MPa], settle keeps it and a value above settles to v only if it equals v: the raw values are
    compared, not settled first (one pass, not four)."""
    out = settle(stats)
    if not share:
        return out, None
    above, first_raw = part[:, first - below + 1:], stats[0]
    kept = (first_raw > 0) & (first_raw <= PRESSURE_LIMIT)
    ties = np.count_nonzero(above == first_raw[:, None], axis=1)
    if not kept.all():  # 0 or inf: every value above that settles to it
        ties[~kept] = np.count_nonzero(settle(above[~kept]) == out[0][~kept, None], axis=1)
    return out, (first + 1 + ties) / n


def family_statistics(family: Family, ranks: list[int], n: int, share: bool, fill=None):
    """(settled order statistics (len(ranks), m) of each member's n raw values, their share ≤ the first or
    None) for 0-based ``ranks`` (the first a high rank where ``share``); None where the ranks' tails are
    too wide for candidates to pay (more than half the draws). ``fill(family, high, low, n, out)`` fills
    the :class:`Statistics` instead of the reference members' blocks (e.g.
    :func:`pampipe.planning.convex.convex_statistics`)."""
    high = [k for k in ranks if 2 * k >= n]
    low = [k for k in ranks if 2 * k < n]
    top = n - min(high) if high else 0
    bottom = max(low) + 1 if low else 0
    top += max(MARGIN, int(top * MARGIN_SHARE)) if high else 0
    bottom += max(MARGIN, int(bottom * MARGIN_SHARE)) if low else 0
    if 2 * (top + bottom) > n:
        return None
    m = family.rows.size
    out = Statistics(np.empty((len(ranks), m)), np.empty(m) if share else None,
                     [(high + low).index(k) for k in ranks])
    if fill is not None:
        fill(family, high, low, n, out)
        return out.stats, out.shares
    bounds = extremes(family)
    start, reach = 0, FIRST_BLOCK // 2
    while start < m:
        reference = min(start + reach, m - 1)
        ref = _reference(family, reference, high, low, top, bottom, n)
        stop = start if ref is None else _cleared(bounds, reference, start, min(start + LARGEST_BLOCK, m),
                                                  ref.gap)
        if stop <= start + 1 and reach > 0:  # the reference too far: one nearer
            reach //= 2
            continue
        if stop <= start + 1:  # no neighbour sure to clear (far apart, or a draw where it does not hold)
            start += whole(family, np.arange(start, min(start + FIRST_BLOCK, m)), high + low, n, out)
            continue
        _block(family, bounds, np.arange(start, stop), ref, high, low, n, out)
        reach = min(4 * (stop - 1 - reference) // 5, LARGEST_BLOCK // 2) if stop > reference else 0
        start = stop
    return out.stats, out.shares


def _cleared(bounds: Extremes, reference: int, start: int, end: int, gap: float) -> int:
    """The first member from ``start`` (up to ``end``) not sure to clear the test against ``reference``: a
    member's statistics lie within [lowest, highest] of the reference's (:func:`_bound`), so it clears where
    highest − lowest is less than the reference's ``gap`` (with 5 % to spare)."""
    lowest, highest = _bound(bounds, np.arange(start, end), reference)
    fails = np.flatnonzero(~(highest - lowest < 0.95 * gap))
    return start + int(fails[0]) if fails.size else end


@dataclass(frozen=True)
class Statistics:
    """What :func:`family_statistics` fills, per member."""

    stats: np.ndarray  # (R, m) settled, in the order of the ranks asked
    shares: np.ndarray | None  # (m,) the share of draws ≤ the first statistic
    slots: list[int]  # row of each asked rank among the high ranks then the low ranks


@dataclass(frozen=True)
class Reference:
    """A reference member's candidates and what bounds the draws off them [Pa]."""

    high: np.ndarray | None  # the draws at or above its (n − top)-th value (None: no high ranks)
    low: np.ndarray | None  # the draws at or below its bottom-th value
    reference: int  # the member
    ceiling: float  # its largest value off the high candidates
    floor: float  # its least value off the low candidates
    gap: float  # the room a member's spread may take: its statistics' distance to the ceiling and floor


def _reference(family, reference: int, high, low, top, bottom, n) -> Reference | None:
    """The :class:`Reference` of member ``reference`` from its n values; None where one is not finite."""
    row = values(family, np.array([reference]), None)[0]
    if not np.all(np.isfinite(row)):
        return None
    sorted_row, gap = np.array(row), np.inf
    above = below = None
    ceiling = floor = np.nan
    if high:  # the candidates: every draw at or above the reference's (n − top)-th value
        sorted_row.partition(n - top)
        above = np.flatnonzero(row >= sorted_row[n - top])
        ceiling = float(np.max(sorted_row[:n - top]))
        gap = np.partition(sorted_row[n - top:], min(high) - n + top)[min(high) - n + top] - ceiling
    if low:  # every draw at or below the reference's bottom-th value
        sorted_row[:n - top].partition(bottom - 1)
        below = np.flatnonzero(row <= sorted_row[bottom - 1])
        floor = float(np.min(sorted_row[bottom:]))
        gap = min(gap, floor - np.partition(sorted_row[:bottom], max(low))[max(low)])
    return Reference(above, below, reference, ceiling, floor, float(gap))


def _block(family, bounds: Extremes, members, ref: Reference, high, low, n, out: Statistics) -> None:
    """Fill ``stats`` (and ``shares``) of ``members`` from the candidates of the reference ``ref``; a member
    that does not clear the test, from all n draws."""
    lowest, highest = _bound(bounds, members, ref.reference)
    good = np.ones(members.size, dtype=bool)
    found = []
    if high:
        below = n - ref.high.size
        part = values(family, members, ref.high)
        raw = select(part, high, below)
        ceiling = ref.ceiling + highest  # the others lie at or below it
        good &= raw.min(axis=0) > ceiling + 4 * SLACK * np.abs(ceiling)
        found.append((raw, part, below))
    if low:
        part = values(family, members, ref.low)
        raw = select(part, low, 0)
        floor = ref.floor + lowest
        good &= raw.max(axis=0) < floor - 4 * SLACK * np.abs(floor)
        found.append((raw, part, 0))
    settled = settle(np.concatenate([raw for raw, _, _ in found]))
    out.stats[:, members[good]] = settled[out.slots][:, good]
    if out.shares is not None:
        raw, part, below = found[0]
        out.shares[members[good]] = exact(raw[:, good], part[good], high[0], below, n, True)[1]
    if not good.all():
        whole(family, members[~good], high + low, n, out)


def whole(family, members, ranks, n, out: Statistics) -> int:
    """Fill ``members`` from all n draws (the plain partition); returns how many."""
    part = values(family, members, None)
    raw = select(part, ranks, 0)
    settled, held = exact(raw, part, ranks[0], 0, n, out.shares is not None)
    out.stats[:, members] = settled[out.slots]
    if held is not None:
        out.shares[members] = held
    return int(members.size)
