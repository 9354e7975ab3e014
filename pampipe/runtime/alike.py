"""Element-wise work done once per distinct row of a long table (issue 39).

A long route repeats its sections: the 10⁵ sections of ``benchmarks/bench_big_mission.py`` hold 1,260
distinct ones, and a network's pipes share a few bores and frictions. A function that maps each row of its
input columns to its outputs by that row alone (every numpy step element by element) gives an alike row the
same floats, so it is evaluated on the distinct rows and its outputs are taken back to every place.

Two rows are alike when each of their values is the same float, bit for bit (``0.0`` and ``-0.0`` differ;
a NaN matches only the same NaN). The rows are grouped by a 64-bit hash of their bits, sorted; a hash
shared by unlike rows is found by comparing every row with its group's first, and the grouping then falls
back to sorting the rows' bytes.
"""

from __future__ import annotations

import numpy as np

#: Tables with fewer rows are evaluated row by row (the grouping would cost more than it saves).
LEAST = 256
#: The odd multipliers of the rows' hash (splitmix64's finaliser, which spreads every input bit over the
#: output: a float's bits are mostly in its top 12, which a plain multiplication would keep there).
_MIX = (np.uint64(0xBF58476D1CE4E5B9), np.uint64(0x94D049BB133111EB))


def _mixed(key: np.ndarray) -> np.ndarray:
    """splitmix64's finaliser of each uint64 of ``key`` (``key`` is overwritten)."""
    key ^= key >> np.uint64(30)
    key *= _MIX[0]
    key ^= key >> np.uint64(27)
    key *= _MIX[1]
    key ^= key >> np.uint64(31)
    return key


def distinct_rows(columns) -> tuple[np.ndarray, np.ndarray] | None:
    """(first, index) of the rows of ``columns`` (1-D arrays of one length n, as floats) by
    :func:`grouped_columns`; None where n < :data:`LEAST` or fewer than half the rows repeat another."""
    floats = [np.ascontiguousarray(c, dtype=float) for c in columns]
    if floats[0].size < LEAST:
        return None
    first, index = grouped_columns([c.view(np.uint64) for c in floats])
    return None if 2 * first.size > floats[0].size else (first, index)


def grouped_rows(bits: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(first, index) of the rows of the 2-D array ``bits`` of 8-byte numbers, grouped by their bits:
    ``first`` the place of each distinct row's first occurrence (ascending), ``index`` the distinct row at
    each place, so that ``bits[first][index]`` is ``bits``."""
    bits = np.ascontiguousarray(bits).view(np.uint64)
    if bits.shape[1] == 0 or bits.shape[0] == 0:
        return np.zeros(min(bits.shape[0], 1), dtype=np.intp), np.zeros(bits.shape[0], dtype=np.intp)
    return grouped_columns([bits[:, k] for k in range(bits.shape[1])])


def grouped_columns(columns: list[np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    """:func:`grouped_rows` of the table whose columns are ``columns`` (at least one; 1-D arrays of 8-byte
    numbers, of one length), without building the table unless two unlike rows share their hash."""
    key = _mixed(columns[0].view(np.uint64).copy())
    for column in columns[1:]:
        key ^= column.view(np.uint64)
        key = _mixed(key)
    _, first, inverse = np.unique(key, return_index=True, return_inverse=True)
    inverse = inverse.ravel()
    place = first[inverse]
    if not all(np.array_equal(column, column[place]) for column in columns):  # group by the rows' bytes
        table = np.stack([c.view(np.uint64) for c in columns], axis=1)
        rows = table.view(np.dtype((np.void, table.itemsize * table.shape[1]))).ravel()
        _, first, inverse = np.unique(rows, return_index=True, return_inverse=True)
        inverse = inverse.ravel()
    order = np.argsort(first)  # the distinct rows in the order they first appear
    rank = np.empty_like(order)
    rank[order] = np.arange(order.size)
    return first[order], rank[inverse]


def unique_rows(table: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(the distinct rows sorted lexicographically, the place of each one's first occurrence, the distinct
    row at each place) of the 2-D float ``table``: ``np.unique(table, axis=0, return_index=True,
    return_inverse=True)``, by one ``np.lexsort`` of the columns (10× faster than np.unique's sort of the
    rows as records at 10⁵ rows). Rows are alike when every value compares equal (0.0 and −0.0 do; a NaN
    matches nothing), as in np.unique; a table with a NaN is left to np.unique."""
    table = np.asarray(table, dtype=float)
    if table.shape[0] == 0 or table.shape[1] == 0 or np.isnan(table).any():
        rows, first, inverse = np.unique(table, axis=0, return_index=True, return_inverse=True)
        return rows, first, np.asarray(inverse).reshape(-1)
    order = np.lexsort(table.T[::-1])  # stable: the first of alike rows comes first
    ordered = table[order]
    new = np.ones(order.size, dtype=bool)
    new[1:] = (ordered[1:] != ordered[:-1]).any(axis=1)
    inverse = np.empty(order.size, dtype=np.intp)
    inverse[order] = np.cumsum(new) - 1
    return ordered[new], order[new], inverse


class Picked:
    """A column of a few values, one per row picked by ``index``: ``values[index[row]]`` (the column-wise
    JSON writer groups such rows by ``index``, without looking at each row's value)."""

    __slots__ = ("index", "values")

    def __init__(self, values, index: np.ndarray) -> None:
        self.values, self.index = tuple(values), np.asarray(index, dtype=np.intp)


def per_distinct(function, *columns):
    """``function(*columns)`` (a tuple of arrays, or one array, of the columns' length), evaluated once per
    distinct row of ``columns`` (:func:`distinct_rows`) where the rows repeat; ``function`` must map each
    row to its outputs by that row alone."""
    alike = distinct_rows(columns)
    return function(*columns) if alike is None else taken_back(function, columns, *alike)


def taken_back(function, columns, first: np.ndarray, index: np.ndarray):
    """``function`` of the rows ``first`` of ``columns``, its outputs (a tuple of arrays, or one array) taken
    back to every row by ``index`` (:func:`grouped_rows`)."""
    out = function(*(np.asarray(c)[first] for c in columns))
    return tuple(o[index] for o in out) if isinstance(out, tuple) else out[index]
