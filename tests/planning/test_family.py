"""Order statistics from candidate draws (pampipe.planning.family): equal bit for bit to the partition of
every class's n draws, where neighbours share the reference's candidates (inclines 0.01 deg apart) and where
they do not and are evaluated in full (1.9 deg apart); with the bound taken away the far classes come out
wrong, so the bound is what makes them exact."""

from __future__ import annotations

from functools import cache, partial

import numpy as np
import pytest

from pampipe.io.mission_schema import load_mission
from pampipe.planning import family
from pampipe.planning.confidence import sampling_problem
from pampipe.planning.evaluator import Evaluator
from pampipe.planning.law import settle
from pampipe.planning.problem import build_elements, mission_muscles
from pampipe.planning.quantiles import order_statistics, upper_rank
from pampipe.planning.sampling import Deviations, by_families, class_deviations, muscle_draws
from tests.support.problems import PROBLEMS

UNCERTAIN = PROBLEMS / "missions" / "riser-uncertain-friction.yaml"
BORES = ("3 in", "{value: 3.5 in, sd: 0.4 mm}", "{nps: 3, schedule: 40, tolerance: 1 %}")
N = 3000


def _evaluator(tmp_path, step_deg: float) -> Evaluator:
    """The riser robot (fit covariance) on 90 sections of 3 bores (an sd, a tolerance) and 2 frictions with
    an sd, each its own incline, ``step_deg`` apart."""
    head = UNCERTAIN.read_text().split("route:")[0].replace("../pams", str(PROBLEMS / "pams"))
    lines = [f"  - {{name: s{i}, length: 2 m, inner_diameter: {BORES[i % 3]}, "
             f"incline: {i * step_deg - 85:.6f} deg, "
             f"friction: {{value: {0.25 + 0.05 * (i % 2):g}, sd: 0.03}}}}" for i in range(90)]
    path = tmp_path / "route.yaml"
    path.write_text(head + "route:\n" + "\n".join(lines) + "\n")
    mission = load_mission(path)
    muscles = mission_muscles(mission)
    elements = build_elements(mission, muscles)
    problem, classes, _ = sampling_problem(mission, muscles, elements, 0.95, samples=N, seed=7)
    assert set(problem.active) == {"moduli", "bore", "friction"}
    drawn = cache(partial(class_deviations, problem, classes))
    return Evaluator(problem, muscle_draws(problem), classes, 0, np.arange(len(classes)),
                     Deviations(drawn, 0, slice(None)), Deviations(drawn, 1, slice(None)))


CASES = [("all", [upper_rank(N, 0.95), 2730, 2969, upper_rank(N, 0.9), upper_rank(N, 0.99)], True),
         ("moduli", [upper_rank(N, 0.95), upper_rank(N, 0.05)], False),
         ("bore", [upper_rank(N, 0.95), upper_rank(N, 0.05)], False),
         ("friction", [upper_rank(N, 0.95), upper_rank(N, 0.05)], False)]


def _compare(ev: Evaluator, name: str, ranks: list[int], share: bool) -> None:
    sources = ev.problem.active if name == "all" else (name,)
    expected = order_statistics(ev.evaluate(sources, raw=True)[0], ranks, share=share, settle=settle)
    got = by_families(ev, sources, ranks, share)
    assert got is not None
    if share:
        np.testing.assert_array_equal(got[0], expected[0])
        np.testing.assert_array_equal(got[1], expected[1])
    else:
        np.testing.assert_array_equal(got[0], expected)


@pytest.mark.parametrize("step_deg", [0.01, 1.9])
@pytest.mark.parametrize(("name", "ranks", "share"), CASES)
def test_the_candidates_statistics_are_the_whole_rows(tmp_path, monkeypatch, step_deg, name, ranks, share):
    ev = _evaluator(tmp_path, step_deg)
    whole = []
    plain = family.whole
    monkeypatch.setattr(family, "whole",
                        lambda f, members, *a: whole.append(members.size) or plain(f, members, *a))
    _compare(ev, name, ranks, share)
    if step_deg < 1 and name in ("all", "friction"):  # close neighbours: most classes from the candidates
        assert sum(whole) < len(ev.mu) / 4
    if step_deg > 1 and name == "all":  # far apart: the bound sends classes to their whole rows
        assert sum(whole) > 0


def test_without_the_bound_far_classes_come_out_wrong(tmp_path, monkeypatch):
    ev = _evaluator(tmp_path, 1.9)
    _, ranks, share = CASES[1]  # friction alone is convex in μ (pampipe.planning.convex): no bound
    monkeypatch.setattr(family, "MARGIN", 0)  # the candidates: the reference's own tails, no more
    monkeypatch.setattr(family, "MARGIN_SHARE", 0.0)
    _compare(ev, "moduli", ranks, share)
    monkeypatch.setattr(family, "_bound", lambda e, members, reference: (np.full(members.size, 1e300),
                                                                         np.full(members.size, -1e300)))
    with pytest.raises(AssertionError):
        _compare(ev, "moduli", ranks, share)


def test_the_share_counts_the_ties_of_the_settled_values():
    """``exact``'s share of values ≤ the first statistic, against counting on the settled whole row: a
    first raw value below 0 (settles to 0 with every value ≤ 0 above it, −0 too), inside (0, 100 MPa] with
    exact ties, beyond 100 MPa and NaN (settle to inf with every value above them)."""
    rows = np.array([[-5.0, -3.0, -1.0, 0.0, -0.0, 2.0, -2.0, 7.0],
                     [1e5, 3e5, 2e5, 3e5, 3e5, 4e5, 1e5, 5e5],
                     [1e5, 2e8, 3e8, 1.5e8, np.nan, 2e8, 1e5, 4e8],
                     [1.0, np.nan, 2.0, np.nan, np.nan, np.nan, 4.0, 5.0]])
    first = 4  # the 5th value
    part = rows.copy()
    part.partition(first, axis=1)
    stats, share = family.exact(part[:, [first]].T, part, first, 0, rows.shape[1], True)
    settled = settle(rows)
    expected = settle(np.sort(rows, axis=1)[:, first])
    np.testing.assert_array_equal(stats[0], expected)
    np.testing.assert_array_equal(share, np.count_nonzero(settled <= expected[:, None], axis=1) / 8)
    np.testing.assert_array_equal(share, [6 / 8, 6 / 8, 1.0, 1.0])


def test_the_drawn_friction_and_its_order_are_kept_once_per_statement():
    """μ(d) = μ̂ + sd·ξ(d) of the statement's keyed stream, its stable order by μ, read-only, and the same
    arrays for the same statement (every chunk's families of it share one draw and one sort)."""
    mu, order = family.drawn_friction(7, 0.3, 0.05, 500)
    np.testing.assert_array_equal(mu, 0.3 + family.keyed_normal(7, "friction", (0.3, 0.05), 500) * 0.05)
    np.testing.assert_array_equal(order, np.lexsort((np.arange(500), mu)))
    assert not (mu.flags.writeable or order.flags.writeable)
    assert family.drawn_friction(7, 0.3, 0.05, 500)[1] is order
