"""Validated input files kept on disk, so that a file read before loads without the schema library.

Validating a mission or experiment file costs importing pydantic and building its schemas, more than
``pampipe plan`` spends on the plan itself and a tenth of a small ``pampipe identify``. Once a file has
loaded, what it loaded to (a :class:`~pampipe.specs.mission.Mission`; an experiment and its ``fit:`` options)
is kept in the user's cache (:mod:`pampipe.runtime.cache`) as data, never as a pickle: a JSON tree of its
dataclasses' fields (:mod:`pampipe.io.datatree`, which builds nothing but pampipe's dataclasses, numbers,
text and arrays), in an entry named by the hash of the kind of load, the working folder, the path as given,
the file's bytes, the package's source files (names, sizes, times) and the Python version.

The entry names and hashes every file the validation read (the file itself, its PAM files, a network file;
not an experiment's CSV data, which every run reads anyway) and is used only while each of them is
unchanged and the file itself is among them; else the file is validated again and the entry replaced. The
cache checks the entry's owner, permissions, key and SHA-256 before it is parsed. A file that fails
validation is never kept, so an error is always explained by the schema. An unreadable, damaged, untrusted
or unwritable cache is skipped: the file is then validated. Files over :data:`LARGEST_KEPT` bytes, and files
that load to values the tree does not hold, are not kept.
"""

from __future__ import annotations

import hashlib
import json
import os
import sys
from collections.abc import Iterable
from pathlib import Path

from pampipe.io.datatree import from_json, to_json
from pampipe.runtime.cache import cache_root, load, source_stamp, store

#: The entry's file: {"inputs": [[path, sha256], ...], "loaded": the tree}.
LOADED = "loaded.json"
#: Files larger than this [bytes] are not kept: their parse and use, not start-up, set their time, and
#: their entries would fill the cache.
LARGEST_KEPT = 1_000_000


def _file_digest(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def _key(kind: str, path: Path, digest: str) -> str:
    """The SHA-256 of what the entry of ``path`` (read from the current folder as ``kind``, bytes of
    SHA-256 ``digest``) stands for."""
    key = "\0".join(["datatree-1", kind, os.getcwd(), str(path), digest, source_stamp(), sys.version])
    return hashlib.sha256(key.encode()).hexdigest()


def cached(kind: str, path: Path):
    """What ``path`` loaded to as ``kind`` (``mission``, ``experiment``), kept while every file its
    validation read, ``path`` included, is unchanged; else None."""
    root = cache_root()
    if root is None:
        return None
    try:
        if path.stat().st_size > LARGEST_KEPT:
            return None
        digest = _file_digest(path)
        files = load(root, kind, _key(kind, path, digest))
        if files is None:
            return None
        kept = json.loads(files[LOADED])
        inputs = [(name, sha) for name, sha in kept["inputs"]]
        if (str(path), digest) not in inputs:  # an entry must stand for the file itself
            return None
        if all(_file_digest(Path(name)) == sha for name, sha in inputs):
            return from_json(kept["loaded"])
    except Exception:  # missing, damaged, or a file it read is gone: validate again
        pass
    return None


def keep(kind: str, path: Path, loaded, read: Iterable[Path]) -> None:
    """Keep ``loaded`` (just validated from ``path`` as ``kind``) with the hashes of the files ``read``
    and of ``path`` itself."""
    root = cache_root()
    if root is None:
        return
    try:
        if path.stat().st_size > LARGEST_KEPT:
            return
        digest = _file_digest(path)
        names = dict.fromkeys([str(path), *(str(name) for name in read)])
        inputs = [[name, digest if name == str(path) else _file_digest(Path(name))] for name in names]
        data = json.dumps({"inputs": inputs, "loaded": to_json(loaded)}, separators=(",", ":"),
                          allow_nan=False).encode()
    except Exception:  # a value the tree does not hold, a file gone: caching is an optimisation
        return
    store(root, kind, _key(kind, path, digest), {LOADED: data})
