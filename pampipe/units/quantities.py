"""Quantities in, SI floats out: the only place where units are parsed (docs/formats.md §1).

A value is a number (SI: m, Pa, N, kg, s, K; never for an angle, which must carry a unit; in a file only
when the file says ``units: SI``, see :func:`bare_numbers`) or a string
``"<number> <unit>"`` read by a strict grammar (a string without a unit is refused, unless the value is
dimensionless or zero: a bare ``0`` is zero in every unit but a temperature, whose units have offsets)::

    quantity := number [unit]                       at most 100 characters
    number   := [+-] digits [. digits] [e [+-] digits]
    unit     := term (('*' | '·' | '/' | ' ') term)*
    term     := name [('**' | '^') [-]digit | '²' | '³'] | '(' unit ')' | '1' (only as '1/...')

Anything else is refused: arithmetic on numbers (``10**400 Pa``), trailing text (``1 mm; 76.2``),
decimal commas (``0,4 kg``), inch and foot marks (``10"``), and numbers beyond the float range.
``%`` turns a dimensionless value into a fraction (``5 %`` = 0.05) and is refused for angles.
Pressures are gauge pressures: ``psig``/``barg`` are read, ``psia``/``bara`` refused.

Common unit names come from :mod:`pampipe.units.table`; pint is imported only for other names. Results
are cached per distinct string, so a file repeating ``"3 in"`` 10⁵ times parses it once.
"""

from __future__ import annotations

import math
import re
from contextlib import contextmanager
from contextvars import ContextVar
from functools import lru_cache

from pampipe.errors import InputError
from pampipe.units.table import DIMENSIONS, REFUSED, UNITS, Dimension, describe

#: Longest quantity string read [characters]: the parser's work is linear in it, so this bounds its time.
MAX_LENGTH = 100
#: Regular expression of a plain decimal number: the only number syntax in quantities and CSV cells.
NUMBER = r"[+-]?(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][+-]?\d+)?"

_NUMBER = re.compile(rf"\s*({NUMBER})")
_BARE = re.compile(rf"\s*{NUMBER}\s*")  # a number without a unit
_TOKEN = re.compile(r"\s*(?:(\*\*|\^)\s*(-?\d)(?!\d)|([*/·()])|([²³])|(1)(?=\s*/)|([^\W\d]\w*|%|°))")
_QUOTES = "\"'″′”’“‘"
_EXAMPLES = {"length": "3 in", "pressure": "689 kPa", "force": "1024.74 N", "mass": "2.5 kg",
             "angle": "65.92 deg", "time": "2 s", "dimensionless": "0.3", "temperature": "293 K",
             "sonic conductance": "0.5 dm^3/(s*bar)", "area": "0.5 N/MPa", "compliance": "1e-6 1/N",
             "force per length": "0.8 N/m", "mass per length": "80 g/m", "volume flow": "300 L/min"}


#: Units a bare number of each dimension could have meant, for the refusal of a bare number in a file.
_MEANT = {"length": ("mm", "in", "m"), "pressure": ("kPa", "psi", "Pa"), "force": ("N", "lbf", "kN"),
          "mass": ("kg", "lb", "g"), "time": ("s", "ms", "min"), "temperature": ("K", "degC"),
          "sonic conductance": ("dm^3/(s*bar)", "m^3/(s*Pa)"), "area": ("mm^2", "m^2"),
          "compliance": ("1/N", "1/kN"), "force per length": ("N/m", "lbf/ft"),
          "mass per length": ("kg/m", "g/m", "lb/ft"), "volume flow": ("L/min", "m^3/s")}
#: False while a file without ``units: SI`` is read: a bare non-zero number of a dimension is refused.
_BARE_SI: ContextVar[bool] = ContextVar("bare_numbers_are_si", default=True)


@contextmanager
def bare_numbers(si: bool):
    """Within this block a bare number for a dimensioned quantity is SI (``si``) or refused (a file
    without ``units: SI``, docs/formats.md §1). Outside any block (the Python API's arguments) it is SI."""
    token = _BARE_SI.set(si)
    try:
        yield
    finally:
        _BARE_SI.reset(token)


def _bare_refused(value: object, number: float, dimension: str, prefix: str) -> None:
    """Refuse the bare ``number`` of ``dimension`` when the file read does not say ``units: SI``."""
    if (number == 0 and dimension != "temperature") or _BARE_SI.get() or dimension not in _MEANT \
            or not math.isfinite(number):  # NaN and infinity are refused as such
        return
    shown = [f"{number:g} {unit}" for unit in _MEANT[dimension]]
    raise InputError(f"{prefix}{show(value)} has no unit; write {', '.join(shown[:-1])} or {shown[-1]}"
                     f" (or put 'units: SI' at the top of the file to read bare numbers as SI).")


class _Refused(ValueError):
    """A quantity string that breaks the grammar; the message says why (without the key)."""


def example(dimension: str) -> str:
    """A well-formed quantity of ``dimension``, for messages (e.g. '689 kPa')."""
    return _EXAMPLES.get(dimension, "1")


def to_si(value: object, dimension: str, *, where: str | None = None) -> float:
    """Convert ``value`` (a number or a quantity string) to a finite SI float of ``dimension``.

    Raises :class:`InputError` naming ``where``, the value and what is allowed.
    """
    prefix = f"{where}: " if where else ""
    if isinstance(value, bool) or value is None:
        raise InputError(f"{prefix}expected a {dimension} like '{example(dimension)}', got {show(value)}.")
    if isinstance(value, str):
        try:
            number, found = _parse(value)
        except _Refused as exc:
            raise InputError(f"{prefix}{show(value)}: {exc}") from None
        if number == 0 and _BARE.fullmatch(value) and dimension != "temperature":
            return 0.0  # zero is zero in every unit without an offset
        if found == DIMENSIONS["dimensionless"] and dimension == "angle" and value.strip():
            raise InputError(f"{prefix}{show(value)}: {_angle_hint(value, number)}") from None
        _check_dimension(value, found, dimension, prefix)
    elif type(value) is not float and _is_pint(value):  # a float, the common case, is not asked
        number, found = _from_pint(value, prefix)
        _check_dimension(f"{value:~}", found, dimension, prefix)
    elif (number := real_number(value, where=where)) is not None:
        if dimension == "angle" and number != 0:
            raise InputError(f"{prefix}{show(value)} has no unit; an angle must carry one, "
                             f"e.g. '{number:g} deg' or '{number:g} rad'.")
        _bare_refused(value, number, dimension, prefix)
    else:
        raise InputError(f"{prefix}expected a {dimension} as a number or a string like "
                         f"'{example(dimension)}', got {_kind(value)}.")
    if not math.isfinite(number):
        raise InputError(f"{prefix}{show(value)} is not a finite number.")
    return number


def real_number(value: object, *, where: str | None = None) -> float | None:
    """float of a real number of any kind, or None if ``value`` is not one.

    Any :class:`numbers.Real` (int, float, Fraction, numpy integers and floats), a numpy 0-d array of
    reals and :class:`decimal.Decimal`; not bool, str or complex. A value beyond the float range
    raises InputError (named by ``where``); NaN and ±inf come back as they are; so does a masked value
    (``numpy.ma.masked``): it has no number (numpy would read it as 0).
    """
    if type(value) is float:  # the common case first
        return value
    prefix = f"{where}: " if where else ""
    if _is_masked(value):
        raise InputError(f"{prefix}the value is masked (numpy.ma.masked): a masked entry has no number; give "
                         "the value itself, or leave the option out.")
    import numbers
    from decimal import Decimal

    if isinstance(value, bool) or type(value).__name__ == "bool_":
        return None
    if getattr(value, "shape", None) == () and getattr(getattr(value, "dtype", None), "kind", "") in "iuf":
        value = value.item()  # a numpy scalar or 0-d array
    if not isinstance(value, numbers.Real | Decimal) or isinstance(value, bool):
        return None
    try:
        return float(value)
    except OverflowError:  # a huge int or Fraction
        raise InputError(f"{prefix}{show(value)} is beyond the float range (about ±1.8e308).") from None
    except ValueError:  # Decimal('sNaN')
        raise InputError(f"{prefix}{show(value)} is not a finite number.") from None


def _is_masked(value: object) -> bool:
    """True for a numpy masked array or constant with any entry masked (numpy is not imported)."""
    mask = getattr(value, "mask", None)
    if mask is None or not hasattr(value, "filled"):
        return False
    return bool(mask.any()) if hasattr(mask, "any") else bool(mask)


def _is_pint(value: object) -> bool:
    """True for a pint Quantity (of any registry), told by its attributes: pint is not imported."""
    return all(hasattr(value, name) for name in ("magnitude", "units", "to_base_units", "unit_items"))


def _from_pint(value, prefix: str) -> tuple[float, Dimension]:
    """(SI value, dimension) of a scalar pint Quantity; InputError for arrays and odd units."""
    try:
        base = value.to_base_units()
        dimension = _dimension_of(base, f"{value.units:~}")
    except _Refused as exc:
        raise InputError(f"{prefix}{show(value)}: {exc}") from None
    except Exception as exc:  # pint's own errors
        raise InputError(f"{prefix}{show(value)}: pint cannot convert it ({exc}).") from None
    number = real_number(base.magnitude, where=prefix.rstrip(": ") or None)
    if number is None:
        raise InputError(f"{prefix}{show(value)}: the magnitude must be one real number.")
    return number, dimension


def column_factor(unit_text: str, dimension: str, *, where: str) -> float:
    """Factor that converts numbers in ``unit_text`` to SI ``dimension`` (for CSV headers)."""
    text = unit_text.strip()
    if not text:
        raise InputError(f"{where}: the unit [] is empty; write e.g. [{example(dimension).split()[-1]}].")
    try:
        factor, found = _parse_unit(text)
    except _Refused as exc:
        raise InputError(f"{where}: [{_clip(unit_text)}]: {exc}") from None
    if found != DIMENSIONS[dimension]:
        raise InputError(f"{where}: the unit [{_clip(unit_text)}] is not {_a(dimension)} (it is "
                         f"{_a(describe(found))}); use e.g. [{example(dimension).split(' ', 1)[-1]}].")
    return factor


def _check_dimension(text: str, found: Dimension, dimension: str, prefix: str) -> None:
    if found == DIMENSIONS[dimension]:
        return
    if found == DIMENSIONS["dimensionless"] and dimension == "temperature" and _BARE.fullmatch(text):
        raise InputError(f"{prefix}{show(text)} has no unit; a temperature must carry one, because a bare "
                         f"number (even 0) means different temperatures in K and degC: write e.g. '293 K' "
                         f"or '20 degC'.")
    if found == DIMENSIONS["dimensionless"]:
        what = "is a percentage" if "%" in text or "percent" in text else "has no unit"
        raise InputError(f"{prefix}{show(text)} {what}; write {_a(dimension)} with its unit, like "
                         f"'{example(dimension)}'.")
    raise InputError(f"{prefix}{show(text)} is not {_a(dimension)} (it is {_a(describe(found))}); "
                     f"use {_a(dimension)} unit, like '{example(dimension)}'.")


def _a(word: str) -> str:
    """'a pressure', 'an angle', 'a plain number' (for dimensionless)."""
    word = "plain number" if word == "dimensionless" else word
    return f"{'an' if word[:1] in 'aeiou' else 'a'} {word}"


def _angle_hint(text: str, number: float) -> str:
    if "%" in text or "percent" in text:  # number is the fraction: 1 % → 0.01, atan(0.01) = 0.573 deg
        return (f"a percent grade is not an angle; write the angle in degrees (a 1 % grade is 0.573 deg; "
                f"this one is {math.degrees(math.atan(number)):.4g} deg).")
    return f"an angle must carry a unit, e.g. '{text.strip()} deg' or '{text.strip()} rad'."


@lru_cache(maxsize=4096)
def _parse(text: str) -> tuple[float, Dimension]:
    """(SI value, dimension) of a quantity string; raises _Refused. Cached per distinct string."""
    if len(text) > MAX_LENGTH:
        raise _Refused(f"more than {MAX_LENGTH} characters; a quantity is one number and a unit.")
    if any(q in text for q in _QUOTES):
        raise _Refused("inch (\") and foot (') marks are not read, because YAML uses them as quotes; "
                       "write the unit as a word, e.g. '10 in' or '2 ft'.")
    match = _NUMBER.match(text)
    if match is None and re.match(r"\s*[+-]?(nan|inf)", text, re.IGNORECASE):
        raise _Refused("not a finite number (NaN and infinity are not allowed).")
    if match is None:
        raise _Refused(f"no number at the start; write a number and a unit, like '{example('length')}'.")
    rest = text[match.end():]
    if re.match(r",\d", rest):
        raise _Refused("decimal commas are not read; write the number with a decimal point (0.4, not 0,4) "
                       "and without thousands separators.")
    if re.match(r"\s*(\*\*|\^|[*/+\-(\d])", rest) and not re.match(r"\s*1\s*/", rest):
        raise _Refused("arithmetic on numbers is not read; write the value as one number and a unit, "
                       "like '1e5 Pa'.")
    number = float(match.group(1))
    if math.isinf(number):
        raise _Refused("the number is beyond the float range (about ±1.8e308).")
    if number == 0 and re.search(r"[1-9]", match.group(1).split("e")[0].split("E")[0]):
        raise _Refused("the number is too small for a float (below about 1e-308); write 0 if you mean zero.")
    if not rest.strip():
        return number, DIMENSIONS["dimensionless"]
    if _offset_unit(rest.strip()):
        return _pint_offset(number, rest.strip())
    factor, dimension = _parse_unit(rest)
    value = number * factor
    if math.isinf(value):
        raise _Refused("the value is beyond the float range (about ±1.8e308) in SI units.")
    return value, dimension


@lru_cache(maxsize=1024)
def _parse_unit(text: str) -> tuple[float, Dimension]:
    """(SI factor, dimension) of a unit expression such as 'kPa', 'dm^3/(s*bar)'; raises _Refused."""
    if len(text) > MAX_LENGTH:
        raise _Refused(f"a unit of more than {MAX_LENGTH} characters is not read.")
    tokens = _tokens(text)
    if len(tokens) > 1 and any(t in (("name", "%"), ("name", "percent")) for t in tokens):
        raise _Refused("a percent sign stands alone after the number, as in '5 %'.")
    parser = _UnitParser(tokens)
    factor, dimension = parser.expression()
    if parser.position != len(tokens):
        raise _Refused(f"unexpected {tokens[parser.position][1]!r} in the unit.")
    if parser.unknown:
        return _pint_unit(text, parser.unknown)
    return factor, dimension


def _tokens(text: str) -> list[tuple[str, str]]:
    tokens, position = [], 0
    while position < len(text):
        if not text[position:].strip():
            break
        match = _TOKEN.match(text, position)
        if match is None:
            bad = text[position:].strip()[0]
            if bad == ",":
                raise _Refused("commas are not read in quantities; write one number with a decimal point.")
            raise _Refused(f"unexpected {bad!r}; a quantity is one number followed by one unit "
                           "(no trailing text).")
        power, operator, superscript, one, name = match.groups()[1:]
        if match.group(1):
            tokens.append(("power", power))
        elif operator:
            tokens.append(("op", operator))
        elif superscript:
            tokens.append(("power", {"²": "2", "³": "3"}[superscript]))
        elif one:
            tokens.append(("one", one))
        else:
            tokens.append(("name", name))
        position = match.end()
    return tokens


class _UnitParser:
    """Recursive descent over unit tokens, multiplying SI factors and adding dimension exponents."""

    MAX_DEPTH = 4  # parentheses

    def __init__(self, tokens: list[tuple[str, str]]):
        self.tokens, self.position, self.depth = tokens, 0, 0
        self.unknown: list[str] = []

    def peek(self) -> tuple[str, str] | None:
        return self.tokens[self.position] if self.position < len(self.tokens) else None

    def expression(self) -> tuple[float, Dimension]:
        factor, dims = self.term()
        while (token := self.peek()) is not None and token != ("op", ")"):
            divide = token == ("op", "/")
            if token in (("op", "*"), ("op", "·"), ("op", "/")):
                self.position += 1
            f, d = self.term()
            factor = factor / f if divide else factor * f
            dims = tuple(a - b if divide else a + b for a, b in zip(dims, d, strict=True))
        return factor, dims

    def term(self) -> tuple[float, Dimension]:
        token = self.peek()
        if token is None:
            raise _Refused("the unit ends where a unit name was expected.")
        self.position += 1
        kind, text = token
        if token == ("op", "("):
            self.depth += 1
            if self.depth > self.MAX_DEPTH:
                raise _Refused("too many parentheses in the unit.")
            factor, dims = self.expression()
            if self.peek() != ("op", ")"):
                raise _Refused("a '(' in the unit is not closed.")
            self.position += 1
            self.depth -= 1
        elif kind == "one" and self.position == 1:
            factor, dims = 1.0, DIMENSIONS["dimensionless"]
        elif kind == "name":
            factor, dims = self.name(text)
        else:
            raise _Refused(f"unexpected {text!r} in the unit.")
        if (power := self.peek()) is not None and power[0] == "power":
            self.position += 1
            exponent = int(power[1])
            factor, dims = factor**exponent, tuple(e * exponent for e in dims)
        return factor, dims

    def name(self, text: str) -> tuple[float, Dimension]:
        if text in REFUSED:
            raise _Refused(f"'{text}' {REFUSED[text]}.")
        if text in UNITS:
            return UNITS[text]
        self.unknown.append(text)
        return 1.0, DIMENSIONS["dimensionless"]


# ----------------------------------------------------------------------------- pint, for the rest
_BASE = {"meter": 0, "kilogram": 1, "second": 2, "kelvin": 3, "radian": 4}


@lru_cache(maxsize=1)
def registry():
    """The pint unit registry, built on first use (importing pint costs about 0.4 s)."""
    import pint

    return pint.UnitRegistry(autoconvert_offset_to_baseunit=True)


def _pint_quantity(number: float, text: str, unknown: list[str] | None = None):
    expression = text.replace("^", "**").replace("·", "*").replace("²", "**2").replace("³", "**3")
    try:
        return registry().Quantity(number, expression).to_base_units()
    except Exception:  # pint raises many types for undefined or malformed units
        import difflib

        names = unknown or [text]
        close = difflib.get_close_matches(names[0], list(UNITS), n=1)
        hint = f"; did you mean '{close[0]}'?" if close else f"; known units include {', '.join(_COMMON)}."
        raise _Refused(f"unknown unit '{names[0]}'{hint}") from None


def _dimension_of(quantity, text: str) -> Dimension:
    """The dimension of a pint quantity in base units; ``text``, the unit as the user wrote it, names a
    unit of another kind (pint's own base units, 'ampere * meter * second' for 'D', are not shown)."""
    dims = [0] * 5
    for unit, exponent in quantity.unit_items():
        if unit not in _BASE or exponent != int(exponent):
            raise _Refused(f"the unit '{text.strip()}' is not a mechanical unit pampipe reads (a length, "
                           "pressure, force, mass, angle, time or a combination); known units include "
                           f"{', '.join(_COMMON)}.")
        dims[_BASE[unit]] = int(exponent)
    return tuple(dims)


def _pint_unit(text: str, unknown: list[str]) -> tuple[float, Dimension]:
    quantity = _pint_quantity(1.0, text, unknown)
    return float(quantity.magnitude), _dimension_of(quantity, text)


def _offset_unit(text: str) -> bool:
    """True for a temperature with an offset (degC, degF): read by pint on the absolute scale."""
    return text in ("degC", "°C", "degF", "°F", "celsius", "fahrenheit")


def _pint_offset(number: float, text: str) -> tuple[float, Dimension]:
    quantity = _pint_quantity(number, text.replace("°C", "degC").replace("°F", "degF"))
    return float(quantity.magnitude), _dimension_of(quantity, text)


_COMMON = ("mm", "in", "ft", "kPa", "MPa", "bar", "psi", "N", "lbf", "kg", "lb", "deg", "rad", "s", "%")


# ------------------------------------------------------------------------------------- messages
def _clip(text: str, size: int = 40) -> str:
    return text if len(text) <= size else text[:size] + "…"


def show(value: object) -> str:
    """repr of a value, clipped: a message never repeats a whole huge input."""
    if isinstance(value, int) and not isinstance(value, bool) and abs(value) > 10**30:
        return f"an integer of about {int(value.bit_length() * math.log10(2)) + 1} digits"
    return _clip(repr(value), 60)


def _kind(value: object) -> str:
    if isinstance(value, dict):
        return "a mapping"
    if isinstance(value, list):
        return "a list"
    return f"{type(value).__name__} {show(value)}"
