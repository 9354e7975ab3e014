"""Values far outside a plausible range warn with the likely unit slip (issue 42, item 1)."""

from __future__ import annotations

from pampipe.io.mission_schema import load_mission
from pampipe.io.plausible import unit_slips
from tests.support.problems import PROBLEMS


def test_plausible_values_give_no_warning():
    assert unit_slips(689e3, {"m": 0.4}, 2.0) == ()
    assert unit_slips(1e3, {"m": 100.0}, 1000.0) == ()  # the limits themselves are plausible


def test_each_slip_is_named():
    supply, heavy_segment, payload = unit_slips(100.0, {"robot.segments[1].mass": 400.0}, 2000.0)
    assert "supply_pressure is 100 Pa, below 1 kPa: was it meant in kPa or psi (100 kPa, 100 psi)?" in supply
    assert heavy_segment.startswith("robot.segments[1].mass is 400 kg, above 100 kg")
    assert "in g (400 g = 0.4 kg)" in heavy_segment
    assert payload.startswith("robot.payload is 2000 kg")
    assert unit_slips(2e7, {}, 0.0) == (
        "supply_pressure is 20 MPa, above 10 MPa: was it meant in Pa or kPa?",)


def test_a_mission_written_in_the_wrong_units_warns(tmp_path):
    path = tmp_path / "m.yaml"
    text = (PROBLEMS / "missions" / "vertical-climb-3in.yaml").read_text()
    path.write_text(text.replace("../pams/", (PROBLEMS / "pams").as_posix() + "/")
                    .replace("689 kPa", "689 Pa").replace("mass: 0.4 kg", "mass: 400 kg"))
    warnings = load_mission(path).warnings
    assert sum("below 1 kPa" in w for w in warnings) == 1
    assert sum("above 100 kg for one segment" in w for w in warnings) == 3
    assert all(w.startswith(f"{path}: ") for w in warnings)
