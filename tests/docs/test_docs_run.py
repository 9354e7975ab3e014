"""The example commands of README.md and docs/workflows.md run as written (issue 21), and print what the docs
quote (issue 42).

What a doc's ```sh block may assume is the convention in tests/support/doc_commands.py; how a doc shows what a
command printed, and quotes its numbers, is the convention in tests/support/doc_quotes.py.
"""

from __future__ import annotations

import itertools
import re
import sys
from pathlib import Path

import pytest

from tests.support import doc_commands
from tests.support.doc_commands import DOCS, REFERENCE, Command, also_run, commands, printed, run_docs
from tests.support.doc_quotes import problem, quotes
from tests.support.problems import ROOT

#: At least this many quoted outputs and numbers per doc are compared (82 in all when it was written).
QUOTED = {"README.md": 4, "docs/workflows.md": 75}


def test_the_docs_have_commands_to_run():
    steps = commands()
    assert {s.doc for s in steps} == set(DOCS)
    assert all(not s.text.lstrip().startswith("make ") for s in steps)
    assert any(s.text.startswith("pampipe plan") for s in steps)


def test_no_doc_command_and_no_test_uses_a_fixed_folder():
    """Two runs on one machine share a fixed folder such as /tmp/pampipe-demo: commands write into the scratch
    folder, tests into their tmp_path (issue 42, item 9)."""
    fixed = re.compile(r"(?<![\w.~$}])/tmp/")
    assert not [s.where() for s in commands([*DOCS, *REFERENCE]) if fixed.search(s.text)]
    tests = Path(__file__).resolve().parents[1]
    found = [f"{path.relative_to(tests)}:{n}" for path in sorted(tests.rglob("*.py"))
             for n, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1)
             if fixed.search(line) and path.name not in ("test_docs_run.py", "doc_commands.py")]
    assert not found, found


def test_parser_reads_continuations_expectations_and_skips(tmp_path):
    (tmp_path / "d.md").write_text(
        "text\n```sh\nmake demo\n# a comment\necho a \\\n  b\nfalse   # exits 1\n```\n```\nnot run\n```\n"
        "```yaml\nkey: 1\n```\n```sh\ntrue\ncat > f.yaml <<'EOF'  # exits 0\na: 1\n```\nEOF\n```\n")
    steps = commands(["d.md"], tmp_path)
    assert [(s.line, s.block_line, s.text, s.expected) for s in steps] == [
        (5, 2, "echo a \\\n  b", 0), (7, 2, "false   # exits 1", 1), (16, 15, "true", 0),
        (17, 15, "cat > f.yaml <<'EOF'  # exits 0\na: 1\n```\nEOF", 0)]


def test_a_wrong_exit_code_names_the_doc_line_and_command(tmp_path):
    steps = [Command("X.md", 3, 4, "cd problems", 0), Command("X.md", 3, 5, "ls pams > /dev/null", 0),
             Command("X.md", 3, 6, "(exit 5)   # exits 5", 5), Command("X.md", 7, 8, "false", 0),
             Command("X.md", 7, 9, "true", 0)]
    with pytest.raises(pytest.fail.Exception) as info:
        run_docs(Path("/nonexistent"), tmp_path, steps)
    message = str(info.value)
    assert message.startswith("X.md:8 (```sh block at line 7) exited 1, the doc expects 0")
    assert "\n  false\n" in message


#: Each doc's walkthrough by default (the commands another default test runs left out) and in full (slow).
WALKS = [pytest.param(doc, full, id=f"{doc}-{'full' if full else 'default'}",
                      marks=[pytest.mark.slow] if full else [])
         for doc in DOCS for full in (False, True)
         if not full or any(d == doc for d, _ in doc_commands.ALSO_RUN)]


@pytest.mark.parametrize(("doc", "full"), WALKS)
def test_every_doc_command_runs_in_order_in_one_shell_and_prints_what_the_docs_quote(doc, full, tmp_path):
    """The doc's commands as a reader would type them, in a fresh scratch folder (each doc stands alone, and
    the two docs run side by side under ``pytest -n 2``); then every output block and quoted number of the
    doc against what the commands of its ```sh block printed (the conventions above). By default without the
    commands of ALSO_RUN, which their named tests run; the full walk is slow."""
    steps = [s for s in commands() if s.doc == doc and (full or also_run(s) is None)]
    run_docs(Path(sys.executable).parent, tmp_path, steps)
    found = quotes(doc, (ROOT / doc).read_text(encoding="utf-8"))
    assert len(found) >= QUOTED[doc]
    wrong = [p for q in found if (p := problem(q, printed(steps, tmp_path, doc, q.block))) is not None]
    assert not wrong, "\n".join(wrong)


def _outputs(step: Command) -> list[str]:
    """The paths a command writes: the words after -o, --output and --plots."""
    words = step.text.split()
    return [w for flag, w in itertools.pairwise(words) if flag in ("-o", "--output", "--plots")]


def test_each_command_left_out_by_default_is_run_by_a_named_default_test():
    """ALSO_RUN names, for each command the default walk leaves out, a test that exists and is not slow (or a
    doc line that the default walk runs); each entry matches one command; no quote reads a left-out
    command's block alone; no command left in reads what a left-out one wrote."""
    steps = commands()
    assert all(sum(s.doc == doc and s.text.startswith(start) for s in steps) == 1
               for doc, start in doc_commands.ALSO_RUN)
    for where in set(doc_commands.ALSO_RUN.values()):
        if "::" in where:
            path, name = where.split("::")
            source = (ROOT / path).read_text(encoding="utf-8")
            assert f"def {name}(" in source, f"{where}: no such test"
            head = source[:source.index(f"def {name}(")].rsplit("\n\n\n", 1)[-1]
            assert "slow" not in head and "pytestmark" not in source, where
        else:
            doc, line = where.split(":")
            (step,) = [s for s in steps if s.doc == doc and s.line == int(line)]
            assert also_run(step) is None, where
    for doc in DOCS:
        walk = [s for s in steps if s.doc == doc]
        left_out = [s for s in walk if also_run(s) is not None]
        kept_blocks = {s.block_line for s in walk if also_run(s) is None}
        assert {q.block for q in quotes(doc, (ROOT / doc).read_text(encoding="utf-8"))} <= kept_blocks
        for out in left_out:
            later = [s for s in walk if s.line > out.line and also_run(s) is None]
            assert not [(s.where(), p) for p in _outputs(out) for s in later if p in s.text]


def test_the_left_out_check_sees_a_command_that_reads_an_output():
    step = Command("X.md", 1, 2, "pampipe identify e.yaml -o out/fit.yaml \\\n    --plots out/p", 0)
    assert _outputs(step) == ["out/fit.yaml", "out/p"]


@pytest.mark.slow
def test_every_command_of_the_reference_runs_and_prints_what_it_quotes(tmp_path):
    """docs/commands.md's ```sh blocks in order in one shell of their own; its output blocks and quoted
    numbers against what they printed (issue 42: they ran nowhere and could drift). Slow: 29 commands, among
    them diagnose, ky4-network and next-test's preposterior check (16 min on a machine loaded 8-fold)."""
    steps = commands(REFERENCE)
    assert len({s.block_line for s in steps}) >= 15
    run_docs(Path(sys.executable).parent, tmp_path, steps)
    page = REFERENCE[0]
    found = quotes(page, (ROOT / page).read_text(encoding="utf-8"))
    assert len(found) >= 10
    wrong = [p for q in found if (p := problem(q, printed(steps, tmp_path, page, q.block))) is not None]
    assert not wrong, "\n".join(wrong)
