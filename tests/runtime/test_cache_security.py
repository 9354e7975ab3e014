"""The cache runs no one's code and trusts only the user's folders (issue 38 items 1 and 4;
pampipe/runtime/cache.py, pampipe/io/datatree.py, pampipe/io/validated.py).

Each case plants what an attacker sharing the machine (or a damaged disk) would leave in the cache, runs
`pampipe plan` in a fresh process, and checks that the plan is the one an uncached run gives, that nothing
planted ran (the planted pickle would create a file), and that the user is told once which folder or entry
was not trusted and why.
"""

from __future__ import annotations

import hashlib
import json
import os
import pickle
import shutil
import stat
import subprocess
import sys
from pathlib import Path

import pytest

from tests.support.problems import ROOT

DEMO = "problems/missions/vertical-climb-3in.yaml"
OTHER = "problems/missions/downhill-drain.yaml"
MARKER = ".pampipe-cache"
FOREIGN_UID = 4242  # a uid no test process runs as


#: `python -m pampipe ARGS` in a process whose os.geteuid() answers UID (`python -c AS_UID UID ARGS`)
AS_UID = ("import os, runpy, sys; uid = int(sys.argv.pop(1)); os.geteuid = lambda: uid; "
          "runpy.run_module('pampipe', run_name='__main__', alter_sys=True)")


def _plan(mission: str, cache, as_uid: int | None = None, **options) -> subprocess.CompletedProcess:
    env = {**os.environ, "PAMPIPE_NLP_CACHE": str(cache)}
    python = [sys.executable, *(["-m", "pampipe"] if as_uid is None else ["-c", AS_UID, str(as_uid)])]
    return subprocess.run([*python, "plan", mission, "--json", "--reproducible"],
                          capture_output=True, text=True, cwd=ROOT, env=env, timeout=300, **options)


def _give_away(paths) -> tuple[int | None, int]:
    """Make ``paths`` another user's, as far as pampipe can tell, whatever uid runs the suite: as root,
    os.chown them to FOREIGN_UID; otherwise (chown needs root) keep them and plan in a process whose
    effective uid reads FOREIGN_UID. Returns (the uid to plan as, the owner pampipe must name)."""
    if hasattr(os, "geteuid") and os.geteuid() == 0:
        for path in paths:
            os.chown(path, FOREIGN_UID, FOREIGN_UID)
        return None, FOREIGN_UID
    return FOREIGN_UID, os.stat(next(iter(paths))).st_uid


@pytest.fixture(scope="module")
def uncached() -> dict[str, str]:
    """The JSON plans of DEMO and OTHER without a cache."""
    out = {}
    for mission in (DEMO, OTHER):
        run = _plan(mission, "off")
        assert run.returncode == 0, run.stderr
        out[mission] = run.stdout
    return out


class _Planted:
    """Unpickling this creates the file ``path``: proof that a pickle ran."""

    def __init__(self, path: Path):
        self.path = path

    def __reduce__(self):
        return open, (str(self.path), "w")


@pytest.fixture(scope="module")
def warm(tmp_path_factory) -> Path:
    """A cache where `plan` kept DEMO and OTHER (each test works on a copy)."""
    folder = tmp_path_factory.mktemp("warm") / "cache"
    for mission in (DEMO, OTHER):
        assert _plan(mission, folder).returncode == 0
    return folder


@pytest.fixture()
def cache(tmp_path, warm) -> Path:
    """A copy of the warm cache, owned by the test."""
    shutil.copytree(warm, tmp_path / "cache")
    return tmp_path / "cache"


def _entry(cache: Path, mission: str = DEMO) -> Path:
    """The entry of ``mission`` in ``cache``."""
    (entry,) = [p for p in cache.glob("mission-*") if _stands_for(p, mission)]
    return entry


def _stands_for(entry: Path, mission: str) -> bool:
    kept = json.loads((entry / "loaded.json").read_bytes())
    return [mission, hashlib.sha256((ROOT / mission).read_bytes()).hexdigest()] in kept["inputs"]


def _rewrite(entry: Path, name: str, data: bytes) -> None:
    """Replace the file ``name`` of ``entry`` by ``data`` and update its manifest to match, as someone who can
    write the entry would: the format and the trust checks, not the hash, must then keep it out."""
    (entry / name).write_bytes(data)
    manifest = json.loads((entry / "manifest.json").read_bytes())
    manifest["files"][name] = [len(data), hashlib.sha256(data).hexdigest()]
    (entry / "manifest.json").write_text(json.dumps(manifest))


def _legacy_entry(cache: Path, mission: str) -> Path:
    """The folder where the former reader looked for ``mission``'s pickle (kind, working folder, path as
    given, the file's hash, the source stamp, the Python version)."""
    from pampipe.runtime.cache import source_stamp

    digest = hashlib.sha256((ROOT / mission).read_bytes()).hexdigest()
    key = "\0".join(["mission", str(ROOT), mission, digest, source_stamp(), sys.version])
    return cache / f"mission-{hashlib.sha256(key.encode()).hexdigest()[:32]}"


def test_a_planted_pickle_never_runs_and_never_replaces_the_plan(tmp_path, cache, uncached):
    ran = tmp_path / "the-pickle-ran"
    entry = _entry(cache)
    planted = pickle.dumps((_Planted(ran), "a plan of someone else's"))
    _rewrite(entry, "loaded.json", planted)  # in the entry read now, with a matching manifest
    legacy = _legacy_entry(cache, DEMO)  # and where the former reader unpickled it
    legacy.mkdir(mode=0o700)
    (legacy / "loaded.pickle").write_bytes(planted)
    os.chmod(legacy / "loaded.pickle", 0o600)
    run = _plan(DEMO, cache)
    assert run.returncode == 0, run.stderr
    assert not ran.exists(), "the planted pickle ran"
    assert run.stdout == uncached[DEMO]
    assert _plan(DEMO, cache).stdout == uncached[DEMO]  # kept anew, read back: the same plan
    assert not ran.exists()


@pytest.mark.parametrize("inputs", ["none", "the other mission's"])
def test_a_swapped_entry_never_replaces_the_plan(cache, uncached, inputs):
    """The entry of OTHER holding DEMO's mission, with no inputs (or DEMO's own, all unchanged) and a matching
    manifest: an entry stands only for a file it names and hashes, so OTHER is planned from its file."""
    demo, other = _entry(cache, DEMO), _entry(cache, OTHER)
    swapped = json.loads((demo / "loaded.json").read_bytes())
    if inputs == "none":
        swapped["inputs"] = []
    _rewrite(other, "loaded.json", json.dumps(swapped).encode())
    run = _plan(OTHER, cache)
    assert run.returncode == 0, run.stderr
    assert run.stdout == uncached[OTHER] != uncached[DEMO]


def _swap_in(cache: Path, entry: Path) -> None:
    """Put OTHER's mission in ``entry`` (DEMO's) with DEMO's inputs and a matching manifest: used, it would
    plan OTHER for DEMO, so a plan equal to DEMO's shows the entry was not."""
    swapped = json.loads((_entry(cache, OTHER) / "loaded.json").read_bytes())
    swapped["inputs"] = json.loads((entry / "loaded.json").read_bytes())["inputs"]
    _rewrite(entry, "loaded.json", json.dumps(swapped).encode())


def _said(stderr: str, what: str) -> list[str]:
    return [line for line in stderr.splitlines() if what in line]


@pytest.mark.skipif(not hasattr(os, "geteuid"), reason="no uids on this system")
def test_a_foreign_owned_cache_folder_is_skipped_with_one_message(cache, uncached):
    _swap_in(cache, _entry(cache))
    as_uid, owner = _give_away([cache, *cache.rglob("*")])
    before = sorted(p.name for p in cache.rglob("*"))
    run = _plan(DEMO, cache, as_uid)
    assert run.returncode == 0 and run.stdout == uncached[DEMO], run.stderr
    said = _said(run.stderr, "not using the cache folder")
    assert len(said) == 1, run.stderr  # plan looks twice (to read, to keep): told once
    assert str(cache) in said[0] and f"owned by uid {owner}," in said[0]
    assert sorted(p.name for p in cache.rglob("*")) == before  # nothing written into it either


# Root only: a process that only believes it is another uid (as above) finds the folder foreign first.
@pytest.mark.skipif(not hasattr(os, "geteuid") or os.geteuid() != 0,
                    reason="giving a cache entry, not its folder, to another uid needs root (os.chown)")
def test_a_foreign_owned_entry_is_skipped_with_one_message(cache, uncached):
    entry = _entry(cache)
    _swap_in(cache, entry)
    for path in [entry, *entry.iterdir()]:
        os.chown(path, FOREIGN_UID, FOREIGN_UID)
    run = _plan(DEMO, cache)
    assert run.returncode == 0 and run.stdout == uncached[DEMO], run.stderr
    said = _said(run.stderr, "ignoring the cache entry")
    assert len(said) == 1 and str(entry) in said[0] and f"uid {FOREIGN_UID}" in said[0], run.stderr
    assert entry.stat().st_uid == FOREIGN_UID  # neither used nor removed


@pytest.mark.parametrize("where", ["folder", "entry", "file"])
def test_a_group_writable_cache_is_skipped_with_one_message(cache, uncached, where):
    entry = _entry(cache)
    _swap_in(cache, entry)
    loose = {"folder": cache, "entry": entry, "file": entry / "loaded.json"}[where]
    os.chmod(loose, stat.S_IMODE(loose.stat().st_mode) | stat.S_IWGRP)
    run = _plan(DEMO, cache)
    assert run.returncode == 0 and run.stdout == uncached[DEMO], run.stderr
    told = "not using the cache folder" if where == "folder" else "ignoring the cache entry"
    said = _said(run.stderr, told)
    assert len(said) == 1 and "group or others can write it" in said[0], run.stderr
    assert str(cache if where == "folder" else entry) in said[0]


def test_umask_000_still_gives_0700_folders_and_0600_files(tmp_path):
    """The default folder ($XDG_CACHE_HOME/pampipe/nlp), made by a plan and an NLP build under umask 000."""
    env = {key: value for key, value in os.environ.items() if key != "PAMPIPE_NLP_CACHE"}
    env["XDG_CACHE_HOME"] = str(tmp_path / "xdg")
    build = ("import casadi as ca\nfrom pampipe.runtime.ipopt import cached_functions\nx = ca.SX.sym('x')\n"
             "cached_functions('demo', 'umask', lambda: {'f': ca.Function('f', [x], [x * x])})\n")
    for argv in (["-m", "pampipe", "plan", DEMO, "--json"], ["-c", build]):
        run = subprocess.run([sys.executable, *argv], capture_output=True, text=True, cwd=ROOT, env=env,
                             timeout=300, umask=0)
        assert run.returncode == 0, run.stderr
    made = tmp_path / "xdg" / "pampipe"
    paths = [made, *made.rglob("*")]
    assert (made / "nlp" / MARKER).is_file()
    assert {p.name for p in made.glob("nlp/*/*")} == {"loaded.json", "manifest.json", "functions.casadi"}
    modes = {str(p.relative_to(tmp_path)): stat.S_IMODE(p.stat().st_mode) for p in paths}
    wanted = {str(p.relative_to(tmp_path)): 0o700 if p.is_dir() else 0o600 for p in paths}
    assert modes == wanted


def test_a_legacy_cache_is_adopted_and_its_pickles_never_read(tmp_path, uncached):
    """A cache an earlier pampipe made (entries only, no marker) is marked and used; its pickles are left."""
    cache, ran = tmp_path / "cache", tmp_path / "the-pickle-ran"
    legacy = _legacy_entry(cache, DEMO)
    legacy.mkdir(parents=True)
    (legacy / "loaded.pickle").write_bytes(pickle.dumps(_Planted(ran)))
    run = _plan(DEMO, cache)
    assert run.returncode == 0 and run.stdout == uncached[DEMO] and not ran.exists()
    assert (cache / MARKER).is_file() and "not using" not in run.stderr
    assert (legacy / "loaded.pickle").is_file()  # left alone (pruned in turn with the oldest entries)
