"""Shared fixtures (the bundled muscles, an in-process CLI runner) and the session's hooks.

Helpers that tests import live in tests/support/."""

from __future__ import annotations

import os
import shutil
import tempfile

import pytest
from hypothesis import HealthCheck, settings

from pampipe.io.pam_schema import load_pam
from tests.support.order import heavy_first, shuffled
from tests.support.problems import PROBLEMS

#: No test depends on the machine's speed: hypothesis neither times examples nor calls slow data generation
#: an error (both fail on a busy machine, e.g. with two test runs at once). Tests' own settings build on this.
settings.register_profile("pampipe", deadline=None, suppress_health_check=[HealthCheck.too_slow])
settings.load_profile("pampipe")


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


def pytest_configure(config):
    """The on-disk NLP cache of the test run lives in a temporary folder (inherited by the CLI
    subprocesses), never in the user's ~/.cache; a cache the caller chose is kept. Under ``pytest -n N``
    each worker gets a folder of its own (the controller's variable is inherited, hence the marker
    variable), so no two test processes ever store or replace one entry at once."""
    worker = os.environ.get("PYTEST_XDIST_WORKER")
    if "PAMPIPE_NLP_CACHE" not in os.environ or (worker and os.environ.get("PAMPIPE_TEST_NLP_CACHE")):
        config._pampipe_cache = tempfile.mkdtemp(prefix=f"pampipe-test-nlp-{worker or 'main'}-")
        os.environ["PAMPIPE_NLP_CACHE"] = config._pampipe_cache
        os.environ["PAMPIPE_TEST_NLP_CACHE"] = "1"  # ours, not the caller's: a worker makes its own


def pytest_unconfigure(config):
    folder = getattr(config, "_pampipe_cache", None)
    if folder:
        shutil.rmtree(folder, ignore_errors=True)
        os.environ.pop("PAMPIPE_NLP_CACHE", None)
        os.environ.pop("PAMPIPE_TEST_NLP_CACHE", None)


def pytest_collection_modifyitems(session, config, items):
    """``PAMPIPE_TEST_SHUFFLE=SEED`` runs the tests in an order drawn from SEED (an integer), to find tests
    that depend on another test having run first: the modules in a shuffled order, and the tests of each
    module shuffled among themselves (a module's tests stay together: its module fixtures are built once).
    Every pytest-xdist worker draws the same order, as it must. The seed is printed in the header. Either way
    the longest modules go first (:func:`tests.support.order.heavy_first`), so the workers end together."""
    seed = os.environ.get("PAMPIPE_TEST_SHUFFLE")
    if seed:
        items[:] = shuffled(items, int(seed))
    items[:] = heavy_first(items)


def pytest_report_header(config):
    seed = os.environ.get("PAMPIPE_TEST_SHUFFLE")
    return f"test order shuffled: PAMPIPE_TEST_SHUFFLE={seed}" if seed else None


def pytest_terminal_summary(terminalreporter):
    """Report how many fuzz cases ran and how the CLI answered (issue 7)."""
    from tests.support.fuzzing import OUTCOMES

    if OUTCOMES:
        total = sum(OUTCOMES.values())
        parts = ", ".join(f"exit {code}: {n}" for code, n in sorted(OUTCOMES.items()))
        terminalreporter.write_line(f"fuzz: {total} CLI cases run ({parts}); 0 tracebacks")
