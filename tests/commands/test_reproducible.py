"""Reproducibility (issue 7): the same inputs give byte-identical JSON, whatever the thread count.

Wall-clock timings (``*wall_time_s``) are the only entries that differ between runs; ``--reproducible``
writes them as 0, and everything else must match to the byte.
"""

from __future__ import annotations

import os
import subprocess
import sys

import pytest

from tests.support.problems import PROBLEMS, ROOT

MISSION = PROBLEMS / "missions" / "vertical-climb-3in.yaml"
COMMANDS = {
    "simulate": ["simulate", PROBLEMS / "pams" / "paper-radial-pam.yaml", "-d", "3 in", "-d", "3.5 in",
                 "-f", "0 N", "-f", "1024.74 N", "--json"],
    "identify": ["identify", PROBLEMS / "experiments" / "paper-protocol.yaml", "--json"],
    "plan": ["plan", MISSION, "--json", "--max-payload"],
    "plan-confidence": ["plan", PROBLEMS / "missions" / "riser-uncertain-friction.yaml", "--json",
                        "--confidence", "0.9"],
    "gait": ["gait", MISSION, "--json", "--optimal"],
    "design": ["design", PROBLEMS / "inventories" / "plant.yaml", "--json", "--starts", "4"],
}


def _run(args, threads: int) -> bytes:
    env = dict(os.environ, OMP_NUM_THREADS=str(threads), OPENBLAS_NUM_THREADS=str(threads),
               MKL_NUM_THREADS=str(threads))
    out = subprocess.run([sys.executable, "-m", "pampipe", *map(str, args), "--reproducible"],
                         capture_output=True, cwd=ROOT,
                         env=env, timeout=600)
    assert out.returncode == 0, out.stderr.decode()
    return out.stdout


@pytest.mark.parametrize("command", COMMANDS)
def test_json_is_byte_identical_across_runs_and_thread_counts(command):
    """Two runs, each a process of its own, on one and on two threads: equal bytes show both that a run
    repeats and that the thread count changes nothing (a third run on one thread added no other check)."""
    first = _run(COMMANDS[command], threads=1)
    assert first == _run(COMMANDS[command], threads=2)
    assert b'"' in first  # a JSON document was printed (not an empty stdout)
