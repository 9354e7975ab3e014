"""Schema building blocks and validation with messages in pampipe's words (docs/formats.md §1-§4).

:class:`Strict` models forbid unknown keys and do not coerce types (``"yes"`` is not a boolean, ``3.5``
not an integer). :func:`quantity` makes a field that reads a quantity (:func:`pampipe.units.quantities.to_si`)
and checks its range. :func:`validate` turns pydantic's errors into one short message: the key path,
the value, what is allowed, a did-you-mean for misspelt keys, at most :data:`MAX_PROBLEMS` problems.
"""

from __future__ import annotations

import re
from collections.abc import Iterator
from contextlib import contextmanager
from contextvars import ContextVar
from dataclasses import dataclass
from pathlib import Path
from typing import Annotated, Any

import pydantic
from pydantic import BaseModel, BeforeValidator, ConfigDict

from pampipe.errors import InputError
from pampipe.specs.quantity_rule import QuantityRule
from pampipe.units.quantities import NUMBER, example, show

#: Problems listed in one message; the rest are counted.
MAX_PROBLEMS = 10


class Strict(BaseModel):
    """Base of every schema: unknown keys are errors, values are not coerced, objects are frozen."""

    model_config = ConfigDict(extra="forbid", frozen=True, strict=True, defer_build=True)


def quantity(dimension: str, *, gt: float | None = None, ge: float | None = None,
             lt: float | None = None, le: float | None = None, unit: str = "", hint: str = ""):
    """A schema field holding a ``dimension`` quantity, converted to SI and range-checked
    (:class:`~pampipe.specs.quantity_rule.QuantityRule`)."""
    return quantity_field(QuantityRule(dimension, gt=gt, ge=ge, lt=lt, le=le, unit=unit, hint=hint))


def quantity_field(rule: QuantityRule):
    """The schema field of a :class:`~pampipe.specs.quantity_rule.QuantityRule`."""
    return Annotated[float, BeforeValidator(rule), QuantityJson(rule.dimension, rule.unit)]


# ------------------------------------------------------------------------------------- JSON Schema
#: A quantity string of the JSON Schemas in yaml/: a number, then a unit (a name, %, ° or 1/...).
UNIT_PATTERN = rf"^\s*{NUMBER}\s*(?:[^\s\d.+\-]|1\s*/).*$"
_SI_FORM: ContextVar[bool] = ContextVar("json_schema_si_form", default=False)


@contextmanager
def bare_si_schema(si: bool) -> Iterator[None]:
    """JSON Schemas built within this block read a bare number of a quantity as SI (a file that says
    ``units: SI``); outside it a dimensioned quantity needs a unit string (or 0), as pampipe reads a file."""
    token = _SI_FORM.set(si)
    try:
        yield
    finally:
        _SI_FORM.reset(token)


@dataclass(frozen=True)
class QuantityJson:
    """The JSON Schema of a :func:`quantity` field: what a file may hold, not the SI float it becomes."""

    dimension: str
    unit: str

    def __get_pydantic_json_schema__(self, core_schema, handler) -> dict:
        text = {"type": "string", "pattern": UNIT_PATTERN}
        like = example(self.dimension)
        if self.dimension == "dimensionless":
            return {"anyOf": [{"type": "number"}, text], "description": f"a plain number (or a percentage, "
                    f"'5 %'), like {like}"}
        bare = {"type": "number"} if _SI_FORM.get() and self.dimension != "angle" else {"const": 0}
        kinds = [text] if self.dimension == "temperature" else [text, bare]
        si = f" or a bare number in {self.unit}" if bare.get("type") and self.unit else ""
        return {"anyOf": kinds, "description": f"{'an' if self.dimension[0] in 'aeiou' else 'a'} "
                f"{self.dimension} with its unit, like '{like}'{si}"}


def validate(path: Path | str, schema_cls: type[BaseModel], raw: Any, *,
             rename: dict[str, str] | None = None):
    """``schema_cls`` validated from ``raw``; problems raise one :class:`InputError` naming ``path``.

    ``rename`` maps key paths to the names the user typed (``{'fit.seed': '--seed'}``).
    """
    try:
        return schema_cls.model_validate(raw)
    except pydantic.ValidationError as exc:
        tags = _schema_names(Strict) | _SCALAR_TAGS
        errors = _relevant(exc.errors(include_url=False), raw, tags)
        lines: list[str] = []
        used = 0
        for err in errors:
            used += 1
            line = _describe(schema_cls, err, rename or {}, tags)
            if line not in lines:
                lines.append(line)
            if len(lines) == MAX_PROBLEMS:
                break
        more = len(errors) - used
        tail = f"; … and {more:,} more problem{'s' if more > 1 else ''}" if more > 0 else ""
        raise InputError(f"{path}: " + "; ".join(lines) + tail) from None


# ------------------------------------------------------------------------------------- messages
def _relevant(errors: list[dict], raw: Any, tags: set[str]) -> list[dict]:
    """Drop the errors of union members the input cannot be meant for.

    A mapping given for ``friction: 0.3 | {value, sd}`` is meant for the mapping form, so the number
    form's complaint ("not a number") is noise, and the reverse for a scalar; a value that is not text
    is not meant for a word (``'from_pam'``): that member's complaint is noise too.
    """
    kept = [err for err in errors if _consistent(err["loc"], raw, tags)]
    return kept or errors


def _consistent(loc: tuple, raw: Any, tags: set[str]) -> bool:
    node = raw
    for part in loc:
        if _is_union_tag(part, tags):
            if _mapping_member(part, tags) != isinstance(node, dict):
                return False
            if part.startswith("literal[") and not isinstance(node, str):
                return False
            continue
        try:
            node = node[part]
        except (KeyError, IndexError, TypeError):
            return True
    return True


def _describe(schema_cls: type[BaseModel], err: dict, rename: dict[str, str], tags: set[str]) -> str:
    """One readable sentence for one pydantic error: key path, bad value, what is allowed."""
    loc = [part for part in err["loc"] if not _is_union_tag(part, tags)]
    key = ".".join(f"[{p}]" if isinstance(p, int) else str(p) or "''" for p in loc).replace(".[", "[")
    key = rename.get(key, key)
    kind, value, ctx = err["type"], err.get("input"), err.get("ctx") or {}
    if kind == "extra_forbidden":
        import difflib

        allowed = _allowed_keys(schema_cls, err["loc"][:-1], tags)
        close = difflib.get_close_matches(str(loc[-1]), allowed, n=1)
        return (f"unknown key {show(key)}" + (f"; did you mean '{close[0]}'?" if close else "")
                + (f" (allowed keys here: {', '.join(allowed)})" if allowed else ""))
    if kind == "missing":
        return f"missing required key {show(key)}"
    message = _MESSAGES.get(kind, "")
    message = message.format(**ctx) if message else err["msg"].removeprefix("Value error, ")
    where = key or "top level"
    if kind in ("value_error", "too_short", "too_long") or isinstance(value, dict | list):
        return f"{where}: {message}"
    return f"{where}: {message} (got {show(value)})"


_MESSAGES = {
    "float_type": "expected a number", "float_parsing": "expected a number",
    "int_type": "expected a whole number", "int_parsing": "expected a whole number",
    "int_from_float": "expected a whole number",
    "bool_type": "expected true or false", "bool_parsing": "expected true or false",
    "string_type": "expected text", "string_too_short": "must not be empty",
    **dict.fromkeys(("dict_type", "model_type", "model_attributes_type"),
                    "expected a mapping (key: value lines)"),
    "list_type": "expected a list", "tuple_type": "expected a list",
    "too_short": "needs at least {min_length} item(s), got {actual_length}",
    "too_long": "takes at most {max_length} item(s), got {actual_length}",
    "literal_error": "must be {expected}",
    "greater_than": "must be greater than {gt}", "greater_than_equal": "must be at least {ge}",
    "less_than": "must be less than {lt}", "less_than_equal": "must be at most {le}",
    "finite_number": "must be a finite number",
}


_SCALAR_TAGS = {"str", "float", "int", "bool", "list", "dict", "none"}


def _mapping_member(part: str, tags: set[str]) -> bool:
    """True if the union member tagged ``part`` takes a mapping: a schema class, also behind validators
    (``function-after[_inside(), UncertainFriction]``)."""
    if part.startswith("function-"):
        part = re.findall(r"[A-Za-z_]\w*", part)[-1]
    return part not in _SCALAR_TAGS and "[" not in part and part in tags


def _is_union_tag(part, tags: set[str]) -> bool:
    """pydantic puts the member tried (``str``, ``PamSchema``, ``function-after[...]``) into a union's loc.

    ``tags`` holds the schema class names and the scalar member names.
    """
    return isinstance(part, str) and (part in tags or "[" in part)


def _schema_names(cls) -> set[str]:
    names = set()
    for sub in cls.__subclasses__():
        names |= {sub.__name__} | _schema_names(sub)
    return names


def _allowed_keys(schema_cls: type[BaseModel], loc: tuple, tags: set[str]) -> list[str]:
    """The keys (as written: aliases such as ``from``) of the mapping at ``loc``; a union member named
    in ``loc`` (pydantic's tag) picks that member."""
    cls: Any = schema_cls
    annotation = None
    for part in loc:
        if isinstance(part, int):
            continue
        if _is_union_tag(part, tags):
            cls = _model_named(annotation, part) or cls
            continue
        field = cls.model_fields.get(part) if isinstance(cls, type) and issubclass(cls, BaseModel) else None
        if field is None:
            return []
        annotation = field.annotation
        cls = _model_in(annotation)
        if cls is None:
            return []
    if not (isinstance(cls, type) and issubclass(cls, BaseModel)):
        return []
    return [field.alias or name for name, field in cls.model_fields.items()]


def _model_named(annotation, name: str) -> type[BaseModel] | None:
    """The model class called ``name`` among the members of ``annotation``, if any."""
    if isinstance(annotation, type) and issubclass(annotation, BaseModel):
        return annotation if annotation.__name__ == name else None
    for arg in getattr(annotation, "__args__", ()):
        found = _model_named(arg, name)
        if found is not None:
            return found
    return None


def _model_in(annotation) -> type[BaseModel] | None:
    if isinstance(annotation, type) and issubclass(annotation, BaseModel):
        return annotation
    for arg in getattr(annotation, "__args__", ()):
        found = _model_in(arg)
        if found is not None:
            return found
    return None
