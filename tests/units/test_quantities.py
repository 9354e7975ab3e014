"""The strict quantity parser (issue 14, item 1; docs/formats.md §1).

The built-in table is checked against pint; the grammar against hand-picked strings and against an
oracle on random strings: a string built from a plain number and a known unit must read as
number × factor, and any string with an operator on the number, a comma, a quote mark or trailing
text must be refused, never read.
"""

from __future__ import annotations

import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from pampipe.errors import InputError
from pampipe.units.quantities import column_factor, to_si
from pampipe.units.table import DIMENSIONS, UNITS

PINT_NAMES = {"psig": "psi", "barg": "bar", "%": "percent"}  # names pint does not know, read as these


@pytest.fixture(scope="module")
def ureg():
    return pytest.importorskip("pint").UnitRegistry()


@pytest.mark.parametrize("name", sorted(UNITS))
def test_table_agrees_with_pint(name, ureg):
    factor, dimension = UNITS[name]
    quantity = ureg.Quantity(1.0, PINT_NAMES.get(name, name)).to_base_units()
    assert factor == pytest.approx(quantity.magnitude, rel=1e-12)  # both are exact definitions
    exponents = dict(quantity.unit_items())
    expected = tuple(int(exponents.get(unit, 0)) for unit in ("meter", "kilogram", "second", "kelvin",
                                                              "radian"))
    assert dimension == expected


@pytest.mark.parametrize(("text", "dimension", "expected"), [
    ("3 in", "length", 0.0762), ("3in", "length", 0.0762), ("76.2 mm", "length", 0.0762),
    ("105 psi", "pressure", 105 * 6894.757293168361), ("105 psig", "pressure", 105 * 6894.757293168361),
    ("6.89 barg", "pressure", 6.89e5), ("689 kPa", "pressure", 689e3), ("-1.5e-3 MPa", "pressure", -1.5e3),
    ("5 %", "dimensionless", 0.05), ("150 percent", "dimensionless", 1.5), ("0.3", "dimensionless", 0.3),
    ("65.92 deg", "angle", math.radians(65.92)), ("0.5 rad", "angle", 0.5), ("90 °", "angle", math.pi / 2),
    ("2.5 kg", "mass", 2.5), ("5 lb", "mass", 5 * 0.45359237), ("1024.74 N", "force", 1024.74),
    ("1 lbf", "force", 4.4482216152605), ("2 min", "time", 120.0), ("293.15 K", "temperature", 293.15),
    ("20 degC", "temperature", 293.15), ("0.5 dm^3/(s*bar)", "sonic conductance", 5e-9),
    ("0.5 dm**3/(s·bar)", "sonic conductance", 5e-9), ("1e-6 1/N", "compliance", 1e-6),
    ("3 N/MPa", "area", 3e-6), ("2 m²", "area", 2.0), ("1 furlong", "length", 660 * 1200 / 3937),
    ("5 kg m/s^2", "force", 5.0),
])  # 1 furlong: pint's US survey furlong, 660 survey feet of 1200/3937 m
def test_reads(text, dimension, expected):
    assert to_si(text, dimension) == pytest.approx(expected, rel=1e-12)


@pytest.mark.parametrize(("value", "dimension", "fragment"), [
    ("5 %", "angle", "a 1 % grade is 0.573 deg"),
    ("300 %", "pressure", "is a percentage"),
    ("1.5", "angle", "an angle must carry a unit"),
    (1.5, "angle", "has no unit"),
    (90, "angle", "has no unit"),
    ("0,4 kg", "mass", "decimal commas"),
    ("1,000 kg", "mass", "decimal commas"),
    ("10\"", "length", "marks are not read"),
    ("10'", "length", "marks are not read"),
    ("10 ″", "length", "marks are not read"),
    ("1 mm; 76.2", "length", "no trailing text"),
    ("1 mm 76.2", "length", "no trailing text"),
    ("10**400 Pa", "pressure", "arithmetic"),
    ("9**9**9 Pa", "pressure", "arithmetic"),
    ("2*3 Pa", "pressure", "arithmetic"),
    ("1+1 Pa", "pressure", "arithmetic"),
    ("(-1)**0.5 kg", "mass", "no number at the start"),
    ("1e400 Pa", "pressure", "beyond the float range"),
    ("1e308 km", "length", "beyond the float range"),
    ("1e-400 Pa", "pressure", "too small"),
    (10**400, "pressure", "beyond the float range"),
    ("nan kPa", "pressure", "not a finite number"),
    (float("inf"), "pressure", "not a finite number"),
    ("5 kpa", "pressure", "did you mean 'kPa'"),
    ("7 bara", "pressure", "absolute pressure"),
    ("100 psia", "pressure", "absolute pressure"),
    ("5 kPa", "length", "is not a length (it is a pressure)"),
    ("0.3 rad", "dimensionless", "is not a plain number (it is an angle)"),
    ("3 A", "length", "not a mechanical unit"),
    ("m**10", "length", "no number at the start"),
    ("1 m**10", "length", "unexpected"),
    ("x" * 101, "length", "more than 100 characters"),
    (True, "length", "expected a length"),
    ([1, 2], "length", "got a list"),
])
def test_refuses(value, dimension, fragment):
    with pytest.raises(InputError, match=None) as info:
        to_si(value, dimension, where="key")
    assert fragment in str(info.value)
    assert str(info.value).startswith("key: ")


def test_long_integers_are_refused_without_printing_them():
    with pytest.raises(InputError) as info:
        to_si(10**5000, "pressure")
    assert "about 5001 digits" in str(info.value) and len(str(info.value)) < 200


def test_csv_header_units_use_the_same_grammar():
    assert column_factor("kPa", "pressure", where="h") == 1e3
    assert column_factor(" psig ", "pressure", where="h") == pytest.approx(6894.757293168361)
    for bad, fragment in [("%", "is not a pressure"), ("kPa; x", "no trailing text"), ("", "empty"),
                          ("blorp", "unknown unit 'blorp'"), ("psia", "absolute")]:
        with pytest.raises(InputError) as info:
            column_factor(bad, "pressure", where="h")
        assert fragment in str(info.value)


# --------------------------------------------------------------------------------------- oracle
PLAIN = st.one_of(st.integers(-10**6, 10**6).map(str),
                  st.floats(-1e6, 1e6, allow_nan=False).map(lambda x: f"{x:.6g}"),
                  st.floats(1e-3, 1e3).map(lambda x: f"{x:.3e}"))
NAMES = st.sampled_from(["mm", "m", "in", "ft", "kPa", "MPa", "bar", "psi", "psig", "N", "kN", "lbf", "kg",
                         "g", "lb"])
JUNK = st.sampled_from(["**2", "*3", "/0", "+1", "-1", ",5", "'", '"', "″", "; 1", " 76.2", "e", "#1",
                        "(1)", "=1", "^2^2", " % %", "..", " in in"])


@settings(max_examples=300, deadline=None, derandomize=True)
@given(number=PLAIN, name=NAMES, space=st.sampled_from(["", " ", "  "]))
def test_oracle_plain_quantities_read_as_number_times_factor(number, name, space):
    factor, dims = UNITS[name]
    dimension = next(d for d, e in DIMENSIONS.items() if e == dims)
    assert to_si(f"{number}{space}{name}", dimension) == pytest.approx(float(number) * factor, rel=1e-12,
                                                                       abs=1e-300)


@settings(max_examples=300, deadline=None, derandomize=True)
@given(number=PLAIN, name=NAMES, junk=JUNK, where=st.sampled_from(["after number", "after unit"]))
def test_oracle_junk_is_refused_never_read(number, name, junk, where):
    text = f"{number}{junk} {name}" if where == "after number" else f"{number} {name}{junk}"
    dimension = next(d for d, e in DIMENSIONS.items() if e == UNITS[name][1])
    with pytest.raises(InputError):
        to_si(text, dimension)


@settings(max_examples=200, deadline=None, derandomize=True)
@given(st.text(alphabet="0123456789.eE+-*/^()%,'\" kmPaNgbrsi°²", max_size=30))
def test_any_string_is_read_or_refused_cleanly(text):
    """No exception but InputError, whatever the string, and a finite result when read."""
    for dimension in ("length", "pressure", "dimensionless", "angle"):
        try:
            value = to_si(text, dimension)
        except InputError:
            continue
        assert math.isfinite(value)


@pytest.mark.parametrize("dimension", ["length", "pressure", "force", "mass", "time", "angle", "area",
                                       "dimensionless", "sonic conductance", "compliance"])
@pytest.mark.parametrize("zero", ["0", "0.0", "-0", " 0 ", "0e5", 0, 0.0])
def test_bare_zero_is_zero_in_every_unit_without_an_offset(zero, dimension):
    assert to_si(zero, dimension) == 0.0


@pytest.mark.parametrize("value", ["0", "0.0"])
def test_bare_zero_temperature_is_refused_because_k_and_degc_differ(value):
    with pytest.raises(InputError) as info:
        to_si(value, "temperature", where="key")
    assert str(info.value).startswith("key: '0") and "K" in str(info.value) and "degC" in str(info.value)


@pytest.mark.parametrize(("value", "dimension"), [("0.1", "force"), ("1e-9", "length"), ("0 %", "force"),
                                                  ("0.5", "angle")])
def test_a_bare_nonzero_string_still_needs_its_unit(value, dimension):
    with pytest.raises(InputError):
        to_si(value, dimension)
