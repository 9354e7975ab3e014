"""Route sections an engineer can check (issue 12, items 1, 2 and 5): standard sizes and tolerances in a
mission, reasons that name the failing bore, the bore's sd under --confidence, the sections echoed as
parsed, --units, the safety-factor default warned about, gauge pressures."""

from __future__ import annotations

import copy
import json
import math
from types import SimpleNamespace

import numpy as np
import pytest
import yaml

from pampipe import api
from pampipe.cli import main
from pampipe.errors import InputError
from pampipe.model import no_slip
from pampipe.model.muscle import Muscle
from tests.support.problems import PROBLEMS

MISSIONS = PROBLEMS / "missions"
DEMO = MISSIONS / "vertical-climb-3in.yaml"
PSI = 6894.757293168361  # Pa: 1 lbf/in² = 4.4482216152605 N / 0.0254² m², typed independently
BAR = 1e5
INCH = 0.0254


def demo(**route_changes) -> dict:
    """The demo mission as a dict; ``route_changes`` replace keys of its first section (the riser)."""
    doc = yaml.safe_load(DEMO.read_text())
    doc["route"][0].update(route_changes)
    return doc


def plan(doc: dict, **options):
    return api.plan(doc, base=MISSIONS, **options)


@pytest.fixture
def cli(capsys, tmp_path):
    """Run ``pampipe ARGS`` in this process; a dict argument is written as a mission file first."""

    def run(*args) -> SimpleNamespace:
        words = []
        for arg in args:
            if isinstance(arg, dict):
                path = tmp_path / "mission.yaml"
                text = yaml.safe_dump(arg).replace("../pams/", f"{PROBLEMS / 'pams'}/")
                path.write_text(text)
                arg = path
            words.append(str(arg))
        capsys.readouterr()
        code = main(words)
        out = capsys.readouterr()
        return SimpleNamespace(returncode=code, stdout=out.out, stderr=out.err)

    return run


def test_standard_sizes_and_tolerances_reach_the_plan():
    doc = demo(inner_diameter={"nps": 3, "schedule": 40, "tolerance": "1 mm"})
    doc["route"][1]["inner_diameter"] = {"dn": 110, "sdr": 26, "tolerance": "1 %"}
    sections = plan(doc).to_dict()["sections"]
    riser, run = sections
    # NPS 3 Sch 40: 88.9 mm outside, 5.49 mm wall (ASME B36.10M metric columns) -> 77.92 mm bore
    assert riser["inner_diameter_m"] == pytest.approx(0.07792, abs=1e-6)
    assert riser["inner_diameter_range_m"] == pytest.approx([0.07692, 0.07892], abs=1e-6)
    assert riser["inner_diameter_label"] == "NPS 3 Sch 40 (ASME B36.10M) ± 1 mm"
    # DN 110 SDR 26: wall 110/26 = 4.2308 mm, bore 101.538 mm, ± 1 %
    bore = 110 - 2 * 110 / 26
    assert run["inner_diameter_range_m"] == pytest.approx([bore * 0.99e-3, bore * 1.01e-3], rel=1e-12)
    for sec in sections:  # interfaces §7.2: the keys every planned section carries
        keys = {"inner_diameter_m", "inner_diameter_range_m", "length_m", "incline_deg", "friction"}
        assert keys <= set(sec)
    assert riser["incline_deg"] == pytest.approx(90.0) and riser["length_m"] == 3.0


def test_a_bore_with_an_sd_is_accepted_and_used_only_by_confidence():
    doc = demo(inner_diameter={"value": "3 in", "sd": "0.5 mm"})
    nominal = plan(doc)
    assert nominal.to_dict()["sections"][0]["inner_diameter_sd_m"] == pytest.approx(0.0005)
    assert any("only --confidence uses" in w for w in nominal.warnings)
    assert nominal.to_dict()["sections"][0]["segments"][0]["pressure_Pa"] == pytest.approx(
        plan(demo()).to_dict()["sections"][0]["segments"][0]["pressure_Pa"], rel=1e-15)


@pytest.mark.parametrize("confidence", [0.8, 0.95])
def test_bore_sd_under_confidence_holds_in_c_of_monte_carlo_draws(confidence):
    """Sampled σ_D: the pressure holds in C ± 2 % of 10⁴ draws of the bore (the
    Monte Carlo standard error is ≤ 0.4 %; the demo PAM has no covariance, so the bore is the only source).
    """
    sd = 0.3e-3
    doc = demo(inner_diameter={"value": "3 in", "sd": f"{sd * 1e3} mm"})
    result = plan(doc, confidence=confidence)
    mission = api.load_mission(doc, base=MISSIONS)
    seg, sec = mission.segments[0], mission.route[0]
    point = result.sections[0].segments[0]
    assert point.pressure > point.nominal_pressure
    rng = np.random.default_rng(7)
    bores = rng.normal(3 * INCH, sd, 10_000)
    total = sum(s.mass for s in mission.segments) + mission.payload
    load = no_slip.anchor_load(total, seg.mass, sec.incline, sec.friction, mission.tether_drag)
    muscle = Muscle.from_pam(seg.pam)
    share = np.mean(muscle.holding_capacity(point.pressure, bores, load, kappa=1.0, friction=0.3)
                    >= mission.safety_factor * load)
    assert share == pytest.approx(confidence, abs=0.02)


def test_reasons_name_the_bore_that_fails():
    doc = demo()
    doc["supply_pressure"] = "150 kPa"
    doc["robot"]["payload"] = "20 kg"
    doc["route"] = [
        {"name": "tight", "length": "1 m", "inner_diameter": {"value": "60 mm", "tolerance": "5 mm"},
         "incline": "0 deg", "friction": 0.3},
        {"name": "loose", "length": "1 m", "inner_diameter": {"value": "110 mm", "tolerance": "10 mm"},
         "incline": "0 deg", "friction": 0.3},
        {"name": "steep", "length": "1 m", "inner_diameter": {"value": "3 in", "tolerance": "3 mm"},
         "incline": "90 deg", "friction": 0.3}]
    result = plan(doc)
    reasons = dict(zip([s.name for s in result.sections], [s.reason for s in result.sections], strict=True))
    assert "at its smallest bore of 55 mm, not wider than the muscles at rest" in reasons["tight"]
    assert "at its largest bore of 120 mm, wider than the braid" in reasons["loose"]
    worst = result.arrays.diameter[2, 0]
    assert worst == pytest.approx(0.0792, abs=1e-9)  # P* rises with D here: the largest bore is the worst
    assert f"in its worst bore, {worst * 1e3:.4g} mm," in reasons["steep"]
    assert result.arrays.reason_codes == {0: "narrower_than_muscle", 1: "wider_than_braid", 2: "above_supply"}


def test_bad_bores_exit_2_naming_the_section(cli):
    doc = demo(inner_diameter={"nps": 3, "schedule": 41})
    out = cli("plan", doc)
    assert out.returncode == 2
    assert "route[0].inner_diameter.schedule: 41 is not an ASME schedule" in out.stderr
    out = cli("plan", demo(inner_diameter={"value": "3 in", "tolerance": "4 in"}))
    assert out.returncode == 2 and "route[0].inner_diameter.tolerance" in out.stderr


def test_sections_are_echoed_as_parsed_and_units_change_only_the_text(cli):
    doc = demo(inner_diameter={"nps": 3, "schedule": 40, "tolerance": "1 %"})
    kpa = cli("plan", doc, "--json")
    psi = cli("plan", doc, "--json", "--units", "psi")
    bar = cli("plan", doc, "--units", "bar")
    assert kpa.returncode == psi.returncode == bar.returncode == 0
    doc_kpa, doc_psi = json.loads(kpa.stdout), json.loads(psi.stdout)
    doc_kpa["solver"].pop("wall_time_s"), doc_psi["solver"].pop("wall_time_s")
    assert doc_kpa == doc_psi  # the JSON stays SI
    text = psi.stderr
    assert "sections as parsed:" in text and "NPS 3 Sch 40 (ASME B36.10M) ± 1 %" in text
    head, rows = _table(text, "section  bore [mm]")
    riser = rows[0]
    assert riser[0] == "riser" and float(riser[1]) == pytest.approx(77.92, abs=0.01)
    assert float(riser[2]) == pytest.approx(77.92 / 25.4, abs=1e-3) and float(riser[6]) == 90
    head, rows = _table(text, "section  segment")
    pressure = doc_psi["sections"][0]["segments"][0]["pressure_Pa"]
    assert "P [psi]" in head and float(rows[0][2]) == pytest.approx(pressure / PSI, rel=1e-3)
    head, rows = _table(bar.stdout, "section  segment")
    assert "P [bar]" in head and float(rows[0][2]) == pytest.approx(pressure / BAR, rel=1e-3)
    assert f"supply {689e3 / PSI:.4g} psi" in text


def _table(text: str, start: str) -> tuple[str, list[list[str]]]:
    """(header line, rows split on runs of spaces) of the table whose header begins with ``start``."""
    lines = [line.strip() for line in text.splitlines()]
    at = next(i for i, line in enumerate(lines) if line.startswith(start))
    rows = []
    for line in lines[at + 2:]:
        if not line or line.endswith(":") or line.startswith(("P_anchor", "feasible", "INFEASIBLE")):
            break
        rows.append([cell for cell in line.split("  ") if cell.strip()])
    return lines[at], [[c.strip() for c in r] for r in rows]


def test_a_missing_safety_factor_defaults_to_1_with_a_warning(cli):
    doc = demo()
    del doc["safety_factor"]
    out = cli("plan", doc, "--json")
    assert out.returncode == 0
    result = json.loads(out.stdout)
    assert result["safety_factor"] == 1.0
    assert any("no safety_factor, so 1 is used" in w for w in result["warnings"])
    assert "warning:" in out.stderr and "safety factor 1 (none given: default)" in out.stderr
    given = cli("plan", demo(), "--json")
    assert not any("safety_factor" in w for w in json.loads(given.stdout)["warnings"])


def test_gauge_units_are_read_as_gauge_and_absolute_ones_refused(cli):
    doc = demo()
    doc["supply_pressure"] = "100 psig"
    assert api.load_mission(doc, base=MISSIONS).supply_pressure == pytest.approx(100 * PSI, rel=1e-15)
    doc["supply_pressure"] = "6.89 barg"
    assert api.load_mission(doc, base=MISSIONS).supply_pressure == pytest.approx(6.89 * BAR, rel=1e-15)
    doc["supply_pressure"] = "100 psia"
    out = cli("plan", doc)
    assert out.returncode == 2 and "absolute pressure" in out.stderr and "gauge" in out.stderr


def test_thin_contact_margin_is_warned_and_a_tolerance_covers_it():
    """The demo plans 4.8 kPa above touching the 3 in bore, less than a braid angle 1° off costs (5.3 kPa;
    a 1 mm wider bore: 3.8 kPa): warned.
    With the bore's tolerance the plan holds in the largest bore, so the margin is measured there."""
    nominal = plan(demo())
    riser = nominal.sections[0].segments[0]
    assert riser.thin_contact and riser.contact_cost_bore < riser.contact_margin < riser.contact_cost_angle
    assert any(w.startswith("riser: PAM1 is planned only") and "give the bore's tolerance" in w
               for w in nominal.warnings)
    ranged_plan = plan(demo(inner_diameter={"value": "3 in", "tolerance": "1 mm"}))
    # a tolerance is given: the advice is about bores beyond it, not to give one
    riser_warning = next(w for w in ranged_plan.warnings if w.startswith("riser: PAM1"))
    assert "wider than the stated range" in riser_warning and "give the bore" not in riser_warning
    ranged = ranged_plan.sections[0].segments[0]
    # the plan rises with the bore: the 77.2 mm bore's own plan
    larger = plan(demo(inner_diameter="77.2 mm")).sections[0].segments[0]
    assert ranged.pressure == pytest.approx(larger.pressure, rel=1e-9)
    assert ranged.largest_bore_anchoring_pressure == pytest.approx(larger.anchoring_pressure, rel=1e-12)


def test_missions_keep_the_input_errors_of_a_list_route():
    doc = copy.deepcopy(demo())
    doc["route"][1]["name"] = "riser"
    with pytest.raises(InputError, match="section names must be unique"):
        api.load_mission(doc, base=MISSIONS)
    doc = demo()
    doc["route"] = []
    with pytest.raises(InputError, match="route"):
        api.load_mission(doc, base=MISSIONS)
    assert math.isclose(api.load_mission(demo(), base=MISSIONS).route.diameter[0], 3 * INCH)
