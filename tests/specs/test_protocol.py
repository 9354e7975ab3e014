"""specs/protocol.cluster_levels against the definition it implements faster: a stable argsort of the values,
the widest gaps by a stable argsort of the gaps, levels numbered by the sorted rows' cumulative cuts and
np.median per cluster (the reference below, as the function was before the sorts were replaced)."""

import numpy as np
import pytest

from pampipe.specs.protocol import MIN_ROWS, SEPARATION, TIGHT, _widest, cluster_levels


def reference(values, max_levels):
    n = values.size
    order = np.argsort(values, kind="stable")
    ordered = values[order]
    gaps = np.diff(ordered)
    widest = np.argsort(gaps, kind="stable")[::-1]
    best = None
    for k in range(2, min(max_levels, n // MIN_ROWS) + 1):
        narrowest = gaps[widest[k - 2]]
        if narrowest <= 0:
            break
        cuts = np.sort(widest[:k - 1]) + 1
        starts, ends = np.concatenate([[0], cuts]), np.concatenate([cuts, [n]]) - 1
        if np.max(ordered[ends] - ordered[starts]) < SEPARATION * narrowest:
            best = (cuts, starts, ends)
    if best is None:
        if ordered[-1] - ordered[0] > TIGHT * max(float(np.max(np.abs(ordered))), 1e-300):
            return None
        best = (np.zeros(0, dtype=np.int64), np.array([0]), np.array([n - 1]))
    cuts, starts, ends = best
    marks = np.zeros(n, dtype=np.int64)
    marks[cuts] = 1
    index = np.empty(n, dtype=np.int64)
    index[order] = np.cumsum(marks)
    return index, np.array([np.median(ordered[a:b + 1]) for a, b in zip(starts, ends, strict=True)])


def draws(rng, kind, n):
    levels = rng.choice([0.0, 1.0, 5.0, 7.5, 100.0, -3.0], size=int(rng.integers(1, 6)))
    v = rng.choice(levels, n)
    if kind == "noisy levels":
        return v + rng.normal(0, 0.01, n)
    if kind == "rounded levels":  # many equal gaps: ties among the widest
        return np.round(v + rng.normal(0, 0.3, n), 1)
    if kind == "ramp":
        return rng.uniform(0, 1, n)
    if kind == "signed zeros":  # -0.0 among +0.0: the stable order and numpy's median decide the sign
        return np.where(rng.random(n) < 0.3, -0.0, v)
    if kind == "only zeros":
        return np.where(rng.random(n) < 0.5, -0.0, 0.0)
    if kind == "a NaN":
        v = v.copy()
        v[rng.integers(0, n)] = np.nan
        return v
    return np.round(v * 3 + rng.integers(0, 3, n), 0)  # integers: equal gaps of 1


KINDS = ["noisy levels", "rounded levels", "ramp", "signed zeros", "only zeros", "a NaN", "integers"]


@pytest.mark.parametrize("kind", KINDS)
def test_cluster_levels_as_the_stable_sorts_number_them(kind):
    rng = np.random.default_rng(sum(map(ord, kind)))
    for _ in range(150):
        values = draws(rng, kind, int(rng.integers(1, 400)))
        max_levels = int(rng.choice([2, 4, 12, 64]))
        found, expected = cluster_levels(values, max_levels=max_levels), reference(values, max_levels)
        if expected is None:
            assert found is None
            continue
        np.testing.assert_array_equal(found.index, expected[0])
        np.testing.assert_array_equal(found.values, expected[1])  # NaN where numpy's median gives NaN
        np.testing.assert_array_equal(np.signbit(found.values), np.signbit(expected[1]))


@pytest.mark.parametrize("steps", [0.1, 1.0])
def test_the_widest_gaps_later_first_among_equal_ones(steps):
    rng = np.random.default_rng(int(10 * steps))
    for _ in range(200):
        gaps = np.round(rng.exponential(1.0, int(rng.integers(2, 300))) / steps) * steps
        count = int(rng.integers(1, gaps.size))
        np.testing.assert_array_equal(_widest(gaps, count), np.argsort(gaps, kind="stable")[::-1][:count])


def test_levels_of_a_million_noisy_rows():
    rng = np.random.default_rng(5)
    steps = np.linspace(0.0, 689e3, 11)
    truth = rng.integers(0, steps.size, 1_000_000)
    found = cluster_levels(steps[truth] + rng.normal(0, 300, truth.size))
    np.testing.assert_array_equal(found.index, truth)
    np.testing.assert_allclose(found.values, steps, atol=30)  # the median of ~9·10⁴ draws of sd 300 Pa
