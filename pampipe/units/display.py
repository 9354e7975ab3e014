"""The user's units in text output: ``--units si|metric|us`` or one pressure unit (docs/commands.md, units).

Inside pampipe everything is SI, and the text is written in the metric units (kPa, mm, m, N). The
display context converts it late, at the two places all text passes through:

- :func:`column` (called by :func:`pampipe.views.tables.table`): a column whose header names a unit in
  brackets (``P [kPa]``, ``f_r [N/m]``) is shown in the chosen system, value x (from / to);
- :func:`localize` (called where a command prints its report, warnings and reasons): every number
  followed by a metric unit (``12.5 kPa``, ``48 mm``, ``3.2 m``, ``120 N``) is converted the same way,
  to as many significant digits as it was written with (at least 3).

Presets: ``si`` (Pa, m, N), ``metric`` (kPa, mm and m, N, kg: the default, today's text unchanged) and
``us`` (psi, in, ft and mi, lbf, lb). A single pressure unit (``psi``, ``bar``, ``kPa``, ``MPa``, ``Pa``)
changes pressures only. Per-metre units take the short length (``N/m`` -> ``lbf/in``, ``1/m`` -> ``1/in``).
JSON is never converted. The command line sets the units for its run (:func:`shown_in`); the Python API's
default is :func:`set_units`.
"""

from __future__ import annotations

import re
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass, replace
from numbers import Real

from pampipe.units.table import DIMENSIONS, UNITS


@dataclass(frozen=True)
class Units:
    """Display units: pressure, short length (bores, muscles), length (pipes), far (networks), force."""

    pressure: str = "kPa"
    length: str = "mm"
    distance: str = "m"
    far: str = "km"
    force: str = "N"
    mass: str = "kg"

    def target(self, unit: str) -> str | None:
        """The display unit of metric/SI ``unit`` (None for a unit it does not convert)."""
        if unit == "m":
            return self.distance
        if unit == "km":
            return self.far
        if unit not in UNITS:
            return None
        dimension = UNITS[unit][1]
        if dimension == DIMENSIONS["pressure"]:
            return self.pressure
        if dimension == DIMENSIONS["length"]:
            return self.length
        if dimension == DIMENSIONS["force"]:
            return self.force
        if dimension == DIMENSIONS["mass"]:
            return self.mass
        return None


PRESETS = {
    "si": Units(pressure="Pa", length="m", distance="m", force="N"),
    "metric": Units(),
    "us": Units(pressure="psi", length="in", distance="ft", far="mi", force="lbf", mass="lb"),
}
PRESSURES = ("kPa", "psi", "bar", "MPa", "Pa")
#: Every value of --units.
CHOICES = (*PRESETS, *PRESSURES)
#: Metric units that :func:`localize` converts in free text (after a number; also per a unit: mm/s).
TEXT_UNITS = ("kPa", "MPa", "Pa", "mm", "m", "km", "kN", "N", "kg")

_current = {"units": PRESETS["metric"]}


def units_for(name: str) -> Units:
    """The display units of a --units value: a preset, or a pressure unit with metric lengths and forces."""
    if isinstance(name, str) and name in PRESETS:
        return PRESETS[name]
    if isinstance(name, str) and name in PRESSURES:
        return replace(PRESETS["metric"], pressure=name)
    from pampipe.errors import InputError

    raise InputError(f"units: {name!r} is not one of {', '.join(CHOICES)}.")


def set_units(name: str) -> None:
    """Show results in ``name`` from now on, in this process (the Python API: ``str(result)``,
    ``result.to_text()``, ``result.plot()``): a preset (si, metric, us) or a pressure unit. A command
    line run keeps its own --units (metric by default); JSON, ``to_dict()`` and ``to_frame()`` stay SI."""
    _current["units"] = units_for(name)


def current() -> Units:
    """The display units in force (metric unless a command set others)."""
    return _current["units"]


@contextmanager
def shown_in(name: str) -> Iterator[Units]:
    """Show text in ``name`` within the block; the previous units after it."""
    saved = _current["units"]
    _current["units"] = units_for(name)
    try:
        yield _current["units"]
    finally:
        _current["units"] = saved


def factor(source: str, target: str) -> float:
    """Multiply a value in ``source`` by this to get it in ``target`` (same dimension)."""
    return UNITS[source][0] / UNITS[target][0]


_HEADER = re.compile(r"\[([A-Za-z]+|1)(?:/([A-Za-z]+))?\]")  # [kPa], [N/m], [1/m]
_NUMBER = re.compile(r"(?<![\w.])(-?)(\d+(?:\.\d*)?(?:[eE][-+]?\d+)?)")
_VALUE = r"(-?\d+(?:\.\d*)?(?:[eE][-+]?\d+)?)"
#: A number, or a range 'a - b', 'a -> b', 'a to b', 'a of b', then a space and a metric unit (names such
#: as 'radial-3in-0N' are left alone).
_IN_TEXT = re.compile(r"(?<![\w.-])(?:" + _VALUE + r"(\s*(?:->|-|–|to|of)\s*))?" + _VALUE + "( )("
                      + "|".join((*TEXT_UNITS, "1")) + r")(?:/([A-Za-z]+))?(?![\w/²³^])")


def _convert(unit: str, per: str | None, units: Units) -> tuple[str, float] | None:
    """The display unit and factor of ``unit`` (or ``unit/per``), or None when nothing changes (metric
    shows the text as written, MPa included)."""
    if unit == "1" and per is None:
        return None
    to = "1" if unit == "1" else units.target(unit)  # '1/m': a curvature
    if to is None or units == PRESETS["metric"]:
        return None
    scale = 1.0 if unit == "1" else factor(unit, to)
    shown = to
    if per is not None:
        if per not in UNITS:
            return None
        per_to = units.target(per) or per  # a per-second stays one
        if per == "m" and units.distance != "m":
            per_to = units.length  # lbf/in, not lbf/ft
        scale /= factor(per, per_to)
        shown = f"{to}/{per_to}"
    if shown == (unit if per is None else f"{unit}/{per}"):
        return None
    return shown, scale


def scaled(unit: str) -> tuple[str, float]:
    """The display unit of metric ``unit`` (or 'a/b') and the factor to it, for numbers a caller formats
    itself (a table whose unit is in its title, a value with its interval)."""
    top, _, per = unit.partition("/")
    if top not in (*TEXT_UNITS, "1"):
        return unit, 1.0
    return _convert(top, per or None, current()) or (unit, 1.0)


def relabel(label: str) -> tuple[str, float] | None:
    """``label`` with its bracketed metric unit ('P [kPa]') replaced by the display unit, and the factor
    to it; None when the display units leave it as it is."""
    match = _HEADER.search(label)
    if match is None or match.group(1) not in (*TEXT_UNITS, "1"):
        return None
    converted = _convert(match.group(1), match.group(2), current())
    if converted is None:
        return None
    shown, scale = converted
    return label[:match.start()] + f"[{shown}]" + label[match.end():], scale


def column(header: str, values: list[object]) -> tuple[str, list[object]]:
    """A table column (or a row, labelled ``header``) in the display units: the bracketed unit replaced
    and the numbers scaled (floats and ints; numbers inside text cells such as '12.3 (thin)' or
    '10.1-12.5')."""
    relabelled = relabel(header)
    if relabelled is None:
        return header, values
    header, scale = relabelled
    out: list[object] = []
    for v in values:
        if isinstance(v, bool):
            out.append(v)
        elif isinstance(v, Real):
            out.append(_significant(repr(float(v)), scale, digits=4))  # as report.table shows floats
        elif isinstance(v, str):
            out.append(_NUMBER.sub(lambda m: m.group(1) + _significant(m.group(2), scale), v))
        else:
            out.append(v)
    return header, out


def localize(text: str) -> str:
    """``text`` with every number followed by a metric unit shown in the display units."""
    units = current()
    if units == PRESETS["metric"]:
        return text

    def one(m: re.Match) -> str:
        low, between, value, space, unit, per = m.groups()
        converted = _convert(unit, per, units)
        if converted is None:
            return m.group(0)
        shown, scale = converted
        first = "" if low is None else _significant(low, scale) + between
        return f"{first}{_significant(value, scale)}{space}{shown}"

    return _IN_TEXT.sub(one, text)


def _significant(number: str, scale: float, digits: int | None = None) -> str:
    """``number`` x ``scale`` with ``digits`` significant digits, by default as many as ``number`` was
    written with (3 to 8)."""
    if digits is None:
        mantissa = re.split(r"[eE]", number.lstrip("-"))[0]
        digits = max(3, min(len(mantissa.replace(".", "").lstrip("0")), 8))
    value = float(number) * scale
    text = f"{value:.{digits}g}"
    return f"{float(text):.0f}" if "e" in text and 1 <= abs(value) < 1e9 else text  # 12500, not 1.25e+04



def counted(count: int, noun: str) -> str:
    """``count`` and ``noun`` in the number it takes: '1 pipe', '3 pipes', '0 tests' (nouns that add -s)."""
    return f"{count} {noun}" if count == 1 else f"{count} {noun}s"
