"""The planning problem of one mission, as per-element arrays (docs/physics.md §5, §7, §8).

An *element* is one (section s, segment i) pair. The gait of docs/physics.md §8 anchors, in steps
I…VII, the segments {2}, {1,2}, {1}, {1,3}, {3}, {2,3}, {2}: every segment is the only anchor in
some step, so in every section each segment must hold the section's whole load alone.

* Load on the single anchor i in section s (incline φ, wall friction μ, M = segment masses + payload):
  W = g·(M·|sin φ| + μ·cos φ·(M − m_i)) + tether_drag  [N]  (:func:`pampipe.model.slip.anchor_load`).
* No slip: μπF_r(P, D_s, κW) ≥ SF·W, asked of the segment's :class:`~pampipe.model.muscle.Muscle`.
* Contact: P ≥ max(P_a(κW), 0), the pressure at which the loaded muscle presses on the wall.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from pampipe.model.muscle import Muscle
from pampipe.model.slip import STANDARD_GRAVITY, anchor_load


@dataclass(frozen=True)
class Elements:
    """Per-element arrays of shape (sections, segments), SI; invalid elements hold finite placeholders."""

    diameter: np.ndarray  # D_s [m] (a placeholder inside the muscle's range where invalid)
    length: np.ndarray  # anchored length L_p = L(D_s) [m]
    amplification: np.ndarray  # A(D_s) [-]
    volume: np.ndarray  # V(L_p) = πD²L/4 [m³], the air the segment takes per pascal
    load: np.ndarray  # W [N], required hold
    load_per_payload: np.ndarray  # ∂W/∂payload = g(|sin φ| + μ cos φ) [N/kg]
    friction: np.ndarray  # μ [-]
    anchoring: np.ndarray  # P_a(κW) [Pa]: the loaded muscle reaches the wall
    free_anchoring: np.ndarray  # P_a(0) [Pa]: the unloaded muscle reaches the wall
    kappa: float  # κ of the load path
    safety_factor: float  # SF
    valid: np.ndarray  # inside the model's domain: D₀ < D < D(B/√3) and μ > 0

    @property
    def lower_bound(self) -> np.ndarray:
        """Contact constraint as a bound: P ≥ max(P_a(κW), 0) [Pa]."""
        return np.maximum(self.anchoring, 0.0)


def mission_muscles(mission) -> tuple[Muscle, ...]:
    """The muscle of every segment, rear to front (InputError if a PAM has no moduli)."""
    return tuple(Muscle.from_pam(seg.pam, where=f"{mission.source}: robot.segments[{i}].pam")
                 for i, seg in enumerate(mission.segments))


def build_elements(mission, muscles: tuple[Muscle, ...], *, payload: float | None = None) -> Elements:
    """Evaluate the muscles once per element for ``mission`` (payload [kg] overrides the mission's)."""
    payload = mission.payload if payload is None else float(payload)
    route = mission.route
    diameter = np.array([s.diameter for s in route], dtype=float)
    incline = np.array([s.incline for s in route], dtype=float)
    friction = np.array([s.friction for s in route], dtype=float)
    total_mass = sum(seg.mass for seg in mission.segments) + payload
    per_kg = STANDARD_GRAVITY * (np.abs(np.sin(incline)) + friction * np.cos(incline))
    columns = []
    for seg, muscle in zip(mission.segments, muscles, strict=True):
        g = muscle.geometry
        valid = (diameter > g.initial_diameter) & (diameter < g.largest_diameter) & (friction > 0)
        safe = np.where(valid, diameter, 0.5 * (g.initial_diameter + g.largest_diameter))
        length = muscle.anchored_length(safe)
        load = anchor_load(total_mass, seg.mass, incline, friction, mission.tether_drag) * np.ones_like(safe)
        columns.append({
            "diameter": safe, "length": length, "amplification": muscle.amplification_factor(safe),
            "volume": muscle.enclosed_volume(length), "load": load, "load_per_payload": per_kg,
            "friction": friction, "anchoring": muscle.anchoring_pressure(safe, mission.kappa * load),
            "free_anchoring": muscle.anchoring_pressure(safe, 0.0 * load), "valid": valid})
    stacked = {key: np.stack([np.broadcast_to(c[key], diameter.shape) for c in columns], axis=1)
               for key in columns[0]}
    return Elements(**stacked, kappa=mission.kappa, safety_factor=mission.safety_factor)
