"""A damaged cache never crashes a command and never changes its answer (issue 38 items 3 and 4;
pampipe/runtime/cache.py, pampipe/runtime/ipopt.py).

Every file of a cache entry (and the folder's marker) is damaged 20 times (a kept mission's files 9 times),
seeded: bits flipped, the file cut short, a span zero-filled. Each damage is read in a child process, so that
a crash (CasADi reading a damaged serialisation used to end ``identify`` with SIGSEGV) shows as its exit
code, and the answer must be the uncached one to the byte.
"""

from __future__ import annotations

import inspect
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from tests.support.problems import PROBLEMS, ROOT

DAMAGES = 20
DEMO = "problems/missions/vertical-climb-3in.yaml"
EXPERIMENT = str(PROBLEMS / "experiments" / "paper-protocol.yaml")


def damaged(data: bytes, seed: int, i: int) -> bytes:
    """``data`` with damage ``i`` of the series ``seed``: 1-3 bits flipped (i = 0 mod 3), cut short (1) or a
    span zero-filled (2)."""
    import numpy as np

    rng, how, out = np.random.default_rng([seed, i]), i % 3, bytearray(data)
    if how == 0:
        for bit in rng.choice(8 * len(out), size=min(3, 8 * len(out)), replace=False):
            out[bit // 8] ^= 1 << (bit % 8)
    elif how == 1:
        del out[rng.integers(len(out)):]
    else:
        start = int(rng.integers(len(out)))
        stop = min(len(out), start + int(rng.integers(1, 4096)))
        out[start:stop] = bytes(stop - start)
    return bytes(out)


def _files(cache: Path) -> list[Path]:
    """Every file of the cache, the marker included, relative to it."""
    return sorted(p.relative_to(cache) for p in cache.rglob("*") if p.is_file())


#: Run in a child: for each damage, restore the warm cache, damage one file, run the command in-process;
#: exit 1 at the first answer that differs (a crash ends the child with a signal).
_DRIVER = """
import contextlib, io, shutil, sys
from pathlib import Path
from pampipe.cli import main
{damaged}
pristine, cache, name, seed = {pristine!r}, {cache!r}, {name!r}, {seed}
argv, reference = {argv!r}, {reference!r}
for i in {damages!r}:
    shutil.rmtree(cache, ignore_errors=True)
    shutil.copytree(pristine, cache)
    target = Path(cache) / name
    target.write_bytes(damaged(target.read_bytes(), seed, i))
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        code = main(argv)
    if code != 0 or out.getvalue() != reference:
        print(f"damage {{i}} of {{name}}: exit {{code}}, a different answer", file=sys.stderr)
        sys.exit(1)
"""


def _damage_each_file(tmp_path, argv: list[str], *, child_each: bool, damages: int = DAMAGES) -> None:
    """``damages`` seeded damages of every file a warm run of ``argv`` kept, each giving the uncached
    answer; ``child_each``: one child per damage (a command that keeps what it loaded in memory)."""
    reference = subprocess.run([sys.executable, "-m", "pampipe", *argv], capture_output=True, text=True,
                               cwd=ROOT, env={**os.environ, "PAMPIPE_NLP_CACHE": "off"}, timeout=600)
    assert reference.returncode == 0, reference.stderr
    pristine, cache = tmp_path / "pristine", tmp_path / "cache"
    env = {**os.environ, "PAMPIPE_NLP_CACHE": str(cache)}
    warm = subprocess.run([sys.executable, "-m", "pampipe", *argv], capture_output=True, text=True, cwd=ROOT,
                          env=env, timeout=600)
    assert warm.stdout == reference.stdout
    shutil.copytree(cache, pristine)
    files = _files(pristine)
    assert len(files) >= 3, files  # the marker, an entry's data and its manifest at least
    series = [[i] for i in range(damages)] if child_each else [list(range(damages))]
    for seed, name in enumerate(files):
        for damages in series:
            driver = _DRIVER.format(damaged=inspect.getsource(damaged), pristine=str(pristine),
                                    cache=str(cache), name=str(name), seed=seed, argv=argv,
                                    reference=reference.stdout, damages=damages)
            run = subprocess.run([sys.executable, "-c", driver], capture_output=True, text=True, cwd=ROOT,
                                 env=env, timeout=1800)
            assert run.returncode == 0, f"{name} {damages}: exit {run.returncode}\n{run.stderr[-2000:]}"


def test_damaged_mission_entries_give_the_uncached_plan(tmp_path):
    """9 damages of each file, 3 of each kind (a mission entry is JSON under a SHA-256 manifest: any damage
    is caught by the hash or the parse, so 20 add no case; the NLP files keep 20, where CasADi crashed)."""
    _damage_each_file(tmp_path, ["plan", DEMO, "--json", "--reproducible"], child_each=False, damages=9)


def test_an_entry_changed_under_its_manifest_is_not_used(tmp_path):
    """A kept mission whose JSON still parses after a change (the payload: 2 kg → 3 kg) is not read: its
    SHA-256 no longer matches the manifest."""
    argv = [sys.executable, "-m", "pampipe", "plan", DEMO, "--json", "--reproducible"]
    env = {**os.environ, "PAMPIPE_NLP_CACHE": str(tmp_path / "cache")}
    first = subprocess.run(argv, capture_output=True, text=True, cwd=ROOT, env=env, timeout=300)
    (kept,) = (tmp_path / "cache").glob("mission-*/loaded.json")
    text = kept.read_text()
    assert text.count('"payload":2.0,') == 1
    kept.write_text(text.replace('"payload":2.0,', '"payload":3.0,'))
    again = subprocess.run(argv, capture_output=True, text=True, cwd=ROOT, env=env, timeout=300)
    assert again.returncode == 0 and again.stdout == first.stdout


def build():
    """A small NLP solver (an nlpsol, as identify keeps) and a function, built fresh."""
    import casadi as ca

    x = ca.SX.sym("x", 3)
    f = ca.dot(x - 1, x - 1) + ca.sin(x[0])
    solver = ca.nlpsol("solver", "ipopt", {"x": x, "f": f, "g": x[1] + x[2]},
                       {"print_time": False, "ipopt": {"print_level": 0, "sb": "yes"}})
    return {"solver": solver, "f": ca.Function("f", [x], [f])}


#: In a child: keep the NLP, then for each damage restore it, damage one file, load it (rebuilt if damaged)
#: and check the loaded functions compute what the built ones do; then it must load from disk again.
_NLP_DRIVER = """
import shutil
from pathlib import Path
import numpy as np
from pampipe.runtime.ipopt import cached_functions
{damaged}
{build}
pristine, cache, name, seed = {pristine!r}, {cache!r}, {name!r}, {seed}
reference = build()
want = (float(reference["f"]([0.3, -1.2, 2.5])), reference["solver"](x0=[0, 0, 0], lbg=1, ubg=1)["x"].full())
for i in range({damages}):
    shutil.rmtree(cache, ignore_errors=True)
    shutil.copytree(pristine, cache)
    target = Path(cache) / name
    target.write_bytes(damaged(target.read_bytes(), seed, i))
    functions, _ = cached_functions("demo", "damage", build)
    got = (float(functions["f"]([0.3, -1.2, 2.5])),
           functions["solver"](x0=[0, 0, 0], lbg=1, ubg=1)["x"].full())
    assert got[0] == want[0] and np.array_equal(got[1], want[1]), (i, got, want)
    assert cached_functions("demo", "damage", build)[1] == "disk", i  # replaced by a whole entry
"""


#: The damage series of the NLP files: read unchecked, its damages 0 and 15 of functions.casadi crash CasADi
#: (SIGSEGV) with CasADi 3.8 (found by trying series), so the test fails if the check is taken away.
NLP_SEED = 9


def test_damaged_nlp_entries_never_crash_and_are_replaced(tmp_path):
    pristine, cache = tmp_path / "pristine", tmp_path / "cache"
    env = {**os.environ, "PAMPIPE_NLP_CACHE": str(pristine)}
    keep = (f"{inspect.getsource(build)}\nfrom pampipe.runtime.ipopt import cached_functions\n"
            "assert cached_functions('demo', 'damage', build)[1] == 'built'\n")
    assert subprocess.run([sys.executable, "-c", keep], cwd=ROOT, env=env, timeout=300).returncode == 0
    files = _files(pristine)
    assert {f.name for f in files} == {".pampipe-cache", "functions.casadi", "manifest.json"}
    env["PAMPIPE_NLP_CACHE"] = str(cache)
    for name in files:
        driver = _NLP_DRIVER.format(damaged=inspect.getsource(damaged), build=inspect.getsource(build),
                                    pristine=str(pristine), cache=str(cache), name=str(name), seed=NLP_SEED,
                                    damages=DAMAGES)
        run = subprocess.run([sys.executable, "-c", driver], capture_output=True, text=True, cwd=ROOT,
                             env=env, timeout=600)
        assert run.returncode == 0, f"{name}: exit {run.returncode}\n{run.stderr[-2000:]}"


def test_identify_with_flipped_bits_in_its_nlp_file_gives_the_same_fit(tmp_path):
    """The case of the issue: 3 bit flips in identify's kept NLP ended every run with SIGSEGV (these flips,
    damage 0 of series 23, do so with CasADi 3.8 when the file is read unchecked). Also the default run's
    check that a second process loads the NLP the first built and gives the same fit (the last run)."""
    argv = [sys.executable, "-m", "pampipe", "identify", EXPERIMENT, "--json", "--reproducible"]
    env = {**os.environ, "PAMPIPE_NLP_CACHE": str(tmp_path / "cache")}
    first = subprocess.run(argv, capture_output=True, text=True, cwd=ROOT, env=env, timeout=600)
    assert first.returncode == 0, first.stderr
    assert "loaded from the on-disk cache" not in first.stderr  # built: the cache was empty
    (kept,) = (tmp_path / "cache").glob("identify-*/functions.casadi")
    kept.write_bytes(damaged(kept.read_bytes(), 23, 0))
    runs = [subprocess.run(argv, capture_output=True, text=True, cwd=ROOT, env=env, timeout=600)
            for _ in range(2)]
    assert [r.returncode for r in runs] == [0, 0], runs[0].stderr[-2000:]
    assert [r.stdout for r in runs] == [first.stdout] * 2
    assert ["loaded from the on-disk cache" in r.stderr for r in runs] == [False, True]  # rebuilt, replaced


@pytest.mark.slow
def test_damaged_experiment_and_nlp_entries_give_the_uncached_fit(tmp_path):
    _damage_each_file(tmp_path, ["identify", EXPERIMENT, "--json", "--reproducible"], child_each=True)
