"""Shared fixtures: the bundled problem files and a CLI runner."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from pampipe.io.config import load_pam

ROOT = Path(__file__).resolve().parent.parent
PROBLEMS = ROOT / "problems"


@pytest.fixture(scope="session")
def radial_pam():
    """The paper's radial-test muscle with the demo moduli (docs/physics.md §7)."""
    return load_pam(PROBLEMS / "pams" / "paper-radial-pam.yaml")


@pytest.fixture(scope="session")
def axial_load_pam():
    """The paper's axial-load test muscle (docs/physics.md §5.8)."""
    return load_pam(PROBLEMS / "pams" / "paper-axial-load-pam.yaml")


def run_cli(*args: str, cwd: Path | None = None, timeout: float = 300) -> subprocess.CompletedProcess:
    """Run ``python -m pampipe ARGS`` in a subprocess, as a user would."""
    return subprocess.run([sys.executable, "-m", "pampipe", *map(str, args)], capture_output=True,
                          text=True, cwd=cwd or ROOT, timeout=timeout)


def pytest_terminal_summary(terminalreporter):
    """Report how many fuzz cases ran and how the CLI answered (issue 7)."""
    from tests.fuzzing import OUTCOMES

    if OUTCOMES:
        total = sum(OUTCOMES.values())
        parts = ", ".join(f"exit {code}: {n}" for code, n in sorted(OUTCOMES.items()))
        terminalreporter.write_line(f"fuzz: {total} CLI cases run ({parts}); 0 tracebacks")
