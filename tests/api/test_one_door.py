"""One model everywhere (docs/commands.md §11.2): for a PAM with each library effect, plan, gait,
simulate and the plots' numbers agree, each quantity computed two ways.

* plan's pressure P* against an independent bisection on F_r from :mod:`pampipe.model.effects`
  (the effect functions, not the :class:`Muscle` that plan asks);
* gait's ``no_slip_pressure_Pa`` against plan's ``pressure_Pa`` (exact: one door, one formula);
* plan's ``holding_capacity_N`` against the curve its plot draws (``MissionPlan.capacity_curve``);
* simulate's radial force at plan's pressure, without load, against the effect functions;
* simulate's anchoring pressure against a bisection on the effect functions.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import yaml

from pampipe import api
from pampipe.model import effects as effect_model
from pampipe.model.effects import LIBRARY
from tests.support.problems import PROBLEMS

#: Effect values within the library's bounds, large enough to move the plan by > 1 kPa.
VALUES = {"braid_friction": {"f0": "8 N", "f1": "20 N/MPa"},
          "braid_extensibility": {"compliance": "0.5 1/MN"},
          "end_effects": {"volume_taper": 0.3, "end_length": 0.5},
          "contact_stiffening": {"axial_increment": "0.4 MPa", "hoop_increment": "0.7 MPa"},
          "pressure_offset": {"offset": "9 kPa", "gain": 1.03},
          "axial_preload": {"preload": "55 N", "pulley_friction": 0.05}, "wall_friction": {"lock": 0.01},
          "pressure_hysteresis": {"h0": "6 N", "h1": "15 N/MPa"},
          "prestrain": {"axial_prestrain": 0.004, "hoop_prestrain": 0.02}}
CASES = [None, *LIBRARY]


def _mission(tmp_path, effect):
    pam = yaml.safe_load((PROBLEMS / "pams" / "paper-radial-pam.yaml").read_text())
    if effect is not None:
        pam["effects"] = {effect: VALUES[effect]}
    (tmp_path / "pam.yaml").write_text(yaml.safe_dump(pam))
    mission = yaml.safe_load((PROBLEMS / "missions" / "vertical-climb-3in.yaml").read_text())
    for segment in mission["robot"]["segments"]:
        segment["pam"] = "pam.yaml"
    path = tmp_path / "mission.yaml"
    path.write_text(yaml.safe_dump(mission))
    return path, tmp_path / "pam.yaml"


def _bisect(predicate, low=0.0, high=2e6, steps=100):
    """Least P in [low, high] with predicate(P) (monotone): an independent root finder."""
    for _ in range(steps):
        mid = 0.5 * (low + high)
        low, high = (low, mid) if predicate(mid) else (mid, high)
    return high


def test_every_library_effect_has_a_case():
    assert set(VALUES) == set(LIBRARY)


@pytest.mark.parametrize("effect", CASES, ids=lambda e: e or "baseline")
def test_plan_gait_simulate_and_plots_agree(tmp_path, effect):
    mission_file, pam_file = _mission(tmp_path, effect)
    mission = api.load_mission(mission_file)
    pam = mission.segments[0].pam
    plan = api.plan(mission)
    assert plan.feasible
    active = pam.effects
    theta, pref = pam.moduli.as_vector(), pam.moduli.reference_pressure
    contact = pam.moduli.contact_vector() if np.any(pam.moduli.contact_vector()) else None

    def radial(p, diameter, load):
        return float(effect_model.radial_force_with_effects(p, diameter, pam.geometry, theta, pref, load,
                                                            contact, active))

    for s, section in enumerate(plan.sections):
        route = mission.route[s]
        gait = api.gait(mission, section=section.name).to_dict()
        for k, segment in enumerate(section.segments):
            w = segment.required_hold
            expected = _bisect(lambda p, w=w, d=route.diameter, mu=route.friction: radial(p, d, w) > 0
                               and mu * math.pi * radial(p, d, w) >= plan.safety_factor * w)
            # plan solves by bisection (80 halvings) or the closed form; 100 halvings here: both ~1e-9 Pa
            assert segment.pressure == pytest.approx(expected, rel=1e-9, abs=1e-6)
            # gait asks the same door for its no-slip threshold: identical numbers
            assert gait["segments"][k]["no_slip_pressure_Pa"] == pytest.approx(segment.pressure, rel=1e-12)
            # the plot's curve at the operating point is the table's capacity (same muscle, same call)
            drawn = plan.capacity_curve(s, k, [segment.pressure])[0]
            assert drawn == pytest.approx(segment.holding_capacity, rel=1e-12)
        at = section.segments[0].pressure
        simulated = api.simulate(pam_file, pipe_diameter=route.diameter, pressure=[at])
        point = simulated.to_dict()["points"][0]
        assert point["radial_force_N"] == pytest.approx(radial(at, route.diameter, 0.0), rel=1e-12)
        anchoring = _bisect(lambda p, d=route.diameter: radial(p, d, 0.0) > 0)
        # closed form (baseline) or 80-halving bisection on [0, 100 MPa] (1e-16 Pa): 1e-6 Pa covers both
        assert simulated.to_dict()["anchoring_pressure_Pa"] == pytest.approx(anchoring, abs=1e-6)
        assert section.segments[0].anchoring_pressure == pytest.approx(anchoring, abs=1e-6)
