"""`plan_mission`: the least anchoring pressure of every segment in every section of a route."""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from pampipe.errors import InputError, SolverError
from pampipe.model import forces, slip
from pampipe.plan import diagnosed
from pampipe.plan.checks import cross_check
from pampipe.plan.confidence import confidence_pressure
from pampipe.plan.feasibility import element_feasible, section_reasons
from pampipe.plan.payload import element_payloads
from pampipe.plan.payload import max_payload as route_max_payload
from pampipe.plan.problem import Elements, build_elements
from pampipe.plan.result import MissionPlan, PlanArrays
from pampipe.plan.solve import Solution, solve
from pampipe.simulate import require_moduli

#: Largest accepted relative disagreement between the NLP and its cross-checks.
CHECK_TOLERANCE = 1e-6


def plan_mission(mission, *, payload: float | None = None, confidence: float | None = None,
                 method: str = "kkt", check: bool = True, with_max_payload: bool = False) -> MissionPlan:
    """Plan ``mission`` (a :class:`pampipe.mission.Mission`); ``payload`` [kg] overrides its payload.

    ``confidence`` C ∈ [0.5, 1) plans the pressure that holds with probability C (first order, see
    :mod:`pampipe.plan.confidence`). ``check`` compares the NLP's pressures with the closed form and
    a bisection on the model and raises :class:`SolverError` beyond a relative 1e-6.
    """
    for i, seg in enumerate(mission.segments):
        require_moduli(seg.pam, source=f"{mission.source}: robot.segments[{i}].pam")
    if payload is not None:
        if not (math.isfinite(payload) and payload >= 0):
            raise InputError(f"payload: {payload!r} kg must be a finite mass of at least 0 kg.")
        mission = dataclasses.replace(mission, payload=float(payload))
    elements = build_elements(mission)
    solution = solve(elements, mission.supply_pressure, method=method)
    checks = {}
    if check:
        checks = cross_check(mission, elements, solution.pressure)
        worst = max((v for v in checks.values() if v is not None), default=0.0)
        if worst > CHECK_TOLERANCE:
            raise SolverError(f"the planning NLP disagrees with its cross-checks by {worst:.3g} "
                              f"(relative): {checks}", status="cross_check_failed")
    effect_segments = diagnosed.diagnosed_segments(mission)
    if effect_segments:  # the NLP was checked on the baseline model; now the diagnosed one
        pressure = solution.pressure.copy()
        for i in effect_segments:
            pressure[:, i] = np.where(elements.valid[:, i], diagnosed.least_pressure(mission, i, elements),
                                      solution.pressure[:, i])
        solution = dataclasses.replace(solution, pressure=pressure)
    nominal = None
    if confidence is not None:
        nominal = solution.pressure
        pressure = confidence_pressure(mission, nominal, confidence)
        solution = dataclasses.replace(solution, pressure=pressure,
                                       slip_active=solution.slip_active | (pressure > nominal))
    payloads = element_payloads(mission, elements)
    reasons = section_reasons(mission, elements, solution, payloads, confidence=confidence)
    arrays = _arrays(mission, elements, solution, reasons, nominal)
    limit = route_max_payload(mission) if with_max_payload else None
    return MissionPlan(feasible=all(r is None for r in reasons), arrays=arrays,
                       mission=str(mission.source), supply_pressure=mission.supply_pressure,
                       safety_factor=mission.safety_factor, load_path=mission.load_path,
                       payload=mission.payload, method=solution.method, iterations=solution.iterations,
                       checks=checks, confidence=confidence, max_payload=limit)


def _arrays(mission, e: Elements, solution: Solution, reasons, nominal) -> PlanArrays:
    capacity, radial, contact = (np.stack(c, axis=1) for c in zip(
        *(_evaluate(mission, e, solution.pressure, i) for i in range(len(mission.segments))), strict=True))
    complete = e.valid.all(axis=1) & np.isfinite(solution.pressure).all(axis=1)
    return PlanArrays(
        pressure=solution.pressure, anchoring_pressure=e.free_anchoring,
        loaded_anchoring_pressure=e.anchoring,
        required_hold=e.load, holding_capacity=capacity, radial_force=radial, contact_pressure=contact,
        air_volume=e.volume, slip_active=solution.slip_active,
        feasible=element_feasible(e, solution, mission.supply_pressure), complete=complete,
        nominal_pressure=nominal, segment_names=tuple(seg.name for seg in mission.segments),
        route=mission.route, reasons=tuple(reasons))


def _evaluate(mission, e: Elements, pressure: np.ndarray, i: int):
    """(holding capacity, F_r, p_c) of segment i in every section, from the model at the plan."""
    m = mission.segments[i].pam.moduli
    geometry, theta, pref = mission.segments[i].pam.geometry, m.as_vector(), m.reference_pressure
    contact = m.contact_vector() if np.any(m.contact_vector()) else None
    p = np.where(np.isfinite(pressure[:, i]) & e.valid[:, i], pressure[:, i], 0.0)
    d = np.where(e.valid[:, i], e.diameter[:, i], 0.5 * (geometry.initial_diameter
                                                         + geometry.largest_diameter))
    load = e.load[:, i]
    if mission.segments[i].pam.effects:
        radial = diagnosed.radial_force(mission, i, p, d, mission.kappa * load)
        capacity = e.friction[:, i] * math.pi * radial
        return capacity, radial, forces.contact_pressure(radial, d, e.length[:, i])
    radial = forces.radial_force(p, d, geometry, theta, pref, mission.kappa * load, contact)
    capacity = slip.holding_capacity(p, d, geometry, theta, pref, load, mission.kappa, e.friction[:, i],
                                     contact)
    return capacity, radial, forces.contact_pressure(radial, d, e.length[:, i])
