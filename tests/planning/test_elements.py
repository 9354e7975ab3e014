"""The plan's element table: built in chunks, from Section objects or columns, one muscle kind per segment."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from pampipe.io.mission_schema import load_mission
from pampipe.planning import plan_mission, problem
from pampipe.planning.problem import build_elements, mission_muscles
from pampipe.planning.solve import solve
from pampipe.specs.mission import Section
from tests.support.mixed_route import mixed_kinds
from tests.support.problems import PROBLEMS

FIELDS = ("diameter", "length", "volume", "load", "load_per_payload", "friction", "anchoring",
          "free_anchoring", "valid", "least_pressure")


@pytest.fixture(scope="module")
def mixed():
    """The demo robot with a baseline PAM1, contact increments on PAM2 and an axial preload on PAM3,
    on 23 sections: three outside the model (narrow, wide, frictionless) and, at a 160 kPa supply,
    eight more that cannot be crossed (the wall out of reach, or more than the supply needed)."""
    demo = load_mission(PROBLEMS / "missions" / "vertical-climb-3in.yaml")
    segments = list(demo.segments)
    moduli = segments[1].pam.moduli
    contact = moduli.as_vector() * 0.0 + np.r_[0.4e6, 0, 0, 0, 0, 0, 0, 0, 1.0e6, 0, 0, 0, 0, 0, 0, 0]
    segments[1] = dataclasses.replace(segments[1], pam=dataclasses.replace(
        segments[1].pam, moduli=dataclasses.replace(moduli, contact=tuple(contact))))
    segments[2] = dataclasses.replace(segments[2], pam=dataclasses.replace(
        segments[2].pam, effects={"axial_preload": {"preload": 50.0}}))
    rng = np.random.default_rng(7)
    diameters, incline, friction = mixed_kinds(rng)
    route = tuple(Section(f"s{k}", 1.0, d, phi, mu, 0.0)
                  for k, (d, phi, mu) in enumerate(zip(diameters, incline, friction, strict=True)))
    return dataclasses.replace(demo, segments=tuple(segments), route=route, supply_pressure=160e3)


def test_chunks_columns_and_objects_give_the_same_table(mixed, monkeypatch):
    """Chunks of 5 sections, the default chunk, and the route given as columns give identical
    elements and pressures: the work is element by element, so not even round-off may differ."""
    muscles = mission_muscles(mixed)
    whole = build_elements(mixed, muscles)
    reference = solve(muscles, whole, mixed.supply_pressure)
    columns = dataclasses.make_dataclass("Columns", ["diameter", "incline", "friction"])(
        *(np.array([getattr(s, k) for s in mixed.route]) for k in ("diameter", "incline", "friction")))
    monkeypatch.setattr(problem, "CHUNK", 5)
    for elements in (build_elements(mixed, muscles), build_elements(mixed, muscles, route=columns)):
        for name in FIELDS:
            assert np.array_equal(getattr(elements, name), getattr(whole, name), equal_nan=True), name
        again = solve(muscles, elements, mixed.supply_pressure)
        assert np.array_equal(again.pressure, reference.pressure)
        assert np.array_equal(again.slip_active, reference.slip_active)
    assert not whole.valid[[3, 9, 17]].any() and whole.valid[np.r_[0:3, 4:9]].all()
    assert np.isinf(reference.pressure[[3, 9, 17]]).all()


def test_each_element_equals_its_muscle_asked_alone(mixed):
    """Every valid element's pressure is what its Muscle answers for that one pipe (scalars, no table)."""
    muscles = mission_muscles(mixed)
    plan = plan_mission(mixed)
    total = sum(s.mass for s in mixed.segments) + mixed.payload
    for s, sec in enumerate(mixed.route):
        for i, (seg, muscle) in enumerate(zip(mixed.segments, muscles, strict=True)):
            if s in (3, 9, 17):
                continue
            load = 9.80665 * (total * abs(np.sin(sec.incline))
                              + sec.friction * np.cos(sec.incline) * (total - seg.mass))
            alone = float(muscle.least_holding_pressure(sec.diameter, load, kappa=mixed.kappa,
                                                        friction=sec.friction,
                                                        safety_factor=mixed.safety_factor))
            # the same formula on the same floats: the table may only differ by round-off (a few ulp)
            assert plan.arrays.pressure[s, i] == pytest.approx(alone, rel=1e-13), (s, i)
            assert plan.arrays.required_hold[s, i] == pytest.approx(load, rel=1e-13)


def test_reasons_only_for_the_sections_that_cannot_be_planned(mixed):
    plan = plan_mission(mixed)
    pressure = plan.arrays.pressure
    held = (np.isfinite(pressure) & (pressure <= mixed.supply_pressure)).all(axis=1)
    infeasible = set(np.flatnonzero(~held).tolist())
    assert set(plan.arrays.reasons) == infeasible and {3, 9, 17} < infeasible
    assert plan.feasible is False
    assert [sec.feasible for sec in plan.sections] == held.tolist()
    assert [r.split(":")[0] for r in plan.reasons] == [f"s{s}" for s in sorted(infeasible)]
