"""The largest payload the robot carries through each section, and the route, at supply pressure.

The anchor load is affine in the payload m: W(m) = W(m₀) + (m − m₀)·g(|sin φ| + μ cos φ), and each
element holds at most W_max(P_supply) (:meth:`pampipe.model.muscle.Muscle.largest_load`), so the
largest payload of an element is m₀ + (W_max − W(m₀)) / (g(|sin φ| + μ cos φ)); a section takes the
least of its segments, the route the least of its sections.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

from pampipe.planning.feasibility import pressure_limits
from pampipe.planning.problem import Elements, build_elements, mission_muscles


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
    """Largest payload [kg] through the whole route at supply pressure, and where it binds.

    ``section_payloads`` and ``limiting_segments`` hold every section's limit as arrays;
    ``sections`` are built from them on first use.
    """

    payload: float | None  # None: not even the empty robot gets through
    section: str
    segment: str
    supply_pressure: float  # [Pa]
    section_payloads: np.ndarray = field(repr=False)  # (S,) [kg], −inf where the pipe is impassable
    limiting_segments: np.ndarray = field(repr=False)  # (S,) index of the limiting segment
    route: tuple = field(repr=False)  # the mission's sections
    segment_names: tuple[str, ...] = field(repr=False)

    @cached_property
    def sections(self) -> tuple[SectionPayload, ...]:
        """One SectionPayload per route section."""
        return tuple(SectionPayload(sec.name, p, self.segment_names[i]) for sec, p, i in zip(
            self.route, self.section_payloads.tolist(), self.limiting_segments.tolist(), strict=True))

    def as_document(self) -> dict:
        return {"max_payload_kg": self.payload, "limiting_section": self.section,
                "limiting_segment": self.segment, "supply_pressure_Pa": self.supply_pressure,
                "sections": [{"name": s.name, "limiting_segment": s.segment,
                              "max_payload_kg": s.payload if np.isfinite(s.payload) else None}
                             for s in self.sections]}


def element_payloads(mission, muscles, elements: Elements) -> np.ndarray:
    """Largest payload [kg] of every element at its pressure limit (the supply, or the muscle's rated
    ``max_pressure`` when lower), shape (S, segments)."""
    e = elements
    limits = pressure_limits(mission)
    def largest(muscle, limit):  # W_max of each distinct section, once
        return lambda d, mu: muscle.largest_load(limit, d, kappa=e.kappa, friction=mu,
                                                 safety_factor=e.safety_factor)

    held = np.stack([e.per_section(largest(m, limits[i]), e.diameter[:, i], e.friction[:, i])
                     for i, m in enumerate(muscles)], axis=1)
    usable = e.valid & np.isfinite(e.free_anchoring) & (held >= 0)
    per_kg = np.where(usable, e.load_per_payload, 1.0)  # > 0 where valid (μ > 0)
    payload = mission.payload + (held - e.load) / per_kg
    return np.where(usable, payload, -np.inf)


def payload_limit(mission, payloads: np.ndarray) -> PayloadLimit:
    """The route's largest payload from its element payloads (:func:`element_payloads`): the least per
    section, then the least section.
    """
    worst = np.argmin(payloads, axis=1)
    per_section = payloads[np.arange(payloads.shape[0]), worst]
    s = int(np.argmin(per_section))
    value = float(per_section[s])
    names = tuple(seg.name for seg in mission.segments)
    return PayloadLimit(value if value >= 0 else None, mission.route[s].name, names[worst[s]],
                        mission.supply_pressure, per_section, worst, mission.route, names)


def max_payload(mission) -> PayloadLimit:
    """Largest payload [kg] the robot can carry through the whole route at supply pressure."""
    muscles = mission_muscles(mission)
    return payload_limit(mission, element_payloads(mission, muscles, build_elements(mission, muscles)))
