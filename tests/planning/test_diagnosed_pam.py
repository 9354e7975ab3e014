"""`plan` with a diagnosed PAM (an ``effects:`` block written by `diagnose -o`), against closed forms.

With an axial preload F₀ the anchor must satisfy μπA(F_ax(P) − κW − F₀) ≥ SF·W, and with wall
friction (locked-in share λ) μπA(F_ax(P) − κW)/(1 + λπA) ≥ SF·W. Both stay affine in P, so
P = [target − F_ax(0, L_p)]/∂_P F_ax is an independent answer for the bisection the planner runs.
"""

from __future__ import annotations

import math

import pytest
import yaml

from pampipe.cli import main
from pampipe.io.mission_schema import load_mission
from pampipe.model import braid, forces, no_slip
from pampipe.planning import max_payload, plan_mission
from tests.support.problems import PROBLEMS

SECTIONS = [
    {"name": "riser", "length": "3 m", "inner_diameter": "3 in", "incline": "90 deg", "friction": 0.3},
    {"name": "slope", "length": "5 m", "inner_diameter": "3.25 in", "incline": "30 deg", "friction": 0.4},
    {"name": "run", "length": "10 m", "inner_diameter": "3.5 in", "incline": "0 deg", "friction": 0.3},
]


def _mission(tmp_path, effects, *, payload="2 kg"):
    pam = yaml.safe_load((PROBLEMS / "pams" / "paper-radial-pam.yaml").read_text())
    if effects is not None:
        pam["effects"] = effects
    (tmp_path / "pam.yaml").write_text(yaml.safe_dump(pam))
    mission = {"robot": {"segments": [{"name": f"PAM{k}", "pam": "pam.yaml", "mass": "0.4 kg"}
                                      for k in (1, 2, 3)], "payload": payload},
               "supply_pressure": "689 kPa", "safety_factor": 1.5, "route": SECTIONS}
    path = tmp_path / "mission.yaml"
    path.write_text(yaml.safe_dump(mission))
    return path


def _closed_form(mission, s, i, extra_force, grip_divisor):
    """P with μπA(F_ax(P) − κW − F₀)/(1 + λπA) = SF·W, written out from the model's affine form."""
    seg, sec = mission.segments[i], mission.route[s]
    g, m = seg.pam.geometry, seg.pam.moduli
    total = sum(x.mass for x in mission.segments) + mission.payload
    load = no_slip.anchor_load(total, seg.mass, sec.incline, sec.friction)
    amp = braid.amplification_factor(sec.diameter, g)
    at_zero, slope = forces.axial_force_affine(braid.length_at_diameter(sec.diameter, g), g, m.as_vector(),
                                               m.reference_pressure)
    divisor = grip_divisor(amp)
    target = mission.kappa * load + extra_force + mission.safety_factor * load * divisor / (
        sec.friction * math.pi * amp)
    return (target - at_zero) / slope


@pytest.mark.parametrize(("effects", "extra", "divisor"), [
    ({"axial_preload": {"preload": "200 N"}}, 200.0, lambda amp: 1.0),
    ({"wall_friction": {"lock": 0.2}}, 0.0, lambda amp: 1 + 0.2 * math.pi * amp),
])
def test_diagnosed_plan_matches_closed_form(tmp_path, effects, extra, divisor):
    mission = load_mission(_mission(tmp_path, effects))
    plan = plan_mission(mission)
    for s, section in enumerate(plan.sections):
        for i, segment in enumerate(section.segments):
            expected = _closed_form(mission, s, i, extra, divisor)
            # bisection to ~1e-16 Pa; the model's own round-off is ~1e-12 relative
            assert segment.pressure == pytest.approx(expected, rel=1e-9)
            assert segment.holding_capacity == pytest.approx(mission.safety_factor * segment.required_hold,
                                                             rel=1e-8)


def test_null_effects_plan_like_the_baseline(tmp_path):
    """Effects at their null values reproduce the baseline plan (the KKT solution) to round-off."""
    base = plan_mission(load_mission(_mission(tmp_path, None)))
    null = plan_mission(load_mission(_mission(tmp_path, {"axial_preload": {"preload": "0 N"},
                                                         "pressure_offset": {"offset": "0 kPa"}})))
    for a, b in zip(base.sections, null.sections, strict=True):
        for x, y in zip(a.segments, b.segments, strict=True):
            assert y.pressure == pytest.approx(x.pressure, rel=1e-9)


def test_diagnosed_max_payload_is_where_the_supply_runs_out(tmp_path):
    """At the reported max payload the limiting segment needs exactly the supply pressure."""
    path = _mission(tmp_path, {"axial_preload": {"preload": "300 N"}})
    limit = max_payload(load_mission(path))
    assert limit.payload is not None and limit.payload > 0
    plan = plan_mission(load_mission(path), payload=limit.payload)
    section = next(s for s in plan.sections if s.name == limit.section)
    needed = max(seg.pressure for seg in section.segments)
    assert needed == pytest.approx(load_mission(path).supply_pressure, rel=1e-6)


def test_confidence_with_effects_is_refused(tmp_path, capsys):
    path = _mission(tmp_path, {"axial_preload": {"preload": "100 N"}})
    assert main(["plan", str(path), "--confidence", "0.9"]) == 2
    assert "does not yet propagate uncertainty through diagnosed effects" in capsys.readouterr().err
