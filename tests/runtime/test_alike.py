"""Rows grouped by their bits (pampipe.runtime.alike, issue 39): against grouping by Python tuples."""

from __future__ import annotations

import numpy as np
import pytest

from pampipe.runtime import alike
from pampipe.runtime.alike import distinct_rows, grouped_rows, per_distinct, unique_rows


def _grouped(columns) -> tuple[list[int], list[int]]:
    """(first places, index) by Python: rows as tuples of their floats' bits, in order of first place."""
    rows = [tuple(np.float64(v).tobytes() for v in row) for row in zip(*columns, strict=True)]
    first: dict[tuple, int] = {}
    for place, row in enumerate(rows):
        first.setdefault(row, place)
    order = sorted(first.values())
    rank = {rows[p]: k for k, p in enumerate(order)}
    return order, [rank[row] for row in rows]


def _columns(rng, count: int = 600) -> list[np.ndarray]:
    values = np.array([0.0, -0.0, 1.0, 0.1 + 0.2, 0.3, np.nan, 1e-300])
    return [values[rng.integers(0, values.size, count)] for _ in range(3)]


@pytest.mark.parametrize("collide", [False, True])
def test_rows_are_grouped_by_their_bits(collide, monkeypatch):
    """0.0 and -0.0 are different rows, 0.1 + 0.2 and 0.3 too, a NaN matches itself; with every row
    hashed alike (collide) the bytes decide, with the same answer."""
    if collide:
        monkeypatch.setattr(alike, "_mixed", lambda key: key * np.uint64(0))
    columns = _columns(np.random.default_rng(3))
    first, index = distinct_rows(columns)
    expected_first, expected_index = _grouped(columns)
    assert first.tolist() == expected_first and index.tolist() == expected_index
    for column in columns:
        assert np.array_equal(column[first][index], column, equal_nan=True)


def test_short_or_unrepeated_tables_are_not_grouped():
    rng = np.random.default_rng(4)
    assert distinct_rows(_columns(rng, alike.LEAST - 1)) is None
    assert distinct_rows([rng.random(1000), np.zeros(1000)]) is None  # no row repeats


def test_per_distinct_evaluates_each_distinct_row_once():
    columns = _columns(np.random.default_rng(5))
    seen = []

    def function(a, b, c):
        seen.append(a.size)
        return a * b - c, np.sqrt(np.abs(a + c))

    with np.errstate(invalid="ignore"):
        got, direct = per_distinct(function, *columns), function(*columns)
    assert seen == [len(distinct_rows(columns)[0]), columns[0].size]
    for a, b in zip(got, direct, strict=True):
        assert np.array_equal(a, b, equal_nan=True)


def test_grouped_rows_of_no_columns_or_rows():
    first, index = grouped_rows(np.zeros((3, 0), dtype=np.int64))
    assert first.tolist() == [0] and index.tolist() == [0, 0, 0]
    first, index = grouped_rows(np.zeros((0, 2), dtype=np.int64))
    assert first.size == 0 and index.size == 0


@pytest.mark.parametrize("nan", [False, True])
def test_unique_rows_are_numpys(nan):
    """The rows, first places and index of np.unique(axis=0): repeated rows, 0.0 and −0.0 (alike), ties in
    the first columns broken by the later ones; with a NaN (never alike), np.unique's own answer."""
    rng = np.random.default_rng(3)
    table = rng.choice([-1.5, -0.0, 0.0, 2.0, 7.25], size=(400, 4))
    if nan:
        table[[5, 9], 2] = np.nan
    rows, first, index = unique_rows(table)
    expected = np.unique(table, axis=0, return_index=True, return_inverse=True)
    assert np.array_equal(rows, expected[0], equal_nan=True)
    assert first.tolist() == expected[1].tolist() and index.tolist() == expected[2].ravel().tolist()
    assert np.array_equal(rows[index], table, equal_nan=True) and rows.shape[0] < 400
