"""`plan` through bends (docs/physics.md §14, docs/formats.md §4 bends): JSON bends[], exit codes, reasons,
fitting length, the flexible model, joints, reducers and bad bend data. Expected numbers are by hand."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
import yaml

from pampipe.bends.steering import curvature_of_lengths
from pampipe.io.pam_schema import load_pam
from pampipe.model.muscle import Muscle
from tests.support.problems import PROBLEMS

INCH = 0.0254
BORE = 3 * INCH
L0, D0 = 0.310662, 0.05715  # the paper's radial muscle (problems/pams/paper-radial-pam.yaml)
PAMS = PROBLEMS / "pams"


def _mission(tmp_path, bends, *, robot=None, top=None, bores=None):
    """A mission of len(bends) + 1 level 3 in sections, section i ending with bends[i] (None: straight on)."""
    segments = [{"name": f"PAM{i}", "pam": str(PAMS / "paper-radial-pam.yaml"), "mass": "0.4 kg"}
                for i in (1, 2, 3)]
    route = []
    for i in range(len(bends) + 1):
        section = {"name": f"s{i}", "length": "2 m", "inner_diameter": (bores or {}).get(i, "3 in"),
                   "friction": 0.3}
        if i < len(bends) and bends[i] is not None:
            section["bend"] = bends[i]
        route.append(section)
    doc = {"robot": {"segments": segments, **(robot or {})}, "supply_pressure": "689 kPa",
           "safety_factor": 1.5, "route": route, **(top or {})}
    path = tmp_path / "m.yaml"
    path.write_text(yaml.safe_dump(doc), encoding="utf-8")
    return path


def _classical(radius, d=D0, bore=BORE):
    """2√(R_o² − (R_i + d)²), the chord of a long bend, by hand."""
    return 2 * math.sqrt((radius + bore / 2) ** 2 - (radius - bore / 2 + d) ** 2)


def test_shipped_example_passes_two_bends_and_not_the_long_radius_elbow(cli):
    out = cli("plan", PROBLEMS / "missions" / "elbows-3in.yaml", "--json")
    assert out.returncode == 3
    doc = json.loads(out.stdout)
    bends = doc["bends"]
    assert [b["after_section"] for b in bends] == ["run-1", "run-2", "riser"]
    assert [b["passable"] for b in bends] == [True, True, False]
    for key in ("after_section", "angle_deg", "radius_m", "passable", "limiting_segment",
                "longest_passable_length_m", "clearance_m", "steering"):
        assert all(key in b for b in bends)
    elbow = bends[2]
    assert elbow["angle_deg"] == pytest.approx(90) and elbow["radius_m"] == pytest.approx(1.5 * BORE)
    assert elbow["longest_passable_length_m"] == pytest.approx(_classical(1.5 * BORE), rel=1e-9)
    assert elbow["clearance_m"] == pytest.approx(_classical(1.5 * BORE) - L0, rel=1e-9)
    # the reason names the bend, the segment, by how much it is too long and what would pass
    reason = elbow["reason"]
    short = (L0 - _classical(1.5 * BORE)) * 1e3
    for fragment in ("after section 'riser'", "PAM1", f"{short:.4g} mm too long",
                     f"longest that passes at 57.15 mm wide is {_classical(1.5 * BORE) * 1e3:.4g} mm",
                     "elbow radius would have to be at least"):
        assert fragment in reason
    assert "1 of 3 bends cannot be passed (after 'riser')" in out.stderr
    # the elbow radius it names passes, by hand: 2√(R_o² − (R_i + d)²) = L0
    needed = elbow["elbow_radius_needed_m"]
    assert _classical(needed) == pytest.approx(L0, abs=1e-6)


def test_steering_reaches_each_bend_curvature(cli):
    """The JSON pressures, put through the model outside the NLP, bend the module to 1/R within 2 %."""
    doc = json.loads(cli("plan", PROBLEMS / "missions" / "elbows-3in.yaml", "--json").stdout)
    muscle = Muscle.from_pam(load_pam(PAMS / "extensile-steering.yaml"))
    for bend in doc["bends"]:
        steering = bend["steering"]
        assert steering["reached"] is True
        lengths = muscle.free_length(steering["pressures_Pa"])
        assert curvature_of_lengths(lengths, 0.015) == pytest.approx(1 / bend["radius_m"], rel=0.02)
        assert max(steering["pressures_Pa"]) <= 689e3


def test_text_report_has_a_bend_table(cli):
    out = cli("plan", PROBLEMS / "missions" / "elbows-3in.yaml")
    assert out.returncode == 3
    assert "bends (each deflated segment as a rigid cylinder" in out.stdout
    assert "riser" in out.stdout and "no" in out.stdout


def test_fitting_length_makes_a_passing_segment_too_long(tmp_path, cli):
    """15° at 3 D passes 324.4 mm; L0 = 310.7 mm passes, L0 + 20 mm of fittings does not."""
    bend = {"angle": "15 deg", "radius": "3 D"}
    out = cli("plan", _mission(tmp_path, [bend]), "--json")
    assert out.returncode == 0 and json.loads(out.stdout)["bends"][0]["passable"]
    pam = yaml.safe_load((PAMS / "paper-radial-pam.yaml").read_text())
    pam["geometry"]["fitting_length"] = "20 mm"
    (tmp_path / "fitted.yaml").write_text(yaml.safe_dump(pam))
    path = _mission(tmp_path, [bend])
    doc = yaml.safe_load(path.read_text())
    doc["robot"]["segments"][1]["pam"] = str(tmp_path / "fitted.yaml")
    path.write_text(yaml.safe_dump(doc))
    out = cli("plan", path, "--json")
    assert out.returncode == 3
    bend_doc = json.loads(out.stdout)["bends"][0]
    assert bend_doc["limiting_segment"] == "PAM2"
    assert [s["rigid_length_m"] for s in bend_doc["segments"]][1] == pytest.approx(L0 + 0.02)


def test_flexible_model_passes_a_bend_wide_enough_for_the_least_bend_radius(tmp_path, cli):
    """ρ_min = (D0/2)/(1/cos α0 − 1) by hand; a 90° elbow with R + (D − D0)/2 ≥ ρ_min passes bent, one
    just tighter does not (and neither passes rigid)."""
    alpha = math.radians(90 - 66.4373)
    rho = D0 / 2 / (1 / math.cos(alpha) - 1)
    fits = rho - (BORE - D0) / 2
    for radius, passes in ((fits * 1.01, True), (fits * 0.99, False)):
        path = _mission(tmp_path, [{"angle": "90 deg", "radius": f"{radius * 1e3} mm"}],
                        top={"bend_model": "flexible"})
        out = cli("plan", path, "--json")
        bend = json.loads(out.stdout)["bends"][0]
        assert bend["passable"] is passes and out.returncode == (0 if passes else 3)
        assert bend["segments"][0]["least_bend_radius_m"] == pytest.approx(rho, rel=1e-9)
        assert bend["segments"][0]["longest_passable_length_m"] < L0  # rigid, it would not pass


def test_joint_angle_limit(tmp_path, cli):
    """Segments laid as chords of a 15° bend at 3 D need the whole 15° at a joint: 10° is not enough."""
    path = _mission(tmp_path, [{"angle": "15 deg", "radius": "3 D"}], robot={"joint_angle": "10 deg"})
    out = cli("plan", path, "--json")
    assert out.returncode == 3
    bend = json.loads(out.stdout)["bends"][0]
    assert not bend["joints_pass"] and bend["joint_angle_deg"] == pytest.approx(15)
    assert "joint_angle" in bend["reason"]


def test_reducer_is_reported_and_passes_into_the_smaller_bore(tmp_path, cli):
    path = _mission(tmp_path, [None], bores={1: "3.5 in"})
    out = cli("plan", path, "--json")
    assert out.returncode == 0
    (reducer,) = json.loads(out.stdout)["reducers"]
    assert reducer["from_inner_diameter_m"] == pytest.approx(BORE)
    assert reducer["to_inner_diameter_m"] == pytest.approx(3.5 * INCH)
    assert reducer["passable"] and "smaller" in reducer["reason"]


def test_elbow_radius_default_and_multiples(tmp_path, cli):
    path = _mission(tmp_path, [{"angle": "30 deg"}, {"angle": "30 deg", "radius": "200 mm"}],
                    top={"elbow_radius": "2 D"})
    bends = json.loads(cli("plan", path, "--json").stdout)["bends"]
    assert bends[0]["radius_m"] == pytest.approx(2 * BORE) and bends[1]["radius_m"] == pytest.approx(0.2)


def test_a_reducer_at_an_elbow_takes_the_radius_of_the_smaller_bore(tmp_path, cli):
    """1.5 D at a 4 in -> 3 in elbow is 1.5 x 3 in, the bore the segments pass, as in a network route; a
    stated 2 D at 3 in -> 4 in the same way (2 x 3 in); 4 in -> 4 in keeps 1.5 x 4 in."""
    bends = [{"angle": "30 deg"}, {"angle": "30 deg", "radius": "2 D"}, {"angle": "30 deg"}]
    path = _mission(tmp_path, bends, bores={0: "4 in", 2: "4 in", 3: "4 in"})
    bends = json.loads(cli("plan", path, "--json").stdout)["bends"]
    assert [b["radius_m"] for b in bends] == pytest.approx([1.5 * BORE, 2 * BORE, 1.5 * 4 * INCH])


@pytest.mark.parametrize(("bend", "extra", "fragments"), [
    ({"angle": "-30 deg"}, {}, ["route[0].bend.angle", "-30 deg", "0 to 180 deg"]),
    ({"angle": "30 deg", "radius": "0.4 D"}, {}, ["route[0].bend.radius", "at least half the bore"]),
    ({"angle": "30 deg", "radius": "30 mm"}, {}, ["route[0].bend.radius", "at least half the bore"]),
    ({"angle": "30 deg"}, {"top": {"elbow_radius": "0.3 D"}}, ["elbow_radius", "at least half the bore"]),
    ({"angle": "30 deg", "radius": "5 kPa"}, {}, ["route[0].bend.radius", "multiple of the bore"]),
    ({"angle": "30 deg"}, {"robot": {"steering": {"pam": str(PAMS / "paper-radial-pam.yaml"),
                                                  "radius": "15 mm"}}},
     ["robot.steering.pam", "extensile", "54.74"]),
])
def test_bad_bend_data_exits_2(tmp_path, cli, bend, extra, fragments):
    out = cli("plan", _mission(tmp_path, [bend], **extra))
    assert out.returncode == 2, out.stderr
    assert "Traceback" not in out.stderr
    for fragment in fragments:
        assert fragment in out.stderr


def test_extensile_segment_cannot_anchor(tmp_path, cli):
    path = _mission(tmp_path, [None])
    doc = yaml.safe_load(path.read_text())
    doc["robot"]["segments"][0]["pam"] = str(PAMS / "extensile-steering.yaml")
    path.write_text(yaml.safe_dump(doc))
    out = cli("plan", path)
    assert out.returncode == 2 and "robot.segments[0].pam" in out.stderr and "contractile" in out.stderr


def test_ky4_route_says_which_elbows_the_paper_muscle_passes(cli):
    """Every bend of the route is listed with its verdict; those that fail name PAM1 and by how much; the
    verdict is L0 ≤ L* of that bend (by hand where the chord lies on the arc)."""
    out = cli("plan", PROBLEMS / "missions" / "ky4-route.yaml", "--json")
    assert out.returncode == 3
    bends = json.loads(out.stdout)["bends"]
    blocked = [b for b in bends if not b["passable"]]
    assert len(blocked) == 5 and len(bends) > len(blocked)
    assert all(b["angle_deg"] > 30 for b in blocked)
    for b in bends:
        assert b["passable"] == (b["longest_passable_length_m"] >= L0)
        if not b["passable"]:
            assert "PAM1" in b["reason"] and "too long" in b["reason"]
        if b["binding_position"] == "mid-bend, ends on the arc":
            bore = b["inner_diameter_m"]
            by_hand = _classical(b["radius_m"], bore=bore)
            assert b["longest_passable_length_m"] == pytest.approx(by_hand, rel=1e-9)


def test_steering_fill_time_is_the_choked_flow_closed_form(cli):
    """Filling a PAM to 55.6 kPa from a 689 kPa supply stays choked (p/p_supply < 0.3, absolute), so with an
    isothermal chamber of constant volume t = V·P/(R·T·C·ρ₀·p_supply), by hand."""
    doc = json.loads(cli("plan", PROBLEMS / "missions" / "elbows-3in.yaml", "--json").stdout)
    bend = doc["bends"][0]
    pressure = max(bend["steering"]["pressures_Pa"])
    length = bend["steering"]["lengths_m"][0]
    assert (pressure + 101325) / (689e3 + 101325) < 0.3
    pam = load_pam(PAMS / "extensile-steering.yaml")
    g = pam.geometry
    n_pi = g.initial_length * math.tan(g.braid_angle) / g.initial_diameter  # Nπ
    b = g.initial_length / math.cos(g.braid_angle)
    volume = math.pi / 4 * (b**2 - length**2) / n_pi**2 * length  # πD²L/4 with D = √(B² − L²)/(Nπ)
    r0 = g.initial_diameter / 2
    volume -= math.pi * (r0**2 - (r0 - g.bladder_thickness) ** 2) * g.initial_length  # the bladder
    flow = 5e-9 * 1.185 * (689e3 + 101325)  # C ρ₀ p₁, the default valve
    by_hand = volume * pressure / (287.05 * 293.15 * flow)
    fill = bend["gait"]["steps"][0]
    assert fill["step"] == "steer-in" and fill["duration_s"] == pytest.approx(by_hand, rel=1e-3)
    assert doc["bends_extra_time_s"] == pytest.approx(sum(b["gait"]["extra_time_s"] for b in doc["bends"]))


def test_gait_reports_the_bends_extra_steps_and_time(cli):
    out = cli("gait", PROBLEMS / "missions" / "elbows-3in.yaml", "--json")
    assert out.returncode == 0, out.stderr
    doc = json.loads(out.stdout)
    bends = doc["bends"]
    assert bends["count"] == 3 and bends["extra_steps"] == 6
    assert bends["walking_time_s"] == pytest.approx(14 / doc["speed_m_per_s"], rel=1e-9)  # 4 + 3 + 2 + 5 m
    assert bends["route_time_s"] == pytest.approx(bends["walking_time_s"] + bends["extra_time_s"])
    assert "steering steps add" in out.stderr


def test_plots_mark_the_bends_and_draw_the_tightest(tmp_path, cli):
    out = cli("plan", PROBLEMS / "missions" / "elbows-3in.yaml", "--plots", tmp_path)
    assert out.returncode == 3
    for name in ("route_profile.png", "tightest_bend.png"):
        assert (tmp_path / name).stat().st_size > 10_000


def test_route_command_writes_the_network_bends(tmp_path, cli):
    """`pampipe route -o` writes a bend per turning joint; its plan lists the bends of the network route."""
    written = tmp_path / "r.yaml"
    assert cli("route", "ky4", "--from", "J-315", "--to", "J-897", "--max-bore", "4.5 in",
               "-o", written).returncode == 0
    listed = json.loads(cli("plan", written, "--json").stdout)["bends"]
    network = json.loads(cli("plan", PROBLEMS / "missions" / "ky4-route.yaml", "--json").stdout)["bends"]
    assert [b["after_section"] for b in listed] == [b["after_section"] for b in network]
    for a, b in zip(listed, network, strict=True):
        assert a["angle_deg"] == pytest.approx(b["angle_deg"], rel=1e-3)
        assert a["radius_m"] == pytest.approx(1.5 * 4 * INCH)  # 1.5 D of the nominal 4 in


def _tiny_network(tmp_path, incline_1_deg, incline_2_deg, turn_deg):
    """A → B → C, 100 m pipes of 100 mm, the second turned by ``turn_deg`` in plan view."""
    z_b = 100 * math.sin(math.radians(incline_1_deg))
    z_c = z_b + 100 * math.sin(math.radians(incline_2_deg))
    run_1 = 100 * math.cos(math.radians(incline_1_deg))
    run_2 = 100 * math.cos(math.radians(incline_2_deg))
    turn = math.radians(turn_deg)
    c = (run_1 + run_2 * math.cos(turn), run_2 * math.sin(turn))
    text = f"""[JUNCTIONS]
A  0  0
B  {z_b:.9f}  0
C  {z_c:.9f}  0
[PIPES]
P1  A  B  100  100  100  0  Open
P2  B  C  100  100  100  0  Open
[COORDINATES]
A  0  0
B  {run_1:.9f}  0
C  {c[0]:.9f}  {c[1]:.9f}
[OPTIONS]
Units LPS
[END]
"""
    (tmp_path / "tiny.inp").write_text(text)
    return tmp_path / "tiny.inp"


@pytest.mark.parametrize(("incline_1", "incline_2", "turn"),
                         [(0, 0, 90), (0, 30, 0), (30, -30, 90), (10, 20, 45)])
def test_network_bend_is_the_angle_between_the_pipes_in_3d(tmp_path, cli, incline_1, incline_2, turn):
    """By hand: the angle between the unit vectors (cos i₁, 0, sin i₁) and (cos i₂ cos δ, cos i₂ sin δ,
    sin i₂)."""
    network = _tiny_network(tmp_path, incline_1, incline_2, turn)
    i1, i2, delta = (math.radians(v) for v in (incline_1, incline_2, turn))
    d1 = np.array([math.cos(i1), 0.0, math.sin(i1)])
    d2 = np.array([math.cos(i2) * math.cos(delta), math.cos(i2) * math.sin(delta), math.sin(i2)])
    by_hand = math.degrees(math.acos(float(d1 @ d2)))
    path = tmp_path / "m.yaml"
    doc = yaml.safe_load(_mission(tmp_path, []).read_text())
    doc["route"] = {"network": str(network), "from": "A", "to": "C", "friction": 0.3}
    doc["elbow_radius"] = "2 D"
    path.write_text(yaml.safe_dump(doc))
    out = cli("plan", path, "--json")
    assert out.returncode in (0, 3), out.stderr
    (bend,) = json.loads(out.stdout)["bends"]
    assert bend["after_section"] == "P1" and bend["angle_deg"] == pytest.approx(by_hand, abs=1e-6)
    assert bend["radius_m"] == pytest.approx(0.2)
