"""Progress of long commands on stderr: a live bar on a terminal, plain lines otherwise, or nothing.

The command line opens :func:`shown` for the run (nothing under ``--json`` or ``--quiet``); code
anywhere reports through :func:`count` (``done`` of ``total`` of a kind of step, e.g. design starts;
:func:`overall` makes the stages of a block one count) and :func:`note` (a step's description).
Without :func:`shown` both do nothing, so library and notebook use stay silent. :func:`deferred` notes a
step only once it has run for a second, so that a command whose steps are usually quick (identify on a
small experiment) says nothing unless one is slow.
"""

from __future__ import annotations

import sys
import threading
from collections.abc import Iterator
from contextlib import contextmanager

BAR = 24  # characters of the live bar
SLOW = 1.0  # [s] a step that runs longer than this is noted by :func:`deferred`

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
    """``done`` of ``total`` ``what`` (e.g. "design starts") are finished; inside :func:`overall` for
    ``what``, counted on from the steps of the block finished before."""
    stream = _state["stream"]
    if stream is None:
        return
    done, total = _overall(what, done, total)
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


@contextmanager
def overall(what: str, planned: int = 0) -> Iterator[None]:
    """Count every ``what`` of the block as one total (N of M overall, not per stage): a stage's
    ``done`` of ``total`` is shown after the steps of the stages before it, out of ``planned`` (the steps
    the block expects) or, once more come (a stage added on the way), of all those known so far."""
    saved = _state.get("overall")
    _state["overall"] = {"what": what, "before": 0, "planned": planned}
    try:
        yield
    finally:
        _state["overall"] = saved


def _overall(what: str, done: int, total: int) -> tuple[int, int]:
    """(done, total) of the block's :func:`overall` count for ``what``; as given outside one."""
    block = _state.get("overall")
    if block is None or block["what"] != what:
        return done, total
    before = block["before"]
    if done >= total:  # this stage is over: the next one counts on from here
        block["before"] += total
    return before + done, max(block["planned"], before + total)


def note(text: str) -> None:
    """A line describing the step now under way (its quantities in the display units of --units)."""
    stream = _state["stream"]
    if stream is None:
        return
    from pampipe.units.display import localize

    _end_line()
    stream.write(localize(text) + "\n")
    stream.flush()


class Deferred:
    """A progress callback that notes a step only if it is still running ``after`` seconds after it
    began; the next step, or :meth:`cancel`, ends the wait. ``timer`` is the pending wait (or None)."""

    def __init__(self, after: float):
        self.after = after
        self.timer: threading.Timer | None = None
        self._lock = threading.Lock()
        self._step = 0

    def __call__(self, text: str) -> None:
        with self._lock:
            self._cancel()
            if _state["stream"] is None:
                return
            self.timer = threading.Timer(self.after, self._show, (text, self._step))
            self.timer.daemon = True
            self.timer.start()

    def _show(self, text: str, step: int) -> None:
        with self._lock:
            if step == self._step:  # not a step that ended while this wait fired
                note(text)

    def _cancel(self) -> None:
        self._step += 1
        if self.timer is not None:
            self.timer.cancel()
            self.timer = None

    def cancel(self) -> None:
        """Note nothing more: the pending step ended."""
        with self._lock:
            self._cancel()


@contextmanager
def deferred(after: float = SLOW) -> Iterator[Deferred]:
    """A :class:`Deferred` callback for the steps of the block; a step still pending at its end is not
    noted (it ended in time)."""
    later = Deferred(after)
    try:
        yield later
    finally:
        later.cancel()
