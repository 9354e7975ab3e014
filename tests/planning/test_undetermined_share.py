"""Exit 3 where it matters (issue 35, item 4; docs/physics.md §15, *Undetermined directions*).

A direction the data leave open over ± s is covered: each draw holds at the worst of the muscle at q̂ and at
q̂ ± s·v. A segment stops (exit 3, `"pressure_Pa": null`) only where that cover moves its C-quantile by more
than OPEN_SHARE (a tenth) of its margin to the supply: the same direction stops a plan with little headroom
and lets one with plenty go."""

from __future__ import annotations

import dataclasses
import json

import numpy as np
import pytest

from pampipe.io.mission_schema import load_mission
from pampipe.io.pam_schema import load_pam
from pampipe.io.pamfile import write_pam
from pampipe.model.uncertainty import ParameterUncertainty, UndeterminedDirection, moduli_names
from pampipe.planning import plan_mission
from pampipe.planning.sampling import OPEN_SHARE
from tests.support.problems import PROBLEMS

DEMO = PROBLEMS / "missions" / "vertical-climb-3in.yaml"
HOOP_A0 = 8  # index of hoop.a0 in the moduli vector


def open_pam(scale: float, shift: float = 0.0):
    """The demo muscle with a fit covariance on the axial moduli, its hoop.a0 open over ± ``scale`` MPa
    (moved by ``shift`` MPa, for the muscle at an end of the width)."""
    pam = load_pam(PROBLEMS / "pams" / "paper-radial-pam.yaml")
    if shift:
        theta = pam.moduli.as_vector().copy()
        theta[HOOP_A0] += shift * 1e6
        moduli = type(pam.moduli).from_vector(theta, reference_pressure=pam.moduli.reference_pressure)
        pam = dataclasses.replace(pam, moduli=moduli)
    vector = np.zeros(16)
    vector[HOOP_A0] = 1.0
    direction = UndeterminedDirection(vector, scale, {}, "a radial test at 76.2 mm (3 in)")
    directions = (direction,) if scale else ()
    cov = np.diag(np.r_[np.full(8, 0.05e6), np.zeros(8)] ** 2)
    return pam.with_uncertainty(ParameterUncertainty(moduli_names(3), cov, 0.0, directions))


def mission_with(pam, supply: float | None = None):
    mission = load_mission(DEMO)
    segments = tuple(dataclasses.replace(s, pam=pam) for s in mission.segments)
    mission = dataclasses.replace(mission, segments=segments)
    return mission if supply is None else dataclasses.replace(mission, supply_pressure=supply)


def test_an_open_direction_within_its_share_is_covered_over_its_whole_width():
    """Open over ± 1 MPa: the plan goes, at the worst end of the width (hoop.a0 enters P* monotonically, so
    per draw the worst end is one end, the same in every draw: the plan is the plan of that end's muscle)."""
    covered = plan_mission(mission_with(open_pam(1.0)), confidence=0.95, samples=2000)
    assert covered.feasible and not covered.arrays.reason_codes
    ends = [plan_mission(mission_with(open_pam(0.0, shift)), confidence=0.95, samples=2000).arrays.pressure
            for shift in (1.0, -1.0)]
    middle = plan_mission(mission_with(open_pam(0.0)), confidence=0.95, samples=2000).arrays.pressure
    np.testing.assert_allclose(covered.arrays.pressure, np.maximum(*ends), rtol=1e-9)
    shift = covered.uncertainty.open_shift
    np.testing.assert_allclose(shift, covered.arrays.pressure - middle, rtol=1e-9)
    assert np.all(shift > 5e3)  # it matters: 1 MPa of hoop modulus is worth kPa here
    margin = covered.supply_pressure - middle
    assert np.all(shift <= OPEN_SHARE * margin)
    doc = covered.to_dict()["sections"][0]["segments"][0]
    assert doc["undetermined"] is False and doc["undetermined_shift_Pa"] == pytest.approx(shift[0, 0])


def test_the_same_direction_stops_a_plan_whose_margin_it_exceeds(tmp_path, cli):
    """± 1 MPa moves the riser's plan by about 29 kPa: a go at the 689 kPa supply (a tenth of ~570 kPa),
    exit 3 at 300 kPa (a tenth of ~180 kPa); the stopped segments carry no pressure, no probability."""
    write_pam(tmp_path / "open.yaml", open_pam(1.0))
    text = DEMO.read_text().replace("../pams/paper-radial-pam.yaml", "open.yaml")
    for supply, code in (("689 kPa", 0), ("300 kPa", 3)):
        path = tmp_path / f"mission-{code}.yaml"
        path.write_text(text.replace("supply_pressure: 689 kPa", f"supply_pressure: {supply}"))
        out = cli("plan", path, "--confidence", "0.95", "--samples", "2000", "--json")
        assert out.returncode == code, out.stderr
        riser = json.loads(out.stdout)["sections"][0]
        for seg in riser["segments"]:
            assert seg["undetermined"] is bool(code)
            if code:
                assert seg["pressure_Pa"] is None and seg["holding_probability"] is None
            else:
                assert seg["pressure_Pa"] > seg["nominal_pressure_Pa"] and seg["holding_probability"] >= 0.95
        if code:
            assert riser["feasible"] is False
            assert "10 % of its" in riser["reason"] and "radial test" in riser["reason"]
