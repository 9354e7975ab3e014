"""The mutation harness (scripts/mutate.py, `make mutate`) keys a mutant by the mutated line's code, not its
number: a mutant judged equivalent stays listed (scripts/mutants-equivalent.txt) when code above it moves, and
a listed key whose line changed is named, never silently matched to another mutant."""

from __future__ import annotations

import dataclasses
import importlib.util
import json
import os
import subprocess
import sys

import pytest

from tests.support.problems import ROOT

SPEC = importlib.util.spec_from_file_location("mutate", ROOT / "scripts" / "mutate.py")
mutate = sys.modules.setdefault("mutate", importlib.util.module_from_spec(SPEC))  # dataclasses look it up
SPEC.loader.exec_module(mutate)

SOURCE = '''"""A module."""
LIMIT = 2.0  # the largest [Pa]


def f(x, y):
    if x > 0 and y > 0:  # both
        return max(x, y) * LIMIT
    return min(x, y) * LIMIT
'''


def keys(source: str) -> list[str]:
    return [m.key("m.py") for m in mutate.mutants(source)]


def test_a_key_names_the_change_and_the_line_without_its_comment():
    found = {m.key("m.py"): m for m in mutate.mutants(SOURCE)}
    assert set(found) == {
        "m.py: 2.0->2.02 @8: LIMIT = 2.0",
        "m.py: And->Or @3: if x > 0 and y > 0:",
        "m.py: Gt->GtE @3: if x > 0 and y > 0:", "m.py: 0->1 @7: if x > 0 and y > 0:",
        "m.py: Gt->GtE @13: if x > 0 and y > 0:", "m.py: 0->1 @17: if x > 0 and y > 0:",
        "m.py: Mult->Div @7: return max(x, y) * LIMIT", "m.py: max->min @7: return max(x, y) * LIMIT",
        "m.py: Mult->Div @7: return min(x, y) * LIMIT", "m.py: min->max @7: return min(x, y) * LIMIT"}
    changed = found["m.py: max->min @7: return max(x, y) * LIMIT"].source
    assert "return min(x, y) * LIMIT" in changed and "return max(x, y)" not in changed


def test_keys_survive_code_moving_above_and_go_stale_when_their_line_changes():
    moved = SOURCE.replace('"""A module."""', '"""A module."""\nimport math\n\nSCALE = math.pi\n')
    assert set(keys(SOURCE)) <= set(keys(moved))  # the same keys at other line numbers
    before = {m.key("m.py"): m.line for m in mutate.mutants(SOURCE)}
    after = {m.key("m.py"): m.line for m in mutate.mutants(moved)}
    assert all(after[k] == before[k] + 4 for k in before)
    edited = SOURCE.replace("return max(x, y) * LIMIT", "return max(x, y) * LIMIT / 2")
    listed = {"m.py: max->min @7: return max(x, y) * LIMIT", "m.py: 2.0->2.02 @8: LIMIT = 2.0"}
    gone = mutate.stale("m.py", mutate.mutants(edited), listed)
    assert gone == {"m.py: max->min @7: return max(x, y) * LIMIT"}


def test_the_same_change_on_a_repeated_line_is_counted():
    twice = "def f(x):\n    x = x + 1\n    x = x + 1\n    return x\n"
    assert keys(twice) == ["m.py: Add->Sub @4: x = x + 1", "m.py: Add->Sub @4: x = x + 1 [2]",
                           "m.py: 1->2 @8: x = x + 1", "m.py: 1->2 @8: x = x + 1 [2]"]


@pytest.mark.parametrize("module", list(mutate.TARGETS))
def test_every_listed_equivalent_names_a_mutant_of_today(module):
    """Each key of scripts/mutants-equivalent.txt names a mutant of the module as it is now (else the line it
    judged changed: judge the new line again), and the keys parse back (no ``  # `` inside a key)."""
    found = mutate.mutants((ROOT / module).read_text(encoding="utf-8"))
    assert not mutate.stale(module, found, mutate.equivalents())
    assert all("  # " not in m.key(module) for m in found)


def test_select_runs_the_tests_that_run_the_mutated_line(tmp_path):
    """``--select``: a traced run (scripts/mutate_trace.py) maps each test to the lines it runs; a mutant
    runs only the tests that run its line, and every test where its line runs at import or in no test."""
    (tmp_path / "tests").mkdir()
    (tmp_path / "m.py").write_text(SOURCE)
    (tmp_path / "tests" / "test_m.py").write_text(
        "from m import f\n\n\ndef test_both():\n    assert f(1, 2) == 4.0\n\n\n"
        "def test_one():\n    assert f(-1, 2) == -2.0\n")
    env = {**os.environ, "PYTHONPATH": f"{tmp_path}{os.pathsep}{ROOT / 'scripts'}",
           "MUTATE_TRACE": str(tmp_path / "m.py"), "MUTATE_TRACE_OUT": str(tmp_path / "lines.json")}
    subprocess.run([sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", "-p", "mutate_trace",
                    "tests"], cwd=tmp_path, env=env, check=True, capture_output=True)
    lines = {k: set(v) for k, v in json.loads((tmp_path / "lines.json").read_text()).items()}
    both, one = "tests/test_m.py::test_both", "tests/test_m.py::test_one"
    assert lines[both] == {5, 6, 7} and lines[one] == {5, 6, 8} and 2 in lines[""]
    tests = ("tests/test_m.py",)
    chosen = {m.key("m.py"): mutate.selected(m, lines, tests) for m in mutate.mutants(SOURCE)}
    assert chosen["m.py: max->min @7: return max(x, y) * LIMIT"] == (both,)
    assert chosen["m.py: min->max @7: return min(x, y) * LIMIT"] == (one,)
    assert chosen["m.py: And->Or @3: if x > 0 and y > 0:"] == (both, one)
    assert chosen["m.py: 2.0->2.02 @8: LIMIT = 2.0"] == tests  # module level: every test
    assert mutate.selected(dataclasses.replace(mutate.mutants(SOURCE)[0], line=99, end_line=99), lines,
                           tests) == tests  # a line no test runs here (a subprocess may): every test


def test_the_mutants_run_in_a_snapshot_of_head_not_in_the_working_tree(tmp_path):
    """Editing the tree while a run goes on must not give false kills: the run's files are HEAD's (git
    archive), an edit or an untracked file left out, a link kept a link."""
    repo, work = tmp_path / "repo", tmp_path / "work"
    repo.mkdir()
    work.mkdir()
    (repo / "m.py").write_text(SOURCE)
    (repo / "link").symlink_to("/dev/zero")
    git = ["git", "-C", str(repo), "-c", "user.name=t", "-c", "user.email=t@t", "-c", "commit.gpgsign=false"]
    subprocess.run([*git, "init", "-q"], check=True)
    subprocess.run([*git, "add", "."], check=True)
    subprocess.run([*git, "commit", "-q", "-m", "one"], check=True)
    (repo / "m.py").write_text(SOURCE.replace("LIMIT = 2.0", "LIMIT = 3.0"))  # edited after the commit
    (repo / "new.py").write_text("x = 1\n")
    head = mutate.snapshot(repo, str(work))
    assert (head / "m.py").read_text() == SOURCE
    assert not (head / "new.py").exists()
    assert os.readlink(head / "link") == "/dev/zero"
    copy = mutate._copy(head, str(work / "mutant"))
    assert (copy / "m.py").read_text() == SOURCE and os.readlink(copy / "link") == "/dev/zero"


def test_each_verdict_is_reported_as_it_is_judged_so_a_stopped_run_keeps_it():
    found = mutate.mutants(SOURCE)[:3]
    verdicts = iter([True, False])

    def run(mutant):
        return next(verdicts)  # the third mutant: StopIteration, as a run stopped by hand

    reported = []
    with pytest.raises(StopIteration):
        mutate.judge("m.py", found, run, reported.append)
    assert len(reported) == 2
    assert reported[0].startswith("m.py: 1/3 killed ") and reported[0].endswith("[so far 1/1 killed: 100%]")
    assert reported[1].startswith("m.py: 2/3 SURVIVED ") and reported[1].endswith("[so far 1/2 killed: 50%]")
    assert found[1].key("m.py") in reported[1]
    assert mutate.judge("m.py", found[:2], lambda m: m is found[0], reported.append) == [found[1]]
