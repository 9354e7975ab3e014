"""A long route's alike sections are evaluated once (pampipe.runtime.alike, issue 39): the elements and the
plan against evaluating every section."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from pampipe.io.mission_schema import load_mission
from pampipe.planning import plan_mission
from pampipe.planning.problem import build_elements, mission_muscles
from pampipe.runtime import alike
from pampipe.specs.mission import Route, Section
from tests.support.mixed_route import mixed_kinds
from tests.support.problems import PROBLEMS

REPORT = ("length", "volume", "free_anchoring", "largest_bore_anchoring")
FIELDS = ("diameter", "diameter_high", "load", "load_per_payload", "friction", "anchoring", "least_pressure",
          "valid", *REPORT)


@pytest.fixture(scope="module")
def repeated():
    """The demo robot on 23 sections repeated 20 times in a shuffled order: bores with and without a
    tolerance, three outside the model (narrow, wide, frictionless), some beyond a 160 kPa supply."""
    demo = load_mission(PROBLEMS / "missions" / "vertical-climb-3in.yaml")
    rng = np.random.default_rng(7)
    d, incline, friction = mixed_kinds(rng)
    tolerance = np.where(np.arange(23) % 3 == 0, 1e-3, 0.0)
    kinds = [Section(f"k{k}", 1.0, d[k], incline[k], friction[k], 0.0, d[k] - tolerance[k],
                     d[k] + tolerance[k]) for k in range(23)]
    order = rng.permutation(np.repeat(np.arange(23), 20))
    route = Route.from_sections(dataclasses.replace(kinds[k], name=f"s{i}", length=1.0 + i % 7)
                                for i, k in enumerate(order.tolist()))
    return dataclasses.replace(demo, route=route, supply_pressure=160e3)


def test_alike_sections_give_the_elements_of_every_section(repeated, monkeypatch):
    """The same floats in every element array as evaluating each section, a segment's column contiguous
    as before; the whole plan's arrays too."""
    muscles = mission_muscles(repeated)
    grouped, grouped_plan = build_elements(repeated, muscles), plan_mission(repeated, with_max_payload=True)
    monkeypatch.setattr(alike, "LEAST", 10**9)
    whole, whole_plan = build_elements(repeated, muscles), plan_mission(repeated, with_max_payload=True)
    assert not whole.valid.all() and whole.valid.any()
    for name in FIELDS:
        a, b = getattr(grouped, name), getattr(whole, name)
        assert np.array_equal(a, b, equal_nan=True), name
        assert a.T.flags.c_contiguous == b.T.flags.c_contiguous, name
    for field in dataclasses.fields(grouped_plan.arrays):
        a, b = getattr(grouped_plan.arrays, field.name), getattr(whole_plan.arrays, field.name)
        if isinstance(a, np.ndarray):
            assert np.array_equal(a, b, equal_nan=True), field.name
    assert grouped_plan.arrays.reasons == whole_plan.arrays.reasons
    assert grouped_plan.checks == whole_plan.checks and grouped_plan.warnings == whole_plan.warnings
    assert grouped_plan.max_payload.as_document() == whole_plan.max_payload.as_document()
    assert grouped.alike is not None and whole.alike is None
