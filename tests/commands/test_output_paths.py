"""Two outputs of one command never share a path (issue 38 item 5; pampipe/io/files.py
check_distinct_outputs): `plan M -o x.html --report x.html` wrote twice and kept only the HTML."""

from __future__ import annotations

import os

import pytest

from tests.support.problems import PROBLEMS
from tests.support.processes import run_cli

MISSION = PROBLEMS / "missions" / "vertical-climb-3in.yaml"
EXPERIMENT = PROBLEMS / "experiments" / "paper-protocol.yaml"


@pytest.mark.parametrize(("command", "first", "second"), [
    (["plan", MISSION], "-o", "--report"),
    (["plan", MISSION], "--plots", "--report"),
    (["identify", EXPERIMENT], "-o", "--plots"),
    (["diagnose", EXPERIMENT], "--report", "-o"),
    (["design", PROBLEMS / "inventories" / "riser.yaml"], "-o", "--plots"),
])
@pytest.mark.parametrize("spelling", ["same", "dotted", "link"])
def test_two_outputs_on_one_path_are_refused_before_any_work(tmp_path, command, first, second, spelling):
    target = tmp_path / "out.html"
    other = {"same": target, "dotted": tmp_path / "." / "sub" / ".." / "out.html", "link": tmp_path / "link"}
    (tmp_path / "sub").mkdir()
    if spelling == "link":  # an existing output (a folder where it may be --plots'), named through a link
        if "--plots" in (first, second):
            target.mkdir()
        else:
            target.write_text("kept")
        os.symlink(target, tmp_path / "link")
    before = sorted(tmp_path.rglob("*"))
    run = run_cli(*command, first, target, second, other[spelling])
    assert run.returncode == 2, run.stderr
    said = run.stderr.splitlines()
    assert len(said) == 1 and "are the same path" in said[0], run.stderr
    assert f"{first} {target}" in said[0] and f"{second} {other[spelling]}" in said[0]
    assert sorted(tmp_path.rglob("*")) == before  # nothing written
    if target.is_file():
        assert target.read_text() == "kept"

def test_distinct_outputs_are_all_written(tmp_path):
    run = run_cli("plan", MISSION, "-o", tmp_path / "plan.json", "--report", tmp_path / "plan.html")
    assert run.returncode == 0, run.stderr
    assert (tmp_path / "plan.json").read_text().startswith("{") and (tmp_path / "plan.html").is_file()
