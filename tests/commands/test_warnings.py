"""A user sees pampipe's words, not numpy's: no "RuntimeWarning: invalid value encountered" on stderr.

The one-row-per-test fit (issue 27's case) takes √ of a negative number on its way to the PAM it writes with
nearly every direction open; numpy's warning used to reach the terminal before pampipe's own lines."""

from __future__ import annotations

import shutil
import subprocess
import sys

from tests.support.problems import PROBLEMS


def test_numpy_floating_point_warnings_do_not_reach_the_user(tmp_path):
    folder = shutil.copytree(PROBLEMS / "experiments", tmp_path / "case")
    for csv in (folder / "data" / "paper-protocol").glob("*.csv"):
        csv.write_text("\n".join(csv.read_text().splitlines()[:2]) + "\n")  # the header and one row
    command = [sys.executable, "-m", "pampipe", "identify", "paper-protocol.yaml", "-o", "fit.yaml"]
    run = subprocess.run(command, cwd=folder, capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stderr
    assert "Warning" not in run.stderr and "Traceback" not in run.stderr, run.stderr
    # what stderr holds is pampipe's own lines (progress, the bad-fit warning), never a library's
    assert all(line.startswith(("pampipe", "warning", "  ")) or not line.strip()
               for line in run.stderr.splitlines()), run.stderr
    assert "site-packages" not in run.stderr, run.stderr
    assert (folder / "fit.yaml").exists()
