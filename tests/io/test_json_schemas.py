"""The JSON Schemas in yaml/ (issue 42, item 10): current, valid for every bundled problem, strict on keys and
units, as a standard validator (jsonschema) reads them."""

from __future__ import annotations

import json
import os
import subprocess
import sys

import jsonschema
import pytest

from pampipe.errors import InputError
from pampipe.io.mission_schema import load_mission
from pampipe.io.yamlfile import load_mapping, loads
from tests.support.problems import PROBLEMS, ROOT

KINDS = {"missions": "mission", "pams": "pam", "experiments": "experiment", "inventories": "inventory",
         "menus": "menu"}
BUNDLED = sorted((folder, path) for folder in KINDS for path in (PROBLEMS / folder).glob("*.yaml"))


def _validator(kind: str) -> jsonschema.Draft202012Validator:
    schema = json.loads((ROOT / "yaml" / f"{kind}.schema.json").read_text(encoding="utf-8"))
    jsonschema.Draft202012Validator.check_schema(schema)
    return jsonschema.Draft202012Validator(schema)


def _errors(kind: str, document: dict) -> list[str]:
    """Every error, with those inside a union's members (``route``: a list of sections or a network)."""
    out, pending = [], list(_validator(kind).iter_errors(document))
    while pending:
        error = pending.pop()
        out.append(f"{'.'.join(map(str, error.absolute_path))}: {error.message}")
        pending += error.context or []
    return out


def test_the_schemas_are_what_the_models_give():
    done = subprocess.run([sys.executable, "scripts/write_schemas.py", "--check"], cwd=ROOT,
                          capture_output=True, text=True, env={**os.environ, "PYTHONPATH": str(ROOT)},
                          timeout=300)
    assert done.returncode == 0, done.stderr


@pytest.mark.parametrize(("folder", "path"), BUNDLED, ids=[f"{f}/{p.stem}" for f, p in BUNDLED])
def test_every_bundled_problem_names_its_schema_and_validates(folder, path):
    first = path.read_text(encoding="utf-8").splitlines()[0]
    assert first == f"# yaml-language-server: $schema=../../yaml/{KINDS[folder]}.schema.json"
    assert _errors(KINDS[folder], load_mapping(path)) == []


MISSION = (PROBLEMS / "missions" / "vertical-climb-3in.yaml").read_text(encoding="utf-8")


@pytest.mark.parametrize(("change", "found"), [
    (("supply_pressure:", "supply_presure:"), "'supply_presure' was unexpected"),
    (("friction: 0.3}", "frction: 0.3}"), "'frction' was unexpected"),
    (("payload: 2 kg", "payload: 2"), "robot.payload: 2 is not valid"),  # a bare number without units: SI
    (("incline: 90 deg", "incline: 90"), "route.0.incline: 90 is not valid"),
    (("payload: 2 kg", "payload: 2 kgs"), None),  # the unit's name is pampipe's to check, not the schema's
])
def test_the_schema_flags_a_misspelt_key_and_a_missing_unit(change, found):
    document = loads(MISSION.replace(*change))
    errors = _errors("mission", document)
    if found is None:
        assert errors == []
    else:
        assert any(found in e for e in errors), errors


def test_units_si_allows_bare_numbers_but_not_bare_angles():
    document = loads("units: SI\n" + MISSION.replace("payload: 2 kg", "payload: 2")
                     .replace("supply_pressure: 689 kPa", "supply_pressure: 689000"))
    assert _errors("mission", document) == []
    angle = {**document, "route": [{**document["route"][0], "incline": 1.5}]}
    assert any("route.0.incline" in e for e in _errors("mission", angle))
    assert _errors("mission", {**document, "units": "US"}) != []


@pytest.mark.parametrize("value", ["2 kg", "2", "0", "-1 kg", "2 kPa"])
def test_schema_and_pampipe_agree_on_the_unit_of_a_value(tmp_path, value):
    """A payload the schema flags for its unit is refused by pampipe, and the reverse (the range and the
    dimension are pampipe's: '-1 kg' and '2 kPa' pass the schema's pattern and are refused by the command)."""
    text = MISSION.replace("payload: 2 kg", f"payload: {value}").replace("../pams/", f"{PROBLEMS / 'pams'}/")
    path = tmp_path / "m.yaml"
    path.write_text(text)
    schema_ok = _errors("mission", loads(text)) == []
    try:
        load_mission(path)
        pampipe_ok = True
    except InputError:
        pampipe_ok = False
    assert schema_ok == (value in ("2 kg", "0", "-1 kg", "2 kPa"))
    assert pampipe_ok == (value in ("2 kg", "0"))


MENU = (PROBLEMS / "menus" / "radial-menu.yaml").read_text(encoding="utf-8")


@pytest.mark.parametrize(("change", "found"), [
    (("kind: isometric", "kind: twist"), "tests.4"),  # no test of that kind
    (("cost: 0.5 h}", "cost: 0.5}"), "tests.4.cost: 0.5 is not valid"),  # a cost without its unit
    (("trials: 3,", "trails: 3,"), "'trails' was unexpected"),
    (("69 kPa .. 689 kPa in 69 kPa steps", "69 kPa to 689 kPa"), "pressures: '69 kPa to"),
    (("pressures: 69 kPa", "presures: 69 kPa"), "'presures' was unexpected"),
    (("cost: 2 h}", "cost: 2 h, pressures: [100 kPa, 0]}"), None),
])
def test_the_menu_schema_flags_a_wrong_kind_key_or_unit_as_pampipe_does(tmp_path, change, found):
    """What the menu's schema flags, load_menu refuses too (kind, key, unit and the form of the levels)."""
    from pampipe.io.menu_file import load_menu
    from pampipe.io.pam_schema import load_pam

    text = MENU.replace(*change)
    assert text != MENU
    errors = _errors("menu", loads(text))
    path = tmp_path / "menu.yaml"
    path.write_text(text)
    pam = load_pam(PROBLEMS / "pams" / "paper-radial-pam-uncertain.yaml")
    if found is None:
        assert errors == []
        load_menu(path, pam)
    else:
        assert any(found in e for e in errors), errors
        with pytest.raises(InputError):
            load_menu(path, pam)


def test_a_menu_in_si_reads_bare_numbers_as_si(tmp_path):
    from pampipe.io.menu_file import load_menu
    from pampipe.io.pam_schema import load_pam

    text = "units: SI\ntests:\n  - {kind: radial, pipe_diameter: 0.0762, axial_load: 10, cost: 3600}\n"
    assert _errors("menu", loads(text)) == []
    path = tmp_path / "menu.yaml"
    path.write_text(text)
    test, = load_menu(path, load_pam(PROBLEMS / "pams" / "paper-radial-pam-uncertain.yaml")).tests
    assert (test.pipe_diameter, test.axial_load, test.cost) == (0.0762, 10.0, 3600.0)
    assert _errors("menu", loads(text.replace("units: SI\n", ""))) != []
