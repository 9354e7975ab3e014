"""Writing YAML through one emitter, so that every file pampipe writes reads back identically.

Documents are plain dicts; :func:`dump` emits them with PyYAML's safe dumper, which quotes every
string another YAML reader could take for something else (``yes``, ``1:30``, ``010``, ``#`` inside
a name, digits only), and writes floats with their shortest exact (round-trip) representation.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import yaml

from pampipe.io.files import atomic_write_text
from pampipe.io.yamlfile import is_plain_text


class _Dumper(yaml.SafeDumper):
    """Safe dumper that keeps the key order and indents block sequences under their key."""

    def increase_indent(self, flow=False, indentless=False):
        return super().increase_indent(flow, False)


def _flow_list(dumper: yaml.SafeDumper, data: list):
    """Lists of numbers on one line (coefficient vectors, matrix rows); other lists as blocks."""
    flat = all(isinstance(v, int | float) and not isinstance(v, bool) for v in data)
    return dumper.represent_sequence("tag:yaml.org,2002:seq", data, flow_style=flat)


def _text(dumper: yaml.SafeDumper, data: str):
    """Quote what YAML 1.2 core would not read back as text (``0o17``, ``.inf``); PyYAML's 1.1 rules quote
    the rest (``yes``, ``1:30``, ``010``)."""
    style = None if is_plain_text(data) else "'"
    return dumper.represent_scalar("tag:yaml.org,2002:str", data, style=style)


_Dumper.add_representer(list, _flow_list)
_Dumper.add_representer(str, _text)


def dump(document: dict, *, comments: Sequence[str] = ()) -> str:
    """YAML text of ``document``, after ``comments`` written as ``# `` lines."""
    head = "".join(f"# {line}\n" if line else "#\n" for text in comments for line in str(text).splitlines())
    body = yaml.dump(document, Dumper=_Dumper, sort_keys=False, allow_unicode=True, width=100,
                     default_flow_style=False)
    return head + body


def write(target: Path, document: dict, *, comments: Sequence[str] = ()) -> None:
    """Write :func:`dump` of ``document`` to ``target`` atomically (the caller protects inputs)."""
    atomic_write_text(Path(target), dump(document, comments=comments))
