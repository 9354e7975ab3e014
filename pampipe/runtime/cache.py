"""The user's on-disk cache of pampipe: its folder, its pruning and the hash of the package's source.

Built NLPs (:func:`pampipe.runtime.ipopt.cached_functions`) and validated missions and experiments
(:mod:`pampipe.io.validated`) are kept there as one folder per entry. Importing this module loads
neither CasADi nor pydantic.
"""

from __future__ import annotations

import hashlib
import os
import shutil
import tempfile
from collections.abc import Callable
from functools import cache
from pathlib import Path

#: Environment variable: the cache folder, or ``off`` to disable it.
CACHE_VARIABLE = "PAMPIPE_NLP_CACHE"
#: Entries kept in the cache folder (the oldest are removed beyond this).
CACHE_ENTRIES = 64


def cache_folder() -> Path | None:
    """Where entries are kept: $PAMPIPE_NLP_CACHE, else $XDG_CACHE_HOME/pampipe/nlp (default
    ~/.cache/pampipe/nlp); None when the variable is ``off``."""
    chosen = os.environ.get(CACHE_VARIABLE, "")
    if chosen.lower() in ("off", "0", "no", "false"):
        return None
    if chosen:
        return Path(chosen)
    base = os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache"
    return Path(base) / "pampipe" / "nlp"


def prune(folder: Path) -> None:
    """Remove all but the :data:`CACHE_ENTRIES` newest entries (folders not starting with '.')."""
    entries = sorted((p for p in folder.iterdir() if p.is_dir() and not p.name.startswith(".")),
                     key=lambda p: p.stat().st_mtime)
    for old in entries[:-CACHE_ENTRIES]:
        shutil.rmtree(old, ignore_errors=True)


@cache
def source_digest() -> str:
    """A hash of the package's source files (any edit invalidates every cached entry)."""
    root = Path(__file__).resolve().parent.parent
    digest = hashlib.sha256()
    for path in sorted(root.rglob("*.py")):
        digest.update(path.relative_to(root).as_posix().encode())
        digest.update(path.read_bytes())
    return digest.hexdigest()


@cache
def source_stamp() -> str:
    """A hash of the package's source files' names, sizes and modification times: as :func:`source_digest`
    for any edit (an edit changes a file's time), without reading the files (~1 ms instead of ~6 ms)."""
    root = Path(__file__).resolve().parent.parent
    digest = hashlib.sha256()
    for folder, _, names in sorted(os.walk(root)):
        for name in sorted(n for n in names if n.endswith(".py")):
            stat = os.stat(os.path.join(folder, name))
            where = f"{os.path.relpath(folder, root)}/{name}"
            digest.update(f"{where}\0{stat.st_size}\0{stat.st_mtime_ns}\0".encode())
    return digest.hexdigest()


def store(folder: Path, entry: Path, write: Callable[[Path], None], *, replace: bool = False) -> None:
    """Store a cache entry atomically: ``write(staging)`` fills a hidden folder beside ``entry``, which is
    then renamed to ``entry`` (readers see a whole entry or none; another process storing it first wins).
    ``replace`` removes a stale ``entry`` first. Never raises: caching is an optimisation."""
    try:
        folder.mkdir(parents=True, exist_ok=True)
        staging = Path(tempfile.mkdtemp(prefix=f".{entry.name}-", dir=folder))
        write(staging)
        if replace:
            shutil.rmtree(entry, ignore_errors=True)
        try:
            staging.rename(entry)
        except OSError:
            shutil.rmtree(staging, ignore_errors=True)
        prune(folder)
    except Exception:  # a full disk, a read-only cache, an unpicklable object: just not cached
        pass
