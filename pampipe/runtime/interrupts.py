"""Ctrl-C and SIGTERM, honoured even inside IPOPT (docs/commands.md §1.3: exit 130 for SIGINT, 143 for
SIGTERM: 128 + the signal's number, as a shell reports a process the signal ended).

CasADi polls Python's signals while IPOPT iterates; a KeyboardInterrupt raised there is swallowed,
and IPOPT stops with ``User_Requested_Stop`` (or, if the signal lands between iterations, finishes).
So the handler also sets a flag, and every solver call is followed by :func:`check`, which turns a
set flag or a user-requested stop into KeyboardInterrupt.
"""

from __future__ import annotations

import signal
from collections.abc import Iterator
from contextlib import contextmanager

_state = {"requested": False, "signal": signal.SIGINT}


def _handler(signum, frame):
    if not _state["requested"]:  # the first signal names the exit code
        _state["signal"] = signum
    _state["requested"] = True
    raise KeyboardInterrupt


@contextmanager
def handled() -> Iterator[None]:
    """Install the SIGINT/SIGTERM handler for the duration of a command, then restore the old ones."""
    _state.update(requested=False, signal=signal.SIGINT)
    previous = {s: signal.signal(s, _handler) for s in (signal.SIGINT, signal.SIGTERM)}
    try:
        yield
    finally:
        for s, old in previous.items():
            signal.signal(s, old)


def requested() -> bool:
    """True once SIGINT or SIGTERM has arrived during the current command."""
    return _state["requested"]


def exit_code() -> int:
    """128 + the number of the signal that interrupted the command: 130 (SIGINT, also a KeyboardInterrupt
    raised without a signal) or 143 (SIGTERM)."""
    return 128 + int(_state["signal"])


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
