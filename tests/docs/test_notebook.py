"""The notebook walkthrough (docs/notebook.md) runs, and result objects show themselves briefly."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

import pampipe
from pampipe.results import REPR_LIMIT, records, tidy
from tests.support.problems import ROOT

DOC = ROOT / "docs" / "notebook.md"


def test_walkthrough_runs_in_order(tmp_path, monkeypatch):
    blocks = re.findall(r"```python\n(.*?)```", DOC.read_text(), flags=re.S)
    assert len(blocks) >= 4
    monkeypatch.chdir(tmp_path)
    scope: dict = {}
    for block in blocks:
        exec(compile(block, str(DOC), "exec"), scope)
    assert (tmp_path / "plan.svg").read_text().lstrip().startswith("<?xml")
    saved = pampipe.load_pam(tmp_path / "my-pam.yaml")
    original = pampipe.load_pam(tmp_path / "demo" / "pams" / "paper-radial-pam.yaml")
    assert saved.moduli.as_vector() == pytest.approx(original.moduli.as_vector())
    plan, frame = scope["plan"], scope["frame"]
    # the long table holds every segment of every section, with the JSON's numbers
    document = plan.to_dict()
    expected = [(s["name"], x["name"], x["pressure_Pa"]) for s in document["sections"] for x in s["segments"]]
    assert list(zip(frame["section_name"], frame["name"], frame["pressure_Pa"], strict=True)) == expected
    # tidy: the plan's own scalars are in attrs, not repeated on every row (issue 42)
    assert "mission" not in frame.columns and frame.attrs["mission"] == document["mission"]
    assert frame.attrs["solver.wall_time_s"] == document["solver"]["wall_time_s"]
    assert len(repr(plan)) < 300 and "feasible=True" in repr(plan)
    assert "<table>" in plan._repr_html_()


def test_save_pam_refuses_an_existing_file_without_force(tmp_path):
    from pampipe.errors import InputError

    source = Path(pampipe.__file__).parents[1] / "problems" / "pams" / "paper-radial-pam.yaml"
    target = tmp_path / "pam.yaml"
    target.write_text("mine\n")
    with pytest.raises(InputError, match="force=True"):
        pampipe.save_pam(source, target)
    assert target.read_text() == "mine\n"
    pampipe.save_pam(source, target, force=True)
    assert pampipe.load_pam(target).name == "paper-radial-pam"


def test_records_flatten_the_deepest_list_with_prefixed_context():
    doc = {"mission": "m", "sections": [{"name": "a", "segments": [{"name": "P1", "pressure_Pa": 1.0},
                                                                  {"name": "P2", "pressure_Pa": 2.0}]},
                                        {"name": "b", "segments": [{"name": "P1", "pressure_Pa": 3.0}]}],
           "warnings": []}
    assert records(doc) == [
        {"mission": "m", "section_name": "a", "name": "P1", "pressure_Pa": 1.0},
        {"mission": "m", "section_name": "a", "name": "P2", "pressure_Pa": 2.0},
        {"mission": "m", "section_name": "b", "name": "P1", "pressure_Pa": 3.0}]


def test_tidy_keeps_what_varies_and_moves_the_constants_to_attrs():
    doc = {"mission": "m", "solver": {"iterations": 3, "interval_s": [1.0, 2.0]},
           "law": {"a": [1.5, -0.1]},
           "sections": [{"name": "a", "kind": "pipe",
                         "segments": [{"name": "P1", "ok": True}, {"name": "P2", "ok": True}]},
                        {"name": "b", "kind": "pipe", "segments": [{"name": "P1", "ok": True}]}]}
    rows, constants = tidy(doc)
    # a record's own keys stay, constant or not
    assert rows == [{"section_name": "a", "name": "P1", "ok": True},
                    {"section_name": "a", "name": "P2", "ok": True},
                    {"section_name": "b", "name": "P1", "ok": True}]
    assert constants == {"mission": "m", "solver.iterations": 3, "solver.interval_s_low": 1.0,
                         "solver.interval_s_high": 2.0, "law.a.0": 1.5, "law.a.1": -0.1,
                         "section_kind": "pipe"}
    assert tidy({"x": 1.0, "y": [1, 2]}) == ([{"x": 1.0, "y.0": 1, "y.1": 2}], {})


def test_records_follow_a_list_of_records_inside_a_nested_dict():
    doc = {"fit": {"tests": [{"name": "t1", "levels": [{"p": 1}, {"p": 2}]},
                             {"name": "t2", "levels": [{"p": 3}]}]}}
    assert records(doc) == [{"test_name": "t1", "p": 1}, {"test_name": "t1", "p": 2},
                            {"test_name": "t2", "p": 3}]


def test_repr_is_short_even_for_a_long_document():
    from pampipe.results import short_repr

    text = short_repr("Big", {f"key_{i}": float(i) for i in range(200)}, ())
    assert len(text) <= REPR_LIMIT and text.endswith("…>")


def test_commands_as_functions_convert_options_like_the_command_line(tmp_path):
    result = pampipe.synth(tmp_path / "out", seed=3, force_noise="1.5 N", cycles=1)
    document = result.to_dict()
    assert document["force_noise_N"] == 1.5 and document["seed"] == 3
    assert Path(document["experiment"]).is_file()
    with pytest.raises(TypeError, match="unexpected option 'colour'"):
        pampipe.synth(tmp_path / "other", colour="red")
    from pampipe.errors import InputError

    with pytest.raises(InputError, match="cycles"):
        pampipe.synth(tmp_path / "other", cycles=0)
    assert "missions" in pampipe.example().to_dict()["examples"]
