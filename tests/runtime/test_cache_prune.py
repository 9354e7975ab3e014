"""The cache deletes only what pampipe made (issue 38 items 2, 3 and 4; pampipe/runtime/cache.py).

Pruning needs the marker file pampipe writes in a folder it makes its cache, and touches only entries of its
name pattern; a folder of the user's is refused as the cache (the command runs uncached); staging folders
are removed when a store fails and, when stale, by the next run.
"""

from __future__ import annotations

import errno
import hashlib
import os
import subprocess
import sys
import time

import pytest

from pampipe.runtime import cache as disk
from tests.support.problems import ROOT

DEMO = "problems/missions/vertical-climb-3in.yaml"


def _plan(cache, cwd=ROOT) -> subprocess.CompletedProcess:
    env = {**os.environ, "PAMPIPE_NLP_CACHE": str(cache)}
    argv = [sys.executable, "-m", "pampipe", "plan", str(ROOT / DEMO), "--json", "--reproducible"]
    return subprocess.run(argv, capture_output=True, text=True, cwd=cwd, env=env, timeout=300)


def _user_folders(place, count=100):
    """``count`` folders of the user's in ``place``, each holding a file; their names."""
    names = [f"{('data', 'mission', 'notes', 'run')[i % 4]}-{i:03d}" for i in range(count)]
    for name in names:
        (place / name).mkdir(parents=True)
        (place / name / "keep.txt").write_text(name)
    return names


def test_a_folder_of_the_users_is_refused_as_the_cache_and_nothing_deleted(tmp_path):
    """PAMPIPE_NLP_CACHE=. in a project folder of 100 folders: the plan runs uncached, one message, no file
    written or removed, and pruning it (were it asked) removes nothing either."""
    project = tmp_path / "project"
    names = _user_folders(project)
    (project / "notes.txt").write_text("mine")
    before = sorted(str(p.relative_to(project)) for p in project.rglob("*"))
    run = _plan(".", cwd=project)
    assert run.returncode == 0, run.stderr
    said = [line for line in run.stderr.splitlines() if "not using the cache folder" in line]
    assert len(said) == 1 and "not pampipe's cache" in said[0], run.stderr
    disk.prune(project)
    disk.remove_stale_staging(project)
    assert sorted(str(p.relative_to(project)) for p in project.rglob("*")) == before
    assert all((project / name / "keep.txt").read_text() == name for name in names)


def test_pruning_a_marked_cache_removes_only_the_oldest_of_its_own_entries(tmp_path, monkeypatch):
    """A cache (made by pampipe) where the user also put 100 folders: beyond CACHE_ENTRIES entries the
    oldest entries go, the user's folders stay."""
    cache = tmp_path / "cache"
    monkeypatch.setenv(disk.CACHE_VARIABLE, str(cache))
    root = disk.cache_root()
    assert root == cache and (cache / disk.MARKER).is_file()
    names = _user_folders(cache)
    extra = 5
    digests = [hashlib.sha256(str(i).encode()).hexdigest() for i in range(disk.CACHE_ENTRIES + extra)]
    now = time.time()
    for age, digest in enumerate(digests):
        disk.store(root, "demo", digest, {"data": digest.encode()})
        entry = cache / disk.entry_name("demo", digest)
        os.utime(entry, (now - 1000 + age,) * 2)  # the first stored is the oldest
    disk.prune(root)
    left = [digest for digest in digests if disk.load(root, "demo", digest) is not None]
    assert left == digests[extra:]
    assert all((cache / name / "keep.txt").read_text() == name for name in names)


def test_a_stale_staging_folder_is_removed_by_the_next_run_and_nothing_else(tmp_path):
    cache = tmp_path / "cache"
    assert _plan(cache).returncode == 0
    hour = disk.STALE_AFTER
    folders = {
        f".staging-identify-{'a' * 32}-123-abcdefgh": (2 * hour, False),  # a killed store: removed
        f".identify-{'b' * 32}-abcdefgh": (2 * hour, False),  # a killed store of the former version
        f".staging-identify-{'c' * 32}-123-abcdefgh": (0.0, True),  # a store under way: kept
        ".staging-mine": (2 * hour, True),  # not pampipe's name: kept
        ".hidden-notes": (2 * hour, True),
    }
    for name, (age, _) in folders.items():
        (cache / name).mkdir()
        (cache / name / "part").write_bytes(b"x" * 100)
        os.utime(cache / name, (time.time() - age, time.time() - age))
    assert _plan(cache).returncode == 0
    left = {name: (cache / name).is_dir() for name in folders}
    assert left == {name: kept for name, (_, kept) in folders.items()}


@pytest.mark.parametrize("failure", ["raises", "disk full"])
def test_a_failed_store_leaves_no_staging_folder_and_no_entry(tmp_path, monkeypatch, failure):
    cache = tmp_path / "cache"
    monkeypatch.setenv(disk.CACHE_VARIABLE, str(cache))
    root = disk.cache_root()
    write = os.write

    def short(fd, data):  # a disk that fills after 1000 bytes
        if failure == "raises":
            raise OSError(errno.EIO, "I/O error")
        if os.fstat(fd).st_size >= 1000:
            raise OSError(errno.ENOSPC, "No space left on device")
        return write(fd, data[:1000])

    monkeypatch.setattr(disk.os, "write", short)
    disk.store(root, "demo", "d" * 64, {"functions.casadi": b"f" * 5000})
    monkeypatch.setattr(disk.os, "write", write)
    assert sorted(p.name for p in cache.iterdir()) == [disk.MARKER]
    assert disk.load(root, "demo", "d" * 64) is None
