"""A per-process memo of what the chunks of a confidence plan share (docs/physics.md §15, *Shared draws*).

The muscle's parameter draws, and its coefficients at the anchored length, depend on the draw and the
bore only, not on the load: every chunk of classes in the same bore needs the same ones. A chunk is a task
on any executor (:mod:`pampipe.runtime.executors`), so they are kept per process, under a key that names
everything
they depend on (the draws' key, the segment, the sources, the bore statement); a process computes them
once, whatever the chunks it runs and their order, and the numbers are those it would compute again.
"""

from __future__ import annotations

import threading

import numpy as np


class Memo:
    """Values (numpy arrays, or objects holding some) by key, the oldest forgotten first beyond ``budget``
    bytes of arrays; thread-safe (a Dask worker may run chunks in several threads)."""

    def __init__(self, budget: int):
        self.budget = budget
        self._values: dict = {}
        self._sizes: dict = {}
        self._total = 0  # the sum of _sizes [B]
        self._lock = threading.Lock()

    def get(self, key, compute):
        """The value kept under ``key``, else ``compute()`` (outside the lock), kept."""
        with self._lock:
            if key in self._values:
                return self._values[key]
        value = compute()
        parts = [value] if isinstance(value, np.ndarray) else vars(value).values()
        size = sum(v.nbytes for v in parts if isinstance(v, np.ndarray))
        with self._lock:
            self._total += size - self._sizes.get(key, 0)  # another thread may have kept it meanwhile
            self._values[key], self._sizes[key] = value, size
            while self._total > self.budget and len(self._values) > 1:
                oldest = next(iter(self._values))
                self._total -= self._sizes.pop(oldest)
                del self._values[oldest]
        return value
