"""The column-wise JSON writer (pampipe.io.json_columns): the same bytes as the plain definition,
json.dumps of each record with every float as float(f"{x:.12g}") and sorted keys, written out here."""

from __future__ import annotations

import json

import numpy as np
import pytest

from pampipe.errors import SolverError
from pampipe.io.files import JsonText, Streamed, json_chunks
from pampipe.io.json_columns import (
    NotFinite,
    Texts,
    float_texts,
    grouped,
    joined_records,
    record_texts,
    rounded,
)


def _twelve(x: float) -> float:
    return float(f"{x:.12g}")


def _hard_values() -> np.ndarray:
    """Values at the edges of the numpy rounding: halves of the 12th digit (both sides, one ulp off),
    powers of ten and their neighbours, a carry to 13 digits, the range limits and both zeros."""
    rng = np.random.default_rng(7)
    halves = [float(f"{m}5e{e}") for m in rng.integers(10**11, 10**12, 40) for e in (-30, -12, -3, 0, 5, 20)]
    near = [np.nextafter(h, s) for h in halves for s in (np.inf, -np.inf)]
    powers = [10.0**e for e in range(-320, 309, 7)] + [float(f"1e{e}") for e in range(-25, 25)]
    edges = [9.9999999999995, 9.99999999999949, 0.1 + 0.2, 2.0**-1074, 1.7976931348623157e308,
             123456789012.5, 1234567890123.5, 0.0, -0.0, 5e-324]
    values = np.array(halves + near + powers + edges, dtype=float)
    return np.concatenate([values, -values, rng.standard_normal(2000) * 10.0 ** rng.integers(-15, 15, 2000)])


def test_rounded_is_the_twelve_digit_text_parsed():
    values = _hard_values()
    got = rounded(values)
    want = np.array([_twelve(x) for x in values.tolist()])
    assert got.tolist() == want.tolist()
    assert (np.signbit(got) == np.signbit(want)).all()  # -0.0 stays -0.0


def test_float_texts_are_json_dumps_of_the_rounded_values_and_refuse_nan():
    values = np.concatenate([_hard_values(), _hard_values()[:50]])  # repeated values: formatted once each
    assert float_texts(values) == [json.dumps(_twelve(x)) for x in values.tolist()]
    for bad in (np.nan, np.inf, -np.inf):
        with pytest.raises(NotFinite):
            float_texts(np.array([1.0, bad]))


def test_records_are_sorted_json_of_each_row():
    rng = np.random.default_rng(3)
    n = 50
    floats = rng.standard_normal(n) * 1e5
    pairs = rng.random((n, 2))
    flags = rng.random(n) < 0.5
    counts = rng.integers(-5, 5, n)
    words = [["PAM1", "naïve \"quote\"", None, "50%"][i % 4] for i in range(n)]
    mixed = [[1, None, 2.5, True, {"b": 0.1 + 0.2}][i % 5] for i in range(n)]
    inner = {"in_N": floats * 3, "out_N": floats / 7}
    fields = {"z_float": floats, "a_pair": pairs, "m_flag": flags, "c_count": counts, "w%d": words,
              "mixed": mixed, "nested": inner, "raw": Texts(f"[{i}]" for i in range(n))}
    got = record_texts(fields, n)
    for i, text in enumerate(got):
        record = {"z_float": _twelve(floats[i]), "a_pair": [_twelve(x) for x in pairs[i]],
                  "m_flag": bool(flags[i]), "c_count": int(counts[i]), "w%d": words[i],
                  "mixed": {"b": _twelve(0.1 + 0.2)} if i % 5 == 4 else mixed[i],
                  "nested": {"in_N": _twelve(floats[i] * 3), "out_N": _twelve(floats[i] / 7)}, "raw": [i]}
        assert text == json.dumps(record, sort_keys=True)


def test_grouped_lists_present_rows_only():
    present = np.array([True, False, True])
    assert grouped(["1", "2", "3", "4"], 2, present) == ["[1, 2]", "[]", "[3, 4]"]
    assert record_texts({}, 2) == ["{}", "{}"]


def test_a_nan_in_any_column_is_refused():
    for column in (np.array([1.0, np.nan]), np.array([[1.0, 2.0], [np.inf, 0.0]]), [1.0, float("nan")],
                   {"inner": np.array([0.0, -np.inf])}):
        with pytest.raises(NotFinite):
            record_texts({"key": column}, 2)


def test_joined_records_are_the_records_in_parts_of_a_few():
    """A column of distinct names is written into each record after its combination of the others."""
    n = 23
    fields = {"name": [f"s{i} 50%" for i in range(n)], "x%": np.arange(n) % 3 * 0.1,
              "k": np.arange(n) % 2 == 0}
    texts = list(joined_records(fields, n, part=5))
    assert [t.items for t in texts] == [5, 5, 5, 5, 3]
    assert ", ".join(texts) == ", ".join(json.dumps({"name": f"s{i} 50%", "x%": _twelve(i % 3 * 0.1),
                                                     "k": i % 2 == 0}, sort_keys=True) for i in range(n))


def test_a_bad_value_after_joined_items_is_named_at_its_place():
    joined = JsonText("1, 2, 3")
    joined.items = 3
    document = {"xs": Streamed(iter([joined, {"v": float("nan")}]))}
    with pytest.raises(SolverError, match=r"xs\[3\]"):
        "".join(json_chunks(document))
    written = "".join(json_chunks({"xs": Streamed(iter([joined, {"v": 1.5}]))}))
    assert written == '{"xs": [1, 2, 3, {"v": 1.5}]}\n'
