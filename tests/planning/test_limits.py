"""The maker's limits in the PAM file (max_pressure, max_contraction): no plan goes beyond them, and the
reason names the limit that binds. The demo mission needs 121.8 kPa in its 3 in riser and 166.5 kPa in
its 3.5 in run (docs/physics.md §7)."""

from __future__ import annotations

import json
import math

import pytest

from pampipe.io.yamlfile import load_mapping
from pampipe.io.yamlwrite import write
from tests.support.problems import PROBLEMS
from tests.support.processes import run_cli

RISER, RUN = 0.0762, 0.0889  # [m]


def _mission(tmp_path, **limits):
    pam = load_mapping(PROBLEMS / "pams" / "paper-radial-pam.yaml", what="PAM file") | limits
    write(tmp_path / "pam.yaml", pam)
    mission = load_mapping(PROBLEMS / "missions" / "vertical-climb-3in.yaml", what="mission file")
    for segment in mission["robot"]["segments"]:
        segment["pam"] = "pam.yaml"
    write(tmp_path / "mission.yaml", mission)
    return tmp_path / "mission.yaml"


def _plan(path):
    result = run_cli("plan", path, "--json")
    return result.returncode, json.loads(result.stdout)


def test_a_rating_between_the_two_needs_fails_only_the_run(tmp_path):
    code, doc = _plan(_mission(tmp_path, max_pressure="150 kPa"))
    assert code == 3 and not doc["feasible"]
    riser, run = doc["sections"]
    assert riser["feasible"] and riser["segments"][0]["pressure_Pa"] == pytest.approx(121.8e3, rel=1e-3)
    assert not run["feasible"]
    assert "150 kPa rating" in run["reason"] and "max_pressure" in run["reason"]


def test_a_rating_above_the_needs_changes_nothing(tmp_path):
    code, doc = _plan(_mission(tmp_path, max_pressure="2 bar"))
    assert code == 0 and doc["feasible"]


def _contraction(diameter: float) -> float:
    """1 − L(D)/L₀ from the braid's inextensibility, L² + (NπD)² = B² (docs/physics.md §2)."""
    length, d0, alpha = 0.310662, 0.05715, math.radians(90 - 66.4373)
    braid, turns = length / math.cos(alpha), length * math.tan(alpha) / (math.pi * d0)
    return 1 - math.sqrt(braid**2 - (turns * math.pi * diameter) ** 2) / length


def test_max_contraction_rules_out_the_wider_bore(tmp_path):
    between = 0.5 * (_contraction(RISER) + _contraction(RUN))  # 7.7 % and 14.6 %
    code, doc = _plan(_mission(tmp_path, max_contraction=f"{between * 100:.4g} %"))
    assert code == 3
    riser, run = doc["sections"]
    assert riser["feasible"] and not run["feasible"]
    assert f"{_contraction(RUN) * 100:.3g} %" in run["reason"] and "max_contraction" in run["reason"]


def test_export_obeys_the_rating_and_the_contraction(tmp_path):
    """The exported C law answers as plan does: the 3.5 in run is above PAM1's 150 kPa rating (code 4),
    the riser is not; with max_contraction between the two bores' contractions the run is too wide (2)."""
    from tests.support.export_c import build, compiler, run_law

    (tmp_path / "rated").mkdir()
    rated = _mission(tmp_path / "rated", max_pressure="150 kPa")
    assert run_cli("export", rated, "-o", tmp_path / "rated" / "c").returncode == 0
    rows = [(RISER, math.pi / 2, 0.3, 2.0), (RUN, 0.0, 0.3, 2.0)]
    between = 0.5 * (_contraction(RISER) + _contraction(RUN))
    (tmp_path / "short").mkdir()
    short = _mission(tmp_path / "short", max_contraction=f"{between * 100:.4g} %")
    assert run_cli("export", short, "-o", tmp_path / "short" / "c").returncode == 0
    if compiler() is None:
        pytest.skip("no C compiler")
    codes, pressures = run_law(build(tmp_path / "rated" / "c"), rows)
    assert codes.tolist() == [0, 4]
    assert pressures[0, 0] == pytest.approx(121.8e3, rel=1e-3) and pressures[1, 0] > 150e3
    codes, _ = run_law(build(tmp_path / "short" / "c"), rows)
    assert codes.tolist() == [0, 2]
