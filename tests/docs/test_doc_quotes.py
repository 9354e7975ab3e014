"""The check that the docs quote what their commands print (tests/support/doc_quotes.py, issue 42 item 5).

The run itself, against the real commands, is tests/docs/test_docs_run.py; here the reading of the convention
and the comparison, on hand-made docs and on the real docs with a quoted number changed by hand.
"""

from __future__ import annotations

import pytest

from tests.support.doc_commands import DOCS
from tests.support.doc_quotes import half_unit, problem, quotes
from tests.support.problems import ROOT

DOC = """Intro.
```sh
pampipe plan m.yaml
```

```
section  P [kPa]  W [N]
  riser    121.83 ...
...
```

It needs 121.8 kPa in the riser, within 2 iterations.
<!-- printed: 121.8 "riser"; 2 ±1 "iterations" -->

```text
pampipe plan MISSION.yaml [--json]
```
"""
PRINTED = ["warning: thin", "section     P [kPa]   W [N]", "  riser   121.83   31.38", "IPOPT: 3 iterations"]


def test_output_lines_and_marker_items_are_read_with_their_sh_block():
    found = quotes("d.md", DOC)
    assert [(q.line, q.block, q.number, q.tol, q.context) for q in found] == [
        (7, 2, "", None, ""), (8, 2, "", None, ""), (13, 2, "121.8", None, "riser"),
        (13, 2, "2", 1.0, "iterations")]
    assert [problem(q, PRINTED) for q in found] == [None] * 4


@pytest.mark.parametrize(("text", "printed", "wrong"), [
    ("is 121.9 kPa", "121.9", True),  # the quote changed, the marker not
    ("is 121.9 kPa", None, True),  # both changed: 121.83 does not round to 121.9
    ("is 121.83 kPa", "121.83", False),
    ("is 122 kPa", "122", False),
    ("is 121.8 kPa", '121.8 "W [N]"', True),  # the context's line prints no such number
    ("is 120 kPa", "120 ±2", False),  # a Monte-Carlo figure within its stated tolerance
    ("is 118 kPa", "118 ±2", True),
    ("is 121.8 kPa", "121.8 kPa in the riser", True),  # an item the marker grammar does not read
])
def test_a_number_is_checked_to_its_last_digit_or_its_tolerance(text, printed, wrong):
    marker = printed if printed is not None else text.split()[1]
    doc = f"```sh\npampipe plan m.yaml\n```\nIt {text}.\n<!-- printed: {marker} -->\n"
    (quote,) = quotes("d.md", doc)
    assert (problem(quote, PRINTED) is not None) is wrong


@pytest.mark.parametrize(("line", "wrong"), [
    ("section P [kPa] W [N]", False), ("  riser  121.83 ...", False), ("  riser  121.8   31.38", True),
    ("IPOPT: 4 iterations", True)])
def test_an_output_line_must_be_printed_spaces_squashed_dots_for_any_text(line, wrong):
    (quote,) = quotes("d.md", f"```sh\npampipe plan m.yaml\n```\n```\n{line}\n```\n")
    assert (problem(quote, PRINTED) is not None) is wrong


def test_half_a_unit_of_the_last_digit():
    assert [half_unit(x) for x in ("196", "4.519", "−1.61", "1.061e+04")] == [0.5, 0.0005, 0.005, 5.0]


def test_the_docs_quote_through_the_convention():
    """Enough markers and output lines, every item readable, and no plain block after a ```sh block that holds
    a usage line (those go in ```text)."""
    found = {doc: quotes(doc, (ROOT / doc).read_text(encoding="utf-8")) for doc in DOCS}
    assert sum(1 for q in found["docs/workflows.md"] if q.number) >= 40
    assert sum(1 for q in found["docs/workflows.md"] if not q.number) >= 15
    assert all(q.prose for items in found.values() for q in items)
    assert not [q.where() for items in found.values() for q in items
                if not q.number and ("[--" in q.prose or ".yaml [" in q.prose)]


@pytest.mark.parametrize(("old", "new"), [("4.519 MPa", "4.42 MPa"),
                                         ("45.19 mm per cycle", "45.2 mm per cycle")])
def test_a_quoted_number_changed_by_hand_fails(old, new):
    text = (ROOT / "docs/workflows.md").read_text(encoding="utf-8")
    assert text.count(old) == 1
    changed = quotes("docs/workflows.md", text.replace(old, new))
    reasons = [reason for q in changed if (reason := problem(q, [old])) and "does not quote" in reason]
    assert len(reasons) == 1 and old.split()[0] in reasons[0]
