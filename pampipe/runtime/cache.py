"""The user's on-disk cache of pampipe: its folder, whom it trusts, its entries, their checks and pruning.

Built NLPs (:func:`pampipe.runtime.ipopt.cached_functions`) and validated missions and experiments
(:mod:`pampipe.io.validated`) are kept there as one folder per entry. What is read back is trusted only as
far as it is checked:

* **The folder** ($PAMPIPE_NLP_CACHE, default ~/.cache/pampipe/nlp) is used only if it is the user's (owned
  by the effective uid, writable by neither group nor others) and pampipe's: it holds the marker file
  :data:`MARKER`, which pampipe writes when it creates the folder (or finds it empty, or holding only
  pampipe's entries). Otherwise the command runs uncached and says once, on stderr, which folder and why.
  Folders pampipe creates are 0700 and its files 0600, whatever the umask.
* **An entry** (a folder named ``<kind>-<32 hex digits>``) is read only if it and its files are the user's
  and writable by no one else, and only if its manifest (:data:`MANIFEST`: the SHA-256 of the key the
  entry stands for, and the length and SHA-256 of each file) matches the key asked for and the bytes on
  disk, before anything is parsed. A damaged entry is ignored, and replaced by the next store.
* **Pruning** removes only entries of that name pattern in a marked folder (the oldest beyond
  :data:`CACHE_ENTRIES`) and staging folders of pampipe's staging name older than :data:`STALE_AFTER`
  seconds (left by a killed process); anything else in the folder is left alone.

Importing this module loads neither CasADi nor pydantic.
"""

from __future__ import annotations

import hashlib
import json
import os
import re
import stat
import sys
import time
from functools import cache
from pathlib import Path

#: Environment variable: the cache folder, or ``off`` to disable it.
CACHE_VARIABLE = "PAMPIPE_NLP_CACHE"
#: Entries kept in the cache folder (the oldest are removed beyond this).
CACHE_ENTRIES = 64
#: The file that marks a folder as pampipe's cache (written when pampipe makes the folder its cache).
MARKER = ".pampipe-cache"
#: Each entry's list of what it stands for and of its files' lengths and SHA-256.
MANIFEST = "manifest.json"
#: Staging folders older than this [s] are left by a process that died while storing: removed.
STALE_AFTER = 3600.0
#: The names of pampipe's entries and of its staging folders (this version's and the former one's).
ENTRY_NAME = re.compile(r"[a-z][a-z0-9_]*-[0-9a-f]{32}")
STAGING_NAME = re.compile(r"\.(staging-)?[a-z][a-z0-9_]*-[0-9a-f]{32}-([0-9]+-)?[a-z0-9_]{8}")

_MARKER_TEXT = (b"This folder is pampipe's cache (PAMPIPE_NLP_CACHE). pampipe deletes only its own entries\n"
                b"here (folders named <kind>-<32 hex digits>, and .staging-* folders older than an hour).\n")
_said: set[str] = set()  # the folders and entries this process has already told the user about
_swept: set[str] = set()  # the cache folders whose stale staging folders this process has removed


class _Untrusted(OSError):
    """A file of the cache that is not the user's, or that others can write."""


def cache_folder() -> Path | None:
    """Where entries are kept: $PAMPIPE_NLP_CACHE, else $XDG_CACHE_HOME/pampipe/nlp (default
    ~/.cache/pampipe/nlp); None when the variable is ``off``. Not checked: see :func:`cache_root`."""
    chosen = os.environ.get(CACHE_VARIABLE, "")
    if chosen.lower() in ("off", "0", "no", "false"):
        return None
    if chosen:
        return Path(chosen)
    base = os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache"
    return Path(base) / "pampipe" / "nlp"


def cache_root() -> Path | None:
    """The cache folder if it can be trusted (created 0700 with its marker if missing); else None (``off``,
    or not the user's or not pampipe's: said once on stderr). Never raises."""
    folder = cache_folder()
    if folder is None:
        return None
    try:
        info = os.stat(folder)
    except FileNotFoundError:
        return folder if _create(folder) else None
    except OSError as exc:
        return _refuse(folder, f"it cannot be read ({exc.strerror or exc})")
    if not stat.S_ISDIR(info.st_mode):
        return _refuse(folder, "it is not a folder")
    if (why := untrusted(info)) is not None:
        return _refuse(folder, why)
    try:
        marker = os.lstat(folder / MARKER)
    except FileNotFoundError:
        return folder if _adopt(folder) else None
    except OSError as exc:
        return _refuse(folder, f"its marker file cannot be read ({exc.strerror or exc})")
    if not stat.S_ISREG(marker.st_mode) or (why := untrusted(marker)) is not None:
        return _refuse(folder, f"its marker file {MARKER} is not the user's ({why or 'not a file'})")
    if str(folder) not in _swept:
        _swept.add(str(folder))
        remove_stale_staging(folder)  # once per process: a killed store's leftovers
    return folder


def untrusted(info: os.stat_result) -> str | None:
    """Why a file or folder with ``info`` is not trusted (another user's, or others can write it), or None."""
    if hasattr(os, "geteuid") and info.st_uid != os.geteuid():
        return f"it is owned by uid {info.st_uid}, not by this user (uid {os.geteuid()})"
    if info.st_mode & (stat.S_IWGRP | stat.S_IWOTH):
        return f"group or others can write it (mode {stat.S_IMODE(info.st_mode):04o})"
    return None


def _refuse(folder: Path, why: str) -> None:
    """Say once per process that ``folder`` is not used as the cache, and why."""
    key = f"refused:{folder}"
    if key not in _said:
        _said.add(key)
        given = CACHE_VARIABLE if os.environ.get(CACHE_VARIABLE) else f"the default, {CACHE_VARIABLE} unset"
        print(f"pampipe: not using the cache folder {folder} ({given}): {why}; running without the cache. "
              f"Point {CACHE_VARIABLE} at a folder only you can write, or set it to 'off'.",
              file=sys.stderr, flush=True)
    return None


def _create(folder: Path) -> bool:
    """Make ``folder`` (and the parents it needs) 0700 and mark it as pampipe's cache."""
    missing = []
    for place in (folder, *folder.parents):
        if os.path.lexists(place):
            break
        missing.append(place)
    try:
        for place in reversed(missing):
            try:
                os.mkdir(place, 0o700)
            except FileExistsError:  # another process made it meanwhile
                continue
            os.chmod(place, 0o700)  # whatever the umask
    except OSError:  # a read-only home: skipped silently, as an unwritable cache always was
        return False
    return _adopt(folder)


def _adopt(folder: Path) -> bool:
    """Mark ``folder`` as pampipe's cache if it is empty or holds only pampipe's entries (a cache of an
    earlier version); else refuse it: it is someone's folder, and pruning it would delete their files."""
    try:
        foreign = [name for name in os.listdir(folder)
                   if name != MARKER and not ENTRY_NAME.fullmatch(name) and not STAGING_NAME.fullmatch(name)]
    except OSError as exc:
        _refuse(folder, f"it cannot be listed ({exc.strerror or exc})")
        return False
    if foreign:
        _refuse(folder, f"it is not pampipe's cache (it holds {foreign[0]!r} among {len(foreign)} other "
                        f"files or folders, and no marker file {MARKER})")
        return False
    try:
        os.chmod(folder, 0o700)
        _write_new(folder / MARKER, _MARKER_TEXT)
    except FileExistsError:  # another process marked it meanwhile
        pass
    except OSError as exc:
        _refuse(folder, f"it cannot be marked as pampipe's cache ({exc.strerror or exc})")
        return False
    return True


def _write_new(path: Path, data: bytes) -> None:
    """Write ``data`` to a new file ``path`` (0600, never through a link); OSError unless all is written."""
    fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_NOFOLLOW", 0), 0o600)
    try:
        os.fchmod(fd, 0o600)
        view = memoryview(data)
        while view:
            view = view[os.write(fd, view):]
        if os.fstat(fd).st_size != len(data):  # checked after writing: a short write is no entry
            raise OSError(f"{path}: {os.fstat(fd).st_size} of {len(data)} bytes written")
    finally:
        os.close(fd)


def _read_trusted(path: Path) -> bytes:
    """The bytes of the file ``path`` if it is a regular file of the user's that no one else can write;
    else OSError. Never follows a link."""
    fd = os.open(path, os.O_RDONLY | getattr(os, "O_NOFOLLOW", 0))
    try:
        info = os.fstat(fd)
        if not stat.S_ISREG(info.st_mode) or (why := untrusted(info)) is not None:
            raise _Untrusted(f"{path.name}: {why or 'it is not a regular file'}")
        with os.fdopen(os.dup(fd), "rb") as handle:
            return handle.read()
    finally:
        os.close(fd)


def entry_name(kind: str, key_digest: str) -> str:
    """The folder of the entry of kind ``kind`` (lower-case letters) for the key of SHA-256 ``key_digest``."""
    return f"{kind}-{key_digest[:32]}"


def load(root: Path, kind: str, key_digest: str) -> dict[str, bytes] | None:
    """The files of the entry for ``key_digest`` (the SHA-256 of everything it stands for), checked: the
    entry and its files are the user's, its manifest names this key, every file has the length and SHA-256
    the manifest gives. None if it is missing, untrusted (said once) or damaged. Never raises."""
    entry = root / entry_name(kind, key_digest)
    try:
        info = os.lstat(entry)
    except OSError:
        return None
    if not stat.S_ISDIR(info.st_mode):
        return None
    if (why := untrusted(info)) is not None:
        return _ignore(entry, why)
    try:
        manifest = json.loads(_read_trusted(entry / MANIFEST))
        if manifest.get("key") != key_digest:
            return None
        files = {}
        for name, (length, digest) in manifest["files"].items():
            if name == MANIFEST or os.sep in name or not name or name.startswith("."):
                return None
            data = _read_trusted(entry / name)
            if len(data) != length or hashlib.sha256(data).hexdigest() != digest:
                return None
            files[name] = data
        return files
    except _Untrusted as exc:
        return _ignore(entry, str(exc))
    except Exception:  # missing, damaged or of another version: built again and replaced
        return None


def _ignore(entry: Path, why: str) -> None:
    """Say once per process that the entry ``entry`` is ignored, and why."""
    key = f"ignored:{entry}"
    if key not in _said:
        _said.add(key)
        print(f"pampipe: ignoring the cache entry {entry}: {why}.", file=sys.stderr, flush=True)
    return None


def store(root: Path, kind: str, key_digest: str, files: dict[str, bytes]) -> None:
    """Store the entry for ``key_digest`` (see :func:`load`) atomically, replacing a stale or damaged one of
    the user's: the files and their manifest fill a staging folder beside it, which is then renamed into
    place (readers see a whole entry or none; another process storing it first wins). A staging folder
    is removed whatever happens. Never raises: caching is an optimisation."""
    import shutil  # imported here: a warm run never stores
    import tempfile

    name = entry_name(kind, key_digest)
    entry = root / name
    staging = None
    try:
        staging = Path(tempfile.mkdtemp(prefix=f".staging-{name}-{os.getpid()}-", dir=root))
        manifest = {"key": key_digest, "files": {}}
        for file, data in files.items():
            _write_new(staging / file, data)
            manifest["files"][file] = [len(data), hashlib.sha256(data).hexdigest()]
        _write_new(staging / MANIFEST, json.dumps(manifest).encode())
        if _owned_folder(entry):
            shutil.rmtree(entry, ignore_errors=True)  # stale or damaged: it is replaced
        try:
            staging.rename(entry)
            staging = None
        except OSError:  # another process stored it first, or a foreign entry is in the way
            pass
        prune(root)
    except Exception:  # a full disk, a read-only cache: just not cached
        pass
    finally:
        if staging is not None:
            shutil.rmtree(staging, ignore_errors=True)


def _owned_folder(path: Path) -> bool:
    """True if ``path`` is a folder (not a link) of this user's."""
    try:
        info = os.lstat(path)
    except OSError:
        return False
    return stat.S_ISDIR(info.st_mode) and (not hasattr(os, "geteuid") or info.st_uid == os.geteuid())


def prune(root: Path) -> None:
    """Remove all but the :data:`CACHE_ENTRIES` newest of pampipe's entries in the marked folder ``root``
    (folders of the user's named as :data:`ENTRY_NAME`), and stale staging folders; nothing else."""
    import shutil

    if not os.path.isfile(root / MARKER):
        return
    entries = []
    for item in os.scandir(root):
        if ENTRY_NAME.fullmatch(item.name) and _owned_folder(Path(item.path)):
            entries.append((item.stat(follow_symlinks=False).st_mtime, item.path))
    for _, old in sorted(entries)[:-CACHE_ENTRIES]:
        shutil.rmtree(old, ignore_errors=True)
    remove_stale_staging(root)


def remove_stale_staging(root: Path) -> None:
    """Remove the staging folders in ``root`` that match :data:`STAGING_NAME`, are the user's and were last
    changed more than :data:`STALE_AFTER` seconds ago (a store killed midway). Never raises."""
    try:
        stale = [item.path for item in os.scandir(root)
                 if STAGING_NAME.fullmatch(item.name) and _owned_folder(Path(item.path))
                 and time.time() - item.stat(follow_symlinks=False).st_mtime > STALE_AFTER]
    except OSError:
        return
    if stale:
        import shutil

        for path in stale:
            shutil.rmtree(path, ignore_errors=True)


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
            stat_ = os.stat(os.path.join(folder, name))
            where = f"{os.path.relpath(folder, root)}/{name}"
            digest.update(f"{where}\0{stat_.st_size}\0{stat_.st_mtime_ns}\0".encode())
    return digest.hexdigest()
