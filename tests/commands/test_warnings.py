"""A user sees pampipe's words, not numpy's: no "RuntimeWarning: invalid value encountered" on stderr.

The one-row fit of the hostile corpus takes √ of a negative number on its way to its (correct) refusal;
numpy's warning used to reach the terminal before pampipe's error line."""

from __future__ import annotations

import shutil
import subprocess
import sys

from tests.support.problems import BAD_INPUTS

CASE = BAD_INPUTS / "identify-one-row-per-test-writes-no-pam"


def test_numpy_floating_point_warnings_do_not_reach_the_user(tmp_path):
    folder = shutil.copytree(CASE, tmp_path / "case")
    command = [sys.executable, "-m", "pampipe", "identify", "paper-protocol.yaml", "-o", "fit.yaml"]
    run = subprocess.run(command, cwd=folder, capture_output=True, text=True, timeout=300)
    assert run.returncode == 2, run.stderr
    assert "Warning" not in run.stderr, run.stderr
    # progress lines may come first on a slow machine (they show after a second of work): the error is the
    # last thing said, and nothing but pampipe's own lines comes before it
    before, error, _ = run.stderr.partition("pampipe identify: error:")
    assert error, run.stderr
    assert "Traceback" not in before and "site-packages" not in before, run.stderr
    assert not (folder / "fit.yaml").exists()
