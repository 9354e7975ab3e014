"""A small coverage study in the default run (issue 35, items 1 and 8): the sampling law of
`plan --confidence` against muscles drawn OUTSIDE the code, each judged by its own closed-form least holding
pressure.

The fitted PAM: the paper's radial-test muscle, its braid angle calibrated (the fit's ±0.05°) and two moduli
uncertain (the fit's covariance), with the lot's stated sds (L₀ 1 mm, D₀ 0.5 mm, α₀ 1°, t₀ 0.25 mm).
Siblings of the tested muscle are the fit's draw plus a draw of every stated sd (the calibrated angle's too),
one muscle each; the tested muscle is the fit's draw alone. A plan at C must hold on a share C of the muscles
its unit names (within the Monte Carlo errors of both samples); a tested plan does not cover the siblings."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from pampipe.io.mission_schema import load_mission
from pampipe.io.pam_schema import load_pam
from pampipe.model import no_slip
from pampipe.model.muscle import Muscle
from pampipe.model.uncertainty import ParameterUncertainty, moduli_names
from pampipe.planning import plan_mission
from tests.support.problems import PROBLEMS

LOT_SD = {"initial_length": 1e-3, "initial_diameter": 0.5e-3, "braid_angle": math.radians(1.0),
          "bladder_thickness": 0.25e-3}
FIT_SD = {"axial.a0": 0.05e6, "hoop.a0": 0.1e6, "braid_angle": math.radians(0.05)}
LEVEL = 0.9
MUSCLES = 3000  # drawn outside the code: the share's standard error is 0.55 %, the plan's own about as much


def fitted_pam():
    pam = load_pam(PROBLEMS / "pams" / "paper-radial-pam.yaml")
    names = (*moduli_names(3), "braid_angle")
    cov = np.diag([FIT_SD.get(name, 0.0) ** 2 for name in names])
    return dataclasses.replace(pam.with_uncertainty(ParameterUncertainty(names, cov, 0.0, ())),
                               geometry_sd=dict(LOT_SD))


def riser_mission(unit: str):
    mission = load_mission(PROBLEMS / "missions" / "vertical-climb-3in.yaml")
    pam = fitted_pam()
    segments = tuple(dataclasses.replace(s, pam=pam, pam_file=None, unit=unit) for s in mission.segments)
    return dataclasses.replace(mission, segments=segments, route=mission.route[:1])


def drawn_muscles(lot: bool, rng) -> list[Muscle]:
    """Muscles drawn here, not by the planner: the fit's draw, plus (``lot``) the lot's spread."""
    pam = fitted_pam()
    theta0 = pam.moduli.as_vector()
    k0, k8 = moduli_names(3).index("axial.a0"), moduli_names(3).index("hoop.a0")
    out = []
    for _ in range(MUSCLES):
        theta = theta0.copy()
        theta[k0] += rng.normal(0.0, FIT_SD["axial.a0"])
        theta[k8] += rng.normal(0.0, FIT_SD["hoop.a0"])
        g = pam.geometry
        moved = {"braid_angle": g.braid_angle + rng.normal(0.0, FIT_SD["braid_angle"])}
        if lot:
            moved = {k: (moved.get(k, getattr(g, k))) + rng.normal(0.0, sd) for k, sd in LOT_SD.items()}
        out.append(Muscle(dataclasses.replace(g, **moved), theta, pam.moduli.reference_pressure))
    return out


def share_held(mission, pressure: float, muscles) -> float:
    seg, sec = mission.segments[0], mission.route[0]
    load = no_slip.anchor_load(sum(s.mass for s in mission.segments) + mission.payload, seg.mass, sec.incline,
                               sec.friction, mission.tether_drag)
    need = [float(m.least_holding_pressure(sec.diameter, load, kappa=mission.kappa, friction=sec.friction,
                                           safety_factor=mission.safety_factor)) for m in muscles]
    return float(np.mean(pressure >= np.asarray(need)))


@pytest.fixture(scope="module")
def muscles():
    rng = np.random.default_rng(35)
    return {"lot": drawn_muscles(True, rng), "tested": drawn_muscles(False, rng)}


@pytest.mark.parametrize("unit", ["lot", "tested"])
def test_a_plan_holds_on_a_share_c_of_the_muscles_its_unit_names(unit, muscles):
    mission = riser_mission(unit)
    plan = plan_mission(mission, confidence=LEVEL, samples=4000, seed=5)
    pressure = plan.arrays.pressure[0]
    for i in range(3):
        assert share_held(mission, pressure[i], muscles[unit]) == pytest.approx(LEVEL, abs=0.025), (unit, i)


def test_a_tested_plan_does_not_cover_the_siblings_and_a_lot_plan_costs_more(muscles):
    """The issue's finding, kept: judged against siblings, a tested muscle's plan holds far less often."""
    tested = plan_mission(riser_mission("tested"), confidence=LEVEL, samples=4000, seed=5)
    lot = plan_mission(riser_mission("lot"), confidence=LEVEL, samples=4000, seed=5)
    assert share_held(riser_mission("lot"), tested.arrays.pressure[0, 0], muscles["lot"]) < 0.75
    assert np.all(lot.arrays.pressure[0] > tested.arrays.pressure[0, 0] + 3e3)
