"""The quick check of a well-formed file (pampipe.io.quick_schemas) gives what the pydantic schema gives, and
hands everything else to the schema (issue 39: a new mission without pydantic's cost, every message as
before).

The answers are the schema's: each bundled mission and PAM file, and thousands of broken variants of them
(each value replaced by values of other types and out of range, each key dropped, an unknown key added),
are read by both. Wherever the quick check accepts, the schema must accept and give the same fields, types
and floats (bit for bit); on every broken variant the quick check must fall back.
"""

from __future__ import annotations

import copy
import math

import pydantic
import pytest

from pampipe.io.file_units import read_units
from pampipe.io.mission_model import MissionSchema
from pampipe.io.mission_schema import load_mission
from pampipe.io.pam_model import PamSchema
from pampipe.io.quick_check import Fallback, Record
from pampipe.io.quick_schemas import MISSION, PAM
from pampipe.specs.schema import validate
from tests.support.problems import PROBLEMS

MISSIONS = sorted((PROBLEMS / "missions").glob("*.yaml"))
PAMS = sorted((PROBLEMS / "pams").glob("*.yaml"))
#: What each value of a file is replaced by in turn: other types, out of range, other units, nothing.
REPLACEMENTS = (None, True, 0, -1, 1.5, 1e300, "", "x", "3 in", "-2 m", "90 deg", "700 deg", "5 %",
                "1e9 Pa", [], [1.0], {}, {"value": 0.3}, {"value": 0.3, "sd": 0.1}, "from_pam", 3, 7)


def tree(value):
    """A comparable tree of a validated value: a schema object or a Record as (class name, fields), a float
    as its repr (so -0.0, 1 and 1.0 differ), anything else with its type."""
    if isinstance(value, Record):
        return value.kind, {k: tree(v) for k, v in value.fields().items()}
    if isinstance(value, pydantic.BaseModel):
        return type(value).__name__, {k: tree(getattr(value, k)) for k in type(value).model_fields}
    if isinstance(value, list):
        return [tree(v) for v in value]
    if isinstance(value, dict):
        return {k: tree(v) for k, v in value.items()}
    if isinstance(value, float):
        return "float", repr(value)
    return type(value).__name__, value


def places(node, where=()):
    """Every key path of a YAML tree, leaves and branches."""
    if isinstance(node, dict):
        for key, value in node.items():
            yield (*where, key)
            yield from places(value, (*where, key))
    elif isinstance(node, list):
        for i, value in enumerate(node):
            yield (*where, i)
            yield from places(value, (*where, i))


def variants(content: dict):
    """Copies of ``content`` with one value replaced, one key dropped or one unknown key added."""
    for place in list(places(content)):
        for replacement in REPLACEMENTS:
            changed = copy.deepcopy(content)
            parent = changed
            for part in place[:-1]:
                parent = parent[part]
            parent[place[-1]] = replacement
            yield changed
        if isinstance(place[-1], str):
            dropped = copy.deepcopy(content)
            parent = dropped
            for part in place[:-1]:
                parent = parent[part]
            del parent[place[-1]]
            parent["unknown_key"] = 1
            yield dropped
            del parent["unknown_key"]
            yield dropped


def agree(shape, schema, content) -> str:
    """'quick' when the quick check accepted ``content`` (and the schema gave the same), else 'schema'."""
    try:
        quick = shape(content)
    except Fallback:
        return "schema"
    assert tree(quick) == tree(schema.model_validate(content)), content  # the schema must accept it too
    return "quick"


@pytest.mark.parametrize("path", MISSIONS + PAMS, ids=lambda p: p.name)
def test_a_bundled_file_is_read_quickly_to_what_the_schema_gives(path):
    shape, schema = (MISSION, MissionSchema) if path.parent.name == "missions" else (PAM, PamSchema)
    with read_units(path, None, what="file") as content:
        assert agree(shape, schema, content) == "quick"


@pytest.mark.parametrize("path", MISSIONS + PAMS, ids=lambda p: p.name)
def test_a_broken_variant_is_always_told_by_the_schema(path):
    shape, schema = (MISSION, MissionSchema) if path.parent.name == "missions" else (PAM, PamSchema)
    told = {"quick": 0, "schema": 0}
    with read_units(path, None, what="file") as content:
        for variant in variants(content):
            told[agree(shape, schema, variant)] += 1
    assert told["schema"] > 0 and told["quick"] > 0  # the variants reach both paths


def test_an_inline_pam_and_a_tether_in_a_mission_agree(tmp_path):
    pam = {"name": "inline", "geometry": {"initial_length": "310 mm", "initial_diameter": {"value": "57 mm",
                                                                                          "sd": "0.2 mm"},
                                          "braid_angle_from_axis": "24 deg", "bladder_thickness": "3 mm"},
           "moduli": {"axial": {"a": [1.5, 0], "b": [0, 0]}, "hoop": {"a": [4, -1], "b": [0, 0]}},
           "contact": {"friction": {"value": 0.3, "sd": 0.02}, "tested_pipe_diameters": ["3 in"]}}
    section = {"name": "a", "length": "3 m", "inner_diameter": "3 in", "friction": "from_pam",
               "bend": {"angle": "90 deg"}}
    mission = {"robot": {"segments": [{"name": f"s{i}", "pam": pam, "mass": "0.4 kg"} for i in range(3)]},
               "supply_pressure": "689 kPa", "route": [section],
               "tether": {"weight": "80 g/m", "friction": {"value": 0.35}, "length": "400 m",
                          "hose": {"inner_diameter": "6 mm"}}}
    with read_units(tmp_path / "m.yaml", mission, what="file") as content:
        assert agree(MISSION, MissionSchema, content) == "quick"
    weight = MISSION(mission).tether.weight
    assert math.isclose(weight, 0.080 * 9.80665)  # a mass per length times g


@pytest.mark.parametrize("broken", [
    {"supply_pressure": "689 kg"},  # another dimension
    {"safety_factor": 0.5},  # below its range
    {"route": []},  # no section
    {"robot": {"segments": []}},
    {"load_path": "everywhere"},
    {"route": [{"name": "a", "length": "3 m", "inner_diameter": "3 in", "lenght": "2 m"}]},
])
def test_a_broken_mission_says_what_the_schema_says(tmp_path, broken):
    source = (PROBLEMS / "missions" / "vertical-climb-3in.yaml").read_text()
    path = tmp_path / "vertical-climb-3in.yaml"
    path.write_text(source.replace("../pams/", str(PROBLEMS / "pams") + "/"))
    with read_units(path, None, what="mission file") as content:
        raw = {**content, **broken}
    with pytest.raises(Fallback):
        MISSION(raw)
    with pytest.raises(Exception) as told:
        load_mission(path, raw=raw)
    with pytest.raises(Exception) as schema:
        validate(path, MissionSchema, raw)
    assert str(told.value) == str(schema.value)


def test_a_well_formed_mission_loads_without_pydantic():
    """The point of the quick check: the demo mission and its PAM files load without importing the schema
    library (a fresh interpreter, so nothing imported it before)."""
    import subprocess
    import sys

    demo = PROBLEMS / "missions" / "vertical-climb-3in.yaml"
    code = ("import sys; from pampipe.io.mission_schema import load_mission; "
            f"m = load_mission({str(demo)!r}); print(len(m.route), 'pydantic' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.split() == ["2", "False"]


def _shapes(check, found: dict) -> dict:
    """Every quick-check Shape reachable from ``check`` (its fields' checks, the closures they are made of
    and the module names a plain function reads), by kind."""
    from pampipe.io.quick_check import Shape

    if isinstance(check, Shape):
        if check.kind in found:
            return found
        found[check.kind] = check
        for inner, _ in check.fields.values():
            _shapes(inner, found)
    inners = [cell.cell_contents for cell in getattr(check, "__closure__", None) or ()]
    code = getattr(check, "__code__", None)
    if code is not None:
        inners += [check.__globals__[name] for name in code.co_names if name in check.__globals__]
    for inner in inners:
        for each in inner if isinstance(inner, tuple | list) else (inner,):
            if callable(each) and not isinstance(each, type):
                _shapes(each, found)
    return found


def test_every_quick_shape_mirrors_its_schema_class_field_for_field():
    """A field added to (or a default changed in) a schema class without its mirror fails here, before any
    file exercises it: the same field names, aliases and defaults, class by class."""
    from pydantic_core import PydanticUndefined

    from pampipe.io import mission_model, pam_model, tether_schema
    from pampipe.io.quick_check import REQUIRED

    classes = {name: cls for module in (mission_model, pam_model, tether_schema)
               for name, cls in vars(module).items()
               if isinstance(cls, type) and issubclass(cls, pydantic.BaseModel)}
    shapes = {**_shapes(MISSION, {}), **_shapes(PAM, {})}
    assert {"MissionSchema", "PamSchema", "SectionSchema", "TetherSchema", "HoseSchema"} <= set(shapes)
    for kind, shape in shapes.items():
        fields = classes[kind].model_fields
        assert set(shape.fields) == set(fields), kind
        for name, (_, default) in shape.fields.items():
            want = fields[name].get_default(call_default_factory=True)
            assert (default is REQUIRED) == (want is PydanticUndefined), (kind, name)
            if default is not REQUIRED:
                assert repr(default) == repr(want), (kind, name)
            alias = next(key for key, field in shape.keys.items() if field == name)
            assert alias == (fields[name].alias or name), (kind, name)
