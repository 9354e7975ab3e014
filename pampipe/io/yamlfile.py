"""Reading YAML input files as YAML 1.2 core, safely (docs/formats.md §1).

* **YAML 1.2 core schema**: ``010`` is 10, ``0o10`` is 8, ``1:30`` and ``yes``/``no``/``on``/``off``
  stay strings, dates stay strings; ``true``/``false``, ``null``/``~``, ``.inf``/``.nan`` as in 1.2.
* Merge keys (``<<: *defaults``) work; explicit keys win over merged ones.
* Refused with the line and column: duplicate keys, a list or mapping as a key, recursive aliases,
  tags other than the core ones, several documents in one file.
* Bounded: at most :data:`MAX_BYTES` bytes, :data:`MAX_DEPTH` levels of nesting, and aliases may
  add at most :data:`MAX_ALIAS_NODES` nodes (or as many as the file holds itself) to the document
  (the "billion laughs" attack expands 30 bytes into 10⁹ nodes).

The document is built in one pass over libyaml's events (PyYAML's C parser when present): no node
graph, no recursion, so a deep file cannot exhaust the stack.

Long routes are lines like ``- {name: s1, length: 2 m, inner_diameter: {nps: 3, schedule: 40}}``: a
list entry holding one flow mapping of plain names and values on one line. Such lines are read by
:func:`_flow_lines` (a regular expression and the same 1.2-core resolution), and the parser sees, for
each run of such lines at one indentation, one plain placeholder list entry followed by empty lines (so
that every later line keeps its number) instead of 12 events per line; the document is the same. The
shortcut is kept only if every run came back as list entries at its place; otherwise, or on any error, the
file is parsed again without it, so messages and line/column marks are those of the parser. A long route's
lines differ mostly in their first value (the name): the pairs after a plain first one are read once per
distinct text (10⁵ sections of ``benchmarks/bench_big_mission.py`` hold 1,260), each line getting its own
mappings.
"""

from __future__ import annotations

import re
from pathlib import Path

import yaml

from pampipe.errors import InputError
from pampipe.io.paths import read_bounded

#: Largest YAML input [bytes]: 64 MB holds a route of about 10⁶ sections.
MAX_BYTES = 64 * 2**20
#: Deepest nesting of mappings and lists (pampipe's own files need fewer than 12 levels).
MAX_DEPTH = 100
#: Nodes that aliases may add beyond the larger of this and the document's own node count.
MAX_ALIAS_NODES = 1_000_000
#: What a refused file is told it may hold (the parser's own message comes before it).
_ALLOWED = f"pampipe reads one YAML 1.2 core document nested at most {MAX_DEPTH} levels deep"



class _PyParser(yaml.reader.Reader, yaml.scanner.Scanner, yaml.parser.Parser):
    """PyYAML's pure-Python event parser, for installations without libyaml."""

    def __init__(self, text: str) -> None:
        yaml.reader.Reader.__init__(self, text)
        yaml.scanner.Scanner.__init__(self)
        yaml.parser.Parser.__init__(self)


_Parser = yaml.cyaml.CParser if yaml.__with_libyaml__ else _PyParser  # libyaml's C parser when present
_INT = re.compile(r"[-+]?[0-9]+")
_FLOAT = re.compile(r"[-+]?(?:\.[0-9]+|[0-9]+(?:\.[0-9]*)?)(?:[eE][-+]?[0-9]+)?")
_SPECIAL = {"": None, "~": None, "null": None, "Null": None, "NULL": None,
            "true": True, "True": True, "TRUE": True, "false": False, "False": False, "FALSE": False,
            ".inf": float("inf"), ".Inf": float("inf"), ".INF": float("inf"),
            "+.inf": float("inf"), "+.Inf": float("inf"), "+.INF": float("inf"),
            "-.inf": float("-inf"), "-.Inf": float("-inf"), "-.INF": float("-inf"),
            ".nan": float("nan"), ".NaN": float("nan"), ".NAN": float("nan")}
_NUMERIC_START = frozenset("0123456789+-.")
_CORE = "tag:yaml.org,2002:"
#: Longest integer literal read [digits]: far beyond the float range, below Python's 4300-digit limit.
MAX_INT_DIGITS = 1000


#: A plain scalar in flow context made of names, numbers and units: no indicator, no ': ', no ' #'.
_PLAIN = r"(?:[A-Za-z0-9_.+/]|-(?=[A-Za-z0-9_.]))[A-Za-z0-9_.+/%\- ]*"
_NAME = r"[A-Za-z_][A-Za-z0-9_]*"
_PAIR = rf"{_NAME}: +{_PLAIN}"
_OUTER = rf"{_NAME}: +(?:\{{ *{_PAIR}(?:, *{_PAIR})* *\}}|{_PLAIN})"
#: A block list entry holding one flow mapping of plain pairs (values may be such mappings) on one line.
_FLOW_LINE = re.compile(rf"^( *- )\{{ *({_OUTER}(?:, *{_OUTER})*) *\}}(?: +#[^\n]*)?$", re.M)
_FLOW_PAIR = re.compile(rf"({_NAME}): +(?:\{{([^{{}}]*)\}}|([^,{{}}]*))(?:,|$)")
_PLAIN_PAIR = re.compile(rf" *({_NAME}): +([^,]*?) *(?:,|$)")
#: The first pair of a flow line's mapping when its value is plain, and the comma after it.
_FIRST_PAIR = re.compile(rf" *({_NAME}): +([^,{{}}]*?) *, *")
#: What the parser reads in place of a flow line's mapping (see the module's docstring).
_FLOW = "__pampipe_flow_line__"


class _Error(Exception):
    """A problem at a place in the file: (message, mark)."""

    def __init__(self, message: str, mark) -> None:
        super().__init__(message)
        self.mark = mark


def read_text(path: Path, *, what: str = "file") -> str:
    """Read a UTF-8 text file of at most :data:`MAX_BYTES`; failures raise :class:`InputError`."""
    raw = read_bounded(path, what=what, limit=MAX_BYTES)
    if b"\x00" in raw:
        raise InputError(f"{path}: is a binary file, expected a text {what}.")
    try:
        return raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        line = raw.count(b"\n", 0, exc.start) + 1
        raise InputError(f"{path}: line {line}: is not UTF-8 text (byte {exc.start}).") from None


def load_mapping(path: Path, *, what: str = "YAML file") -> dict:
    """Parse a YAML file whose top level must be a mapping."""
    text = read_text(path, what=what)
    if not text.strip():
        raise InputError(f"{path}: the {what} is empty; expected a YAML mapping.")
    document = loads(text, source=str(path))
    if not isinstance(document, dict):
        raise InputError(f"{path}: the top level must be a YAML mapping (key: value lines), "
                         f"got {_type_name(document)}.")
    return document


def loads(text: str, *, source: str = "<text>"):
    """The one document in ``text`` as Python objects (YAML 1.2 core); errors raise InputError."""
    try:
        return _document(text)
    except _Error as exc:
        raise InputError(f"{source}:{_where(exc.mark)}: {exc}") from None
    except yaml.MarkedYAMLError as exc:
        mark = exc.problem_mark or exc.context_mark
        raise InputError(f"{source}:{_where(mark)}: invalid YAML (the YAML parser says: "
                         f"{exc.problem or exc.context}); {_ALLOWED}.") from None
    except yaml.YAMLError as exc:
        raise InputError(f"{source}: invalid YAML (the YAML parser says: {str(exc)[:200]}); "
                         f"{_ALLOWED}.") from None


def _document(text: str):
    """The document of ``text``, its one-line flow-mapping list entries read by :func:`_flow_lines`."""
    try:
        flows, marked = _flow_lines(text)
    except _Error:  # an integer too long: the parse below says where
        flows = {}
    if flows:
        try:
            builder = _Builder(_Parser(marked), flows)
            document = builder.document()
            if builder.replaced == len(flows):
                return document
        except (_Error, yaml.YAMLError):
            pass  # parsed again below, for the parser's own message
    return _Builder(_Parser(text)).document()


def _flow_lines(text: str) -> tuple[dict, str]:
    """({(line, column): (mappings, nodes, depth)}, ``text`` with each run of consecutive lines
    ``- {key: value, ...}`` (plain names and values, no repeated key) at one indentation replaced by one
    list entry :data:`_FLOW` and as many line ends: the run's mappings in order, their nodes and deepest
    nesting, at the run's first line."""
    flows: dict[tuple[int, int], tuple[list, int, int]] = {}
    resolved = _Resolved()  # route lines repeat their keys and units
    rests: dict[str, tuple] = {}  # and all but their names
    pieces: list[str] = []
    done = line = 0  # text[:done] is written to pieces; line: the line at done
    run: list = []  # the open run: [prefix, start, end, mappings, nodes, depth]
    for match in _FLOW_LINE.finditer(text):
        prefix, body = match.group(1, 2)
        mapping, nodes, depth = _named_flow_mapping(body, resolved, rests)
        if mapping is None:
            continue
        start = match.start()
        if run and start == run[2] + 1 and prefix == run[0]:  # the next line, at the same indentation
            run[2] = match.end()
            run[3].append(mapping)
            run[4] += nodes
            run[5] = max(run[5], depth)
            continue
        if run:
            line = _close_run(text, run, done, line, pieces, flows)
            done = run[2]
        run = [prefix, start, match.end(), [mapping], nodes, depth]
    if not run:
        return flows, text
    _close_run(text, run, done, line, pieces, flows)
    pieces.append(text[run[2]:])
    return flows, "".join(pieces)


def _close_run(text: str, run: list, done: int, line: int, pieces: list, flows: dict) -> int:
    """Write ``text[done:]`` up to the end of ``run`` into ``pieces`` with the run replaced (see
    :func:`_flow_lines`), enter the run into ``flows``; the line at the run's end."""
    prefix, start, _, mappings, nodes, depth = run
    line += text.count("\n", done, start)
    flows[line, len(prefix)] = mappings, nodes, depth
    pieces += (text[done:start], prefix, _FLOW, "\n" * (len(mappings) - 1))
    return line + len(mappings) - 1


def _named_flow_mapping(body: str, resolved: _Resolved, rests: dict) -> tuple[dict | None, int, int]:
    """(mapping, nodes, depth) of :func:`_flow_mapping` of ``body``, its pairs after a plain first one (a
    section's name) read once per distinct text (``rests``: text → (mapping, nodes, its nested keys)); each
    line gets its own mappings. depth: 2 with a nested mapping, else 1."""
    first = _FIRST_PAIR.match(body)
    if first is None:
        mapping, nodes = _flow_mapping(body, resolved)
        return mapping, nodes, 1 + ("{" in body)
    rest = body[first.end():]
    parsed = rests.get(rest)
    if parsed is None:
        mapping, nodes = _flow_mapping(rest, resolved)
        nested = () if mapping is None else tuple(k for k, v in mapping.items() if type(v) is dict)
        parsed = rests[rest] = mapping, nodes, nested
    mapping, nodes, nested = parsed
    key, value = first.group(1, 2)
    key = resolved[key]
    if mapping is None or key in mapping:
        return None, 0, 0
    # a name is text unless it reads as something else (most names: 10⁵ distinct ones are not cached)
    line = {key: value if value[:1] not in _NUMERIC_START and value not in _SPECIAL else resolved[value],
            **mapping}
    for k in nested:  # a nested mapping is the line's own
        line[k] = dict(line[k])
    return line, nodes + 2, 1 + bool(nested)


def _flow_mapping(body: str, resolved: _Resolved) -> tuple[dict | None, int]:
    """(mapping, nodes) of ``key: value, ...`` (values plain or ``{key: value, ...}``, as
    :data:`_FLOW_LINE` checked); None for a repeated key."""
    if "{" not in body:  # plain values only
        pairs = _PLAIN_PAIR.findall(body)
        mapping = {resolved[key]: resolved[value] for key, value in pairs}
        return (mapping, 1 + 2 * len(pairs)) if len(mapping) == len(pairs) else (None, 0)
    mapping: dict = {}
    nodes = 1
    for key, inner, plain in _FLOW_PAIR.findall(body):
        key = resolved[key]
        if key in mapping:
            return None, 0
        if inner:
            value, size = _flow_mapping(inner, resolved)
            if value is None:
                return None, 0
        else:
            value, size = resolved[plain.rstrip()], 1
        mapping[key] = value
        nodes += 1 + size
    return mapping, nodes


class _Resolved(dict):
    """Plain scalar → its value (:func:`_resolve`), computed at the first lookup."""

    def __missing__(self, plain: str):
        value = self[plain] = _resolve(plain, None)
        return value


def _where(mark) -> str:
    return f" line {mark.line + 1}, column {mark.column + 1}" if mark is not None else ""


def _type_name(value) -> str:
    return {dict: "a mapping", list: "a list", str: "text", type(None): "nothing"}.get(
        type(value), type(value).__name__)


class _Frame:
    """An open mapping or list while its events arrive."""

    __slots__ = ("anchor", "container", "key", "key_mark", "merges", "seen", "size", "start")

    def __init__(self, container, anchor, start) -> None:
        self.container, self.anchor, self.start = container, anchor, start
        self.size = 1  # nodes of the expanded subtree, aliases included
        self.key = self.key_mark = None
        self.seen: set | None = None if isinstance(container, list) else set()
        self.merges: list = []


class _Builder:
    """Python objects from parser events, with the 1.2-core schema and the bounds above."""

    def __init__(self, parser, flows: dict | None = None) -> None:
        self.parser = parser
        self.flows = flows or {}  # (line, column) -> (mappings, nodes, depth) read by _flow_lines
        self.replaced = 0
        self.anchors: dict[str, tuple[object, int]] = {}
        self.open_anchors: set[str] = set()
        self.written = 0  # nodes written in the file
        self.expanded = 0  # nodes added by aliases

    def document(self):
        events = self.parser
        events.get_event()  # stream start
        start = events.get_event()
        if isinstance(start, yaml.StreamEndEvent):
            return None
        stack: list[_Frame] = []
        result = _NOTHING = object()
        while True:
            event = events.get_event()
            kind = type(event)
            if kind is yaml.ScalarEvent:
                if event.value == _FLOW and event.tag is None and event.implicit[0]:
                    self.flow(event, stack)  # a run of list entries, added to the list
                    continue
                value, size = self.scalar(event), 1
                self.written += size
                if event.anchor is not None:
                    self.anchors[event.anchor] = (value, 1)
            elif kind is yaml.MappingStartEvent or kind is yaml.SequenceStartEvent:
                self.check_tag(event, "map" if kind is yaml.MappingStartEvent else "seq")
                if len(stack) >= MAX_DEPTH:
                    raise _Error(f"nested deeper than {MAX_DEPTH} levels", event.start_mark)
                frame = _Frame({} if kind is yaml.MappingStartEvent else [], event.anchor, event.start_mark)
                if event.anchor is not None:
                    self.open_anchors.add(event.anchor)
                stack.append(frame)
                self.written += 1
                continue
            elif kind is yaml.MappingEndEvent or kind is yaml.SequenceEndEvent:
                frame = stack.pop()
                if frame.merges:
                    self.merge(frame)
                value, size = frame.container, frame.size
                if frame.anchor is not None:
                    self.open_anchors.discard(frame.anchor)
                    self.anchors[frame.anchor] = (value, size)
            elif kind is yaml.AliasEvent:
                if event.anchor in self.open_anchors:
                    raise _Error(f"the alias *{event.anchor} refers to a collection that contains it",
                                 event.start_mark)
                if event.anchor not in self.anchors:
                    raise _Error(f"the alias *{event.anchor} has no anchor &{event.anchor} before it",
                                 event.start_mark)
                value, size = self.anchors[event.anchor]
                self.expanded += size
                if self.expanded > max(MAX_ALIAS_NODES, self.written):
                    raise _Error(f"aliases expand the document beyond {max(MAX_ALIAS_NODES, self.written):,} "
                                 "extra nodes (an alias bomb?)", event.start_mark)
            elif kind is yaml.DocumentEndEvent:
                if not isinstance(events.get_event(), yaml.StreamEndEvent):
                    raise _Error("the file holds several YAML documents; expected one", event.end_mark)
                return None if result is _NOTHING else result
            else:
                raise _Error(f"unexpected {kind.__name__}", event.start_mark)
            if not stack:
                result = value
                continue
            self.add(stack[-1], value, size, event)

    def flow(self, event, stack: list[_Frame]) -> None:
        """Add the run of mappings that :func:`_flow_lines` read for this placeholder to the list it is an
        entry of."""
        mark = event.start_mark
        mappings, nodes, depth = self.flows.get((mark.line, mark.column), (None, 0, 0))
        if mappings is None or not stack or stack[-1].seen is not None or len(stack) + depth > MAX_DEPTH \
                or event.anchor is not None:
            raise _Error("not a flow line read in place", mark)  # the caller parses without flow lines
        self.replaced += 1
        self.written += nodes
        stack[-1].container.extend(mappings)
        stack[-1].size += nodes

    def add(self, frame: _Frame, value, size: int, event) -> None:
        frame.size += size
        container = frame.container
        if frame.seen is None:
            container.append(value)
            return
        if frame.key is None and frame.key_mark is None:
            if isinstance(value, dict | list):
                raise _Error(f"{_type_name(value)} cannot be a key; keys are names or numbers",
                             event.start_mark)
            frame.key, frame.key_mark = value, event.start_mark
            if value == "<<" and type(event) is yaml.ScalarEvent and event.implicit[0]:
                frame.key = _MERGE
            return
        key, mark = frame.key, frame.key_mark
        frame.key = frame.key_mark = None
        if key is _MERGE:
            sources = value if isinstance(value, list) else [value]
            if not all(isinstance(s, dict) for s in sources):
                raise _Error("a merge key '<<' takes a mapping or a list of mappings", mark)
            frame.merges.extend(sources)
            return
        if key in frame.seen:
            raise _Error(f"duplicate key {_clip(key)}", mark)
        frame.seen.add(key)
        container[key] = value

    def merge(self, frame: _Frame) -> None:
        """Merged keys first (earlier sources win), then the explicit keys (which win over merged)."""
        merged: dict = {}
        for source in frame.merges:
            for key, value in source.items():
                merged.setdefault(key, value)
        merged.update(frame.container)
        frame.container.clear()
        frame.container.update(merged)

    def check_tag(self, event, expected: str) -> None:
        if event.tag not in (None, "!", _CORE + expected):
            raise _Error(f"the tag {_clip(event.tag)} is not read; pampipe reads plain YAML",
                         event.start_mark)

    def scalar(self, event):
        value, tag = event.value, event.tag
        if tag is None:
            return _resolve(value, event.start_mark) if event.implicit[0] else value
        if tag == "!" or tag == _CORE + "str":
            return value
        if tag in (_CORE + "int", _CORE + "float", _CORE + "bool", _CORE + "null"):
            resolved = _resolve(value, event.start_mark)
            wanted = {"int": int, "float": (int, float), "bool": bool, "null": type(None)}[tag[len(_CORE):]]
            if not isinstance(resolved, wanted) or (tag.endswith("int") and isinstance(resolved, bool)):
                raise _Error(f"{_clip(value)} is not a valid {tag[len(_CORE):]}", event.start_mark)
            return float(resolved) if tag.endswith("float") else resolved
        raise _Error(f"the tag {_clip(tag)} is not read; pampipe reads plain YAML", event.start_mark)


_MERGE = object()


def is_plain_text(value: str) -> bool:
    """True if ``value`` written as a plain scalar reads back as this text (not a number, bool, null)."""
    try:
        return _resolve(value, None) == value and isinstance(_resolve(value, None), str)
    except _Error:  # an integer too long to read
        return False


def _resolve(value: str, mark):
    """A plain scalar under the YAML 1.2 core schema."""
    if value in _SPECIAL:
        return _SPECIAL[value]
    if value[0] not in _NUMERIC_START:
        return value
    if _INT.fullmatch(value):
        if len(value) > MAX_INT_DIGITS:
            raise _Error(f"an integer of {len(value)} digits is beyond any range pampipe reads", mark)
        return int(value)
    if _FLOAT.fullmatch(value):
        return float(value)
    if value.startswith("0o") and re.fullmatch(r"0o[0-7]+", value) and len(value) < MAX_INT_DIGITS:
        return int(value[2:], 8)
    if value.startswith("0x") and re.fullmatch(r"0x[0-9a-fA-F]+", value) and len(value) < MAX_INT_DIGITS:
        return int(value[2:], 16)
    return value


def _clip(value, size: int = 40) -> str:
    text = repr(value)
    return text if len(text) <= size else text[:size] + "…"
