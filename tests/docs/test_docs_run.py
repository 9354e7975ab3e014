"""The example commands of README.md and docs/workflows.md run as written (issue 21), and print what the docs
quote (issue 42).

What a doc's ```sh block may assume is the convention in tests/support/doc_commands.py; how a doc shows what a
command printed, and quotes its numbers, is the convention in tests/support/doc_quotes.py.
"""

from __future__ import annotations

import re
import sys
from pathlib import Path

import pytest

from tests.support.doc_commands import DOCS, REFERENCE, Command, commands, printed, run_docs
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


@pytest.mark.parametrize("doc", DOCS)
def test_every_doc_command_runs_in_order_in_one_shell_and_prints_what_the_docs_quote(doc, tmp_path):
    """The doc's commands as a reader would type them, in a fresh scratch folder (each doc stands alone, and
    the two docs run side by side under ``pytest -n 2``); then every output block and quoted number of the
    doc against what the commands of its ```sh block printed (the conventions above)."""
    steps = [s for s in commands() if s.doc == doc]
    run_docs(Path(sys.executable).parent, tmp_path, steps)
    found = quotes(doc, (ROOT / doc).read_text(encoding="utf-8"))
    assert len(found) >= QUOTED[doc]
    wrong = [p for q in found if (p := problem(q, printed(steps, tmp_path, doc, q.block))) is not None]
    assert not wrong, "\n".join(wrong)


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
