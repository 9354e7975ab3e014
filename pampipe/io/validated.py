"""Validated input files kept on disk, so that a file read before loads without the schema library.

Validating a mission or experiment file costs importing pydantic and building its schemas, more than
``pampipe plan`` spends on the plan itself and a tenth of a small ``pampipe identify``. Once a file has
loaded, what it loaded to (a :class:`~pampipe.specs.mission.Mission`; an experiment and its ``fit:`` options)
is
kept (pickled) in the user's cache (:mod:`pampipe.runtime.cache`), in an entry named by the kind of load, the
hash
of the working folder, the path as given, the file's bytes, the package's source files (names, sizes,
times) and the Python version. The entry records the hash of every file the validation read (the file
itself, its PAM files, a network file; not an experiment's CSV data, which every run reads anyway); it is
used only while each of those files is unchanged, else the file is validated again. A file that fails
validation is never kept, so an error is always explained by the schema. An unreadable, damaged or
unwritable cache is skipped: the file is then validated. Files over :data:`LARGEST_KEPT` bytes are not kept.
"""

from __future__ import annotations

import hashlib
import os
import pickle
import sys
from collections.abc import Iterable
from pathlib import Path

from pampipe.runtime.cache import cache_folder, source_stamp, store

PICKLE = "loaded.pickle"
#: Files larger than this [bytes] are not kept: their parse and use, not start-up, set their time, and
#: their entries would fill the cache.
LARGEST_KEPT = 1_000_000


def _file_digest(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def _entry(folder: Path, kind: str, path: Path) -> Path:
    """The entry of ``path`` (read from the current folder, loaded as ``kind``) under ``folder``."""
    key = "\0".join([kind, os.getcwd(), str(path), _file_digest(path), source_stamp(), sys.version])
    return folder / f"{kind}-{hashlib.sha256(key.encode()).hexdigest()[:32]}"


def cached(kind: str, path: Path):
    """What ``path`` loaded to as ``kind`` (``mission``, ``experiment``), kept while every file its
    validation read is unchanged; else None."""
    folder = cache_folder()
    if folder is None:
        return None
    try:
        if path.stat().st_size > LARGEST_KEPT:
            return None
        with open(_entry(folder, kind, path) / PICKLE, "rb") as handle:
            inputs, loaded = pickle.load(handle)
        if all(_file_digest(Path(name)) == digest for name, digest in inputs):
            return loaded
    except Exception:  # missing, damaged, or a file it read is gone: validate again
        pass
    return None


def keep(kind: str, path: Path, loaded, read: Iterable[Path]) -> None:
    """Keep ``loaded`` (just validated from ``path`` as ``kind``) with the hashes of the files ``read``."""
    folder = cache_folder()
    if folder is None:
        return
    try:
        if path.stat().st_size > LARGEST_KEPT:
            return
        inputs = [(str(name), _file_digest(Path(name))) for name in dict.fromkeys(read)]
        entry = _entry(folder, kind, path)
    except Exception:  # caching is an optimisation, never a failure
        return

    def write(staging: Path) -> None:
        with open(staging / PICKLE, "wb") as handle:
            pickle.dump((inputs, loaded), handle, protocol=pickle.HIGHEST_PROTOCOL)

    store(folder, entry, write, replace=True)  # replace: a file it read has changed
