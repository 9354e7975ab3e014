"""`plan_mission`: the least anchoring pressure of every segment in every section of a route."""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from pampipe.bends.plan import plan_bends
from pampipe.errors import InputError, SolverError
from pampipe.planning.checks import cross_check
from pampipe.planning.contact import contact_costs
from pampipe.planning.feasibility import plan_feasible, section_reasons, undetermined_reasons
from pampipe.planning.payload import element_payloads, payload_limit
from pampipe.planning.problem import Elements, build_elements, mission_muscles
from pampipe.planning.reach import plan_tether
from pampipe.planning.result import MissionPlan, PlanArrays
from pampipe.planning.solve import Solution, solve
from pampipe.planning.warnings import plan_warnings, route_coverage

#: Largest accepted relative disagreement between the NLP and its cross-check.
CHECK_TOLERANCE = 1e-6


def plan_mission(mission, *, payload: float | None = None, confidence: float | None = None,
                 method: str = "kkt", check: bool = True, with_max_payload: bool = False,
                 samples: int | None = None, seed: int | None = None, prior=None,
                 workers: int | None = None, scheduler: str | None = None) -> MissionPlan:
    """Plan ``mission`` (a :class:`pampipe.specs.mission.Mission`); ``payload`` [kg] overrides its payload.

    ``confidence`` C ∈ [0.5, 1) plans the pressure that holds with probability C, from ``samples``
    seeded draws (``seed``) of every uncertain input (:mod:`pampipe.planning.confidence`, imported only
    then: its executors and sampling cost a plain plan's start-up; None: its ``DEFAULT_SAMPLES`` and
    ``DEFAULT_SEED``); ``prior`` is a
    :class:`~pampipe.model.pam.Pam` whose uncertainty serves as prior along undetermined directions;
    ``workers``/``scheduler``: where the sampling runs (:mod:`pampipe.runtime.executors`; the same result).
    ``check`` compares the NLP's pressures with a bisection on the model (:mod:`pampipe.planning.checks`)
    and raises :class:`SolverError` beyond a relative 1e-6.
    """
    muscles = mission_muscles(mission)
    if payload is not None:
        if not (math.isfinite(payload) and payload >= 0):
            raise InputError(f"payload: {payload!r} kg must be a finite mass of at least 0 kg.")
        mission = dataclasses.replace(mission, payload=float(payload))
    elements = build_elements(mission, muscles)
    solution = solve(muscles, elements, mission.supply_pressure, method=method)
    checks = {}
    if check:
        checks = cross_check(muscles, elements, solution.pressure, mission.supply_pressure)
        worst = checks["bisection_max_rel_diff"] or 0.0
        if worst > CHECK_TOLERANCE:
            raise SolverError(f"the planning NLP disagrees with its cross-check by {worst:.3g} "
                              f"(relative): {checks}", status="cross_check_failed")
    nominal = sampled = None
    if confidence is not None:
        from pampipe.planning.confidence import DEFAULT_SAMPLES, DEFAULT_SEED, plan_confidence

        samples = DEFAULT_SAMPLES if samples is None else samples
        seed = DEFAULT_SEED if seed is None else seed
        nominal = solution.pressure
        sampled = plan_confidence(mission, muscles, elements, confidence, samples=samples, seed=seed,
                                  prior=prior, with_payload=with_max_payload, workers=workers,
                                  scheduler=scheduler)
        pressure = np.where(elements.valid, sampled.pressure, nominal)
        solution = dataclasses.replace(solution, pressure=pressure,
                                       slip_active=solution.slip_active | (pressure > nominal))
    payloads = element_payloads(mission, muscles, elements) if sampled is None or sampled.payload is None \
        else sampled.payload
    reasons, codes = section_reasons(mission, muscles, elements, solution, payloads, confidence=confidence)
    if sampled is not None:
        undetermined_reasons(mission, sampled, reasons, codes)
    arrays = _arrays(mission, muscles, elements, solution, reasons, codes, nominal, sampled)
    limit = payload_limit(mission, payloads) if with_max_payload else None
    served = None if mission.route.origin is None else route_coverage(mission.route, codes)
    bends, reducers = plan_bends(mission)
    tether = None if mission.tether is None else plan_tether(mission, muscles, arrays, bends)
    return MissionPlan(feasible=not reasons and all(b.passable for b in bends)
                       and (tether is None or tether.reason() is None), arrays=arrays,
                       mission=str(mission.source), supply_pressure=mission.supply_pressure,
                       safety_factor=mission.safety_factor, load_path=mission.load_path,
                       payload=mission.payload, method=solution.method, iterations=solution.iterations,
                       checks=checks, confidence=confidence, max_payload=limit, muscles=muscles,
                       kappa=elements.kappa, warnings=plan_warnings(mission, arrays, confidence),
                       coverage=served, bends=bends, reducers=reducers, uncertainty=sampled, tether=tether)


def _arrays(mission, muscles, e: Elements, solution: Solution, reasons, codes, nominal,
            sampled) -> PlanArrays:
    pressure = np.where(np.isfinite(solution.pressure) & e.valid, solution.pressure, 0.0)
    capacity, radial, contact = (np.stack(c, axis=1) for c in zip(*(
        _evaluate(m, e, pressure[:, i], i) for i, m in enumerate(muscles)), strict=True))
    complete = e.valid.all(axis=1) & np.isfinite(solution.pressure).all(axis=1)
    return PlanArrays(
        pressure=solution.pressure, anchoring_pressure=e.free_anchoring,
        loaded_anchoring_pressure=e.anchoring,
        required_hold=e.load, holding_capacity=capacity, radial_force=radial, contact_pressure=contact,
        air_volume=e.volume, anchored_length=e.length, slip_active=solution.slip_active,
        feasible=plan_feasible(mission, e, solution) & _determined(sampled, e.valid.shape),
        complete=complete,
        nominal_pressure=nominal, segment_names=tuple(seg.name for seg in mission.segments),
        route=mission.route, reasons=reasons, diameter=np.array(e.diameter),
        largest_bore_anchoring=np.where(e.valid, e.largest_bore_anchoring, np.nan), reason_codes=codes,
        contact_cost=contact_costs(muscles, e))


def _evaluate(muscle, e: Elements, pressure: np.ndarray, i: int):
    """(holding capacity, F_r, p_c) of segment i in every section, from its muscle at the plan (once per
    distinct section of a long route, :meth:`Elements.per_section`)."""
    def evaluate(pressure, d, load, friction):
        radial = np.asarray(muscle.radial_force(pressure, d, e.kappa * load), dtype=float) * np.ones_like(d)
        return friction * np.pi * radial, radial, muscle.contact_pressure(radial, d)

    return e.per_section(evaluate, pressure, e.diameter[:, i], e.load[:, i], e.friction[:, i])


def _determined(sampled, shape) -> np.ndarray:
    """False where an undetermined direction stops the element (``sampled``: the confidence plan, or None)."""
    if sampled is None or sampled.stopped is None:
        return np.ones(shape, dtype=bool)
    return ~sampled.stopped
