"""Quantities in, SI floats out: the only place where units are parsed (pint).

A value may be a number (taken as SI: m, Pa, N, kg, rad, s) or a string ``"<number> <unit>"``.
Pressures are gauge pressures.
"""

from __future__ import annotations

import math
from functools import lru_cache

import pint

from pampipe.errors import InputError

#: Dimension names used in schemas, mapped to the SI unit values are converted to.
SI_UNITS = {
    "length": "m",
    "pressure": "Pa",
    "force": "N",
    "mass": "kg",
    "angle": "rad",
    "time": "s",
    "dimensionless": "",
    "area": "m**2",
    "volume": "m**3",
    "velocity": "m/s",
    "sonic conductance": "m**3/(s*Pa)",  # ISO 6358 C: volume flow per upstream pressure
    "temperature": "K",
    "compliance": "1/N",  # fibre strain per newton (docs/physics.md §9b braid extensibility)
}


@lru_cache(maxsize=1)
def registry() -> pint.UnitRegistry:
    """The package's single unit registry."""
    return pint.UnitRegistry(autoconvert_offset_to_baseunit=True)


def to_si(value: object, dimension: str, *, where: str | None = None) -> float:
    """Convert ``value`` to a finite SI float of the given ``dimension``.

    Raises :class:`InputError` naming ``where`` for a wrong dimension, an unknown unit,
    a non-numeric value, NaN or infinity.
    """
    unit = SI_UNITS[dimension]
    where = f"{where}: " if where else ""
    if isinstance(value, bool) or value is None:
        raise InputError(f"{where}expected a {dimension}, got {value!r}.")
    if isinstance(value, int | float):
        number = float(value)
    elif isinstance(value, str):
        number = _parse_string(value, dimension, unit, where)
    else:
        raise InputError(
            f"{where}expected a {dimension} as a number or a string like "
            f"'{_example(dimension)}', got {type(value).__name__} {value!r}."
        )
    if not math.isfinite(number):
        raise InputError(f"{where}{value!r} is not a finite number.")
    return number


def _parse_string(text: str, dimension: str, unit: str, where: str) -> float:
    ureg = registry()
    try:
        quantity = ureg.Quantity(text.strip())
    except Exception as exc:  # pint raises many types for unparsable text
        raise InputError(
            f"{where}cannot read {text!r} as a {dimension} ({exc.__class__.__name__}); "
            f"write a number and a unit, like '{_example(dimension)}'."
        ) from None
    if not isinstance(quantity, ureg.Quantity) or quantity.unitless:  # a bare number: SI
        return float(getattr(quantity, "magnitude", quantity))
    if not math.isfinite(float(quantity.magnitude)):
        return float(quantity.magnitude)
    try:
        return float(quantity.to(unit).magnitude) if unit else float(quantity.to("").magnitude)
    except pint.DimensionalityError:
        raise InputError(
            f"{where}{text!r} is not a {dimension} (its unit is '{quantity.units:~}'); "
            f"use a {dimension} unit, like '{_example(dimension)}'."
        ) from None


def _example(dimension: str) -> str:
    return {
        "length": "3 in",
        "pressure": "689 kPa",
        "force": "1024.74 N",
        "mass": "2.5 kg",
        "angle": "65.92 deg",
        "time": "2 s",
        "dimensionless": "0.3",
        "sonic conductance": "0.5 dm**3/(s*bar)",
        "temperature": "293 K",
    }.get(dimension, "1")


def column_factor(unit_text: str, dimension: str, *, where: str) -> float:
    """Factor that converts numbers in ``unit_text`` to SI ``dimension`` (for CSV headers)."""
    ureg = registry()
    try:
        quantity = ureg.Quantity(1.0, unit_text.strip())
        return float(quantity.to(SI_UNITS[dimension]).magnitude)
    except pint.DimensionalityError:
        raise InputError(
            f"{where}: the unit [{unit_text}] is not a {dimension}; use e.g. "
            f"[{_example(dimension).split(' ', 1)[-1]}]."
        ) from None
    except Exception:
        raise InputError(f"{where}: unknown unit [{unit_text}].") from None
