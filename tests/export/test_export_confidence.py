"""`export --confidence C`: the exported law plans at C on the mission's sections, through a stated margin."""

from __future__ import annotations

import numpy as np
import pytest

from pampipe import api
from pampipe.io.mission_schema import load_mission
from pampipe.planning import plan_mission
from tests.support.problems import PROBLEMS

UNCERTAIN = PROBLEMS / "missions" / "riser-uncertain-friction.yaml"


def test_exported_law_at_confidence_covers_the_sampled_plan_and_states_its_margin():
    mission = load_mission(UNCERTAIN)
    plan = plan_mission(mission, confidence=0.95)
    nominal = api.export_mission(UNCERTAIN)
    export = api.export_mission(UNCERTAIN, confidence=0.95)
    margins = export.law.margins
    route = mission.route
    tight = []
    for s in range(len(route)):
        _, base = nominal.law.evaluate(route.diameter[s], route.incline[s], route.friction[s],
                                       mission.payload)
        reason, law = export.law.evaluate(route.diameter[s], route.incline[s], route.friction[s],
                                          mission.payload)
        assert int(reason) == 0
        np.testing.assert_allclose(law - base, margins, rtol=1e-12)
        assert np.all(law >= plan.arrays.pressure[s] * (1 - 1e-9))  # at least the sampled plan
        tight.append(law - plan.arrays.pressure[s])
    assert np.min(np.abs(tight)) == pytest.approx(0.0, abs=1e-6)  # and no more where it binds
    header = export.files["pampipe_plan.h"]
    assert "CONFIDENCE 0.95" in header and f"+{margins[0] / 1e3:.4g} kPa" in header
    assert export.to_dict()["confidence"]["level"] == 0.95
    assert "CONFIDENCE" not in nominal.files["pampipe_plan.h"] and nominal.to_dict()["confidence"] is None
