"""YAML input as YAML 1.2 core, with bounds (issue 14, item 2)."""

from __future__ import annotations

from unittest import mock

import pytest
import yaml

from pampipe.errors import InputError
from pampipe.io import yamlfile
from pampipe.io.yamlfile import loads

CORE = [  # (text, value of key a) under the YAML 1.2 core schema
    ("a: 010", 10), ("a: 0o10", 8), ("a: 0x1F", 31), ("a: +12", 12), ("a: -0", 0),
    ("a: 1:30", "1:30"), ("a: 1_000", "1_000"), ("a: 2001-12-14", "2001-12-14"),
    ("a: yes", "yes"), ("a: No", "No"), ("a: on", "on"), ("a: OFF", "OFF"), ("a: y", "y"),
    ("a: true", True), ("a: FALSE", False), ("a: ~", None), ("a:", None), ("a: Null", None),
    ("a: 1e3", 1000.0), ("a: 1.", 1.0), ("a: -.5", -0.5), ("a: .inf", float("inf")),
    ("a: -.Inf", float("-inf")), ("a: '010'", "010"), ("a: !!str 12", "12"), ("a: !!float 1", 1.0),
    ("a: 3 in", "3 in"), ("a: 1e", "1e"), ("a: 0b101", "0b101"),
]


@pytest.mark.parametrize(("text", "expected"), CORE)
def test_core_schema(text, expected):
    assert loads(text) == {"a": expected}


def test_nan_is_a_float():
    value = loads("a: .nan")["a"]
    assert isinstance(value, float) and value != value


def test_pure_python_parser_gives_the_same_documents(monkeypatch):
    """Without libyaml the pure-Python event parser is used; the documents must not change."""
    texts = [t for t, _ in CORE] + ["b: &x {c: 1}\nd: {<<: *x, e: 2}", "- [1, 2]\n- {f: g}"]
    expected = [loads(t) for t in texts]
    monkeypatch.setattr(yamlfile, "_Parser", yamlfile._PyParser)
    assert [loads(t) for t in texts] == expected


def test_merge_keys():
    doc = loads("base: &b {x: 1, y: 2}\nc:\n  <<: *b\n  y: 3\nd: {<<: [{p: 1}, {p: 2, q: 3}], r: 0}\n")
    assert doc["c"] == {"x": 1, "y": 3}  # an explicit key wins over a merged one
    assert doc["d"] == {"p": 1, "q": 3, "r": 0}  # earlier merge sources win
    assert loads("'<<': 1") == {"<<": 1}  # a quoted << is an ordinary key


@pytest.mark.parametrize(("text", "fragment"), [
    ("a: 1\na: 2", "line 2, column 1: duplicate key 'a'"),
    ("1: a\n1.0: b", "duplicate key 1.0"),
    ("[a, b]: 1", "a list cannot be a key"),
    ("? {a: 1}\n: 2", "a mapping cannot be a key"),
    ("a: &x [*x]", "refers to a collection that contains it"),
    ("a: *nope", "has no anchor"),
    ("--- 1\n--- 2", "several YAML documents"),
    ("a: !!python/object:os.system x", "is not read"),
    ("a: !foo x", "is not read"),
    ("a: !!int x", "is not a valid int"),
    ("a: {<<: 1}", "merge key"),
    ("a: b: c", "invalid YAML"),
    ("a: " + "1" * 2000, "an integer of 2000 digits"),
])
def test_refused(text, fragment):
    with pytest.raises(InputError) as info:
        loads(text, source="f.yaml")
    assert fragment in str(info.value) and str(info.value).startswith("f.yaml:")


def test_depth_is_bounded_before_the_stack():
    """10⁵ brackets crashed libyaml's composer (C stack); events stop at MAX_DEPTH."""
    for depth in (101, 150, 100_000):  # pampipe's bound or the parser's own (PyYAML ≥ 6.0.4), whichever first
        with pytest.raises(InputError) as info:
            loads("a: " + "[" * depth + "]" * depth, source="f.yaml")
        message = str(info.value)
        assert message.startswith("f.yaml: line 1, column "), message
        assert "at most 100 levels deep" in message or "nested deeper than 100 levels" in message, message
    nested = "a: " + "[" * 99 + "]" * 99
    assert loads(nested)["a"] is not None


def test_alias_expansion_is_bounded():
    laughs = "a0: &a0 [x, x, x, x, x, x, x, x, x, x]\n" + "".join(
        f"a{i}: &a{i} [" + ", ".join([f"*a{i - 1}"] * 10) + "]\n" for i in range(1, 9))
    with pytest.raises(InputError, match="alias bomb"):
        loads(laughs)
    shared = "s: &s {k: 1}\nlist: [" + ", ".join(["*s"] * 1000) + "]\n"  # modest reuse is fine
    assert len(loads(shared)["list"]) == 1000


def test_size_is_bounded(tmp_path, monkeypatch):
    monkeypatch.setattr(yamlfile, "MAX_BYTES", 1000)
    path = tmp_path / "big.yaml"
    path.write_text("a: " + "x" * 2000 + "\n")
    with pytest.raises(InputError, match="larger than"):
        yamlfile.load_mapping(path)


def test_error_messages_are_short():
    """A malformed 1 MB scalar is not repeated in the message."""
    with pytest.raises(InputError) as info:
        loads("a: 'unterminated " + "x" * 2**20)
    assert len(str(info.value)) < 300


def test_agrees_with_pyyaml_on_plain_documents():
    text = "name: x\nlist: [1, 2.5, 'three', {k: v}]\nnested: {a: {b: [true, null]}}\n"
    assert loads(text) == yaml.safe_load(text)


# One-line flow mappings in a block list ("- {name: s1, length: 2 m}") are read without the parser's events
# (yamlfile._flow_lines); the reference is the same text parsed event by event (_without_flow_lines).
FLOW_ROUTE = """\
route:   # a comment
  - {name: s0, length: 1 m, inner_diameter: 3 in, incline: -45 deg, friction: 0.2}
  - {name: s1,  length: 2.5 m , inner_diameter: {nps: 3, schedule: 40, tolerance: 1 %}}   # a comment
  - {name: 010, n: 0o10, x: 1e3, y: -.inf, z: yes, w: null, v: 1_000, u: 3  in, t: a/b, s: .5}
  - {name: True, ok: null, no: Null}
  -   {name: spaced}
  - {name: 'quoted', a: 1}
nested:
  - - {a: 1}
"""


def _outcome(text: str, *, flow_lines: bool = True):
    """The document of ``text``, or the message it is refused with; without flow lines: event by event."""
    reader = yamlfile._flow_lines if flow_lines else lambda text: ({}, text)
    with mock.patch.object(yamlfile, "_flow_lines", reader):
        try:
            return loads(text, source="f.yaml")
        except InputError as exc:
            return str(exc)


def test_flow_lines_read_as_the_parser_reads_them():
    flows, _ = yamlfile._flow_lines(FLOW_ROUTE)
    # one run of 4 lines: not the spaced, quoted or nested-list entries
    assert [(place, len(mappings)) for place, (mappings, _, _) in flows.items()] == [((1, 4), 4)]
    doc = loads(FLOW_ROUTE)
    assert doc == _outcome(FLOW_ROUTE, flow_lines=False)
    route = doc["route"]
    assert route[0] == {"name": "s0", "length": "1 m", "inner_diameter": "3 in", "incline": "-45 deg",
                        "friction": 0.2}
    assert route[1] == {"name": "s1", "length": "2.5 m", "inner_diameter": {"nps": 3, "schedule": 40,
                                                                          "tolerance": "1 %"}}
    assert route[2] == {"name": 10, "n": 8, "x": 1000.0, "y": float("-inf"), "z": "yes", "w": None,
                        "v": "1_000", "u": "3  in", "t": "a/b", "s": 0.5}  # YAML 1.2 core
    assert route[3] == {"name": True, "ok": None, "no": None}
    reference = _outcome(FLOW_ROUTE, flow_lines=False)["route"]
    assert [list(entry) for entry in route] == [list(entry) for entry in reference]  # the keys' order


RUNS = """\
a:
  - {name: a0, x: 1}
  - {name: a1, x: 1}
  # a comment ends a run
  - {name: a2, x: {k: 1}}

  - {name: a3, x: {k: 1}}
  - b:
    - {name: b0, x: 1}
    - {name: b1, x: 2}
  - {name: a4, x: 1}
c: [1, {d: 2}]
"""


def test_runs_of_flow_lines_are_one_entry_each_and_keep_the_lines_after_them():
    """A run is consecutive lines at one indentation: a comment, an empty line or another indentation
    starts the next; an error after the runs is told at its own line."""
    flows, marked = yamlfile._flow_lines(RUNS)
    assert [(place, len(mappings)) for place, (mappings, _, _) in flows.items()] == [
        ((1, 4), 2), ((4, 4), 1), ((6, 4), 1), ((8, 6), 2), ((10, 4), 1)]
    assert marked.count("\n") == RUNS.count("\n")
    doc = loads(RUNS)
    assert doc == _outcome(RUNS, flow_lines=False)
    doc["a"][2]["x"]["k"] = 5  # each line's nested mapping is its own
    assert doc["a"][3]["x"] == {"k": 1}
    assert "line 13, column 1: duplicate key 'a'" in _outcome(RUNS + "a: 1\n")


@pytest.mark.parametrize("text", [
    "notes: |\n  - {a: b}\n  - {c: d}\nx: 1\n",  # inside a block scalar: text, not a list
    "notes: >\n  - {a: b}\n",
    "a: 'quoted\n  - {a: b}\n  end'\n",  # inside a quoted scalar
    "a: plain text\n  - {a: b}\n",  # a continuation line of a plain scalar
    "- &x {a: 1}\n- *x\n",  # anchors are the parser's
])
def test_flow_lines_elsewhere_keep_their_meaning(text):
    assert _outcome(text) == _outcome(text, flow_lines=False)


@pytest.mark.parametrize(("text", "fragment"), [
    ("route:\n  - {a: 1}\n  - {a: 1, a: 2}\n", "line 3, column 12: duplicate key 'a'"),
    ("route:\n  - {a: 1}\n  - {b: 2}\nroute: 3\n", "line 4, column 1: duplicate key 'route'"),
    ("route:\n  - {a: 1}\n  - {b: 2}\n x: [\n", "line 4"),
    ("x: - {a: 1}\n", "line 1"),
    ("- {a: " + "1" * 2000 + "}\n", "line 1, column 7: an integer of 2000 digits"),
])
def test_flow_lines_keep_the_parsers_errors(text, fragment):
    message = _outcome(text)
    assert fragment in message, message
    assert message == _outcome(text, flow_lines=False)


def test_flow_lines_count_toward_the_bounds():
    deep = "a:\n" + "".join("  " * i + "-\n" for i in range(1, 99)) + "  " * 99 + "- {b: {c: 1}}\n"
    with pytest.raises(InputError, match="nested deeper than 100 levels"):
        loads(deep)
    laughs = "a0: &a0\n" + "".join(f"  - {{k{i}: 1, j{i}: {{x: 1, y: 2}}}}\n" for i in range(10)) + "".join(
        f"a{i}: &a{i} [" + ", ".join([f"*a{i - 1}"] * 10) + "]\n" for i in range(1, 6))
    with pytest.raises(InputError, match="alias bomb"):
        loads(laughs)
    flows, marked = yamlfile._flow_lines(laughs)
    assert flows  # the shortcut itself counts the nodes its lines add
    with pytest.raises(yamlfile._Error, match="alias bomb"):
        yamlfile._Builder(yamlfile._Parser(marked), flows).document()


def test_pure_python_parser_reads_flow_lines_alike(monkeypatch):
    expected = loads(FLOW_ROUTE)
    monkeypatch.setattr(yamlfile, "_Parser", yamlfile._PyParser)
    assert loads(FLOW_ROUTE) == expected


def test_flow_lines_that_differ_only_in_their_first_value_are_each_their_own():
    """Lines whose pairs after the first (plain) one are the same text are read once (issue 39); each line
    still gets its own mappings, its first value resolved on its own, and a repeated key is refused."""
    text = ("route:\n" + "".join(f"  - {{name: {n}, d: {{nps: 3, schedule: 40}}, f: 0.2}}\n"
                                 for n in ("s0", "1", "true", "s3"))
            + "  - {name: s4, name: s5}\n")
    with pytest.raises(InputError, match="line 6, column 16: duplicate key 'name'"):
        loads(text)
    text = text.rsplit("  - {name: s4", 1)[0]
    route = loads(text)["route"]
    assert route == _outcome(text, flow_lines=False)["route"]
    assert [entry["name"] for entry in route] == ["s0", 1, True, "s3"]
    route[0]["d"]["nps"] = 4  # one section's bore, edited, is not another's
    assert route[1]["d"] == {"nps": 3, "schedule": 40}
