"""Writing results safely: atomic files, never over an input, deterministic JSON.

The policy every command follows (docs/commands.md §1.2):

* an input of the command is never overwritten, not even with ``--force`` (:func:`check_not_input`);
* an existing data file (a CSV or an experiment file that ``synth`` would write) is replaced only with
  ``--force`` (:func:`check_overwrite`); results (``-o``, plots) are replaced, as a re-run regenerates them;
* only regular files are replaced: ``-o /dev/null`` or a FIFO is refused, never swapped for a file;
* a file is written to a temporary name beside the target and renamed over it, so a crash or an
  interrupt leaves the old file or the new one, never half of one. The new file gets the mode of the
  file it replaces, or the mode the umask allows (0644 under umask 022);
* the output folder of ``-o`` must exist; ``--plots DIR`` and ``synth OUT_DIR`` create theirs;
* two outputs of one command never share a path (``-o x.html --report x.html``: one would replace the
  other), :func:`check_distinct_outputs`.

:func:`written` lists the files this process has written, so an interrupt can say truthfully which
outputs exist.
"""

from __future__ import annotations

import contextlib
import json
import math
import os
import stat
from collections.abc import Callable, Iterable
from pathlib import Path

from pampipe.errors import InputError, SolverError
from pampipe.io.paths import kind_of
from pampipe.runtime import interrupts

_WRITTEN: list[Path] = []


def written() -> tuple[Path, ...]:
    """The files written (completely) by this process since :func:`forget_written`."""
    return tuple(_WRITTEN)


def forget_written() -> None:
    """Start a new record of written files (called once per command run)."""
    _WRITTEN.clear()


def check_not_input(target: Path, inputs: Iterable[Path], *, option: str) -> None:
    """Refuse (exit 2) to write ``target`` if it is one of the command's input files."""
    target = Path(target)
    for source in inputs:
        source = Path(source)
        if target.exists() and source.exists() and os.path.samefile(target, source):
            raise InputError(f"{option} {target}: refusing to write over the input file {source}; "
                             "choose another output path.")
        if target.resolve() == source.resolve():
            raise InputError(f"{option} {target}: refusing to write over the input file {source}.")


#: The options naming a command's outputs (argparse ``dest`` → the flag as messages show it).
OUTPUT_OPTIONS = {"output": "-o", "report": "--report", "plots": "--plots"}


def check_distinct_outputs(args) -> None:
    """Refuse (exit 2) two output options of ``args`` (:data:`OUTPUT_OPTIONS`) that name the same path: the
    same text once made absolute, or the same file or folder on disk (a link, another spelling)."""
    given = [(flag, Path(path)) for dest, flag in OUTPUT_OPTIONS.items()
             if (path := getattr(args, dest, None)) is not None]
    for i, (flag, path) in enumerate(given):
        for other_flag, other in given[:i]:
            if os.path.abspath(path) == os.path.abspath(other) or _same_file(path, other):
                raise InputError(f"{other_flag} {other} and {flag} {path} are the same path, so one output "
                                 "would replace the other; give each its own path.")


def _same_file(a: Path, b: Path) -> bool:
    try:
        return os.path.samefile(a, b)
    except OSError:  # one of them does not exist yet
        return False


def check_overwrite(targets: Iterable[Path], *, force: bool) -> None:
    """Refuse (exit 2) to replace existing data files unless ``force`` (the ``--force`` flag)."""
    existing = [Path(t) for t in targets if os.path.lexists(t)]
    if existing and not force:
        more = f" (and {len(existing) - 1} more of the files to write)" if len(existing) > 1 else ""
        raise InputError(f"{existing[0]}: already exists{more}; choose another folder or name, or pass "
                         "--force to replace existing files.")


def atomic_write(target: Path, write: Callable[[Path], None], *, create_folder: bool = False) -> None:
    """Call ``write(tmp)`` on a temporary file beside ``target``, then rename it over ``target``.

    ``create_folder`` creates a missing output folder; otherwise a missing folder is an error.
    Every failure (read-only folder, disk full, a target that is not a regular file) raises
    :class:`InputError` and leaves no temporary file.
    """
    target = Path(target)
    mode = _mode_for(target)
    folder = target.parent
    if not folder.is_dir():
        if not create_folder:
            raise _no_folder(target)
        try:
            folder.mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            raise InputError(f"{folder}: cannot create the output folder ({exc.strerror or exc}).") from None
    import tempfile  # imported here: it costs 5 ms of every command's start-up

    _remove_stale_temps(target)
    tmp = None
    try:
        fd, tmp_name = tempfile.mkstemp(prefix=f".{target.name}.{os.getpid()}.", suffix=".tmp", dir=folder)
        tmp = Path(tmp_name)
        os.fchmod(fd, mode)
        os.close(fd)
        write(tmp)
        os.replace(tmp, target)
        tmp = None
    except OSError as exc:
        raise InputError(f"{target}: cannot write the output ({exc.strerror or exc}).") from None
    finally:
        if tmp is not None and tmp.exists():
            tmp.unlink()
    _WRITTEN.append(target)


def _remove_stale_temps(target: Path) -> None:
    """Remove ``.NAME.PID.XXXX.tmp`` files of ``target`` left by killed processes (SIGKILL mid-write)."""
    prefix = f".{target.name}."
    try:
        entries = [e for e in os.scandir(target.parent)
                   if e.name.startswith(prefix) and e.name.endswith(".tmp")]
    except OSError:
        return
    for entry in entries:
        pid = entry.name[len(prefix):].split(".")[0]
        if pid.isdigit() and not _running(int(pid)) and entry.is_file(follow_symlinks=False):
            with contextlib.suppress(OSError):
                os.unlink(entry.path)


def check_output(target: Path, inputs: Iterable[Path], *, option: str) -> None:
    """Before any work: ``target`` is not an input, its folder exists, and it is a regular file or absent.

    So that a command fails (exit 2) before it computes or prints anything it could not write.
    """
    target = Path(target)
    check_not_input(target, inputs, option=option)
    _mode_for(target)
    if not target.parent.is_dir():
        raise _no_folder(target)


def _no_folder(target: Path) -> InputError:
    return InputError(f"{target}: the output folder {target.parent} does not exist; create it first.")


def _mode_for(target: Path) -> int:
    """Permission bits of the new file: those of the file it replaces, else 0666 minus the umask."""
    try:
        info = os.stat(target)
    except FileNotFoundError:
        umask = os.umask(0o022)
        os.umask(umask)
        return 0o666 & ~umask
    except OSError as exc:
        raise InputError(f"{target}: cannot write the output ({exc.strerror or exc}).") from None
    if not stat.S_ISREG(info.st_mode):
        raise InputError(f"{target}: is {kind_of(info.st_mode)}, not a regular file; refusing to replace "
                         "it. Give a file name for the output.")
    return stat.S_IMODE(info.st_mode)


def atomic_write_text(target: Path, text: str, *, create_folder: bool = False) -> None:
    """Write ``text`` (UTF-8) to ``target`` atomically."""
    atomic_write(target, lambda tmp: tmp.write_text(text, encoding="utf-8"), create_folder=create_folder)


#: Significant digits of every float in JSON output: fixed, so that results are byte-identical across
#: thread counts (BLAS may reorder sums and change the last bits).
JSON_DIGITS = 12


#: Key suffix of wall-clock measurements (``wall_time_s``, ``build_wall_time_s``, ...): the only entries
#: ``--reproducible`` zeroes. Physical durations (``cycle_time_s``, ``duration_s``) keep their values.
WALL_CLOCK_SUFFIX = "wall_time_s"


def _clean(value, parent: tuple = (), timings: bool = True):
    """JSON-ready copy of ``value``; a NaN or infinite number is an error, never printed.

    Every float is rounded to :data:`JSON_DIGITS` significant digits, ``float(f"{x:.12g}")``.
    With ``timings=False`` every ``*wall_time_s`` entry (a wall-clock measurement) is written as 0.
    ``parent`` is the key path of ``value``, spelled out only in the error message (the path inside
    ``value`` is found again when a non-finite number is met: the fast walk builds no paths).
    """
    try:
        return _cleaned(value, timings)
    except _NonFinite:
        inner, bad = _non_finite(value, parent, timings)
        raise SolverError(f"{_path(inner)} came out as {bad}: the computation left the model's valid "
                          "domain; please report the input that caused it", status="non_finite") from None


class _NonFinite(Exception):
    """A NaN or infinite float met by :func:`_cleaned` (its path is found by :func:`_non_finite`)."""


#: Floats rounded before, and their rounding: a document repeats its values (bores, loads, pressures of
#: alike sections), and a lookup costs a tenth of the formatting and parsing. Cleared when it is full.
_ROUNDED: dict[float, float] = {}
ROUNDED_KEPT = 1 << 16

#: Types written as they are (bool and int are exact; str and None have no digits).
_PLAIN = frozenset({str, int, bool, type(None)})


def _cleaned(value, timings: bool):
    """:func:`_clean` without the key path: dispatch on the exact type first (the common case: dicts,
    lists and builtin floats, ints and strings), subclasses and numpy scalars after."""
    kind = type(value)
    if kind is float:
        rounded = _ROUNDED.get(value)
        if rounded is None:
            if value - value != 0.0:  # inf - inf and nan - nan are nan
                raise _NonFinite
            if value == 0.0:  # 0.0 and -0.0 (equal as keys): each its own rounding
                return value
            if len(_ROUNDED) >= ROUNDED_KEPT:
                _ROUNDED.clear()
            rounded = _ROUNDED[value] = float(f"{value:.{JSON_DIGITS}g}")
        return rounded
    if kind in _PLAIN:
        return value
    if kind is dict:
        if timings:
            return {k if type(k) is str else str(k): v if type(v) in _PLAIN else _cleaned(v, timings)
                    for k, v in value.items()}
        return {str(k): 0.0 if str(k).endswith(WALL_CLOCK_SUFFIX) else _cleaned(v, timings)
                for k, v in value.items()}
    if kind is list or kind is tuple:
        return [v if type(v) in _PLAIN else _cleaned(v, timings) for v in value]
    if isinstance(value, dict):
        return _cleaned(dict(value), timings)
    if isinstance(value, list | tuple):
        return _cleaned(list(value), timings)
    if isinstance(value, float):  # a float subclass
        return _cleaned(float(value), timings)
    if hasattr(value, "item") and hasattr(value, "dtype"):  # numpy scalar
        return _cleaned(value.item(), timings)
    return value


def _non_finite(value, parent: tuple, timings: bool):
    """(key path, value) of the first NaN or infinite float in ``value`` that :func:`_cleaned` writes
    (None if there is none)."""
    if isinstance(value, float) or (hasattr(value, "item") and hasattr(value, "dtype")):
        number = float(value)
        return None if math.isfinite(number) else (parent, number)
    if isinstance(value, dict):
        items = ((k, v) for k, v in value.items() if timings or not str(k).endswith(WALL_CLOCK_SUFFIX))
    elif isinstance(value, list | tuple):
        items = enumerate(value)
    else:
        return None
    for key, item in items:
        if isinstance(item, bool | int | str) or item is None:
            continue
        found = _non_finite(item, (parent, key), timings)
        if found is not None:
            return found
    return None


def _path(parent: tuple) -> str:
    parts = []
    while parent:
        parent, key = parent
        parts.append(f"[{key}]" if isinstance(key, int) else f".{key}")
    return "result" + "".join(reversed(parts))


def to_json(document: dict, *, timings: bool = True, indent: int | None = 2) -> str:
    """Deterministic JSON: sorted keys, 12-digit floats; NaN or inf raises SolverError (exit 3).

    ``timings=False`` writes wall-clock ``*wall_time_s`` entries as 0, for byte-identical output.
    ``indent=None`` writes one line (Python's C encoder: about 3× faster than the indented one).
    """
    cleaned = _clean(document, timings=timings)
    return json.dumps(cleaned, sort_keys=True, indent=indent, allow_nan=False) + "\n"


class Streamed:
    """A top-level list of a JSON document that :func:`json_chunks` writes item by item from ``items``
    (an iterable of documents), so that the whole list is never held at once."""

    def __init__(self, items: Iterable) -> None:
        self.items = items


class JsonText:
    """Items of a :class:`Streamed` list already encoded: ``text``, as :func:`json_chunks` would encode them,
    joined by ``", "`` (:mod:`pampipe.io.json_columns` writes long lists of records column-wise); ``items``:
    how many. Held, not a ``str`` subclass, so that megabytes of text are written without a copy."""

    __slots__ = ("items", "text")

    def __init__(self, text: str, items: int) -> None:
        self.text, self.items = text, items


#: Items of a :class:`Streamed` list encoded per chunk of :func:`json_chunks`.
STREAM_CHUNK = 1000


def json_chunks(document: dict, *, timings: bool = True):
    """The text of ``to_json(document, indent=None)`` in pieces, each :class:`Streamed` value of
    ``document`` encoded :data:`STREAM_CHUNK` items at a time (a :class:`JsonText` item as it is): the same
    bytes, without the whole document in memory. A NaN or inf raises SolverError when its item is reached."""
    streamed = {key: value for key, value in document.items() if isinstance(value, Streamed)}
    marks = {key: f"\0streamed {key}" for key in streamed}
    head = json.dumps(_clean({**document, **marks}, timings=timings), sort_keys=True, allow_nan=False)
    for key in sorted(streamed):  # json.dumps wrote the keys sorted: the marks come in this order
        before, head = head.split(json.dumps(marks[key]), 1)
        yield before + "["
        batch: list[str] = []
        separator = ""  # before the next batch: none before the first
        place = 0  # of the next item in the list
        for item in streamed[key].items:
            if type(item) is JsonText:  # written as it is (it may be megabytes: not copied into a batch)
                if batch:
                    yield separator + ", ".join(batch)
                    batch, separator = [], ", "
                yield separator
                yield item.text
                separator, place = ", ", place + item.items
                continue
            batch.append(json.dumps(_clean(item, (((), key), place), timings), sort_keys=True,
                                    allow_nan=False))
            place += 1
            if len(batch) == STREAM_CHUNK:
                yield separator + ", ".join(batch)
                batch, separator = [], ", "
        yield (separator + ", ".join(batch) if batch else "") + "]"
    yield head + "\n"


# ------------------------------------------------------------------------------ a set of files at once
#: Hidden siblings ``.NAME.pampipe-PID-XXXX`` hold a set being written; those of dead processes are removed.
_SET_MARK = ".pampipe-"


def atomic_write_set(folder: Path, texts: dict[str, str]) -> None:
    """Write the files ``texts`` (name → UTF-8 text) into ``folder`` as one set: the old set or the new.

    The set is written into a hidden sibling folder, which then takes ``folder``'s place in one
    step (Linux ``renameat2(RENAME_EXCHANGE)``, or one rename when ``folder`` is new); the other
    files of ``folder`` are carried over as hard links, so they stay the same files. Where that
    cannot be done (another system, a subfolder or a mount point in ``folder``) the files are renamed
    in one at a time; the export's mission hash then keeps a mixed pair from compiling. Leftovers of
    an interrupted run are removed at the next. Failures raise :class:`InputError`.
    """
    folder = Path(folder)
    real = folder.resolve() if folder.is_symlink() else folder.absolute()
    if os.path.lexists(real) and not real.is_dir():
        raise InputError(f"{folder}: exists and is not a folder; give a folder for the output files.")
    for name in texts:
        _mode_for(real / name)  # only regular files are replaced
    try:
        real.parent.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise InputError(f"{real.parent}: cannot create the output folder ({exc.strerror or exc}).") from None
    _remove_stale_sets(real)
    import shutil
    import tempfile

    staging = None
    try:
        try:
            staging = Path(tempfile.mkdtemp(prefix=f".{real.name}{_SET_MARK}{os.getpid()}-", dir=real.parent))
            swap = True
        except OSError:  # a parent we may not write: stage inside the folder and rename file by file
            real.mkdir(exist_ok=True)
            staging = Path(tempfile.mkdtemp(prefix=f".{_SET_MARK}{os.getpid()}-", dir=real))
            swap = False
        for name, text in texts.items():
            path = staging / name
            path.write_text(text, encoding="utf-8")
            os.chmod(path, _mode_for(real / name))
        with interrupts.deferred():  # Ctrl-C waits until the new set is in and the old one gone
            if not (swap and _swap_in(staging, real, texts)):
                real.mkdir(exist_ok=True)
                for name in texts:
                    os.replace(staging / name, real / name)
            shutil.rmtree(staging, ignore_errors=True)
            _WRITTEN.extend(folder / name for name in texts)
    except OSError as exc:
        raise InputError(f"{folder}: cannot write the output files ({exc.strerror or exc}).") from None
    finally:
        if staging is not None and staging.exists():
            shutil.rmtree(staging, ignore_errors=True)


def _swap_in(staging: Path, real: Path, texts: dict[str, str]) -> bool:
    """Put ``staging`` in ``real``'s place in one step; False (nothing changed) where it cannot be done."""
    if not real.exists():
        umask = os.umask(0o022)
        os.umask(umask)
        os.chmod(staging, 0o777 & ~umask)
        try:
            os.rename(staging, real)  # a new folder: one rename
        except OSError:
            return False
        return True
    exchange = _renameat2()
    cwd = Path.cwd()
    if exchange is None or os.path.ismount(real) or cwd == real or real in cwd.parents:
        return False  # a process working inside would be left in the old, removed folder
    info = os.stat(real)
    for entry in os.scandir(real):
        if entry.name in texts:
            continue
        if entry.is_symlink():
            os.symlink(os.readlink(entry.path), staging / entry.name)
        elif entry.is_file(follow_symlinks=False):
            os.link(entry.path, staging / entry.name)
        else:  # a subfolder or a special file cannot be carried over as a link
            return False
    os.chmod(staging, stat.S_IMODE(info.st_mode))
    if not exchange(staging, real):
        return False
    for entry in os.scandir(staging):  # what appeared in the folder meanwhile goes back into it
        if entry.name not in texts and not os.path.lexists(real / entry.name):
            os.rename(entry.path, real / entry.name)
    return True


def _renameat2():
    """A function exchanging two paths atomically (Linux renameat2), or None where there is none."""
    import ctypes
    import sys

    if not sys.platform.startswith("linux"):
        return None
    try:
        libc = ctypes.CDLL(None, use_errno=True)
        call = libc.renameat2
    except (OSError, AttributeError):
        return None
    at_fdcwd, rename_exchange = -100, 2

    def exchange(a: Path, b: Path) -> bool:
        return call(at_fdcwd, os.fsencode(a), at_fdcwd, os.fsencode(b), rename_exchange) == 0

    return exchange


def _remove_stale_sets(real: Path) -> None:
    """Remove staging folders of ``real`` left by processes that no longer run (a kill mid-export)."""
    import shutil

    for place, prefix in ((real.parent, f".{real.name}{_SET_MARK}"), (real, f".{_SET_MARK}")):
        try:
            entries = list(os.scandir(place))
        except OSError:
            continue
        for entry in entries:
            if not entry.name.startswith(prefix) or not entry.is_dir(follow_symlinks=False):
                continue
            pid = entry.name[len(prefix):].split("-")[0]
            if pid.isdigit() and not _running(int(pid)):
                shutil.rmtree(entry.path, ignore_errors=True)


def _running(pid: int) -> bool:
    """True if a process ``pid`` exists (as far as this process can tell)."""
    if pid == os.getpid():
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except OSError:
        return True
    return True
