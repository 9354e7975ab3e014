"""No unit read silently (issue 42, item 1): a bare number in a file needs `units: SI` (docs/formats.md
§1)."""

from __future__ import annotations

import pytest

from pampipe.errors import InputError
from pampipe.io.experiment_schema import load_experiment
from pampipe.io.inventory_file import load_inventory
from pampipe.io.mission_schema import load_mission
from pampipe.io.pam_schema import load_pam
from pampipe.units.quantities import bare_numbers, to_si
from tests.support.problems import PROBLEMS

PAM = (PROBLEMS / "pams" / "paper-radial-pam.yaml").as_posix()
#: The demo mission with every value in units, and the same values written as bare SI numbers.
WITH_UNITS = f"""robot:
  segments:
    - {{name: PAM1, pam: {PAM}, mass: 0.4 kg}}
    - {{name: PAM2, pam: {PAM}, mass: 0.4 kg}}
    - {{name: PAM3, pam: {PAM}, mass: 0.4 kg}}
  payload: 2 kg
supply_pressure: 689 kPa
safety_factor: 1.5
tether_drag: 0
route:
  - {{name: riser, length: 3 m, inner_diameter: 0.0762 m, incline: 90 deg, friction: 0.3}}
"""
BARE = {"0.4 kg": "0.4", "2 kg": "2", "689 kPa": "689000", "3 m": "3", "0.0762 m": "0.0762"}


def _bare(text: str) -> str:
    for unit, number in BARE.items():
        text = text.replace(unit, number)
    return text


def test_bare_numbers_are_refused_naming_key_value_and_candidate_units(tmp_path):
    path = tmp_path / "m.yaml"
    path.write_text(_bare(WITH_UNITS))
    with pytest.raises(InputError) as err:
        load_mission(path)
    message = str(err.value)
    assert message.startswith(f"{path}: ")
    for key, value, candidates in (("robot.segments[0].mass", "0.4", "0.4 kg, 0.4 lb or 0.4 g"),
                                   ("robot.payload", "2", "2 kg, 2 lb or 2 g"),
                                   ("supply_pressure", "689000", "689000 kPa, 689000 psi or 689000 Pa"),
                                   ("route[0].length", "3", "3 mm, 3 in or 3 m")):
        assert f"{key}: {value} has no unit; write {candidates}" in message
    assert "units: SI" in message


def test_units_si_reads_bare_numbers_as_si_exactly_as_written_units(tmp_path):
    with_units, bare = tmp_path / "units.yaml", tmp_path / "bare.yaml"
    with_units.write_text(WITH_UNITS)
    bare.write_text("units: SI\n" + _bare(WITH_UNITS))
    a, b = load_mission(with_units), load_mission(bare)
    assert (b.supply_pressure, b.payload, b.segments[0].mass) == (689e3, 2.0, 0.4)
    assert (a.supply_pressure, a.payload, a.segments[0].mass) == (b.supply_pressure, b.payload,
                                                                  b.segments[0].mass)
    assert a.route.diameter_low.tolist() == b.route.diameter_low.tolist() == [0.0762]
    assert a.route.length.tolist() == b.route.length.tolist() == [3.0]


def test_bare_zero_needs_no_unit_and_dimensionless_values_none(tmp_path):
    path = tmp_path / "m.yaml"
    path.write_text(WITH_UNITS)  # tether_drag: 0, friction: 0.3, safety_factor: 1.5 are bare
    assert load_mission(path).tether_drag == 0.0


@pytest.mark.parametrize("value", ["si", "US", "true", "'SI units'"])
def test_units_takes_si_only(tmp_path, value):
    path = tmp_path / "m.yaml"
    path.write_text(f"units: {value}\n" + WITH_UNITS)
    with pytest.raises(InputError, match="units: must be SI"):
        load_mission(path)


def test_each_file_follows_its_own_units_line(tmp_path):
    """A mission with units: SI does not make the PAM file it names SI; an inline PAM follows the mission."""
    pam = tmp_path / "pam.yaml"
    pam.write_text((PROBLEMS / "pams" / "paper-radial-pam.yaml").read_text()
                   .replace("bladder_thickness: 3.175 mm", "bladder_thickness: 0.003175"))
    mission = tmp_path / "m.yaml"
    mission.write_text("units: SI\n" + _bare(WITH_UNITS).replace(PAM, "pam.yaml"))
    with pytest.raises(InputError, match=r"pam\.yaml: geometry\.bladder_thickness: 0\.003175 has no unit"):
        load_mission(mission)
    pam.write_text("units: SI\n" + pam.read_text())
    assert load_mission(mission).segments[0].pam.geometry.bladder_thickness == 0.003175


def test_a_dict_from_the_api_reads_bare_numbers_as_si(tmp_path):
    raw = {"name": "p", "geometry": {"initial_length": 0.31, "initial_diameter": 0.05715,
                                     "braid_angle_from_transverse": "66 deg", "bladder_thickness": 0.003}}
    assert load_pam(tmp_path / "p.yaml", raw=raw).geometry.initial_length == 0.31


def test_every_bundled_file_states_its_units():
    """The bundled problems load without units: SI (their values carry units)."""
    loaders = {"pams": load_pam, "missions": load_mission, "experiments": load_experiment,
               "inventories": load_inventory}
    for folder, load in loaders.items():
        for path in sorted((PROBLEMS / folder).glob("*.yaml")):
            assert "units: SI" not in path.read_text()
            load(path)


def test_to_si_refuses_bare_numbers_only_inside_a_file():
    assert to_si(100, "pressure") == 100.0  # the API's arguments: SI
    with bare_numbers(False):
        with pytest.raises(InputError, match="100 has no unit; write 100 kPa, 100 psi or 100 Pa"):
            to_si(100, "pressure", where="p")
        assert to_si(0, "pressure") == 0.0
        assert to_si(0.3, "dimensionless") == 0.3
        assert to_si("100 kPa", "pressure") == 1e5
        with pytest.raises(InputError, match="0 has no unit; write 0 K or 0 degC"):
            to_si(0, "temperature")  # 0 K and 0 degC differ
        with bare_numbers(True):
            assert to_si(100, "pressure") == 100.0
    assert to_si(100, "pressure") == 100.0
