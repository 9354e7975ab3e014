"""Opening input files safely: regular files only, bounded reads, errors that name the path.

A FIFO, a device (``/dev/zero``), a socket or a directory given as an input is refused (exit 2) before
a byte is read: opening uses ``O_NONBLOCK``, so even a FIFO without a writer cannot block.
"""

from __future__ import annotations

import os
import stat
from typing import BinaryIO

from pampipe.errors import InputError

_KINDS = ((stat.S_ISDIR, "a directory"), (stat.S_ISFIFO, "a FIFO (named pipe)"),
          (stat.S_ISCHR, "a character device"), (stat.S_ISBLK, "a block device"),
          (stat.S_ISSOCK, "a socket"))


def kind_of(mode: int) -> str:
    """'a directory', 'a FIFO (named pipe)', ... for a non-regular ``st_mode``; 'a special file' else."""
    return next((name for test, name in _KINDS if test(mode)), "a special file")


def open_input(path: os.PathLike | str, *, what: str) -> BinaryIO:
    """Open a regular file for binary reading; anything else raises :class:`InputError`."""
    try:
        fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK | getattr(os, "O_CLOEXEC", 0))
    except FileNotFoundError:
        raise InputError(f"{path}: {what} not found.") from None
    except PermissionError:
        raise InputError(f"{path}: permission denied while reading the {what}.") from None
    except OSError as exc:  # symlink loops, name too long, I/O errors
        raise InputError(f"{path}: cannot read the {what} ({exc.strerror or exc}).") from None
    mode = os.fstat(fd).st_mode
    if not stat.S_ISREG(mode):
        os.close(fd)
        article = "an" if what[:1].lower() in "aeiou" else "a"
        raise InputError(f"{path}: is {kind_of(mode)}, not a regular file; expected {article} {what}.")
    os.set_blocking(fd, True)
    return os.fdopen(fd, "rb")


def read_bounded(path: os.PathLike | str, *, what: str, limit: int) -> bytes:
    """The bytes of a regular file of at most ``limit`` bytes (larger files raise InputError)."""
    with open_input(path, what=what) as handle:
        size = os.fstat(handle.fileno()).st_size
        try:  # read(n) allocates n bytes at once: ask for what the file holds, one more to see growth
            raw = handle.read(min(size, limit) + 1)
            if size < len(raw) <= limit:  # the file grew since fstat: read on, still bounded
                raw += handle.read(limit + 1 - len(raw))
        except OSError as exc:
            raise InputError(f"{path}: cannot read the {what} ({exc.strerror or exc}).") from None
    if len(raw) > limit:
        raise InputError(f"{path}: the {what} is larger than {limit / 2**20:g} MB, the most pampipe reads "
                         "from one YAML file.")
    return raw
