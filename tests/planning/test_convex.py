"""Order statistics of a family convex in μ (pampipe.planning.convex): equal bit for bit to the sorted whole
rows, for loads whose least value lies inside the draws' μ and at either end, with the holding share; the
edge test is what makes the low side exact (taken away, a misplaced window gives wrong statistics)."""

from __future__ import annotations

import numpy as np
import pytest

from pampipe.planning import convex
from pampipe.planning.family import Family, values
from pampipe.planning.law import Terms, settle
from pampipe.planning.quantiles import upper_rank

N = 3000
HIGH = [upper_rank(N, 0.95), 2730, 2969, upper_rank(N, 0.9), upper_rank(N, 0.99)]
BREAKDOWN = [upper_rank(N, 0.95), upper_rank(N, 0.05)]


def _family(members: int = 300) -> Family:
    """μ ~ N(0.3, 0.06²) and two bores' constant terms (k, r [Pa/N], f [Pa]); loads of inclines from −89° to
    89°: g(μ) = s·k·μ + z·r/μ + … has its least value at μ* = √(z·r/(s·k)), inside the draws for some
    members, beyond them for the steep and the level ones."""
    rng = np.random.default_rng(5)
    mu = 0.3 + 0.06 * rng.standard_normal(N)
    incline = np.radians(np.linspace(-89.0, 89.0, members))
    slope, at_zero = 9.81 * 3.0 * np.cos(incline), 9.81 * 4.0 * np.abs(np.sin(incline))
    terms = [Terms(np.array([60.0]), np.array([30.0]), np.array([-1.2e5])),
             Terms(np.array([55.0]), np.array([33.0]), np.array([-1.1e5]))]
    return Family(np.arange(members), terms, mu, True, slope, at_zero, None, N)


def _counted(monkeypatch) -> list[int]:
    """The sizes of the member sets sent to their whole rows, as they are sent."""
    whole, plain = [], convex.whole
    monkeypatch.setattr(convex, "whole",
                        lambda f, members, *a: whole.append(members.size) or plain(f, members, *a))
    return whole


def _expected(family: Family, ranks: list[int], share: bool):
    """The statistics and share ≤ the first from every member's n values sorted (numpy's sort)."""
    whole = np.sort(values(family, np.arange(family.rows.size), None), axis=1)
    stats = settle(whole[:, ranks].T)
    held = (settle(whole) <= stats[0][:, None]).sum(axis=1) / N
    return stats, held if share else None


def test_the_least_values_lie_inside_and_beyond_the_draws():
    family = _family()
    star = np.sqrt(family.at_zero * 30.0 / (family.slope * 60.0))
    assert np.any((star > family.mu.min()) & (star < family.mu.max()))  # a U in μ
    assert np.any(star < family.mu.min()) and np.any(star > family.mu.max())  # rising, falling
    assert convex.applies(family)


@pytest.mark.parametrize(("ranks", "share"), [(HIGH, True), (BREAKDOWN, False)])
def test_the_statistics_are_the_sorted_whole_rows(monkeypatch, ranks, share):
    family = _family()
    whole = _counted(monkeypatch)
    stats, held = convex.chunk_statistics([family], ranks, N, family.rows.size, share)
    expected, expected_held = _expected(family, ranks, share)
    np.testing.assert_array_equal(stats, expected)
    if share:
        np.testing.assert_array_equal(held, expected_held)
    assert sum(whole) < family.rows.size / 20  # nearly every member from its candidates


def test_without_the_edge_test_a_misplaced_window_is_wrong(monkeypatch):
    family = _family()
    expected = _expected(family, BREAKDOWN, False)[0]
    monkeypatch.setattr(convex, "window_start", lambda least, bottom, n, width: np.zeros_like(least))
    whole = _counted(monkeypatch)
    stats, _ = convex.chunk_statistics([family], BREAKDOWN, N, family.rows.size, False)
    np.testing.assert_array_equal(stats, expected)  # the members whose least lies elsewhere: whole rows
    assert sum(whole) > family.rows.size / 4
    monkeypatch.setattr(convex, "bounds_beyond",
                        lambda edge, inner, apart, most, slack: np.ones(edge.size, dtype=bool))
    stats, _ = convex.chunk_statistics([family], BREAKDOWN, N, family.rows.size, False)
    assert not np.array_equal(stats, expected)


def test_a_load_that_makes_g_concave_is_not_taken():
    family = _family()
    concave = Family(family.rows, family.terms, family.mu, True, family.slope, -family.at_zero - 1.0, None, N)
    assert not convex.applies(concave)
    fixed = family.mu[:1].repeat(family.rows.size)  # μ not drawn: nothing to be convex in
    assert not convex.applies(Family(family.rows, family.terms, fixed, False, family.slope, family.at_zero,
                                     None, N))
