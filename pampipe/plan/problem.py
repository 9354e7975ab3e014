"""The planning problem of one mission, as per-element arrays (docs/physics.md §5, §7, §8).

An *element* is one (section s, segment i) pair. The gait of docs/physics.md §8 anchors, in steps
I…VII, the segments {2}, {1,2}, {1}, {1,3}, {3}, {2,3}, {2}: every segment is the only anchor in
some step, so in every section each segment must hold the section's whole load alone.

* Load on the single anchor i in section s (incline φ, wall friction μ, M = segment masses + payload):
  W = g·(M·|sin φ| + μ·cos φ·(M − m_i)) + tether_drag  [N]  (:func:`pampipe.model.slip.incline_load`).
* No slip: μπF_r(P, D_s, κW) ≥ SF·W, asked of the segment's :class:`~pampipe.model.muscle.Muscle`.
* Contact: P ≥ max(P_a(κW), 0), the pressure at which the loaded muscle presses on the wall.
"""

from __future__ import annotations

from dataclasses import dataclass
from operator import attrgetter

import numpy as np

from pampipe.model.muscle import Muscle
from pampipe.model.slip import STANDARD_GRAVITY, incline_load


@dataclass(frozen=True)
class Elements:
    """Per-element arrays of shape (sections, segments), SI; invalid elements hold finite placeholders.

    Each array is the transposed view of a (segments, sections) block, so that a segment's column is
    contiguous; ``friction`` and ``load_per_payload``, equal for every segment, are broadcast views.
    """

    diameter: np.ndarray  # D_s [m] (a placeholder inside the muscle's range where invalid)
    length: np.ndarray  # anchored length L_p = L(D_s) [m]
    volume: np.ndarray  # V(L_p) = πD²L/4 [m³], the air the segment takes per pascal
    load: np.ndarray  # W [N], required hold
    load_per_payload: np.ndarray  # ∂W/∂payload = g(|sin φ| + μ cos φ) [N/kg]
    friction: np.ndarray  # μ [-]
    anchoring: np.ndarray  # P_a(κW) [Pa]: the loaded muscle reaches the wall
    free_anchoring: np.ndarray  # P_a(0) [Pa]: the unloaded muscle reaches the wall
    kappa: float  # κ of the load path
    safety_factor: float  # SF
    valid: np.ndarray  # inside the model's domain: D₀ < D < D(B/√3) and μ > 0
    anchored: tuple = ()  # per segment: its muscle's Muscle.affine_coefficients (None with effects)

    @property
    def lower_bound(self) -> np.ndarray:
        """Contact constraint as a bound: P ≥ max(P_a(κW), 0) [Pa]."""
        return np.maximum(self.anchoring, 0.0)


def mission_muscles(mission) -> tuple[Muscle, ...]:
    """The muscle of every segment, rear to front (InputError if a PAM has no moduli)."""
    return tuple(Muscle.from_pam(seg.pam, where=f"{mission.source}: robot.segments[{i}].pam")
                 for i, seg in enumerate(mission.segments))


def route_columns(route) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(diameter [m], incline [rad], friction) arrays of a route: a sequence of
    :class:`~pampipe.mission.Section`, or columns that carry those three arrays as attributes.
    """
    keys = ("diameter", "incline", "friction")
    if all(hasattr(route, key) for key in keys):
        return tuple(np.asarray(getattr(route, key), dtype=float) for key in keys)
    return tuple(np.fromiter(map(attrgetter(key), route), dtype=float, count=len(route)) for key in keys)


def build_elements(mission, muscles: tuple[Muscle, ...], *, payload: float | None = None,
                   route=None) -> Elements:
    """Evaluate the muscles once per element for ``mission`` (payload [kg] overrides the mission's;
    ``route``, columns as :func:`route_columns` reads them, overrides its route).

    Each muscle without effects is evaluated once per element (:meth:`Muscle.affine_coefficients`),
    and everything else follows from those coefficients; sin φ and cos φ are taken once per section.
    """
    payload = mission.payload if payload is None else float(payload)
    diameter, incline, friction = route_columns(mission.route if route is None else route)
    count, segments = diameter.shape[0], len(muscles)
    total_mass = sum(seg.mass for seg in mission.segments) + payload
    rise, run = np.abs(np.sin(incline)), np.cos(incline)
    per_kg = STANDARD_GRAVITY * (rise + friction * run)
    gripping = friction > 0
    blocks = {key: np.empty((segments, count)) for key in
              ("diameter", "length", "volume", "load", "anchoring", "free_anchoring")}
    valid = np.empty((segments, count), dtype=bool)
    anchored = []
    for i, (seg, muscle) in enumerate(zip(mission.segments, muscles, strict=True)):
        g = muscle.geometry
        inside = (diameter > g.initial_diameter) & (diameter < g.largest_diameter)
        np.logical_and(inside, gripping, out=valid[i])
        middle = 0.5 * (g.initial_diameter + g.largest_diameter)
        safe = diameter if valid[i].all() else np.where(valid[i], diameter, middle)
        load = incline_load(total_mass, seg.mass, rise, run, friction, mission.tether_drag)
        c = None if muscle.has_effects else muscle.affine_coefficients(safe)
        length = muscle.anchored_length(safe) if c is None else c.length
        blocks["diameter"][i], blocks["length"][i], blocks["load"][i] = safe, length, load
        blocks["volume"][i] = muscle.enclosed_volume(length)
        blocks["anchoring"][i] = muscle.anchoring_pressure(safe, mission.kappa * load, anchored=c)
        blocks["free_anchoring"][i] = muscle.anchoring_pressure(safe, 0.0, anchored=c)
        anchored.append(c)
    shared = {"friction": friction, "load_per_payload": per_kg}
    return Elements(**{key: block.T for key, block in blocks.items()},
                    **{key: np.broadcast_to(v[:, None], (count, segments)) for key, v in shared.items()},
                    kappa=mission.kappa, safety_factor=mission.safety_factor, valid=valid.T,
                    anchored=tuple(anchored))
