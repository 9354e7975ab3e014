"""The column-wise JSON writer (pampipe.io.json_columns): the same bytes as the plain definition,
json.dumps of each record with every float as float(f"{x:.12g}") and sorted keys, written out here."""

from __future__ import annotations

import json

import numpy as np
import pytest

from pampipe.errors import SolverError
from pampipe.io import json_columns
from pampipe.io.files import JsonText, Streamed, json_chunks
from pampipe.io.json_columns import NotFinite, Texts, float_texts, rounded, streamed_records
from pampipe.io.streams import safe_text
from pampipe.runtime import alike
from pampipe.runtime.alike import Picked


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
    values = _hard_values()
    assert float_texts(values) == [json.dumps(_twelve(x)) for x in values.tolist()]
    for bad in (np.nan, np.inf, -np.inf):
        with pytest.raises(NotFinite):
            float_texts(np.array([1.0, bad]))


def _rows(column, start: int, stop: int):
    """Records ``start:stop`` of a column."""
    if isinstance(column, dict):
        return {key: _rows(value, start, stop) for key, value in column.items()}
    if isinstance(column, Picked):
        return Picked(column.values, column.index[start:stop])
    return type(column)(column[start:stop]) if isinstance(column, Texts) else column[start:stop]


def _written(fields: dict, count: int, chunk: int, nested: dict | None = None, documents=None) -> str:
    """The list's text as :func:`streamed_records` writes it, ``chunk`` records per pass."""
    nested = nested or {}

    def columns_of(start, stop):
        inner = {}
        for key, (columns, width, present) in nested.items():
            before, upto = int(present[:start].sum()) * width, int(present[:stop].sum()) * width
            inner[key] = (_rows(columns, before, upto), width, present[start:stop])
        return _rows(fields, start, stop), inner

    def documents_of(start, stop):
        return (documents(i) for i in range(start, stop))

    items = streamed_records(count, columns_of, documents_of, chunk=chunk, part=3)
    return "".join(json_chunks({"xs": Streamed(items)}))


def _listed(records: list[dict]) -> str:
    return json.dumps({"xs": records}, sort_keys=True) + "\n"


def _example(n: int):
    """(fields, nested, the records as dicts) of ``n`` records with every kind of column, a few of them
    distinct (their rows repeat every 6), and names all distinct."""
    rng = np.random.default_rng(3)
    floats = np.array([1e5 * rng.standard_normal() for _ in range(5)] + [0.1 + 0.2, 0.3, 0.0, -0.0])
    floats = floats[np.arange(n) % 9]
    pairs = rng.random((6, 2))[np.arange(n) % 6]
    flags = np.arange(n) % 4 == 0
    counts = np.arange(n) % 5 - 2
    words = [["PAM1", "naïve \"quote\"", None, "50%"][i % 4] for i in range(n)]
    mixed = [[1, None, 2.5, True, {"b": 0.1 + 0.2}][i % 5] for i in range(n)]
    names = [f"s{i}" if i % 7 else f"s{i} \x01é" for i in range(n)]
    picked = Picked(("contact", "no_slip"), np.arange(n) % 3 == 0)
    present = np.arange(n) % 4 != 3
    inner_n = int(present.sum()) * 2
    inner = {"p_Pa": np.arange(inner_n) % 3 * 0.5, "unit": Picked(("a", "b"), np.arange(inner_n) % 2)}
    fields = {"z_float": floats, "a_pair": pairs, "m_flag": flags, "c_count": counts, "w%d": words,
              "mixed": mixed, "nested": {"in_N": floats * 3, "out_N": floats / 7}, "name": names,
              "raw": Texts(f"[{i % 3}]" for i in range(n)), "binding": picked}
    records, k = [], 0
    for i in range(n):
        record = {"z_float": _twelve(floats[i]), "a_pair": [_twelve(x) for x in pairs[i]],
                  "m_flag": bool(flags[i]), "c_count": int(counts[i]), "w%d": words[i],
                  "mixed": {"b": _twelve(0.1 + 0.2)} if i % 5 == 4 else mixed[i], "name": names[i],
                  "nested": {"in_N": _twelve(floats[i] * 3), "out_N": _twelve(floats[i] / 7)},
                  "raw": [i % 3], "binding": "no_slip" if i % 3 == 0 else "contact", "segments": []}
        if present[i]:
            record["segments"] = [{"p_Pa": _twelve(j % 3 * 0.5), "unit": "ab"[j % 2]} for j in (k, k + 1)]
            k += 2
        records.append(record)
    return fields, {"segments": (inner, 2, present)}, records


@pytest.mark.parametrize("chunk", [1, 5, 40, 64])
def test_records_are_sorted_json_of_each_row(chunk):
    """Every kind of column, 0.0 and -0.0 and 0.1 + 0.2 and 0.3 apart, in passes of any size: the records
    met again in a later pass are the text written for them in the first."""
    fields, nested, records = _example(64)
    assert _written(fields, 64, chunk, nested) == _listed(records)


@pytest.mark.parametrize("kept", [0, 20])
def test_texts_forgotten_between_passes_are_written_again(kept, monkeypatch):
    """A writer that holds more than KEPT texts forgets them (records, nested ones, words) after a pass:
    the next passes write the same bytes."""
    monkeypatch.setattr(json_columns, "KEPT", kept)
    fields, nested, records = _example(64)
    assert _written(fields, 64, 7, nested) == _listed(records)


def test_names_are_written_into_each_record():
    """A column of distinct names (more than half the records) is left out of the grouping: plain ones
    between quotes, ones that need escaping escaped. The text is ASCII with nothing a terminal would obey
    (the CLI writes it without safe_text's scan)."""
    n = 23
    for names in ([f"s{i} 50%" for i in range(n)], [f"s{i} ü\n\"\x1b[2J\u202e\x7f" for i in range(n)]):
        fields = {"name": names, "x%": np.arange(n) % 3 * 0.1, "k": np.arange(n) % 2 == 0}
        want = [{"name": names[i], "x%": _twelve(i % 3 * 0.1), "k": i % 2 == 0} for i in range(n)]
        text = _written(fields, n, 10)
        assert text == _listed(want)
        assert text.isascii() and safe_text(text) == text


def test_records_whose_hashes_collide_are_told_apart(monkeypatch):
    monkeypatch.setattr(alike, "_mixed", lambda key: key * np.uint64(0))
    fields, nested, records = _example(30)
    assert _written(fields, 30, 12, nested) == _listed(records)


def test_no_columns_or_one_record():
    assert _written({}, 2, 2) == '{"xs": [{}, {}]}\n'
    assert _written({"name": ["only"]}, 1, 1) == '{"xs": [{"name": "only"}]}\n'


def test_a_nan_sends_its_pass_to_the_documents():
    """A NaN or infinity anywhere (a float, a list, a nested object, a plain value) makes its pass the
    documents' (whose writer then names the bad value); the other passes stay column-wise."""
    nan, inf = float("nan"), float("inf")
    cases = [(np.array([1.0, nan, 2.0, 3.0]), [2.0, 3.0]),
             (np.array([[1.0, 2.0], [3.0, inf], [0.0, 0.0], [1.0, 1.0]]), [[0.0, 0.0], [1.0, 1.0]]),
             ([1.0, nan, 2.0, 3.0], [2.0, 3.0]),
             ({"inner": np.array([0.0, -inf, 1.0, 2.0])}, [{"inner": 1.0}, {"inner": 2.0}])]
    for bad, kept in cases:
        text = _written({"key": bad, "i": np.arange(4)}, 4, 2, documents=lambda i: {"document": i})
        columns = ", ".join(json.dumps({"i": i, "key": v}, sort_keys=True)
                            for i, v in zip((2, 3), kept, strict=True))
        assert text == '{"xs": [{"document": 0}, {"document": 1}, ' + columns + "]}\n"


def test_a_bad_value_after_joined_items_is_named_at_its_place():
    joined = JsonText("1, 2, 3", 3)
    document = {"xs": Streamed(iter([joined, {"v": float("nan")}]))}
    with pytest.raises(SolverError, match=r"xs\[3\]"):
        "".join(json_chunks(document))
    written = "".join(json_chunks({"xs": Streamed(iter([joined, {"v": 1.5}]))}))
    assert written == '{"xs": [1, 2, 3, {"v": 1.5}]}\n'


def test_each_distinct_record_is_formatted_once(monkeypatch):
    """Alike records, in one pass or in later ones, are one text: each distinct value is rounded once."""
    seen = []
    monkeypatch.setattr(json_columns, "rounded", lambda values: seen.append(values.size) or rounded(values))
    n = 1000
    fields = {"x": np.arange(n) % 4 * 0.25, "name": [f"s{i}" for i in range(n)]}
    assert _written(fields, n, 100) == _listed([{"x": i % 4 * 0.25, "name": f"s{i}"} for i in range(n)])
    assert sum(seen) == 4
