"""The largest payload the robot carries through each section, and the route, at supply pressure.

The anchor load is affine in the payload m: W(m) = W(m₀) + (m − m₀)·g(|sin φ| + μ cos φ), and each
element holds at most W_max(P_supply) (:meth:`pampipe.model.muscle.Muscle.largest_load`), so the
largest payload of an element is m₀ + (W_max − W(m₀)) / (g(|sin φ| + μ cos φ)); a section takes the
least of its segments, the route the least of its sections.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from pampipe.plan.problem import Elements, build_elements, mission_muscles


@dataclass(frozen=True)
class SectionPayload:
    """Largest payload [kg] through one section and the segment that limits it.

    ``payload`` is −inf where the pipe itself is impassable, and negative where the robot cannot
    even hold its own weight at supply pressure.
    """

    name: str
    payload: float
    segment: str


@dataclass(frozen=True)
class PayloadLimit:
    """Largest payload [kg] through the whole route at supply pressure, and where it binds."""

    payload: float | None  # None: not even the empty robot gets through
    section: str
    segment: str
    supply_pressure: float  # [Pa]
    sections: tuple[SectionPayload, ...]

    def as_document(self) -> dict:
        return {"max_payload_kg": self.payload, "limiting_section": self.section,
                "limiting_segment": self.segment, "supply_pressure_Pa": self.supply_pressure,
                "sections": [{"name": s.name, "max_payload_kg": s.payload, "limiting_segment": s.segment}
                             for s in self.sections]}


def element_payloads(mission, muscles, elements: Elements) -> np.ndarray:
    """Largest payload [kg] of every element at the mission's supply pressure, shape (S, segments)."""
    e = elements
    held = np.stack([m.largest_load(mission.supply_pressure, e.diameter[:, i], kappa=e.kappa,
                                    friction=e.friction[:, i], safety_factor=e.safety_factor)
                     for i, m in enumerate(muscles)], axis=1)
    usable = e.valid & np.isfinite(e.free_anchoring) & (held >= 0)
    per_kg = np.where(usable, e.load_per_payload, 1.0)  # > 0 where valid (μ > 0)
    payload = mission.payload + (held - e.load) / per_kg
    return np.where(usable, payload, -np.inf)


def section_payloads(mission, muscles, elements: Elements) -> tuple[SectionPayload, ...]:
    """Per section: the least element payload and its segment."""
    payloads = element_payloads(mission, muscles, elements)
    worst = np.argmin(payloads, axis=1)
    return tuple(SectionPayload(sec.name, float(payloads[s, worst[s]]), mission.segments[worst[s]].name)
                 for s, sec in enumerate(mission.route))


def max_payload(mission) -> PayloadLimit:
    """Largest payload [kg] the robot can carry through the whole route at supply pressure."""
    muscles = mission_muscles(mission)
    sections = section_payloads(mission, muscles, build_elements(mission, muscles))
    limit = min(sections, key=lambda s: s.payload)
    value = limit.payload if limit.payload >= 0 else None
    return PayloadLimit(value, limit.name, limit.segment, mission.supply_pressure, sections)
