"""Shared fixtures: the bundled problem files and a CLI runner."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import pytest
from hypothesis import HealthCheck, settings

from pampipe.io.pam_schema import load_pam

#: No test depends on the machine's speed: hypothesis neither times examples nor calls slow data generation
#: an error (both fail on a busy machine, e.g. with two test runs at once). Tests' own settings build on this.
settings.register_profile("pampipe", deadline=None, suppress_health_check=[HealthCheck.too_slow])
settings.load_profile("pampipe")

ROOT = Path(__file__).resolve().parent.parent
PROBLEMS = ROOT / "problems"


def in_fresh_interpreter(argv: list[str], watched: set[str], cache, cwd=ROOT):
    """(exit code, stdout, which of the top-level modules ``watched`` were loaded) of `pampipe ARGV` run in a
    fresh interpreter with the cache folder ``cache`` (or ``off``)."""
    code = ("import sys\nfrom pampipe.cli import main\n"
            f"code = main({argv!r})\n"
            f"loaded = sorted({{m.split('.')[0] for m in sys.modules}} & {set(watched)!r})\n"
            "print('LOADED', *loaded, file=sys.stderr)\nsys.exit(code)\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=cwd,
                         env={**os.environ, "PAMPIPE_NLP_CACHE": str(cache)}, timeout=300)
    loaded = next(line for line in out.stderr.splitlines() if line.startswith("LOADED")).split()[1:]
    return out.returncode, out.stdout, loaded


@pytest.fixture(scope="session")
def radial_pam():
    """The paper's radial-test muscle with the demo moduli (docs/physics.md §7)."""
    return load_pam(PROBLEMS / "pams" / "paper-radial-pam.yaml")


@pytest.fixture(scope="session")
def axial_load_pam():
    """The paper's axial-load test muscle (docs/physics.md §5.8)."""
    return load_pam(PROBLEMS / "pams" / "paper-axial-load-pam.yaml")


@pytest.fixture
def cli(capsys):
    """Run ``pampipe ARGS`` in this process (faster than a subprocess); returns code, stdout, stderr."""
    from types import SimpleNamespace

    from pampipe.cli import main

    def run(*args) -> SimpleNamespace:
        capsys.readouterr()
        code = main([str(a) for a in args])
        out = capsys.readouterr()
        return SimpleNamespace(returncode=code, stdout=out.out, stderr=out.err)

    return run


def run_cli(*args: str, cwd: Path | None = None, timeout: float = 300) -> subprocess.CompletedProcess:
    """Run ``python -m pampipe ARGS`` in a subprocess, as a user would."""
    return subprocess.run([sys.executable, "-m", "pampipe", *map(str, args)], capture_output=True,
                          text=True, cwd=cwd or ROOT, timeout=timeout)


def pytest_configure(config):
    """The on-disk NLP cache of the test run lives in a temporary folder (inherited by the CLI
    subprocesses), never in the user's ~/.cache; a cache the caller chose is kept."""
    if "PAMPIPE_NLP_CACHE" not in os.environ:
        config._pampipe_cache = tempfile.mkdtemp(prefix="pampipe-test-nlp-")
        os.environ["PAMPIPE_NLP_CACHE"] = config._pampipe_cache


def pytest_unconfigure(config):
    folder = getattr(config, "_pampipe_cache", None)
    if folder:
        shutil.rmtree(folder, ignore_errors=True)
        os.environ.pop("PAMPIPE_NLP_CACHE", None)


def pytest_terminal_summary(terminalreporter):
    """Report how many fuzz cases ran and how the CLI answered (issue 7)."""
    from tests.fuzzing import OUTCOMES

    if OUTCOMES:
        total = sum(OUTCOMES.values())
        parts = ", ".join(f"exit {code}: {n}" for code, n in sorted(OUTCOMES.items()))
        terminalreporter.write_line(f"fuzz: {total} CLI cases run ({parts}); 0 tracebacks")
