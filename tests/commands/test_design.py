"""`pampipe design` end to end (issue 16): the docs/commands.md §8 JSON, -o, plots, exit 3 with the
binding constraint, exit 2 on bad inventories, and every proposed size planned with `pampipe plan` holds as
promised."""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest
import yaml

from pampipe.io.pam_schema import load_pam
from tests.support.problems import PROBLEMS

INVENTORIES = PROBLEMS / "inventories"
RISER = INVENTORIES / "riser.yaml"
PLANT = INVENTORIES / "plant.yaml"
MATERIAL = PROBLEMS / "pams" / "paper-radial-pam.yaml"
#: plan and design call the same closed form (Muscle.least_holding_pressure) on the same numbers; the
#: JSON rounds to 12 digits.
SAME = 1e-10


def _inventory(tmp_path: Path, **changes) -> Path:
    """The riser inventory with top-level keys (or design.* keys) changed, written to tmp_path."""
    doc = yaml.safe_load(RISER.read_text())
    doc["material"] = str(MATERIAL)
    for key, value in changes.items():
        if key.startswith("design_"):
            doc["design"][key.removeprefix("design_")] = value
        else:
            doc[key] = value
    path = tmp_path / "inventory.yaml"
    path.write_text(yaml.safe_dump(doc))
    return path


def test_riser_json_has_the_interface_keys_and_writes_the_pam(cli, tmp_path):
    out = cli("design", RISER, "--json", "-o", tmp_path / "pam.yaml", "--plots", tmp_path / "plots")
    assert out.returncode == 0, out.stderr
    doc = json.loads(out.stdout)
    assert set(doc["design"]) >= {"initial_length_m", "initial_diameter_m", "braid_angle_from_axis_deg"}
    assert doc["feasible"] is True and doc["binding_constraint"] is None
    (pipe,) = doc["pipes"]
    assert pipe["name"] == "riser" and [s["name"] for s in pipe["segments"]] == ["PAM1", "PAM2", "PAM3"]
    assert pipe["pressure_Pa"] == max(s["pressure_Pa"] for s in pipe["segments"])
    assert doc["objective"] == pytest.approx(pipe["pressure_Pa"], rel=SAME)  # max_pressure: the largest
    assert pipe["pressure_Pa"] < pipe["material_pressure_Pa"]  # better than the material's own muscle here
    d = doc["design"]
    assert 0.2 <= d["initial_length_m"] <= 0.4 and 0.03 <= d["initial_diameter_m"] <= 0.0762 - 0.002
    assert 15 <= d["braid_angle_from_axis_deg"] <= 35
    assert pipe["stride_m"] >= 0.02 * (1 - 1e-9)
    assert doc["starts"]["total"] == 16 and 1 <= doc["starts"]["reached_best"] <= 16
    pam = load_pam(tmp_path / "pam.yaml")
    assert pam.geometry.initial_diameter == pytest.approx(d["initial_diameter_m"], rel=1e-12)
    assert math.degrees(pam.geometry.braid_angle) == pytest.approx(d["braid_angle_from_axis_deg"], rel=1e-12)
    assert pam.moduli == load_pam(MATERIAL).moduli
    assert (tmp_path / "plots" / "design_pressure_vs_bore.png").stat().st_size > 1000
    assert (tmp_path / "plots" / "design_starts.png").stat().st_size > 1000
    assert "riser" in out.stderr and "starts at best" in out.stderr  # the table goes to stderr under --json


def _mission_for(tmp_path: Path, design: dict, size: int, pam_file: str) -> Path:
    """A mission through the pipes ``size`` serves, every segment with the designed PAM."""
    inventory = yaml.safe_load(PLANT.read_text())
    route = [{"name": p["name"], "length": f"{p['length_m']!r} m",
              "inner_diameter": f"{p['inner_diameter_m'] * 1e3!r} mm",
              "incline": f"{p['incline_deg']!r} deg", "friction": p["friction"]}
             for p in design["pipes"] if p["size"] == size]
    mission = {"robot": {"segments": [{"name": f"PAM{i + 1}", "pam": pam_file, "mass": m}
                                      for i, m in enumerate(inventory["robot"]["segments"])],
                         "payload": inventory["robot"]["payload"]},
               "supply_pressure": inventory["supply_pressure"], "safety_factor": inventory["safety_factor"],
               "load_path": inventory["load_path"], "route": route}
    path = tmp_path / f"mission-size{size}.yaml"
    path.write_text(yaml.safe_dump(mission))
    return path


def test_every_proposed_size_holds_as_promised_when_planned(cli, tmp_path):
    """Two sizes for the plant inventory; `pampipe plan` on each size's pipes gives the pressures design
    promised, every one feasible within the supply."""
    out = cli("design", PLANT, "--json", "-o", tmp_path / "plant.yaml")
    assert out.returncode == 0, out.stderr
    doc = json.loads(out.stdout)
    assert doc["coverage"]["length_served_m"] == doc["coverage"]["length_total_m"]
    assert [s["pam_file"] for s in doc["sizes"]] == [str(tmp_path / "plant.yaml"),
                                                     str(tmp_path / "plant-size2.yaml")]
    promised = {p["name"]: p for p in doc["pipes"]}
    for size in doc["sizes"]:
        mission = _mission_for(tmp_path, doc, size["size"], size["pam_file"])
        plan = cli("plan", mission, "--json")
        assert plan.returncode == 0, plan.stderr
        planned = json.loads(plan.stdout)
        assert planned["feasible"] is True
        for section in planned["sections"]:
            want = promised[section["name"]]
            for seg, promise in zip(section["segments"], want["segments"], strict=True):
                assert seg["pressure_Pa"] == pytest.approx(promise["pressure_Pa"], rel=SAME)
                assert seg["pressure_Pa"] <= doc["supply_pressure_Pa"]


@pytest.mark.parametrize(("changes", "binding"), [
    ({"robot": {"segments": ["0.4 kg"] * 3, "payload": "1500 kg"}}, "supply_pressure"),
    ({"design_initial_diameter": ["75 mm", "90 mm"]}, "clearance"),
    ({"design_braid_angle_from_axis": ["34 deg", "35 deg"], "design_initial_diameter": ["30 mm", "40 mm"]},
     "contact_margin"),
])
def test_an_inventory_no_muscle_serves_exits_3_naming_the_binding_constraint(cli, tmp_path, changes, binding):
    out = cli("design", _inventory(tmp_path, **changes), "--json", "--starts", "4")
    assert out.returncode == 3, out.stderr
    doc = json.loads(out.stdout)
    assert doc["feasible"] is False and doc["binding_constraint"] == binding
    assert f"binding constraint: {binding}" in out.stderr and "Traceback" not in out.stderr


def test_the_deletion_filter_names_a_pair(cli, tmp_path):
    """3 in and 8 in together: no muscle strides 20 mm in the narrow pipe and stays stable in the wide one."""
    pipes = [{"name": "narrow", "inner_diameter": "3 in", "incline": "90 deg", "friction": 0.3,
              "length": "10 m"},
             {"name": "wide", "inner_diameter": "8 in", "incline": "0 deg", "friction": 0.3,
              "length": "10 m"}]
    out = cli("design", _inventory(tmp_path, pipes=pipes), "--json", "--starts", "4")
    assert out.returncode == 3, out.stderr
    assert json.loads(out.stdout)["binding_constraint"] == "min_stride + material_stability"


@pytest.mark.parametrize(("changes", "words"), [
    ({"design_braid_angle_from_axis": ["35 deg", "15 deg"]}, "lower bound"),
    ({"design_braid_angle_from_axis": ["15 deg", "60 deg"]}, "would not contract"),
    ({"design_objective": "fastest"}, "design.objective"),
    ({"design_initial_diameter": ["5 mm", "70 mm"]}, "bladder thickness"),
    ({"pipes": [{"name": "a", "inner_diameter": {"nps": 3, "schedule": 41}, "length": "1 m",
                 "friction": 0.3}]}, "schedule"),
    ({"pipes": {"network": "no-such-net", "friction": 0.3}}, "no-such-net"),
    ({"colour": "red"}, "colour"),
])
def test_bad_inventories_exit_2_naming_the_key(cli, tmp_path, changes, words):
    out = cli("design", _inventory(tmp_path, **changes))
    assert out.returncode == 2, out.stderr
    assert words in out.stderr and "Traceback" not in out.stderr


def test_a_material_with_effects_is_refused(cli, tmp_path):
    pam = yaml.safe_load(MATERIAL.read_text())
    pam["effects"] = {"braid_friction": {"f0": "10 N"}}
    (tmp_path / "pam.yaml").write_text(yaml.safe_dump(pam))
    path = _inventory(tmp_path)
    doc = yaml.safe_load(path.read_text())
    doc["material"] = "pam.yaml"
    path.write_text(yaml.safe_dump(doc))
    out = cli("design", path)
    assert out.returncode == 2 and "effects" in out.stderr


def test_output_never_overwrites_an_input(cli, tmp_path):
    path = _inventory(tmp_path)
    out = cli("design", path, "-o", path)
    assert out.returncode == 2 and "refusing" in out.stderr


def test_workers_and_scheduler_together_are_refused(cli):
    out = cli("design", RISER, "--workers", "2", "--scheduler", "tcp://127.0.0.1:1")
    assert out.returncode == 2 and "not both" in out.stderr


def test_the_api_returns_the_cli_document(cli):
    """`pampipe.design` on a dict with unit-free options gives the `design --json` document."""
    import pampipe
    from pampipe import api
    from pampipe.io.files import to_json

    out = cli("design", RISER, "--json", "--reproducible", "--starts", "3")
    raw = yaml.safe_load(RISER.read_text())
    result = pampipe.design_inventory(raw, base=RISER.parent, starts=3)
    assert pampipe.design_inventory is api.design_inventory
    assert to_json(result.to_dict(), timings=False).replace("<inventory dict>", "riser.yaml") \
        == out.stdout.replace(str(RISER), str(RISER.parent / "riser.yaml"))
