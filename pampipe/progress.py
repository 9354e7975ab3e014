"""Progress of long commands on stderr: a live bar on a terminal, plain lines otherwise, or nothing.

The command line opens :func:`shown` for the run (nothing under ``--json`` or ``--quiet``); code
anywhere reports through :func:`count` (``done`` of ``total`` of a kind of step, e.g. design starts)
and :func:`note` (a step's description). Without :func:`shown` both do nothing, so library and
notebook use stay silent.
"""

from __future__ import annotations

import sys
from collections.abc import Iterator
from contextlib import contextmanager

BAR = 24  # characters of the live bar

_state: dict = {"stream": None, "live": False, "open": False}


@contextmanager
def shown(enabled: bool = True, stream=None) -> Iterator[None]:
    """Report progress on ``stream`` (stderr) for the duration: live on a terminal, else plain lines."""
    stream = sys.stderr if stream is None else stream
    saved = dict(_state)
    _state.update(stream=stream if enabled else None, live=enabled and _tty(stream), open=False)
    try:
        yield
    finally:
        _end_line()
        _state.update(saved)


def _tty(stream) -> bool:
    isatty = getattr(stream, "isatty", None)
    return bool(isatty and isatty())


def _end_line() -> None:
    if _state["open"]:
        _state["stream"].write("\n")
        _state["stream"].flush()
        _state["open"] = False


def count(what: str, done: int, total: int) -> None:
    """``done`` of ``total`` ``what`` (e.g. "design starts") are finished."""
    stream = _state["stream"]
    if stream is None:
        return
    if _state["live"]:
        filled = BAR * done // max(total, 1)
        stream.write(f"\r[{'#' * filled}{'.' * (BAR - filled)}] {done}/{total} {what}")
        stream.flush()
        _state["open"] = done < total
        if done >= total:
            stream.write("\n")
    else:
        stream.write(f"{what}: {done}/{total} done\n")
        stream.flush()


def note(text: str) -> None:
    """A line describing the step now under way (its quantities in the display units of --units)."""
    stream = _state["stream"]
    if stream is None:
        return
    from pampipe.display import localize

    _end_line()
    stream.write(localize(text) + "\n")
    stream.flush()
