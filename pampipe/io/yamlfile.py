"""Reading YAML input files safely: clear errors for missing, unreadable or malformed files."""

from __future__ import annotations

from pathlib import Path

import yaml

from pampipe.errors import InputError


class _StrictLoader(yaml.SafeLoader):
    """SafeLoader that rejects duplicate keys instead of silently keeping the last one."""


def _construct_mapping(loader: _StrictLoader, node: yaml.MappingNode, deep: bool = False):
    seen: dict = {}
    for key_node, _ in node.value:
        key = loader.construct_object(key_node, deep=deep)
        if key in seen:
            raise yaml.constructor.ConstructorError(
                None, None, f"duplicate key {key!r} (first at line {seen[key] + 1})", key_node.start_mark)
        seen[key] = key_node.start_mark.line
    return yaml.SafeLoader.construct_mapping(loader, node, deep)


_StrictLoader.add_constructor(yaml.resolver.BaseResolver.DEFAULT_MAPPING_TAG, _construct_mapping)


def read_text(path: Path, *, what: str = "file") -> str:
    """Read a UTF-8 text file; every OS-level failure becomes an :class:`InputError` naming the path."""
    try:
        raw = path.read_bytes()
    except FileNotFoundError:
        raise InputError(f"{path}: {what} not found.") from None
    except IsADirectoryError:
        raise InputError(f"{path}: is a directory, expected a {what}.") from None
    except PermissionError:
        raise InputError(f"{path}: permission denied while reading the {what}.") from None
    except OSError as exc:  # symlink loops, name too long, I/O errors
        raise InputError(f"{path}: cannot read the {what} ({exc.strerror or exc}).") from None
    if b"\x00" in raw:
        raise InputError(f"{path}: is a binary file, expected a text {what}.")
    try:
        return raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise InputError(f"{path}: is not UTF-8 text (byte {exc.start}).") from None


def load_mapping(path: Path, *, what: str = "YAML file") -> dict:
    """Parse a YAML file whose top level must be a mapping."""
    text = read_text(path, what=what)
    if not text.strip():
        raise InputError(f"{path}: the {what} is empty; expected a YAML mapping.")
    try:
        document = yaml.load(text, Loader=_StrictLoader)
    except yaml.MarkedYAMLError as exc:
        mark = exc.problem_mark or exc.context_mark
        where = f" line {mark.line + 1}, column {mark.column + 1}" if mark else ""
        raise InputError(f"{path}:{where}: invalid YAML: {exc.problem or exc.context}.") from None
    except yaml.YAMLError as exc:
        raise InputError(f"{path}: invalid YAML: {exc}.") from None
    if not isinstance(document, dict):
        raise InputError(f"{path}: the top level must be a YAML mapping (key: value lines), "
                         f"got {type(document).__name__}.")
    return document
