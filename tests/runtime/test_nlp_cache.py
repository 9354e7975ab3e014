"""The on-disk cache of built NLPs (pampipe/runtime/ipopt.py): a second process loads what the first built,
the loaded functions compute what the built ones did, damage and ``off`` are handled.

The reference is the function built in this process: a loaded copy must return the same numbers
to the last bit (CasADi's serialisation stores the expression graph, not a re-derivation).
"""

from __future__ import annotations

import os
import subprocess
import sys

import casadi as ca
import pytest

from pampipe.runtime import ipopt as nlp
from tests.support.problems import PROBLEMS, ROOT


def _square_plus_sine():
    x = ca.SX.sym("x", 3)
    return {"f": ca.Function("f", [x], [ca.dot(x, x) + ca.sin(x[0])])}


def _entries(cache):
    """The entries of the cache folder (not its marker file)."""
    return [p for p in cache.iterdir() if p.name != ".pampipe-cache"]


@pytest.fixture()
def cache(tmp_path, monkeypatch):
    folder = tmp_path / "cache"
    monkeypatch.setenv(nlp.CACHE_VARIABLE, str(folder))
    return folder


def test_second_call_loads_what_the_first_built(cache):
    built, origin = nlp.cached_functions("demo", "structure-1", _square_plus_sine)
    assert origin == "built" and len(_entries(cache)) == 1
    loaded, origin = nlp.cached_functions("demo", "structure-1", _square_plus_sine)
    assert origin == "disk"
    point = [0.3, -1.2, 2.5]
    assert float(loaded["f"](point)) == float(built["f"](point))


def test_another_structure_is_another_entry(cache):
    nlp.cached_functions("demo", "structure-1", _square_plus_sine)
    _, origin = nlp.cached_functions("demo", "structure-2", _square_plus_sine)
    assert origin == "built" and len(_entries(cache)) == 2


def test_a_damaged_entry_is_replaced(cache):
    nlp.cached_functions("demo", "structure-1", _square_plus_sine)
    (entry,) = _entries(cache)
    for file in entry.glob("*.casadi"):
        file.write_text("not a casadi function")
    _, origin = nlp.cached_functions("demo", "structure-1", _square_plus_sine)
    assert origin == "built"
    loaded, origin = nlp.cached_functions("demo", "structure-1", _square_plus_sine)
    assert origin == "disk" and float(loaded["f"]([1.0, 0.0, 0.0])) == pytest.approx(1.0 + 0.8414709848078965)


def test_off_builds_every_time_and_writes_nothing(tmp_path, monkeypatch):
    monkeypatch.setenv(nlp.CACHE_VARIABLE, "off")
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    for _ in range(2):
        assert nlp.cached_functions("demo", "structure-1", _square_plus_sine)[1] == "built"
    assert not any(tmp_path.iterdir())


@pytest.mark.slow
def test_identify_in_a_second_process_loads_the_nlp_and_gives_the_same_fit(tmp_path):
    """Two whole `identify` runs sharing one cache folder: built, then loaded; identical JSON. Slow: the
    default run makes the same check within tests/runtime/test_cache_damage.py::
    test_identify_with_flipped_bits_in_its_nlp_file_gives_the_same_fit (built, rebuilt, then loaded: the
    same JSON each time), which costs one identify more than this one and two less than both."""
    env = {**os.environ, nlp.CACHE_VARIABLE: str(tmp_path / "cache")}
    experiment = PROBLEMS / "experiments" / "paper-protocol.yaml"
    command = [sys.executable, "-m", "pampipe", "identify", str(experiment), "--json", "--reproducible"]
    runs = [subprocess.run(command, capture_output=True, text=True, env=env, cwd=ROOT, timeout=300)
            for _ in range(2)]
    assert [r.returncode for r in runs] == [0, 0], runs[0].stderr
    loaded = ["loaded from the on-disk cache" in r.stderr for r in runs]
    assert loaded == [False, True], [r.stderr[:400] for r in runs]
    assert runs[0].stdout == runs[1].stdout
