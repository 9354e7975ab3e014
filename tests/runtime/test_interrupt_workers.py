"""Ctrl-C and SIGTERM of `design --workers 2` at observed moments: exit 130 (143), one line, no process
left behind (issue 26). No wall-clock limit is asserted (a loaded machine may take long to unwind);
the timeouts below only guard against a hang.

Each run starts in its own session, so that Ctrl-C is simulated as a terminal sends it (SIGINT to the
whole process group, workers included) and leftovers are found by their process group. The moment is
chosen after a progress line, the k-th of the run (k random), so the signal lands while starts are
solved, queued or being collected.
"""

from __future__ import annotations

import os
import random
import signal
import subprocess
import sys
import time

import pytest

from tests.support.problems import PROBLEMS, ROOT

INVENTORY = PROBLEMS / "inventories" / "ky4.yaml"


def _group_alive(pgid: int) -> bool:
    try:
        os.killpg(pgid, 0)
    except ProcessLookupError:
        return False
    return True


def interrupt_once(rng: random.Random, tmp_path) -> None:
    target = tmp_path / "designed.yaml"
    process = subprocess.Popen([sys.executable, "-m", "pampipe", "design", str(INVENTORY), "--workers", "2",
                                "-o", str(target)], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                               text=True, cwd=ROOT, start_new_session=True)
    wanted = rng.randint(1, 6)
    seen = []
    try:
        while len(seen) < wanted:
            line = process.stderr.readline()
            if not line:
                pytest.skip(f"the run ended after {len(seen)} progress lines, before the chosen moment")
            seen.append(line)
        group = rng.random() < 0.5
        signum = signal.SIGINT if group else rng.choice([signal.SIGINT, signal.SIGTERM])
        if group:
            os.killpg(process.pid, signum)  # Ctrl-C: the terminal signals the whole foreground group
        else:
            process.send_signal(signum)
        _, rest = process.communicate(timeout=600)  # a guard against a hang, not a measurement
    finally:
        if process.poll() is None:
            os.killpg(process.pid, signal.SIGKILL)
            process.wait()
    # the workers are reaped by init once the parent is gone: wait for that, with a hang guard only
    deadline = time.monotonic() + 600
    while _group_alive(process.pid) and time.monotonic() < deadline:
        time.sleep(0.05)
    left = _group_alive(process.pid)
    if left:
        os.killpg(process.pid, signal.SIGKILL)
    lines = [line for line in rest.splitlines() if line.strip() and not line.startswith("design starts:")]
    context = f"after {wanted} progress lines, {signum.name}{' to the group' if group else ''}: {rest!r}"
    assert process.returncode == 128 + signum, context  # 130 for SIGINT, 143 for SIGTERM
    assert lines == ["pampipe design: interrupted; no partial output was written."], context
    assert not left, f"processes of the run remain; {context}"
    assert not target.exists() and not list(tmp_path.iterdir()), context


@pytest.mark.parametrize("seed", range(3))
def test_design_with_workers_ends_cleanly_when_interrupted(seed, tmp_path):
    interrupt_once(random.Random(seed), tmp_path)


@pytest.mark.slow
def test_thirty_interrupts_under_load(tmp_path_factory):
    """30 interrupts while two busy loops load the machine (the issue saw hangs and child tracebacks)."""
    load = [subprocess.Popen([sys.executable, "-c", "while True: pass"]) for _ in range(2)]
    try:
        rng = random.Random(26)
        for k in range(30):
            interrupt_once(rng, tmp_path_factory.mktemp(f"run{k}"))
    finally:
        for process in load:
            process.kill()
            process.wait()
