"""Keep freed memory in the process for array-heavy loops (glibc only; elsewhere nothing changes).

glibc serves every block above its mmap threshold (128 kB at start, raised as blocks are freed) with a fresh
``mmap`` and returns it with ``munmap``; it also trims the heap top back to the system. A loop of numpy
temporaries of a few MB (the ``--confidence`` sampling: draws × classes) then pays a page fault per 4 kB
of every temporary: 30 % of that sampling's CPU time was system time before this (2·10³ distinct sections,
10⁴ draws: 0.95 s of 3.1 s). Raising both thresholds makes glibc reuse the freed blocks instead. Peak memory
is unchanged: a freed block is reused, not added to.
"""

from __future__ import annotations

import functools
import sys

#: mallopt parameters (glibc malloc.h): M_TRIM_THRESHOLD, M_TOP_PAD, M_MMAP_THRESHOLD.
_M_TRIM_THRESHOLD, _M_TOP_PAD, _M_MMAP_THRESHOLD = -1, -2, -3
#: Blocks up to this size come from the heap and are reused [B] (glibc's largest mmap threshold on 64-bit).
REUSED_BLOCK = 32 << 20
#: Freed memory kept at the heap top before it is given back [B].
KEPT = 256 << 20
#: Extra memory asked for each time the heap grows [B].
TOP_PAD = 16 << 20


@functools.cache
def retain_freed_memory() -> bool:
    """Ask glibc to reuse freed blocks up to :data:`REUSED_BLOCK` rather than unmap them (once per process).

    True where the request was taken; False on another C library or platform (nothing changes there)."""
    if not sys.platform.startswith("linux"):
        return False
    import ctypes

    try:
        mallopt = ctypes.CDLL(None).mallopt
    except (OSError, AttributeError):  # musl and others: no mallopt
        return False
    mallopt.argtypes = (ctypes.c_int, ctypes.c_int)
    return all(mallopt(option, value) == 1 for option, value in (
        (_M_MMAP_THRESHOLD, REUSED_BLOCK), (_M_TRIM_THRESHOLD, KEPT), (_M_TOP_PAD, TOP_PAD)))
