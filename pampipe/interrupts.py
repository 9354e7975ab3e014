"""Ctrl-C and SIGTERM, honoured even inside IPOPT (docs/commands.md §1.3: exit 130).

CasADi polls Python's signals while IPOPT iterates; a KeyboardInterrupt raised there is swallowed,
and IPOPT stops with ``User_Requested_Stop`` (or, if the signal lands between iterations, finishes).
So the handler also sets a flag, and every solver call is followed by :func:`check`, which turns a
set flag or a user-requested stop into KeyboardInterrupt.
"""

from __future__ import annotations

import signal
from collections.abc import Iterator
from contextlib import contextmanager

_state = {"requested": False}


def _handler(signum, frame):
    _state["requested"] = True
    raise KeyboardInterrupt


@contextmanager
def handled() -> Iterator[None]:
    """Install the SIGINT/SIGTERM handler for the duration of a command, then restore the old ones."""
    _state["requested"] = False
    previous = {s: signal.signal(s, _handler) for s in (signal.SIGINT, signal.SIGTERM)}
    try:
        yield
    finally:
        for s, old in previous.items():
            signal.signal(s, old)


def requested() -> bool:
    """True once SIGINT or SIGTERM has arrived during the current command."""
    return _state["requested"]


def check(stats: dict | None = None) -> None:
    """Raise KeyboardInterrupt if a signal arrived or the solver (``stats()``) stopped on request."""
    if _state["requested"] or (stats or {}).get("return_status") == "User_Requested_Stop":
        _state["requested"] = True
        raise KeyboardInterrupt


@contextmanager
def deferred() -> Iterator[None]:
    """Hold SIGINT and SIGTERM back for a short critical step (swapping a set of files in and cleaning
    up); a signal that arrives meanwhile is delivered when the step is done. Where signals cannot be
    blocked (not the main thread, no ``pthread_sigmask``), the step runs unprotected."""
    import threading

    held = {signal.SIGINT, signal.SIGTERM}
    if not hasattr(signal, "pthread_sigmask") or threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = signal.pthread_sigmask(signal.SIG_BLOCK, held)
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, previous)
