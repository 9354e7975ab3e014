"""`plan --json` of a long route writes its sections and reducers column-wise (MissionPlan.section_columns,
reducer_columns, pampipe.io.json_columns): the same text as each section's and reducer's document through
the JSON writer, on bundled missions of every kind (a network route, a tether, infeasible sections,
elbows)."""

from __future__ import annotations

import dataclasses
import json
from itertools import islice
from pathlib import Path

import numpy as np
import pytest

from pampipe import api
from pampipe.errors import SolverError
from pampipe.io.files import Streamed, json_chunks, to_json
from pampipe.io.json_columns import streamed_records
from pampipe.runtime.alike import Picked

MISSIONS = Path(__file__).resolve().parents[2] / "problems" / "missions"


def _streamed(plan, chunk):
    sections = streamed_records(len(plan.arrays.route), plan.section_columns,
                                lambda a, b: islice(plan.section_documents(), a, b), chunk=chunk)
    reducers = streamed_records(len(plan.reducers), plan.reducer_columns,
                                lambda a, b: (r.as_document() for r in plan.reducers[a:b]), chunk=chunk)
    return "".join(json_chunks(plan.as_document(sections=Streamed(sections), reducers=Streamed(reducers))))


@pytest.mark.parametrize("name", ["vertical-climb-3in", "ky4-route", "tethered-climb", "infeasible-survey",
                                  "elbows-3in", "steel-pipe-sizes"])
def test_columns_write_the_documents_bytes(name):
    plan = api.plan(api.load_mission(MISSIONS / f"{name}.yaml"))
    assert _streamed(plan, chunk=3) == to_json(plan.to_dict(), indent=None)


def test_a_nan_falls_back_to_the_documents_and_names_its_path():
    plan = api.plan(api.load_mission(MISSIONS / "vertical-climb-3in.yaml"))
    pressure = plan.arrays.pressure.copy()
    pressure[-1, 0] = np.nan
    broken = dataclasses.replace(plan, arrays=dataclasses.replace(plan.arrays, pressure=pressure))
    last = len(plan.arrays.route) - 1
    with pytest.raises(SolverError, match=rf"result\.sections\[{last}\]\.segments\[0\]\.pressure_Pa"):
        _streamed(broken, chunk=1)


def test_the_reducers_columns_are_their_documents():
    plan = api.plan(api.load_mission(MISSIONS / "steel-pipe-sizes.yaml"))
    assert plan.reducers, "this mission changes bore"
    columns, nested = plan.reducer_columns(0, len(plan.reducers))
    assert nested == {}
    for i, reducer in enumerate(plan.reducers):
        row = {key: value.values[value.index[i]] if isinstance(value, Picked) else value[i]
               for key, value in columns.items()}
        assert row == pytest.approx(reducer.as_document())
    assert json.loads(_streamed(plan, chunk=2))["reducers"] == json.loads(to_json(plan.to_dict()))["reducers"]


def _confident():
    mission = api.load_mission(MISSIONS / "riser-uncertain-friction.yaml")
    return api.plan(mission, confidence=0.95, samples=400, seed=3)


def test_confidence_columns_write_the_documents_bytes():
    plan = _confident()
    assert plan.section_columns(0, len(plan.arrays.route)) is not None  # column-wise, not the documents
    assert _streamed(plan, chunk=2) == to_json(plan.to_dict(), indent=None)


@pytest.mark.parametrize("change", ["stopped", "undetermined shift", "no pressure holds"])
def test_confidence_segments_unlike_the_others_are_their_documents(change):
    plan = _confident()
    u = plan.uncertainty
    shape = u.holding_probability.shape
    if change == "stopped":
        stopped = np.zeros(shape, bool)
        stopped[-1, 1] = True
        u = dataclasses.replace(u, stopped=stopped)
    elif change == "undetermined shift":
        shift = np.full(shape, np.nan)
        shift[0, 0] = 1234.5
        u = dataclasses.replace(u, open_shift=shift)
    else:
        ci = u.pressure_ci95.copy()
        ci[0, 2, 1] = np.inf
        u = dataclasses.replace(u, pressure_ci95=ci)
    changed = dataclasses.replace(plan, uncertainty=u)
    rows = len(plan.arrays.route)
    assert changed.section_columns(0, rows) is None or change == "no pressure holds"
    text = _streamed(changed, chunk=1)
    assert text == to_json(changed.to_dict(), indent=None)
    assert {"stopped": '"pressure_Pa": null', "undetermined shift": '"undetermined_shift_Pa": 1234.5',
            "no pressure holds": ', null]'}[change] in text
