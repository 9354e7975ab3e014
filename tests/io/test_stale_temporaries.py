"""Temporary files of a killed run are removed at the next run (issue 27: one hidden 0-byte file per
SIGKILL during --plots). A temporary file names its process; only those of dead processes go."""

from __future__ import annotations

import os
import subprocess
import sys

from pampipe.io.files import atomic_write_set, atomic_write_text


def _dead_pid() -> int:
    process = subprocess.Popen([sys.executable, "-c", "pass"])
    process.wait()
    return process.pid


def test_stale_temporary_files_of_a_target_are_removed(tmp_path):
    dead = _dead_pid()
    stale = tmp_path / f".plan.png.{dead}.abcd1234.tmp"
    live = tmp_path / f".plan.png.{os.getpid()}.efgh5678.tmp"  # a write of this very process
    other = tmp_path / f".other.png.{dead}.abcd1234.tmp"  # another target's: left to its own next run
    for path in (stale, live, other):
        path.write_bytes(b"")
    atomic_write_text(tmp_path / "plan.png", "new")
    assert not stale.exists() and live.exists() and other.exists()
    assert (tmp_path / "plan.png").read_text() == "new"


def test_stale_staging_folders_of_an_export_are_removed(tmp_path):
    dead = _dead_pid()
    stale = tmp_path / f".firmware.pampipe-{dead}-x1y2"
    stale.mkdir()
    (stale / "pampipe_plan.h").write_text("half")
    atomic_write_set(tmp_path / "firmware", {"a.h": "1", "a.c": "2"})
    assert not stale.exists()
    assert sorted(os.listdir(tmp_path)) == ["firmware"]
    assert (tmp_path / "firmware" / "a.c").read_text() == "2"
