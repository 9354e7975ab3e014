"""`unit: tested | lot` (interfaces §9.1, docs/physics.md §15): which muscle a segment carries, and what
`plan --confidence` draws for it.

A fitted PAM describes the tested unit (the fit's covariance); its stated geometry sds describe its lot. A
``lot`` segment draws the stated sd of every geometry entry (the calibrated braid angle included) around the
fitted geometry, independently per segment; a ``tested`` segment draws the fit's posterior only, and all
tested segments of one PAM file are one muscle (one draw)."""

from __future__ import annotations

import dataclasses
import json
import math

import numpy as np
import pytest

from pampipe.errors import InputError
from pampipe.io.mission_schema import load_mission
from pampipe.planning import plan_mission
from pampipe.planning.confidence import sampling_problem
from pampipe.planning.problem import build_elements, mission_muscles
from pampipe.planning.sampling import muscle_draws
from tests.support.problems import PROBLEMS

#: A PAM as `identify -o` writes it after calibrating the braid angle (its variance in the uncertainty
#: block, (0.01°)²), with the lot's stated sds on D₀ (0.5 mm) and on the braid angle (1°).
FITTED = """\
name: fitted-lot-pam
geometry:
  initial_length: 310.662 mm
  initial_diameter: {value: 57.15 mm, sd: 0.5 mm}
  braid_angle_from_axis: {value: 23.5627 deg, sd: 1 deg}
  bladder_thickness: 3.175 mm
moduli:
  unit: MPa
  reference_pressure: 1 MPa
  axial: {a: [1.5, 0, 0, 0], b: [0, 0, 0, 0]}
  hoop:  {a: [4.443711, -1.615470, 0, 0], b: [0, 0, 0, 0]}
uncertainty:
  unit: MPa
  parameters: [axial.a0, axial.a1, axial.a2, axial.a3, axial.b0, axial.b1, axial.b2, axial.b3,
               hoop.a0, hoop.a1, hoop.a2, hoop.a3, hoop.b0, hoop.b1, hoop.b2, hoop.b3, braid_angle]
  covariance: {covariance}
  model_error: 1 N
"""
ANGLE_FIT_SD = math.radians(0.01)
LOT_SD = {"initial_diameter": 0.5e-3, "braid_angle": math.radians(1.0)}


def write_fitted(folder, units=("tested", "lot", "tested"), pam=None) -> dict:
    """A mission dict (three segments of the given units on the fitted PAM), the PAM written beside."""
    cov = np.zeros((17, 17))
    cov[0, 0], cov[8, 8], cov[16, 16] = 0.02**2, 0.03**2, ANGLE_FIT_SD**2
    (folder / "fitted.yaml").write_text(pam or FITTED.replace("{covariance}", json.dumps(cov.tolist())))
    segments = [{"name": f"PAM{k + 1}", "pam": "fitted.yaml", "mass": "0.4 kg",
                 **({} if unit is None else {"unit": unit})} for k, unit in enumerate(units)]
    return {"robot": {"segments": segments, "payload": "2 kg"},
            "supply_pressure": "689 kPa", "safety_factor": 1.5, "load_path": "through_anchor",
            "route": [{"name": "riser", "length": "3 m", "inner_diameter": "3 in", "incline": "90 deg",
                       "friction": 0.3}]}


def mission_at(tmp_path, **options):
    doc = write_fitted(tmp_path, **options)
    (tmp_path / "mission.yaml").write_text(json.dumps(doc))
    return load_mission(tmp_path / "mission.yaml")


def draws_of(mission, samples=4000):
    muscles = mission_muscles(mission)
    problem = sampling_problem(mission, muscles, build_elements(mission, muscles), 0.95, samples=samples,
                               seed=3)[0]
    return problem, muscle_draws(problem)


def test_the_unit_is_read_and_defaults_to_lot(tmp_path):
    mission = mission_at(tmp_path, units=("tested", None, "lot"))
    assert [s.unit for s in mission.segments] == ["tested", "lot", "lot"]
    with pytest.raises(InputError, match="unit"):
        mission_at(tmp_path, units=("tested", "spare", "lot"))


def test_lot_draws_the_stated_sd_of_every_entry_calibrated_ones_included_per_segment(tmp_path):
    """The lot spread is the stated tolerance: the braid angle's 1° although the fit calibrated it (the fit's
    own 0.01° is the moduli source), D₀'s 0.5 mm; each lot segment its own muscle."""
    problem, draws = draws_of(mission_at(tmp_path, units=("lot", "lot", "tested")))
    names = problem.structures[0].names()
    lot = [draws.params["geometry"][i] for i in (0, 1)]
    for name, sd in LOT_SD.items():
        k = names.index(name)
        for g in lot:
            assert np.std(g[:, k]) == pytest.approx(sd, rel=0.05), name
        assert abs(np.corrcoef(lot[0][:, k], lot[1][:, k])[0, 1]) < 0.06, name  # independent per segment
    k = names.index("initial_length")  # no sd stated: exact
    assert not np.any(lot[0][:, k])
    fitted = draws.params["moduli"][0][:, names.index("braid_angle")]
    assert np.std(fitted) == pytest.approx(ANGLE_FIT_SD, rel=0.05)


def test_tested_segments_draw_the_fit_only_and_are_one_muscle(tmp_path):
    problem, draws = draws_of(mission_at(tmp_path, units=("tested", "lot", "tested")))
    for i in (0, 2):
        assert not np.any(draws.params["geometry"][i])  # the stated sds are not drawn again
    for source in draws.params.values():
        assert np.array_equal(source[0], source[2])
    assert np.array_equal(draws.model_error[0], draws.model_error[2])
    assert not np.array_equal(draws.model_error[0], draws.model_error[1])  # the lot muscle is another
    assert problem.twins == (0, 1, 0)  # one plan for the one tested muscle


def test_a_tested_plan_ignores_the_stated_sds_and_a_lot_plan_needs_more(tmp_path):
    mission = mission_at(tmp_path, units=("tested", "lot", "tested"))
    plan = plan_mission(mission, confidence=0.95, samples=2000)
    bare = tuple(dataclasses.replace(s, pam=dataclasses.replace(s.pam, geometry_sd={}))
                 for s in mission.segments)
    without = plan_mission(dataclasses.replace(mission, segments=bare), confidence=0.95, samples=2000)
    p, q = plan.arrays.pressure[0], without.arrays.pressure[0]
    assert p[0] == q[0] == p[2]  # tested: the sds change nothing
    assert p[1] > q[1] + 5e3 and p[1] > p[0] + 5e3  # lot: 1° and 0.5 mm of spread cost kPa here


def test_tested_needs_a_fitted_pam(tmp_path):
    mission = load_mission(PROBLEMS / "missions" / "vertical-climb-3in.yaml")
    segments = tuple(dataclasses.replace(s, unit="tested") for s in mission.segments)
    route = tuple(dataclasses.replace(s, friction_sd=0.05) for s in mission.route)
    mission = dataclasses.replace(mission, segments=segments, route=route)
    with pytest.raises(InputError, match=r"unit: tested.*no 'uncertainty:' block"):
        plan_mission(mission, confidence=0.95, samples=500)


def test_the_json_the_text_and_the_html_report_name_the_unit_of_each_probability(tmp_path, cli):
    (tmp_path / "mission.yaml").write_text(json.dumps(write_fitted(tmp_path)))
    out = cli("plan", tmp_path / "mission.yaml", "--confidence", "0.9", "--samples", "500", "--json",
              "--report", tmp_path / "plan.html")
    assert out.returncode == 0, out.stderr
    report = (tmp_path / "plan.html").read_text()
    assert "<th>unit</th>" in report and "<td>tested</td>" in report and "<td>lot</td>" in report
    segments = json.loads(out.stdout)["sections"][0]["segments"]
    assert [s["unit"] for s in segments] == ["tested", "lot", "tested"]
    rows = [line.split() for line in out.stderr.splitlines() if line.strip().startswith("riser")]
    assert [r[2] for r in rows[-3:]] == ["tested", "lot", "tested"]  # the confidence table's unit column
    plain = cli("plan", tmp_path / "mission.yaml", "--json")
    assert "unit" not in json.loads(plain.stdout)["sections"][0]["segments"][0]  # no draws, no unit
