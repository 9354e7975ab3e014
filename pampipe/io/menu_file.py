"""The MENU file of `pampipe next-test` (docs/commands.md, next-test): the tests a lab can run, a
:class:`Menu`.

```yaml
tests:
  - {kind: radial, pipe_diameter: 2.5 in, axial_load: 0 N, cost: 1 h}
  - {kind: isometric, length: 250 mm, cost: 0.5 h}
  - {kind: slip, pipe_diameter: 3 in, trials: 3, cost: 2 h}
  - {kind: axial, pressures: [100 kPa, 800 kPa], cost: 1 h}
pressures: 69 kPa .. 689 kPa in 69 kPa steps   # the protocol's levels unless a test says otherwise
```

``pressures`` (top level or per test) is a list of pressures or ``LOW .. HIGH in STEP steps``
(:func:`pampipe.specs.menu.pressure_levels`). Every entry is checked against the muscle it would test: a bore
must lie between the muscle's rest diameter D₀ (narrower: it cannot go in) and its reach D(B/√3) (wider: it
never touches the wall), an isometric length between B/√3 and the rest length.
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import Annotated, Literal

from pydantic import Field

from pampipe.errors import InputError
from pampipe.io.file_units import KEY, read_units
from pampipe.specs.menu import DEFAULT_LEVELS, KINDS, Menu, MenuTest, pressure_levels
from pampipe.specs.schema import Strict, quantity, validate
from pampipe.units.quantities import show, to_si

Pressure = quantity("pressure", ge=0, le=1e8, unit="Pa")
Cost = quantity("time", ge=0, le=1e9, unit="s")
Diameter = quantity("length", gt=0, le=10.0, unit="m")
Load = quantity("force", ge=0, le=1e7, unit="N")
RANGE = re.compile(r"^\s*(.+?)\s*\.\.\s*(.+?)\s+in\s+(.+?)\s+steps?\s*$")
#: ``LOW .. HIGH in STEP steps``, each a pressure with its unit (the schema's pattern; :func:`levels` reads it
#: and names the entry when it does not match).
Levels = Annotated[str, Field(json_schema_extra={"pattern": RANGE.pattern})]


class _Test(Strict):
    cost: Cost
    pressures: list[Pressure] | Levels | None = None


class RadialSchema(_Test):
    kind: Literal["radial"]
    pipe_diameter: Diameter
    axial_load: Load = 0.0


class SlipSchema(_Test):
    kind: Literal["slip"]
    pipe_diameter: Diameter
    axial_load: Load = 0.0
    trials: int = Field(3, ge=1, le=1000)


class IsometricSchema(_Test):
    kind: Literal["isometric"]
    length: quantity("length", gt=0, le=10.0, unit="m")


class AxialSchema(_Test):
    kind: Literal["axial"]


SCHEMAS = {"radial": RadialSchema, "slip": SlipSchema, "isometric": IsometricSchema, "axial": AxialSchema}


class MenuSchema(Strict):
    """The whole MENU file, as its JSON Schema (yaml/menu.schema.json, scripts/write_schemas.py) shows it to
    an editor; :func:`load_menu` checks the same models entry by entry, to name ``tests[i]``."""

    tests: list[Annotated[RadialSchema | SlipSchema | IsometricSchema | AxialSchema,
                          Field(discriminator="kind")]] = Field(min_length=1)
    pressures: list[Pressure] | Levels | None = None


def levels(value, where: str, default: tuple[float, ...]) -> tuple[float, ...]:
    """The pressure levels [Pa] of a ``pressures:`` value: a list, ``LOW .. HIGH in STEP steps`` or None
    (``default``)."""
    if value is None:
        return default
    if isinstance(value, list):
        out = tuple(to_si(v, "pressure", where=where) for v in value)
    else:
        match = RANGE.match(str(value))
        if match is None:
            raise InputError(f"{where}: {show(value)} is not a list of pressures nor 'LOW .. HIGH in STEP "
                             "steps' (e.g. '69 kPa .. 689 kPa in 69 kPa steps').")
        low, high, step = (to_si(part, "pressure", where=where) for part in match.groups())
        if not (0 <= low <= high and step > 0 and (high - low) / step <= 1000):
            raise InputError(f"{where}: {show(value)}: need 0 <= LOW <= HIGH and a STEP > 0 giving at most "
                             "1000 levels.")
        out = pressure_levels(low, high, step)
    if not out or any(p < 0 for p in out):
        raise InputError(f"{where}: {show(value)}: give at least one pressure, each at least 0 Pa.")
    return tuple(sorted(out))


def load_menu(path: str | Path, pam, *, pam_where: str = "PAM file", raw: dict | None = None) -> Menu:
    """Read and validate a MENU file against the ``pam`` (a :class:`~pampipe.model.pam.Pam` with moduli and
    an ``uncertainty:`` block) whose next test it lists; ``raw``: the file's content as a mapping instead (its
    bare numbers SI, as a file that says ``units: SI``)."""
    path = Path(path)
    if getattr(pam, "uncertainty", None) is None:
        raise InputError(f"{pam_where}: the PAM '{pam.name}' has no 'uncertainty:' block: next-test needs "
                         "what its fit leaves uncertain (the joint covariance, model error and undetermined "
                         "directions that `pampipe identify -o` writes). Give the PAM file identify wrote.")
    with read_units(path, raw, what="menu file") as raw:
        unknown = sorted(set(raw) - {"tests", "pressures"})
        if unknown:
            raise InputError(f"{path}: unknown key(s) {', '.join(unknown)}; allowed: tests, pressures, "
                             f"{KEY}.")
        tests = raw.get("tests")
        if not isinstance(tests, list) or not tests:
            raise InputError(f"{path}: tests: give a list of at least one test, e.g. "
                             "'- {kind: radial, pipe_diameter: 3 in, cost: 1 h}'.")
        default = levels(raw.get("pressures"), f"{path}: pressures", pressure_levels(*DEFAULT_LEVELS))
        return Menu(path, tuple(_test(path, i, entry, default, pam) for i, entry in enumerate(tests)))


def _test(path: Path, i: int, entry, default, pam) -> MenuTest:
    where = f"{path}: tests[{i}]"
    kind = entry.get("kind") if isinstance(entry, dict) else None
    if kind not in KINDS:
        raise InputError(f"{where}: kind {show(kind)} is not a test next-test can plan; allowed: "
                         f"{', '.join(KINDS)} (e.g. '{{kind: radial, pipe_diameter: 3 in, cost: 1 h}}').")
    schema = validate(where, SCHEMAS[kind], entry)
    pressures = levels(entry.get("pressures"), f"{where}.pressures", default)
    test = MenuTest(kind, schema.cost, pressures, getattr(schema, "pipe_diameter", None),
                    getattr(schema, "axial_load", None), getattr(schema, "length", None),
                    getattr(schema, "trials", None), i)
    _check_reach(where, test, pam)
    return test


def _check_reach(where: str, test: MenuTest, pam) -> None:
    """A bore within (D₀, D(B/√3)) and an isometric length within [B/√3, L₀] of the ``pam``."""
    g = pam.geometry
    if test.pipe_diameter is not None and not g.initial_diameter < test.pipe_diameter < g.largest_diameter:
        side = "narrower than the muscle at rest" if test.pipe_diameter <= g.initial_diameter \
            else "wider than the muscle can reach"
        raise InputError(
            f"{where}: pipe_diameter {test.pipe_diameter * 1e3:.4g} mm is {side}: the PAM '{pam.name}' "
            f"anchors only in bores between {g.initial_diameter * 1e3:.4g} mm (its rest diameter) and "
            f"{g.largest_diameter * 1e3:.4g} mm (its reach).")
    if test.length is not None and not g.shortest_length <= test.length <= g.initial_length:
        raise InputError(
            f"{where}: length {test.length * 1e3:.4g} mm: the PAM '{pam.name}' can be held only between "
            f"{g.shortest_length * 1e3:.4g} mm (fully contracted) and {g.initial_length * 1e3:.4g} mm "
            "(at rest).")
