"""The cache's data format (pampipe/io/datatree.py): what a file loaded to reads back the same, to the bit and
to the sharing of objects; nothing else is built, nothing outside pampipe's dataclasses is imported.
"""

from __future__ import annotations

import dataclasses
import json
import struct
from pathlib import Path

import numpy as np
import pytest

from pampipe.io import datatree
from pampipe.io.datatree import TreeError, decode, encode
from tests.support.problems import PROBLEMS


def _difference(a, b, where: str, pairs: dict[int, int]) -> str | None:
    """Where ``a`` and ``b`` differ (type, float bits, array dtype/bytes/order, fields, keys, or which
    containers are one object), else None."""
    if type(a) is not type(b):
        return f"{where}: {type(a).__name__} vs {type(b).__name__}"
    if isinstance(a, list | tuple | dict | np.ndarray) or dataclasses.is_dataclass(a):
        if id(a) in pairs or id(b) in pairs.values():
            return None if pairs.get(id(a)) == id(b) else f"{where}: shared differently"
        pairs[id(a)] = id(b)
    if isinstance(a, float):
        return None if struct.pack("<d", a) == struct.pack("<d", b) else f"{where}: {a!r} vs {b!r}"
    if isinstance(a, np.ndarray | np.generic):
        same = (a.dtype == b.dtype and a.shape == b.shape and a.tobytes() == b.tobytes()
                and np.asarray(a).flags.f_contiguous == np.asarray(b).flags.f_contiguous)
        return None if same else f"{where}: arrays differ"
    if dataclasses.is_dataclass(a):
        items = [(f.name, getattr(a, f.name), getattr(b, f.name)) for f in dataclasses.fields(a)]
    elif isinstance(a, list | tuple):
        if len(a) != len(b):
            return f"{where}: {len(a)} vs {len(b)} items"
        items = [(str(i), x, y) for i, (x, y) in enumerate(zip(a, b, strict=True))]
    elif isinstance(a, dict):
        if list(a) != list(b):
            return f"{where}: keys {list(a)} vs {list(b)}"
        items = [(repr(k), a[k], b[k]) for k in a]
    else:
        return None if a == b else f"{where}: {a!r} vs {b!r}"
    return next((d for name, x, y in items if (d := _difference(x, y, f"{where}.{name}", pairs))), None)


def _bundled():
    from pampipe.api import load_mission
    from pampipe.commands.identify import validated

    for path in sorted((PROBLEMS / "missions").glob("*.yaml")):
        yield path.name, lambda path=path: load_mission(path)
    for path in sorted((PROBLEMS / "experiments").glob("*.yaml")):
        yield path.name, lambda path=path: validated(path)


@pytest.mark.parametrize(("name", "load"), list(_bundled()), ids=[name for name, _ in _bundled()])
def test_every_bundled_file_reads_back_the_same(name, load, monkeypatch):
    monkeypatch.setenv("PAMPIPE_NLP_CACHE", "off")
    loaded = load()
    assert _difference(loaded, decode(encode(loaded)), name, {}) is None


def test_the_comparison_sees_a_changed_bit_and_lost_sharing():
    """The check above can fail: one ulp, and two equal arrays that were one object."""
    shared = np.arange(3.0)
    assert _difference([1.0, shared, shared], [np.nextafter(1.0, 2.0), shared, shared], "x", {})
    assert _difference([shared, shared], [shared, shared.copy()], "x", {})
    assert _difference([shared, shared], decode(encode([shared, shared])), "x", {}) is None


@dataclasses.dataclass(frozen=True)
class _NotPampipes:
    value: float


@pytest.mark.parametrize("value", [object(), {1, 2}, np.array([object()]), _NotPampipes(1.0), b"bytes",
                                   np.zeros(2, dtype=[("a", float)])],
                         ids=["object", "set", "object-array", "foreign-dataclass", "bytes", "record-array"])
def test_values_the_format_does_not_hold_are_refused(value):
    with pytest.raises(TreeError):
        encode(value)


@pytest.mark.parametrize("document", [
    {"c": "os:system", "f": {}},  # not pampipe's
    {"c": "builtins:eval", "f": {}},
    {"c": "pampipe.cli:main", "f": {}},  # pampipe's, not a dataclass
    {"c": "pampipe.__main__:x", "f": {}},  # never imported
    {"c": "pampipe.model.pam:Geometry", "f": {"extra": 1}},  # not its fields
    {"a": "AAAA", "dtype": "|O", "shape": [1], "fortran": False},  # objects
    {"a": "AAAA", "dtype": "<f8", "shape": [7], "fortran": False},  # 3 bytes for 7 floats
    {"r": 0}, {"x": "1.5"}, {"q": 1}, {}, [1, 2], {"l": {"not": "a list"}},
    {"d": [[[1], 2]]},  # an unhashable key
], ids=repr)
def test_documents_that_are_not_trees_are_refused(document):
    with pytest.raises(TreeError):
        datatree.from_json(document)


def test_decoding_runs_no_constructor(monkeypatch):
    """Dataclasses are built field by field, as pickle does: no __init__ or __post_init__ runs."""
    from pampipe.specs.mission import Section

    section = Section("a", 1.0, 0.08, 0.0, 0.3, 0.0)
    data = encode(section)

    def refuse(*args, **kwargs):
        raise AssertionError("a constructor ran")

    monkeypatch.setattr(Section, "__init__", refuse)
    monkeypatch.setattr(Section, "__post_init__", refuse)
    assert decode(data) == section


def test_non_finite_floats_and_paths_and_numpy_scalars_round_trip():
    tree = {"nan": float("nan"), "inf": -float("inf"), "path": Path("a/b.yaml"), "n": np.float32(0.1),
            ("t", 1): (True, None, 2**70, "ü")}
    back = decode(encode(tree))
    assert json.loads(encode(tree))  # plain JSON, no NaN literal
    assert _difference({k: v for k, v in tree.items() if k != "nan"},
                       {k: v for k, v in back.items() if k != "nan"}, "t", {}) is None
    assert np.isnan(back["nan"])
