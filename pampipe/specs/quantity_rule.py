"""A quantity field's reading and range check, without the schema library (docs/formats.md §1-§4).

A :class:`QuantityRule` turns what a file holds (``"3 in"``, a bare number) into an SI float with
:func:`pampipe.units.quantities.to_si` and checks it against its bounds, answering in the unit it was given.
The pydantic schemas wrap it as a field (:func:`pampipe.specs.schema.quantity`); the quick check of a
well-formed file (:mod:`pampipe.io.quick_check`) calls it directly, so both read a value the same way.
"""

from __future__ import annotations

import math
import operator
import re
from typing import Any

from pampipe.units.quantities import to_si

#: Distinct quantity strings remembered per rule (a route of 10⁶ distinct lengths is not kept).
MAX_CONVERTED = 10_000

#: Each kind of bound: (the test a value passes, its words in a message).
_BOUNDS = {"gt": (operator.gt, "greater than"), "ge": (operator.ge, "at least"),
           "lt": (operator.lt, "less than"), "le": (operator.le, "at most")}


class QuantityRule:
    """Read a ``dimension`` quantity to SI and check ``gt``/``ge``/``lt``/``le`` (SI bounds).

    A value out of range is answered in the unit it was given ("720 deg must be at most 360 deg", not
    "12.5664 rad must be at most 6.28319 rad"; :func:`given_unit`), a number without one in ``unit``, the
    SI unit; ``hint`` follows the message (what the value means). Calling the rule raises ValueError (a
    range) or :class:`~pampipe.errors.InputError` (not a quantity of the dimension)."""

    def __init__(self, dimension: str, *, gt: float | None = None, ge: float | None = None,
                 lt: float | None = None, le: float | None = None, unit: str = "", hint: str = ""):
        self.dimension, self.unit, self.hint = dimension, unit, hint
        self.bounds = [(kind, bound) for kind, bound in (("gt", gt), ("ge", ge), ("lt", lt), ("le", le))
                       if bound is not None]
        self.converted: dict[str, float] = {}  # quantity string -> SI value: a route repeats its "3 in"

    def convert(self, value: Any) -> float:
        """``value`` in SI (a quantity string converted once per rule)."""
        if type(value) is not str:
            return to_si(value, self.dimension)
        number = self.converted.get(value)
        if number is None:
            number = to_si(value, self.dimension)
            if len(self.converted) < MAX_CONVERTED:
                self.converted[value] = number
        return number

    def __call__(self, given: Any) -> float:
        value = self.convert(given)
        for kind, bound in self.bounds:
            if _BOUNDS[kind][0](value, bound):
                continue
            if kind in ("ge", "le") and self._within_rounding(value, bound):
                value = bound
                continue
            shown, scale, text = given_unit(given, value, self.unit)
            raise ValueError(f"{shown} must be {_BOUNDS[kind][1]} {bound / scale:.6g}{text}"
                             + (f": {self.hint}" if self.hint else ""))
        return value

    def _within_rounding(self, value: float, bound: float) -> bool:
        """An angle one ulp beyond a closed bound is the bound: '100 grad' and '5400 arcmin' are π/2
        rounded up by the conversion (100·π/200 = 1.5707963267948968 > π/2)."""
        return self.dimension == "angle" and abs(value - bound) <= math.ulp(bound)


def given_unit(given: Any, value: float, unit: str) -> tuple[str, float, str]:
    """(the value as given, SI per given unit, " unit") for a message: a quantity string in its own unit
    ("180.0001 deg", π/180, " deg"), anything else as ``value`` in the SI ``unit`` (scale 1)."""
    suffix = f" {unit}" if unit else ""
    if isinstance(given, str):
        found = re.match(r"\s*([+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?)\s*(.*?)\s*$", given)
        number = float(found.group(1)) if found else 0.0
        if found and found.group(2) and number != 0 and math.isfinite(value) and value != 0:
            return f"{found.group(1)} {found.group(2)}", value / number, f" {found.group(2)}"
    return f"{value:.6g}{suffix}", 1.0, suffix
