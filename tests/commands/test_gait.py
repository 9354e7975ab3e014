"""`pampipe gait` as a user runs it: exit codes, messages, JSON and plots."""

from __future__ import annotations

import json

import pytest
import yaml

from tests.support.problems import PROBLEMS
from tests.support.processes import run_cli

DEMO = PROBLEMS / "missions" / "vertical-climb-3in.yaml"
SURVEY = PROBLEMS / "missions" / "infeasible-survey.yaml"


def test_optimal_json_and_plots(tmp_path):
    out = run_cli("gait", DEMO, "--optimal", "--json", "--plots", tmp_path / "plots")
    assert out.returncode == 0, out.stderr
    assert "Traceback" not in out.stderr
    doc = json.loads(out.stdout)  # exactly one JSON document on stdout
    assert doc["schedule"] == "optimal" and doc["section"] == "riser"
    base = doc["sequential"]
    assert base["schedule"] == "sequential"
    for d in (doc, base):
        assert d["speed_m_per_s"] == pytest.approx(d["stride_m"] / d["cycle_time_s"], rel=1e-12)
        assert [s["step"] for s in d["steps"]] == ["I", "II", "III", "IV", "V", "VI", "VII"]
        assert d["steps"][1]["anchored"] == ["PAM1", "PAM2"]
        for s in d["steps"]:
            assert set(s["pressures_Pa"]) == {"PAM1", "PAM2", "PAM3"}
            assert set(s["positions_m"]) == {"rear", "joint_12", "joint_23", "front"}
            assert s["duration_s"] >= 0
    assert doc["speed_gain"] == pytest.approx(doc["speed_m_per_s"] / base["speed_m_per_s"]
                                              * base["stride_m"] / doc["stride_m"] - 1, rel=1e-9)
    assert doc["speed_gain"] > 0
    assert "speed gain of the optimal gait" in out.stderr  # the text report went to stderr
    names = sorted(p.name for p in (tmp_path / "plots").iterdir())
    assert names == ["gait_pressures_optimal.png", "gait_pressures_sequential.png",
                     "gait_space_time_optimal.png", "gait_space_time_sequential.png"]


def test_text_report_has_steps_stride_and_speed():
    out = run_cli("gait", DEMO, "--section", "run")
    assert out.returncode == 0, out.stderr
    for word in ("sequential schedule", "inflate PAM1", "vent PAM2", "stride", "cycle time", "speed"):
        assert word in out.stdout


@pytest.mark.parametrize(("section", "reason"), [
    ("heavy-riser", "more than the 300 kPa supply"),
    ("oily-bend", "friction is zero"),
])
def test_infeasible_section_exits_3_with_its_reason(section, reason):
    out = run_cli("gait", SURVEY, "--section", section, "--optimal")
    assert out.returncode == 3
    assert f"section {section!r} cannot be crossed" in out.stderr and reason in out.stderr
    assert "Traceback" not in out.stderr


def test_bad_gait_block_and_section_exit_2(tmp_path):
    mission = yaml.safe_load(DEMO.read_text())
    for seg in mission["robot"]["segments"]:
        seg["pam"] = str(PROBLEMS / "pams" / "paper-radial-pam.yaml")
    mission["gait"] = {"valve": {"sonic_conductance": "3 kPa"}}
    path = tmp_path / "m.yaml"
    path.write_text(yaml.safe_dump(mission))
    out = run_cli("gait", path)
    assert out.returncode == 2
    assert "gait.valve.sonic_conductance" in out.stderr and "'3 kPa'" in out.stderr
    mission["gait"] = {"valves": {}}
    path.write_text(yaml.safe_dump(mission))
    out = run_cli("gait", path)
    assert out.returncode == 2 and "unknown key 'gait.valves'" in out.stderr
    assert "allowed keys here: valve, gas, vented_pressure, optimal" in out.stderr
    out = run_cli("gait", DEMO, "--section", "attic")
    assert out.returncode == 2 and "'riser', 'run'" in out.stderr
    assert "Traceback" not in out.stderr


def test_gait_options_change_the_timing(tmp_path):
    """Doubling the valve's sonic conductance halves the cycle time (ṁ ∝ C exactly)."""
    mission = yaml.safe_load(DEMO.read_text())
    for seg in mission["robot"]["segments"]:
        seg["pam"] = str(PROBLEMS / "pams" / "paper-radial-pam.yaml")
    times = []
    for c in ("0.5 dm^3/(s*bar)", "1 dm^3/(s*bar)"):
        mission["gait"] = {"valve": {"sonic_conductance": c}}
        path = tmp_path / "m.yaml"
        path.write_text(yaml.safe_dump(mission))
        out = run_cli("gait", path, "--json")
        assert out.returncode == 0, out.stderr
        times.append(json.loads(out.stdout)["cycle_time_s"])
    assert times[0] == pytest.approx(2 * times[1], rel=1e-6)
