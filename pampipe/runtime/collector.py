"""Python's cycle collector paused while large acyclic structures are built (big mission files).

Reading a route of 10⁵ sections allocates millions of dicts, strings and schema objects; each of them
makes the cycle collector's counters tick, and its full passes scan every live object: at 10⁵ sections
that was 0.6 s of a 3 s plan. None of those objects form reference cycles (YAML aliases that would are
refused), so they are freed by reference counting; the collector resumes afterwards and
finds any cycle made meanwhile.
"""

from __future__ import annotations

import gc
from contextlib import contextmanager


@contextmanager
def paused():
    """Pause the cycle collector inside the block (if it was running), resume it after."""
    running = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if running:
            gc.enable()
