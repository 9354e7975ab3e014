"""The process's stdout and stderr, guarded: every write is checked, every text is made safe.

The command line wraps both streams once (:func:`guarded`), so that no command has to:

* a failed write or flush (``> /dev/full``, a closed pipe, EPIPE) raises :class:`StreamError`, which
  the CLI turns into exit 2 and one line on whichever stream still works; a stream closed before the
  run (``>&-``) is refused at once, since nothing could be reported;
* control characters, bidi overrides and other invisible format characters are escaped as ``\\x1b``
  or ``\\u202e`` (:func:`safe_text`), as JSON escapes them, so a name in an input file cannot clear
  the screen or reorder a line. Newlines and tabs pass; JSON is plain ASCII and passes unchanged.
"""

from __future__ import annotations

import contextlib
import os
import re
import sys

from pampipe.errors import StreamError

#: C0 and C1 controls but newline and tab, DEL, and Unicode format characters (Cf: soft hyphen, Arabic
#: and Syriac marks, zero-width characters, bidi embeddings, overrides and isolates, word joiners, BOM,
#: interlinear annotation), line and paragraph separators, lone surrogates.
UNSAFE = re.compile("[\x00-\x08\x0b-\x1f\x7f-\x9f\u00ad\u0600-\u0605\u061c\u06dd\u070f\u0890\u0891\u08e2"
                    "\u180e\u200b-\u200f\u2028-\u202e\u2060-\u2064\u2066-\u206f\ufeff\ufff9-\ufffb"
                    "\ud800-\udfff\U000110bd\U000110cd\U0001bca0-\U0001bca3\U0001d173-\U0001d17a"
                    "\U000e0001\U000e0020-\U000e007f]")

#: The characters of :data:`UNSAFE` that are ASCII: an ASCII text (most reports) is scanned for these alone.
UNSAFE_ASCII = re.compile("[\x00-\x08\x0b-\x1f\x7f]")


def _escape(match: re.Match) -> str:
    code = ord(match.group())
    return f"\\x{code:02x}" if code < 0x100 else f"\\u{code:04x}" if code < 0x10000 else f"\\U{code:08x}"


#: The ASCII bytes that pass unchanged (all but :data:`UNSAFE_ASCII`'s).
_SAFE_ASCII = bytes(code for code in range(128) if not UNSAFE_ASCII.match(chr(code)))


def safe_text(text: str) -> str:
    """``text`` with every character of :data:`UNSAFE` escaped (``\\x1b[2J`` shows as text).

    An ASCII text with nothing to escape (a JSON document: its encoder escapes the controls) is found so
    by deleting its safe bytes (``bytes.translate``, about 4× faster than the expression's scan, which
    took seconds on the 239 MB of a 10⁵-section ``plan --json``) and returned as it is."""
    if text.isascii():
        if not text.encode("ascii").translate(None, _SAFE_ASCII):
            return text
        return UNSAFE_ASCII.sub(_escape, text)
    return UNSAFE.sub(_escape, text)


class GuardedStream:
    """A text stream whose writes are made safe and whose failures raise :class:`StreamError`."""

    def __init__(self, stream, name: str) -> None:
        self._stream = stream
        self.name = name
        self.failed = False

    def write(self, text: str) -> int:
        return self.write_escaped(safe_text(text))

    def write_escaped(self, text: str) -> int:
        """:meth:`write` of a text that needs no escaping, without :func:`safe_text`'s scan (0.3 s of the
        239 MB of a 10⁵-section ``plan --json``): JSON from pampipe's writers, ASCII with every control
        character escaped by the encoder."""
        try:
            return self._stream.write(text)
        except (OSError, ValueError) as exc:  # ValueError: the stream was closed
            raise self._error(exc) from None

    def flush(self) -> None:
        try:
            self._stream.flush()
        except (OSError, ValueError) as exc:
            raise self._error(exc) from None

    def _error(self, exc: Exception) -> StreamError:
        self.failed = True
        why = getattr(exc, "strerror", None) or str(exc) or type(exc).__name__
        return StreamError(f"cannot write to {self.name} ({why}); the output is lost. Check the disk, "
                           f"or the program reading pampipe's {self.name}.", self.name)

    def __getattr__(self, name: str):  # isatty, fileno, encoding, ...: the wrapped stream's
        return getattr(self._stream, name)


@contextlib.contextmanager
def guarded():
    """Wrap sys.stdout and sys.stderr in :class:`GuardedStream` for the block; restore them after.

    Raises :class:`StreamError` at once if either was closed before the run (``>&-``).
    """
    closed = [name for name in ("stdout", "stderr") if getattr(sys, name) is None]
    if closed:
        if sys.stderr is not None:
            with contextlib.suppress(OSError, ValueError):
                print(f"pampipe: error: {closed[0]} is closed; nothing could be reported. Run pampipe with "
                      f"its {closed[0]} open (e.g. redirected to a file).", file=sys.stderr, flush=True)
        raise StreamError(f"{closed[0]} is closed", closed[0])
    saved = sys.stdout, sys.stderr
    sys.stdout, sys.stderr = GuardedStream(saved[0], "stdout"), GuardedStream(saved[1], "stderr")
    try:
        yield
    finally:
        streams = sys.stdout, sys.stderr
        sys.stdout, sys.stderr = saved
        for stream in streams:
            if getattr(stream, "failed", False):
                _silence(stream._stream)


def _silence(stream) -> None:
    """Point a failed stream at /dev/null, so that the interpreter's last flush cannot fail again."""
    with contextlib.suppress(OSError, ValueError, AttributeError):
        null = os.open(os.devnull, os.O_WRONLY)
        os.dup2(null, stream.fileno())
        os.close(null)
