"""Validated missions kept on disk, so that a mission read before starts without the schema library.

Validating a mission file costs importing pydantic and building its schemas, more than ``pampipe plan``
spends on the plan itself. Once a mission file has loaded, the :class:`~pampipe.mission.Mission` is kept
(pickled) in the user's cache (:mod:`pampipe.io.cache`), in an entry named by the hash of the working
folder, the path as given, the file's bytes, the package's source files (names, sizes, times) and the Python
version. The entry
records the hash of every file the mission read (:attr:`Mission.input_files`: itself, its PAM files,
its network file); it is used only while each of those files is unchanged, else the mission is
validated again. A file that fails validation is never kept, so an error is always explained by the
schema. An unreadable, damaged or unwritable cache is skipped: the mission is then validated. Mission files
over :data:`LARGEST_KEPT` bytes are not kept.
"""

from __future__ import annotations

import hashlib
import os
import pickle
import sys
from pathlib import Path

from pampipe.io.cache import cache_folder, source_stamp, store

PICKLE = "mission.pickle"
#: Mission files larger than this [bytes] are not kept: their parse and plan, not start-up, set their time,
#: and their entries would fill the cache.
LARGEST_KEPT = 1_000_000


def _file_digest(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def _entry(folder: Path, path: Path) -> Path:
    """The entry of ``path`` (read from the current folder) under ``folder``."""
    key = "\0".join([os.getcwd(), str(path), _file_digest(path), source_stamp(), sys.version])
    return folder / f"mission-{hashlib.sha256(key.encode()).hexdigest()[:32]}"


def cached_mission(path: Path):
    """The :class:`~pampipe.mission.Mission` kept for ``path`` while every file it read is unchanged;
    else None."""
    folder = cache_folder()
    if folder is None:
        return None
    try:
        if path.stat().st_size > LARGEST_KEPT:
            return None
        with open(_entry(folder, path) / PICKLE, "rb") as handle:
            inputs, mission = pickle.load(handle)
        if all(_file_digest(Path(name)) == digest for name, digest in inputs):
            return mission
    except Exception:  # missing, damaged, or a file it read is gone: validate again
        pass
    return None


def keep_mission(path: Path, mission) -> None:
    """Keep ``mission`` (just validated from ``path``) with the hashes of the files it read."""
    folder = cache_folder()
    if folder is None:
        return
    try:
        if path.stat().st_size > LARGEST_KEPT:
            return
        inputs = [(str(name), _file_digest(Path(name))) for name in dict.fromkeys(mission.input_files)]
        entry = _entry(folder, path)
    except Exception:  # caching is an optimisation, never a failure
        return

    def write(staging: Path) -> None:
        with open(staging / PICKLE, "wb") as handle:
            pickle.dump((inputs, mission), handle, protocol=pickle.HIGHEST_PROTOCOL)

    store(folder, entry, write, replace=True)  # replace: a file the mission read has changed
