"""A tree of pampipe's frozen dataclasses as JSON, field by field: data that cannot run code when read.

The cache of validated files (:mod:`pampipe.io.validated`) keeps what a mission or experiment file loaded to
in this format instead of a pickle, which would run whatever a planted or damaged entry asks for. A tree
holds only: None, bool, int, float, str, lists, tuples, dicts, :class:`~pathlib.Path`, numpy arrays and
scalars of numbers, booleans or text, and dataclasses of pampipe's own modules. :func:`encode` refuses
anything else (the file is then not kept); :func:`decode` builds the dataclasses without calling their
``__init__`` or ``__post_init__`` (as pickle does), imports nothing but pampipe's modules and refuses any
node it does not know, so the worst a forged entry can do is describe a wrong tree (which the cache's
hashes and ownership checks keep out, :mod:`pampipe.runtime.cache`).

An object met twice (a PAM shared by two segments) is written once and referred to after, so the tree
read back shares it the same way (``id``-keyed memos give the same results as on the tree that was
kept). Floats keep every bit (``repr`` round-trips; NaN and infinities are tagged), arrays are their
raw bytes in base64 with their dtype and shape.
"""

from __future__ import annotations

import base64
import dataclasses
import importlib
import json
import math
from functools import cache
from pathlib import Path

import numpy as np

#: dtype kinds an array or numpy scalar may have: booleans, integers, floats, complex numbers, text.
_KINDS = frozenset("biufcU")


class TreeError(ValueError):
    """A value the format does not hold (encode) or a document that is not a tree of it (decode)."""


def encode(tree) -> bytes:
    """``tree`` as UTF-8 JSON; :class:`TreeError` where it holds a value the format does not."""
    return json.dumps(to_json(tree), separators=(",", ":"), allow_nan=False).encode()


def decode(data: bytes):
    """The tree :func:`encode` wrote as ``data``; :class:`TreeError` for anything else."""
    try:
        document = json.loads(data)
    except (ValueError, RecursionError) as exc:
        raise TreeError(f"not JSON: {exc}") from None
    return from_json(document)


def to_json(tree):
    """``tree`` as a JSON value (dicts, lists, numbers, text); :class:`TreeError` as :func:`encode`."""
    return _Encoder().node(tree)


def from_json(document):
    """The tree of the JSON value ``document`` (:func:`to_json`'s); :class:`TreeError` for anything else."""
    try:
        return _Decoder().node(document)
    except TreeError:
        raise
    except (KeyError, TypeError, ValueError, AttributeError, IndexError, RecursionError) as exc:
        raise TreeError(f"not a tree: {type(exc).__name__}: {exc}") from None


class _Encoder:
    def __init__(self):
        self.seen: dict[int, int] = {}  # id(object) → its number, in the order first met
        self.alive: list = []  # keeps every numbered object alive, so that no id is reused meanwhile

    def node(self, value):
        kind = type(value)
        if value is None or kind in (bool, int, str):
            return value
        if kind is float:
            return value if math.isfinite(value) else {"x": repr(value)}
        if isinstance(value, np.generic):
            return {"n": _dtype(value.dtype), "v": _b64(np.asarray(value).tobytes())}
        if isinstance(value, Path):
            return {"p": str(value)}
        number = self.seen.get(id(value))
        if number is not None:
            return {"r": number}
        self.seen[id(value)] = len(self.seen)
        self.alive.append(value)
        if kind is list:
            return {"l": [self.node(v) for v in value]}
        if kind is tuple:
            return {"t": [self.node(v) for v in value]}
        if kind is dict:
            return {"d": [[self.node(k), self.node(v)] for k, v in value.items()]}
        if kind is np.ndarray:
            return {"a": _b64(np.ascontiguousarray(value).tobytes()), "dtype": _dtype(value.dtype),
                    "shape": list(value.shape), "fortran": bool(value.flags.f_contiguous and value.ndim > 1
                                                               and not value.flags.c_contiguous)}
        if dataclasses.is_dataclass(value) and not isinstance(value, type):
            return self.dataclass(value)
        raise TreeError(f"a {kind.__module__}.{kind.__qualname__} is not kept")

    def dataclass(self, value):
        kind = type(value)
        _class(kind.__module__, kind.__qualname__)  # one of pampipe's, importable by name
        names = _names(kind)
        extra = set(getattr(value, "__dict__", {})) - set(names)
        if extra:  # state beyond the fields (a cached property) would be lost
            raise TreeError(f"{kind.__qualname__} holds {sorted(extra)} beyond its fields")
        return {"c": f"{kind.__module__}:{kind.__qualname__}",
                "f": {name: self.node(getattr(value, name)) for name in names}}


class _Decoder:
    def __init__(self):
        self.made: list = []  # the numbered objects, in the order the encoder met them

    def node(self, value):
        if value is None or type(value) in (bool, int, float, str):
            return value
        if type(value) is not dict or len(value) == 0:
            raise TreeError(f"unexpected {type(value).__name__}")
        if "x" in value:
            number = float(value["x"])
            if math.isfinite(number):
                raise TreeError("a tagged float must be NaN or infinite")
            return number
        if "n" in value:
            return np.frombuffer(_unb64(value["v"]), dtype=_known_dtype(value["n"]), count=1)[0]
        if "p" in value:
            return Path(_text(value["p"]))
        if "r" in value:
            made = self.made[value["r"]]
            if made is _PENDING:
                raise TreeError("a reference into an unfinished tuple")
            return made
        number = len(self.made)
        self.made.append(_PENDING)
        if "l" in value:
            self.made[number] = out = []
            out.extend(self.node(v) for v in _list(value["l"]))
        elif "t" in value:
            self.made[number] = out = tuple(self.node(v) for v in _list(value["t"]))
        elif "d" in value:
            self.made[number] = out = {}
            for pair in _list(value["d"]):
                key, item = _list(pair)
                out[self.node(key)] = self.node(item)
        elif "a" in value:
            self.made[number] = out = self.array(value)
        elif "c" in value:
            out = self.dataclass(value, number)
        else:
            raise TreeError(f"unknown node {sorted(value)}")
        return out

    def array(self, value) -> np.ndarray:
        dtype = _known_dtype(value["dtype"])
        shape = tuple(int(n) for n in _list(value["shape"]))
        out = np.frombuffer(_unb64(value["a"]), dtype=dtype).reshape(shape).copy()
        return np.asfortranarray(out) if value["fortran"] is True else out

    def dataclass(self, value, number):
        module, _, name = _text(value["c"]).partition(":")
        kind = _class(module, name)
        out = object.__new__(kind)  # as pickle: no __init__, no __post_init__
        self.made[number] = out
        given = value["f"]
        names = _names(kind)
        if type(given) is not dict or given.keys() != set(names):
            raise TreeError(f"the fields of {name} are not {names}")
        for field_name in names:
            object.__setattr__(out, field_name, self.node(given[field_name]))
        return out


_PENDING = object()


@cache
def _names(kind: type) -> tuple[str, ...]:
    """The field names of the dataclass ``kind``, in order."""
    return tuple(f.name for f in dataclasses.fields(kind))


@cache
def _class(module: str, name: str) -> type:
    """The dataclass ``name`` of pampipe's module ``module``: nothing else is ever imported or built."""
    if not module.startswith("pampipe.") or "__main__" in module or not name.isidentifier():
        raise TreeError(f"{module}:{name} is not one of pampipe's dataclasses")
    try:
        kind = getattr(importlib.import_module(module), name)
    except (ImportError, AttributeError):
        raise TreeError(f"{module}:{name} is not one of pampipe's dataclasses") from None
    if not (isinstance(kind, type) and dataclasses.is_dataclass(kind)):
        raise TreeError(f"{module}:{name} is not a dataclass")
    return kind


def _dtype(dtype: np.dtype) -> str:
    if dtype.kind not in _KINDS or dtype.fields is not None or dtype.subdtype is not None:
        raise TreeError(f"an array of {dtype} is not kept")
    return dtype.str


def _known_dtype(text) -> np.dtype:
    dtype = np.dtype(_text(text))
    _dtype(dtype)
    return dtype


def _b64(data: bytes) -> str:
    return base64.b64encode(data).decode("ascii")


def _unb64(text) -> bytes:
    return base64.b64decode(_text(text), validate=True)


def _text(value) -> str:
    if type(value) is not str:
        raise TreeError(f"expected text, got {type(value).__name__}")
    return value


def _list(value) -> list:
    if type(value) is not list:
        raise TreeError(f"expected a list, got {type(value).__name__}")
    return value
