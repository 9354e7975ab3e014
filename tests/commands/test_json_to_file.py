"""`plan --json -o FILE` writes the document to FILE only; long routes' reducers are summarised (issue 42,
item 4)."""

from __future__ import annotations

import json
from types import SimpleNamespace

from pampipe.views.plan_text import LISTED_REDUCERS, _reducers_text
from tests.support.problems import PROBLEMS
from tests.support.processes import run_cli

DEMO = PROBLEMS / "missions" / "vertical-climb-3in.yaml"


def test_json_with_o_prints_the_report_not_the_document(tmp_path):
    out = tmp_path / "plan.json"
    both = run_cli("plan", DEMO, "--json", "-o", out, "--reproducible")
    assert both.returncode == 0, both.stderr
    document = json.loads(out.read_text())
    assert document["feasible"] is True
    assert not both.stdout.lstrip().startswith("{")  # the text report, not a second copy of the document
    assert f"plan for {DEMO}" in both.stdout
    plain = run_cli("plan", DEMO, "--json", "--reproducible")  # without -o: the document on stdout, as before
    assert json.loads(plain.stdout) == document
    quiet = run_cli("plan", DEMO, "--json", "-o", tmp_path / "q.json", "--quiet")
    assert quiet.returncode == 0 and quiet.stdout == ""
    assert json.loads((tmp_path / "q.json").read_text())["feasible"] is True


def _reducer(before_mm: float, after_mm: float, name: str) -> SimpleNamespace:
    return SimpleNamespace(before=before_mm / 1e3, after=after_mm / 1e3, passable=after_mm >= 80,
                           after_section=name)


def test_a_few_reducers_are_worded_one_by_one():
    text = _reducers_text([_reducer(76.2, 88.9, "a"), _reducer(88.9, 76.2, "b")])
    assert text == ("after 'a' 76.2 -> 88.9 mm: passes (a rigid segment passes if it fits the smaller bore); "
                    "after 'b' 88.9 -> 76.2 mm: does NOT pass (a rigid segment passes if it fits the smaller "
                    "bore)")


def test_many_reducers_are_summarised_by_change_of_bore():
    reducers = [_reducer(76.2, 88.9, f"s{i}") if i % 2 == 0 else _reducer(88.9, 76.2, f"s{i}")
                for i in range(3000)]
    lines = _reducers_text(reducers).split("\n")
    assert lines[0] == "3000 changes of bore, 2 kinds (--json lists every reducer):"
    assert lines[1].startswith("  76.2 -> 88.9 mm: passes")
    assert lines[1].endswith(", 1500 times: after 's0', 's2', 's4', 's6', 's8', 's10' and 1494 more")
    assert lines[2].startswith("  88.9 -> 76.2 mm: does NOT pass")
    assert len(lines) == 3 and max(map(len, lines)) < 200
    assert len(_reducers_text(reducers[:LISTED_REDUCERS]).split("\n")) == 1
