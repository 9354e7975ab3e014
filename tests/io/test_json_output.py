"""The JSON writer (pampipe.io.files.to_json, json_chunks): 12-digit floats, zeroed wall times, NaN refused
with its key path. The fast cleaner is compared with the plain definition, written out here."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from pampipe.errors import SolverError
from pampipe.io.files import Streamed, json_chunks, to_json


def _plain(value, timings):
    """The definition: every float as float(f"{x:.12g}"), dict keys as text, tuples as lists, numpy scalars
    as Python numbers, ``*wall_time_s`` as 0 without timings."""
    if isinstance(value, bool | str) or value is None:
        return value
    if isinstance(value, int) and not isinstance(value, np.integer):
        return value
    if isinstance(value, float | np.floating):
        assert math.isfinite(value)
        return float(f"{float(value):.12g}")
    if isinstance(value, np.integer | np.bool_):
        return value.item()
    if isinstance(value, dict):
        return {str(k): 0.0 if not timings and str(k).endswith("wall_time_s") else _plain(v, timings)
                for k, v in value.items()}
    return [_plain(v, timings) for v in value]


def _document(rng, depth=0):
    """A random nested document of the kinds a result holds."""
    kinds = ["float", "tiny", "huge", "int", "str", "none", "bool", "npfloat", "npint", "zero"]
    kinds += ["dict", "list", "tuple"] if depth < 3 else []
    kind = kinds[rng.integers(len(kinds))]
    if kind == "dict":
        keys = ["a", "b", "wall_time_s", "build_wall_time_s", "cycle_time_s", 3]
        return {keys[i]: _document(rng, depth + 1) for i in rng.permutation(len(keys))[:rng.integers(1, 6)]}
    if kind in ("list", "tuple"):
        items = [_document(rng, depth + 1) for _ in range(rng.integers(0, 5))]
        return items if kind == "list" else tuple(items)
    return {"float": lambda: float(rng.normal() * 10.0 ** rng.integers(-8, 9)),
            "tiny": lambda: 5e-324 * float(rng.integers(1, 9)), "huge": lambda: 1.7976931348623157e308,
            "int": lambda: int(rng.integers(-10**6, 10**6)), "str": lambda: "s\u00e9\"x",
            "none": lambda: None, "bool": lambda: bool(rng.integers(2)),
            "npfloat": lambda: np.float64(rng.normal()), "npint": lambda: np.int64(rng.integers(100)),
            "zero": lambda: -0.0 if rng.integers(2) else 0.0}[kind]()


@pytest.mark.parametrize("timings", [True, False])
def test_to_json_equals_the_plain_definition(timings):
    rng = np.random.default_rng(39)
    for _ in range(300):
        document = {"d": _document(rng), "wall_time_s": 1.25, "x": 1 / 3}
        expected = json.dumps(_plain(document, timings), sort_keys=True, allow_nan=False) + "\n"
        assert to_json(document, timings=timings, indent=None) == expected
        assert to_json(document, timings=timings) == json.dumps(_plain(document, timings), sort_keys=True,
                                                                indent=2, allow_nan=False) + "\n"


def test_rounding_is_to_twelve_significant_digits():
    assert to_json({"x": 0.1 + 0.2, "y": -0.0, "z": 123456789012345.0}, indent=None) == \
        '{"x": 0.3, "y": -0.0, "z": 123456789012000.0}\n'


@pytest.mark.parametrize("bad", [math.nan, math.inf, -math.inf, np.float64("nan")])
def test_a_non_finite_number_is_refused_with_its_path(bad):
    document = {"a": [1.0, {"b": 2.0, "c": (3.0, bad)}]}
    with pytest.raises(SolverError, match=r"result\.a\[1\]\.c\[1\] came out as"):
        to_json(document)
    with pytest.raises(SolverError, match=r"result\.s\[2\]\.a\[1\]\.c\[1\] came out as"):
        "".join(json_chunks({"s": Streamed([{}, {}, document])}))


def test_a_non_finite_wall_time_is_written_as_zero_without_timings():
    assert to_json({"wall_time_s": math.nan}, timings=False, indent=None) == '{"wall_time_s": 0.0}\n'
    with pytest.raises(SolverError, match=r"result\.wall_time_s came out as nan"):
        to_json({"wall_time_s": math.nan})


def test_streamed_chunks_are_the_bytes_of_the_whole_document():
    rng = np.random.default_rng(7)
    items = [_document(rng) for _ in range(2500)]
    document = {"b": 1.0 / 7, "items": Streamed(iter(items)), "z": [np.float64(2) / 3]}
    assert "".join(json_chunks(document, timings=False)) == to_json({**document, "items": items},
                                                                     timings=False, indent=None)
