"""pampipe.runtime.heap: with freed memory retained, a loop of MB-sized numpy temporaries stops faulting
pages in.

Page faults are counted (getrusage), not timed: each fresh 2.6 MB temporary costs ~640 faults when glibc
unmaps it on free, and none when the block is reused."""

from __future__ import annotations

import subprocess
import sys

import pytest

LOOP = """
import resource, sys
import numpy as np
from pampipe.runtime.heap import retain_freed_memory
taken = retain_freed_memory() if sys.argv[1] == "retain" else None
x = np.ones((10000, 33))
before = resource.getrusage(resource.RUSAGE_SELF).ru_minflt
for _ in range(100):
    y = np.sort(x * 2.0 + 1.0, axis=0)
    z = np.where(y > 1, y, 0.0)
    del y, z
print(taken, resource.getrusage(resource.RUSAGE_SELF).ru_minflt - before)
"""


def _faults(mode: str) -> tuple[str, int]:
    out = subprocess.run([sys.executable, "-c", LOOP, mode], capture_output=True, text=True, check=True)
    taken, faults = out.stdout.split()
    return taken, int(faults)


def test_retained_memory_is_reused_without_page_faults():
    taken, retained = _faults("retain")
    if taken != "True":
        pytest.skip("this C library has no mallopt (not glibc): pampipe.runtime.heap changes nothing here")
    _, default = _faults("default")
    assert default > 300 * 100, default  # the control: glibc's default faults every temporary in
    assert retained < default / 10, (retained, default)

