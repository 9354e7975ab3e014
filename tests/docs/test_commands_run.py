"""The examples of docs/commands.md's sections listed in SECTIONS run as written and print what their prose
quotes (issue 36: the next-test examples of §14).

The ```sh blocks of those sections run in one shell, in a scratch folder holding a copy of `problems/`, as
tests/support/doc_commands.py says for README.md and docs/workflows.md; their output and the numbers the prose
quotes (`<!-- printed: ... -->` markers) are checked as tests/support/doc_quotes.py says. A section joins
SECTIONS once its blocks run in the scratch folder in a few seconds each.
"""

from __future__ import annotations

import re
import sys
from pathlib import Path

from tests.support.doc_commands import commands, printed, run_docs
from tests.support.doc_quotes import problem, quotes
from tests.support.problems import ROOT

DOC = "docs/commands.md"
SECTIONS = ("14",)  # next-test
HEADING = re.compile(r"^## (\d+)\.")


def section_lines(text: str, number: str) -> range:
    """The lines (1-based) of the `## N.` section ``number`` of ``text``, up to the next `## ` heading."""
    lines = text.splitlines()
    start = next(i for i, line in enumerate(lines, 1) if (m := HEADING.match(line)) and m.group(1) == number)
    after = (i for i, line in enumerate(lines[start:], start + 1) if line.startswith("## "))
    return range(start, next(after, len(lines) + 1))


def test_section_lines_stop_at_the_next_section():
    text = "# T\n## 1. a\nx\n### 1.1 b\n## 2. c\ny\n"
    assert list(section_lines(text, "1")) == [2, 3, 4]
    assert list(section_lines(text, "2")) == [5, 6]


def test_the_listed_sections_run_and_print_what_they_quote(tmp_path):
    text = (ROOT / DOC).read_text(encoding="utf-8")
    spans = [section_lines(text, number) for number in SECTIONS]
    steps = [s for s in commands((DOC,)) if any(s.block_line in span for span in spans)]
    assert len(steps) >= 2, "no ```sh block found in the listed sections"
    run_docs(Path(sys.executable).parent, tmp_path, steps)
    items = [q for q in quotes(DOC, text) if any(q.block in span for span in spans)]
    assert len(items) >= 6
    wrong = [p for q in items if (p := problem(q, printed(steps, tmp_path, DOC, q.block))) is not None]
    assert not wrong, "\n".join(wrong)
