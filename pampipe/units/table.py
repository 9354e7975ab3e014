"""The unit names pampipe reads without pint: SI factor and dimension of each (docs/formats.md §1).

A dimension is a tuple of exponents of (length, mass, time, temperature, angle). Unlike pint, the
angle is a dimension of its own, so that an angle can never be read as a plain number or a percent.
Every factor here is checked against pint in ``tests/units/test_quantities.py``; names not listed are
looked up in pint (imported only then, it costs 0.4 s).
"""

from __future__ import annotations

import math

Dimension = tuple[int, int, int, int, int]

#: Dimension names used in schemas → exponents of (m, kg, s, K, rad).
DIMENSIONS: dict[str, Dimension] = {
    "dimensionless": (0, 0, 0, 0, 0),
    "length": (1, 0, 0, 0, 0),
    "area": (2, 0, 0, 0, 0),
    "volume": (3, 0, 0, 0, 0),
    "mass": (0, 1, 0, 0, 0),
    "time": (0, 0, 1, 0, 0),
    "temperature": (0, 0, 0, 1, 0),
    "angle": (0, 0, 0, 0, 1),
    "velocity": (1, 0, -1, 0, 0),
    "force": (1, 1, -2, 0, 0),
    "pressure": (-1, 1, -2, 0, 0),
    "sonic conductance": (4, -1, 1, 0, 0),  # ISO 6358 C: m³/(s·Pa), volume flow per upstream pressure
    "compliance": (-1, -1, 2, 0, 0),  # 1/N: fibre strain per newton (docs/physics.md §9b)
    "force per length": (0, 1, -2, 0, 0),  # N/m: a tether's weight per metre (docs/physics.md §16)
    "mass per length": (-1, 1, 0, 0, 0),  # kg/m: its mass per metre
    "volume flow": (3, 0, -1, 0, 0),  # m³/s: a compressor's free-air delivery
}

_L, _M, _T, _K, _A = (tuple(int(i == j) for j in range(5)) for i in range(5))
_P = DIMENSIONS["pressure"]
_F = DIMENSIONS["force"]
_V = DIMENSIONS["volume"]
_ONE = DIMENSIONS["dimensionless"]

PSI = 6894.757293168361  # [Pa], lbf/in²
LBF = 4.4482216152605  # [N]

#: name → (SI factor, dimension). Gauge pressure is pampipe's convention, so psig and barg are psi and bar.
UNITS: dict[str, tuple[float, Dimension]] = {
    **{name: (f, _L) for f, names in (
        (1.0, "m meter meters metre metres"), (1e-3, "mm millimeter millimeters millimetre millimetres"),
        (1e-2, "cm centimeter centimeters"), (0.1, "dm"), (1e3, "km"), (1e-6, "um µm μm micrometer"),
        (0.0254, "in inch inches"), (0.3048, "ft foot feet"), (0.9144, "yd yard yards"),
        (1609.344, "mi mile miles"))
       for name in names.split()},
    **{name: (f, _P) for f, names in (
        (1.0, "Pa pascal"), (1e2, "hPa"), (1e3, "kPa"), (1e6, "MPa"), (1e9, "GPa"),
        (1e5, "bar barg"), (1e2, "mbar"), (PSI, "psi psig"), (1e3 * PSI, "ksi"))
       for name in names.split()},
    **{name: (f, _F) for f, names in (
        (1.0, "N newton newtons"), (1e-3, "mN"), (1e3, "kN"), (1e6, "MN"), (LBF, "lbf"),
        (9.80665, "kgf"))
       for name in names.split()},
    **{name: (f, DIMENSIONS["mass"]) for f, names in (
        (1.0, "kg kilogram kilograms"), (1e-3, "g gram grams"), (1e-6, "mg"), (1e3, "t tonne tonnes"),
        (0.45359237, "lb lbs pound pounds"), (0.028349523125, "oz ounce ounces"))
       for name in names.split()},
    **{name: (f, _T) for f, names in (
        (1.0, "s sec second seconds"), (1e-3, "ms"), (60.0, "min minute minutes"),
        (3600.0, "h hr hour hours"))
       for name in names.split()},
    **{name: (f, _A) for f, names in (
        (1.0, "rad radian radians"), (1e-3, "mrad"), (math.pi / 180, "deg degree degrees °"))
       for name in names.split()},
    **{name: (f, _V) for f, names in ((1e-3, "l L liter liters litre litres"), (1e-6, "ml mL"))
       for name in names.split()},
    "K": (1.0, _K), "kelvin": (1.0, _K),
    "%": (0.01, _ONE), "percent": (0.01, _ONE),
}

#: Names refused with a reason (pampipe's pressures are gauge pressures, docs/formats.md §1).
REFUSED = {name: ("is an absolute pressure; pampipe uses gauge pressures (above the atmosphere): "
                  f"subtract the atmosphere and write {gauge}")
           for name, gauge in (("psia", "psi (or psig)"), ("bara", "bar (or barg)"))}
#: Names pint reads as something else than they look: 'pct' is pico-carat (a mass), not percent.
REFUSED.update({name: "is not read (pint takes it for pico-carat, a mass); did you mean '%'? e.g. '5 %'"
                for name in ("pct", "pcts")})


def dimension_name(dimension: Dimension) -> str | None:
    """The schema name of a dimension ('pressure', ...), or None if it has none."""
    return next((name for name, dims in DIMENSIONS.items() if dims == dimension), None)


def describe(dimension: Dimension) -> str:
    """A dimension in words: its schema name, or its SI unit (e.g. 'm²/s')."""
    name = dimension_name(dimension)
    if name is not None:
        return name
    parts = [f"{unit}{'' if e == 1 else f'^{e}'}" for unit, e in zip(("m", "kg", "s", "K", "rad"), dimension,
                                                                     strict=True) if e]
    return "·".join(parts)
