"""`pampipe plan` end to end: table, JSON (docs/commands.md §4.2), -o, --plots, exit 3 reasons,
exit 2 errors."""

from __future__ import annotations

import json

import pytest
import yaml

from pampipe.io.mission_schema import load_mission
from pampipe.model import forces
from tests.support.problems import PROBLEMS
from tests.support.processes import run_cli

MISSIONS = PROBLEMS / "missions"
DEMO = MISSIONS / "vertical-climb-3in.yaml"
SURVEY = MISSIONS / "infeasible-survey.yaml"


SEGMENT_KEYS = {"name", "pressure_Pa", "anchoring_pressure_Pa", "required_hold_N", "holding_capacity_N",
                "radial_force_N", "contact_pressure_Pa"}


def test_demo_prints_the_table_and_json_matches_interfaces(tmp_path):
    table = run_cli("plan", DEMO)
    assert table.returncode == 0, table.stderr
    for word in ("riser", "run", "PAM1", "PAM3", "P_anchor [kPa]", "capacity [N]", "margin", "feasible"):
        assert word in table.stdout
    out = run_cli("plan", DEMO, "--json", "--max-payload")
    assert out.returncode == 0, out.stderr
    doc = json.loads(out.stdout)  # exactly one JSON document on stdout
    assert doc["feasible"] is True
    assert [s["name"] for s in doc["sections"]] == ["riser", "run"]
    for section in doc["sections"]:
        assert section["feasible"] is True and section["reason"] is None
        assert len(section["segments"]) == 3
        for seg in section["segments"]:
            assert set(seg) >= SEGMENT_KEYS
            # capacity = SF × hold where no slip binds; p_c = F_r/(D L); capacity = μπF_r
            assert seg["holding_capacity_N"] == pytest.approx(1.5 * seg["required_hold_N"], rel=1e-9)
            # F_r = A(F_ax − κW) cancels ~3 digits near anchoring, so allow 1e-9, not round-off
            assert seg["holding_capacity_N"] == pytest.approx(0.3 * 3.141592653589793 * seg["radial_force_N"],
                                                              rel=1e-9)
    to_file = run_cli("plan", DEMO, "--json", "-o", tmp_path / "plan.json", "--max-payload")
    assert to_file.returncode == 0, to_file.stderr
    assert "P_anchor [kPa]" in to_file.stdout  # with -o the document goes to the file, the report to stdout
    written = json.loads((tmp_path / "plan.json").read_text())
    written["solver"].pop("wall_time_s"), doc["solver"].pop("wall_time_s")
    assert written == doc
    assert doc["max_payload"]["limiting_section"] == "riser"
    assert "Traceback" not in out.stderr


def test_every_bundled_mission_gives_a_plan_or_a_reason(cli):
    for path in sorted(MISSIONS.glob("*.yaml")):
        out = cli("plan", path, "--json")
        assert out.returncode in (0, 3), (path, out.stderr)
        doc = json.loads(out.stdout)
        if doc.get("coverage", {}).get("scope") == "network":  # every pipe of a network: some may fail
            assert (out.returncode == 0) is (doc["coverage"]["pipes_feasible"] > 0)
        else:
            assert doc["feasible"] is (out.returncode == 0)
        for section in doc["sections"]:
            assert section["feasible"] or (isinstance(section["reason"], str) and section["reason"])
        assert "Traceback" not in out.stderr


def test_each_infeasibility_reason_and_exit_3():
    out = run_cli("plan", SURVEY, "--json")
    assert out.returncode == 3
    assert "no solution" in out.stderr and "Traceback" not in out.stderr
    doc = json.loads(out.stdout)
    assert doc["feasible"] is False
    reasons = {s["name"]: s["reason"] for s in doc["sections"]}
    assert reasons["ok-run"] is None
    assert "needs" in reasons["heavy-riser"] and "300 kPa supply" in reasons["heavy-riser"]
    assert "at most" in reasons["heavy-riser"] and "kg of payload" in reasons["heavy-riser"]
    assert "not wider than the muscles at rest" in reasons["reducer"]
    assert "reach at the 300 kPa supply" in reasons["wide-run"]
    assert "can ever open" in reasons["header"]
    assert "friction is zero" in reasons["oily-bend"]
    # the pressure that touches the 4.5 in wall, from the closed form of docs/physics.md §7
    pam = load_mission(SURVEY).segments[0].pam
    touch = forces.anchoring_pressure(4.5 * 0.0254, pam.geometry, pam.moduli.as_vector(), 1e6)
    assert f"needs {touch / 1e3:.4g} kPa" in reasons["wide-run"]


def test_the_payload_named_in_the_reason_is_the_one_the_supply_carries(cli, tmp_path):
    """Plan the survey's riser with the payload its reason quotes: feasible, and just infeasible above it."""
    raw = yaml.safe_load(SURVEY.read_text())
    raw["route"] = raw["route"][:1]
    for seg in raw["robot"]["segments"]:
        seg["pam"] = str(MISSIONS / seg["pam"])
    mission = tmp_path / "riser.yaml"
    mission.write_text(yaml.safe_dump(raw))
    doc = json.loads(cli("plan", mission, "--json", "--max-payload").stdout)
    limit = doc["max_payload"]["max_payload_kg"]
    assert f"at most {limit:.3g} kg" in doc["sections"][0]["reason"]
    ok = cli("plan", mission, "--payload", f"{limit * 0.999} kg", "--json")
    assert ok.returncode == 0
    pressure = json.loads(ok.stdout)["sections"][0]["segments"][0]["pressure_Pa"]
    assert pressure == pytest.approx(300e3, rel=2e-3)  # 0.1 % less payload: a little under the supply
    assert cli("plan", mission, "--payload", f"{limit * 1.001} kg").returncode == 3


def test_solver_ipopt_agrees_and_plots_are_written(cli, tmp_path):
    kkt = json.loads(cli("plan", DEMO, "--json").stdout)
    out = cli("plan", DEMO, "--json", "--solver", "ipopt", "--plots", tmp_path / "plots")
    assert out.returncode == 0, out.stderr
    ipopt = json.loads(out.stdout)
    for a, b in zip(kkt["sections"], ipopt["sections"], strict=True):
        for x, y in zip(a["segments"], b["segments"], strict=True):
            assert y["pressure_Pa"] == pytest.approx(x["pressure_Pa"], rel=1e-9)  # IPOPT tol 1e-11
    for name in ("required_pressure.png", "holding_capacity.png"):
        assert (tmp_path / "plots" / name).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_confidence_option(cli):
    out = cli("plan", MISSIONS / "riser-uncertain-friction.yaml", "--confidence", "95%", "--json")
    assert out.returncode == 0, out.stderr
    doc = json.loads(out.stdout)
    assert doc["confidence"]["level"] == 0.95 and doc["confidence"]["samples"] > 0
    seg = doc["sections"][0]["segments"][0]
    assert seg["pressure_Pa"] > seg["nominal_pressure_Pa"]
    bad = cli("plan", DEMO, "--confidence", "0.95")
    assert bad.returncode == 2 and "uncertainty" in bad.stderr
    assert cli("plan", DEMO, "--confidence", "1.5").returncode == 2


def _mission(tmp_path, **edit) -> str:
    raw = yaml.safe_load(DEMO.read_text())
    for seg in raw["robot"]["segments"]:
        seg["pam"] = str(MISSIONS / seg["pam"])
    for key, value in edit.items():
        if key == "section":
            raw["route"][0].update(value)
        elif key == "pam":
            raw["robot"]["segments"][0]["pam"] = value
        else:
            raw[key] = value
    path = tmp_path / "mission.yaml"
    path.write_text(yaml.safe_dump(raw))
    return str(path)


@pytest.mark.parametrize(("edit", "words"), [
    ({"section": {"inner_diameter": "3 kPa"}}, ["inner_diameter", "3 kPa"]),
    ({"section": {"diamter": "3 in"}}, ["unknown key", "diamter", "allowed keys", "inner_diameter"]),
    ({"pam": "no-such-pam.yaml"}, ["no-such-pam.yaml", "robot.segments[0].pam"]),
])
def test_input_errors_exit_2(cli, tmp_path, edit, words):
    out = cli("plan", _mission(tmp_path, **edit))
    assert out.returncode == 2
    assert "Traceback" not in out.stderr
    for word in words:
        assert word in out.stderr


def test_pam_without_moduli_and_output_over_input(cli, tmp_path):
    raw = yaml.safe_load((PROBLEMS / "pams" / "paper-radial-pam.yaml").read_text())
    raw.pop("moduli")
    bare = tmp_path / "bare.yaml"
    bare.write_text(yaml.safe_dump(raw))
    out = cli("plan", _mission(tmp_path, pam=str(bare)))
    assert out.returncode == 2 and "pampipe identify" in out.stderr
    mission = _mission(tmp_path)
    before = (tmp_path / "mission.yaml").read_text()
    out = cli("plan", mission, "-o", mission)
    assert out.returncode == 2 and "refusing to write over the input" in out.stderr
    assert (tmp_path / "mission.yaml").read_text() == before


def test_the_json_document_is_built_only_when_asked_for(cli, tmp_path, monkeypatch):
    """The text report of a big mission does not pay for the JSON document (issue 25); --json and -o do."""
    from pampipe.planning.result import MissionPlan

    built = []
    original = MissionPlan.to_dict
    monkeypatch.setattr(MissionPlan, "to_dict", lambda self: (built.append(1), original(self))[1])
    assert cli("plan", DEMO).returncode == 0 and not built
    assert cli("plan", DEMO, "-o", tmp_path / "plan.json").returncode == 0 and len(built) == 1
    out = cli("plan", DEMO, "--json")
    assert out.returncode == 0 and len(built) == 2
    assert json.loads(out.stdout)["feasible"] is True


def test_a_large_mission_writes_the_same_json_on_one_line(cli, tmp_path, monkeypatch):
    """Above COMPACT_SECTIONS sections the document is written unindented (the C encoder), same content."""
    from pampipe.commands import plan as plan_command

    indented = cli("plan", DEMO, "--json", "--reproducible")
    monkeypatch.setattr(plan_command, "COMPACT_SECTIONS", 1)
    compact = cli("plan", DEMO, "--json", "--reproducible")
    to_file = cli("plan", DEMO, "--reproducible", "-o", tmp_path / "plan.json")
    assert indented.returncode == compact.returncode == to_file.returncode == 0
    assert indented.stdout.count("\n") > 50 and compact.stdout.count("\n") == 1
    assert json.loads(compact.stdout) == json.loads(indented.stdout)
    assert (tmp_path / "plan.json").read_text() == compact.stdout


@pytest.mark.parametrize(("mission", "options"), [
    ("ky4-route.yaml", ()),  # many sections and reducers, an infeasible section (exit 3)
    ("riser-uncertain-friction.yaml", ("--confidence", "0.9", "--samples", "200", "--max-payload")),
])
def test_a_streamed_document_is_the_built_one_byte_for_byte(cli, tmp_path, monkeypatch, mission, options):
    """Above COMPACT_SECTIONS the document is written section by section, in chunks (issue 25): the same
    bytes as the whole document encoded at once, on stdout and in -o."""
    from pampipe import api
    from pampipe.commands import plan as plan_command
    from pampipe.io import files
    from pampipe.planning.result import MissionPlan

    args = dict(zip(options[::2], options[1::2], strict=False))
    confidence, samples = float(args.get("--confidence", 0)) or None, int(args.get("--samples", 0)) or None
    plan = api.plan(api.load_mission(MISSIONS / mission), confidence=confidence, samples=samples,
                    max_payload="--max-payload" in options)
    built = files.to_json(plan.to_dict(), timings=False, indent=None)
    monkeypatch.setattr(plan_command, "COMPACT_SECTIONS", 0)
    monkeypatch.setattr(files, "STREAM_CHUNK", 2)  # several chunks, the last one maybe short
    monkeypatch.setattr(MissionPlan, "to_dict", lambda self: pytest.fail("the document was built whole"))
    out = cli("plan", MISSIONS / mission, *options, "--json", "--reproducible")
    assert out.stdout == built, out.stderr
    written = cli("plan", MISSIONS / mission, *options, "--reproducible", "-o", tmp_path / "plan.json")
    assert out.returncode == written.returncode
    assert (tmp_path / "plan.json").read_text() == built


def test_max_payload_of_impassable_sections_is_null_in_json():
    """An impassable pipe has no largest payload (−inf inside): the JSON says null there, and the route's
    largest payload is null with the first impassable section named; a passable section keeps its number
    (the affine law of physics.md: m₀ + (W_max − W(m₀))/(g(|sin φ| + μ cos φ)) is finite there)."""
    out = run_cli("plan", MISSIONS / "infeasible-survey.yaml", "--json", "--max-payload")
    assert out.returncode == 3, out.stderr
    limit = json.loads(out.stdout)["max_payload"]
    payloads = {s["name"]: s["max_payload_kg"] for s in limit["sections"]}
    assert limit["max_payload_kg"] is None and payloads[limit["limiting_section"]] is None
    assert payloads["reducer"] is None and payloads["header"] is None  # too narrow; too wide for the braid
    assert payloads["ok-run"] > payloads["heavy-riser"] > 0
    assert "came out as" not in out.stderr
