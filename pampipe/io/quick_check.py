"""A quick structural check of a well-formed input file, without the schema library (issue 39).

Importing pydantic, building the schema classes and a first validation cost a new mission about two thirds
of ``pampipe plan``'s start-up. Most files are well-formed, so a file is first read by a :class:`Shape`: a
plain-Python mirror of its strict schema class (the same keys and aliases, defaults, types and the same
:class:`~pampipe.specs.quantity_rule.QuantityRule` for each quantity) that builds :class:`Record` objects
with the fields the schema object would have. Anything it does not plainly accept (a wrong type, a value
out of range, an unknown or missing key, a form it does not know) raises :class:`Fallback`: the caller
then validates the file with the pydantic schema, whose message (the key, the value, what is allowed) is
the one the user sees. So the quick check never explains anything; it only says "well-formed" sooner.

Strictness is pydantic's strict mode, or stricter: text is ``str``, a number is ``int`` or ``float``
(never ``bool``; a float field turns an int into a float), a literal matches type and value.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

from pampipe.errors import InputError

#: A check: the value as read from YAML → the validated value; raises :class:`Fallback`.
Check = Callable[[Any], Any]
#: A field without a default.
REQUIRED = object()


class Fallback(Exception):
    """The quick check does not plainly accept the value: validate it with the schema class."""


class Record:
    """A mapping checked by a :class:`Shape`: its fields as attributes, as on the schema object.

    ``kind`` is the schema class's name (``"SectionSchema"``); :meth:`fields` the values by field name."""

    __slots__ = ("__dict__", "kind")

    def __init__(self, kind: str, values: dict[str, Any]) -> None:
        self.kind = kind
        self.__dict__.update(values)

    def fields(self) -> dict[str, Any]:
        return dict(self.__dict__)

    def __repr__(self) -> str:
        return f"{self.kind}({', '.join(f'{k}={v!r}' for k, v in self.__dict__.items())})"


class Shape:
    """The quick check of one strict schema class ``kind``: ``fields`` maps each field's name to (its
    check, its default or :data:`REQUIRED`); ``aliases`` the keys written for a field (``from``);
    ``after(record)`` the class's own check of the whole (raises ValueError)."""

    def __init__(self, kind: str, fields: dict[str, tuple[Check, Any]], *,
                 aliases: dict[str, str] | None = None, after: Callable[[Record], None] | None = None):
        self.kind, self.fields, self.after = kind, fields, after
        self.keys = {(aliases or {}).get(name, name): name for name in fields}

    def __call__(self, value: Any) -> Record:
        if not isinstance(value, dict) or any(key not in self.keys for key in value):
            raise Fallback
        out = {}
        for key, name in self.keys.items():
            check, default = self.fields[name]
            if key in value:
                out[name] = check(value[key])
            elif default is REQUIRED:
                raise Fallback
            else:
                out[name] = default
        record = Record(self.kind, out)
        if self.after is not None:
            try:
                self.after(record)
            except (ValueError, InputError):
                raise Fallback from None
        return record


def quantity(rule: Callable[[Any], float]) -> Check:
    """A quantity read by ``rule`` (a :class:`~pampipe.specs.quantity_rule.QuantityRule`)."""
    def check(value: Any) -> float:
        try:
            return rule(value)
        except (ValueError, InputError):
            raise Fallback from None
    return check


def then(check: Check, rule: Callable[[Any], Any]) -> Check:
    """``check``, then ``rule`` (a pydantic after-validator: raises ValueError) on its result."""
    def both(value: Any) -> Any:
        try:
            return rule(check(value))
        except (ValueError, InputError):
            raise Fallback from None
    return both


def text(min_length: int = 0, max_length: int | None = None) -> Check:
    def check(value: Any) -> str:
        if not isinstance(value, str) or len(value) < min_length or (
                max_length is not None and len(value) > max_length):
            raise Fallback
        return value
    return check


def number(value: Any) -> float:
    """A strict float: an int or a float (not a bool), as a float."""
    if type(value) is float:
        return value
    if type(value) is int:
        return float(value)
    raise Fallback


def finite_number(value: Any) -> float:
    value = number(value)
    if not math.isfinite(value):
        raise Fallback
    return value


def whole(ge: int | None = None) -> Check:
    def check(value: Any) -> int:
        if type(value) is not int or (ge is not None and value < ge):
            raise Fallback
        return value
    return check


def literal(*allowed: Any) -> Check:
    def check(value: Any) -> Any:
        if not any(type(value) is type(a) and value == a for a in allowed):
            raise Fallback
        return value
    return check


def scalar(*types: type) -> Check:
    """A value of one of ``types`` exactly (``str | float | int`` unions), kept as it is."""
    def check(value: Any) -> Any:
        if type(value) not in types:
            raise Fallback
        return value
    return check


def anything(value: Any) -> Any:
    return value


def optional(check: Check) -> Check:
    """None, or what ``check`` accepts."""
    return lambda value: None if value is None else check(value)


def mapping_or(shape: Shape, check: Check) -> Check:
    """``Scalar | Schema`` unions: a mapping is read by ``shape``, anything else by ``check``."""
    return lambda value: shape(value) if isinstance(value, dict) else check(value)


def listed(check: Check, min_length: int = 0, max_length: int | None = None) -> Check:
    def each(value: Any) -> list:
        if not isinstance(value, list) or len(value) < min_length or (
                max_length is not None and len(value) > max_length):
            raise Fallback
        return [check(item) for item in value]
    return each


def keyed(check: Check, min_length: int = 0) -> Check:
    """``dict[str, ...]``: text keys, each value read by ``check``."""
    def each(value: Any) -> dict:
        if not isinstance(value, dict) or len(value) < min_length:
            raise Fallback
        if any(type(key) is not str for key in value):
            raise Fallback
        return {key: check(item) for key, item in value.items()}
    return each
