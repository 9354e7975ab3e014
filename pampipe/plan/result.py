"""Frozen results of `plan`, and their JSON document (docs/commands.md §6 `plan`). SI units inside."""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from functools import cached_property

import numpy as np

from pampipe.plan.payload import PayloadLimit


@dataclass(frozen=True)
class SegmentPlan:
    """One segment anchored alone in one section.

    ``pressure`` is the least pressure that holds (for an infeasible element: the pressure it would
    need); ``anchoring_pressure`` the pressure at which the unloaded muscle touches the wall;
    ``required_hold`` the axial load W it must hold, before the safety factor; ``holding_capacity``
    μπF_r at ``pressure`` under that load; ``radial_force`` F_r; ``contact_pressure`` F_r/(D L).
    """

    name: str
    pressure: float  # [Pa]
    anchoring_pressure: float  # [Pa], P_a(D_p, 0)
    required_hold: float  # [N]
    holding_capacity: float  # [N]
    radial_force: float  # [N]
    contact_pressure: float  # [Pa]
    loaded_anchoring_pressure: float = math.nan  # [Pa], P_a(D_p, κW): the contact bound
    air_volume: float = math.nan  # [m³], V at the anchored length
    binding: str = "no_slip"  # which constraint sets the pressure: "no_slip" | "contact"
    feasible: bool = True
    nominal_pressure: float | None = None  # [Pa], the plan without uncertainty (with --confidence)

    @property
    def margin(self) -> float:
        """holding_capacity / required_hold [-]: equals the safety factor where no slip binds."""
        return self.holding_capacity / self.required_hold if self.required_hold > 0 else math.inf

    def as_document(self) -> dict:
        doc = {"name": self.name, "pressure_Pa": self.pressure,
               "anchoring_pressure_Pa": self.anchoring_pressure,
               "required_hold_N": self.required_hold, "holding_capacity_N": self.holding_capacity,
               "radial_force_N": self.radial_force, "contact_pressure_Pa": self.contact_pressure,
               "loaded_anchoring_pressure_Pa": self.loaded_anchoring_pressure,
               "air_volume_m3": self.air_volume, "margin": self.margin, "binding": self.binding,
               "feasible": self.feasible}
        if self.nominal_pressure is not None:
            doc["nominal_pressure_Pa"] = self.nominal_pressure
        return doc


@dataclass(frozen=True)
class SectionPlan:
    """The plan of one route section: feasible with its segments, or a reason in words."""

    name: str
    feasible: bool
    reason: str | None
    segments: tuple[SegmentPlan, ...]  # empty where the pipe itself is impassable
    length: float  # [m]
    diameter: float  # [m]
    incline: float  # [rad]
    friction: float  # [-]

    def as_document(self) -> dict:
        return {"name": self.name, "feasible": self.feasible, "reason": self.reason,
                "length_m": self.length, "inner_diameter_m": self.diameter, "incline_rad": self.incline,
                "friction": self.friction, "segments": [s.as_document() for s in self.segments]}


@dataclass(frozen=True)
class PlanArrays:
    """The whole plan as (sections, segments) arrays [SI], for long routes and vectorised use.

    ``complete[s]`` is False where the pipe itself is impassable (no per-segment numbers).
    """

    pressure: np.ndarray  # [Pa]
    anchoring_pressure: np.ndarray  # [Pa], unloaded
    loaded_anchoring_pressure: np.ndarray  # [Pa]
    required_hold: np.ndarray  # [N]
    holding_capacity: np.ndarray  # [N]
    radial_force: np.ndarray  # [N]
    contact_pressure: np.ndarray  # [Pa]
    air_volume: np.ndarray  # [m³]
    anchored_length: np.ndarray  # [m], L(D_p)
    slip_active: np.ndarray  # bool
    feasible: np.ndarray  # bool
    complete: np.ndarray  # bool, per section
    nominal_pressure: np.ndarray | None  # [Pa], with --confidence
    segment_names: tuple[str, ...]
    route: tuple  # the mission's Section objects
    reasons: dict[int, str]  # {section index: why it cannot be planned}, infeasible sections only


@dataclass(frozen=True)
class MissionPlan:
    """The anchoring pressures of a whole mission; ``feasible`` only if every section is.

    ``sections`` (SectionPlan objects) are built on first use from ``arrays``.
    """

    feasible: bool
    arrays: PlanArrays = field(repr=False)
    mission: str  # source file
    supply_pressure: float  # [Pa]
    safety_factor: float
    load_path: str
    payload: float  # [kg]
    method: str  # "kkt" | "ipopt"
    iterations: int
    checks: dict = field(default_factory=dict)  # largest relative differences to the cross-checks
    confidence: float | None = None
    max_payload: PayloadLimit | None = None
    muscles: tuple = field(default=(), repr=False)  # the segments' Muscle objects, rear to front
    kappa: float = 1.0  # κ of the load path
    wall_time: float = 0.0  # [s] from reading the mission to the plan (set by the API)

    def timed(self, wall_time: float) -> MissionPlan:
        """A copy that reports ``wall_time`` [s]."""
        return replace(self, wall_time=wall_time)

    def to_dict(self) -> dict:
        """The `plan --json` document (docs/commands.md §6)."""
        return self.as_document()

    def capacity_curve(self, section: int, segment: int, pressures) -> np.ndarray:
        """μπF_r(P, D, κW) [N] of one segment in one section over ``pressures``, from the plan's muscle."""
        sec = self.arrays.route[section]
        load = self.arrays.required_hold[section, segment]
        capacity = self.muscles[segment].holding_capacity(np.asarray(pressures, dtype=float), sec.diameter,
                                                          load, kappa=self.kappa, friction=sec.friction)
        return np.asarray(capacity, dtype=float) * np.ones(np.shape(pressures))

    @cached_property
    def sections(self) -> tuple[SectionPlan, ...]:
        """One SectionPlan per route section, in travel order."""
        a = self.arrays
        columns = [x.tolist() for x in (a.pressure, a.anchoring_pressure, a.required_hold, a.holding_capacity,
                                        a.radial_force, a.contact_pressure, a.loaded_anchoring_pressure,
                                        a.air_volume, a.slip_active, a.feasible)]
        nominal = None if a.nominal_pressure is None else a.nominal_pressure.tolist()
        out = []
        for s, (sec, complete) in enumerate(zip(a.route, a.complete.tolist(), strict=True)):
            reason = a.reasons.get(s)
            segments = ()
            if complete:
                p, pa, w, cap, fr, pc, pl, vol, active, ok = (c[s] for c in columns)
                segments = tuple(
                    SegmentPlan(name, p[i], pa[i], w[i], cap[i], fr[i], pc[i],
                                loaded_anchoring_pressure=pl[i], air_volume=vol[i],
                                binding="no_slip" if active[i] else "contact", feasible=ok[i],
                                nominal_pressure=None if nominal is None else nominal[s][i])
                    for i, name in enumerate(a.segment_names))
            out.append(SectionPlan(sec.name, reason is None, reason, segments, sec.length, sec.diameter,
                                   sec.incline, sec.friction))
        return tuple(out)

    @property
    def reasons(self) -> list[str]:
        """'section: reason' for every infeasible section."""
        return [f"{self.arrays.route[s].name}: {r}" for s, r in sorted(self.arrays.reasons.items())]

    def as_document(self) -> dict:
        doc = {"feasible": self.feasible, "sections": [s.as_document() for s in self.sections],
               "mission": self.mission, "supply_pressure_Pa": self.supply_pressure,
               "safety_factor": self.safety_factor, "load_path": self.load_path,
               "payload_kg": self.payload, "confidence": self.confidence,
               "solver": {"method": self.method, "iterations": self.iterations, **self.checks,
                          "wall_time_s": self.wall_time}}
        if self.max_payload is not None:
            doc["max_payload"] = self.max_payload.as_document()
        return doc
