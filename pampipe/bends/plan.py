"""Every bend and reducer of a route: can the robot pass it, and the steering command (docs/physics.md §14).

Per bend (the elbow at the end of a section): each segment, deflated, as a rigid cylinder L₀ + fittings
long and D₀ wide, in the bend's smallest bore (:func:`pampipe.bends.geometry.rigid_passage`); with
``bend_model: flexible`` a segment whose least bend radius fits the bend passes bent; the joints between
segments must allow the angle two neighbouring chords make; the steering module's least-pressure triad
(:func:`pampipe.bends.steering.steer`) toward the turn's direction (:mod:`pampipe.specs.turns`), for
bends of :data:`STEERING_LEAST_ANGLE` or more. Per reducer (a change of bore between sections): each segment
must fit the smaller bore.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from itertools import pairwise
from typing import NamedTuple

import numpy as np

from pampipe.bends.geometry import (
    chord_interval,
    elbow_radius_needed,
    flexible_bend_radius,
    rigid_passage,
)
from pampipe.bends.steering import SteeringCommand, steer
from pampipe.model.muscle import Muscle
from pampipe.runtime.alike import Picked
from pampipe.specs.turns import turn_name

#: Bends that turn by less than this [rad] get no steering command (docs/physics.md §14.4): 10°, below the
#: smallest standard elbow fitting (11.25°, a 1/32 bend) and above the deflection pipe joints are laid with
#: (up to 5° per push-on joint of 3–12 in ductile iron, AWWA C600), so the route curves gently over such a
#: joint; the nose of the leading segment meets the outer wall at that glancing angle and slides along it,
#: and the chain's joints take the deflection up within their play.
STEERING_LEAST_ANGLE = math.radians(10.0)


@dataclass(frozen=True)
class SegmentPassage:
    """One segment in one bend: its rigid length [m], the longest rigid length that passes [m] and where
    it binds; ``least_bend_radius`` [m] with the flexible model (else NaN)."""

    name: str
    length: float  # [m] L₀ + fittings
    diameter: float  # [m] D₀
    longest: float  # [m]
    where: str
    passable: bool
    flexible: bool = False  # passes only bent (bend_model: flexible, too long to pass rigid)
    least_bend_radius: float = math.nan  # [m]
    passes_bent: bool = False  # its least bend radius fits the bend (§14.3), whatever the bend_model

    @property
    def clearance(self) -> float:
        """longest − length [m]: negative by as much as the segment is too long."""
        return self.longest - self.length


@dataclass(frozen=True)
class BendPlan:
    """One bend: passability of every segment, the joints and the steering command."""

    index: int  # the section it ends
    after_section: str
    angle: float  # [rad]
    radius: float  # [m]
    bore: float  # [m] the smallest bore of the section it ends
    segments: tuple[SegmentPassage, ...]
    joint_angle: float  # [rad] the angle the joints must take
    joints_pass: bool
    steering: SteeringCommand | None
    radius_needed: float  # [m] least elbow radius at which the limiting segment passes (NaN if it does)
    steps: object | None = None  # pampipe.bends.gait.SteeringSteps of the gait through it
    direction: float = math.pi  # [rad] φ_b, the turn's centre in the steering module (pampipe.specs.turns)
    radius_assumed: bool = False  # the radius is elbow_radius's, not given for this bend

    @property
    def turn(self) -> str:
        """Which way the route turns, along travel: ``left``, ``down``, ``up-right``, …"""
        return turn_name(self.direction)

    @property
    def radius_text(self) -> str:
        """The radius as a multiple of the bore, ``"1.5 D"``, with ``" (assumed)"`` where no bend gave it."""
        return f"{self.radius / self.bore:.3g} D" + (" (assumed)" if self.radius_assumed else "")

    @property
    def steering_note(self) -> str | None:
        """Why a bend has no steering command (None where it has one or the robot has no module)."""
        if self.steering is None and self.angle < STEERING_LEAST_ANGLE:
            return (f"a turn below {math.degrees(STEERING_LEAST_ANGLE):g} deg needs no steering command: the "
                    "leading segment slides along the outer wall and the joints take it up within their play")
        return None

    @property
    def limiting(self) -> SegmentPassage:
        """The segment with the least clearance (a flexible pass counts as ample)."""
        return min(self.segments, key=lambda s: math.inf if s.flexible else s.clearance)

    @property
    def passable(self) -> bool:
        return all(s.passable for s in self.segments) and self.joints_pass

    @property
    def binding_chord(self) -> tuple[float, float]:
        """(τ_back, τ_front) [m]: where the limiting segment may lie in its binding, symmetric mid-bend
        position (ψ = 0), from the inner wall's tangent point
        (:func:`pampipe.bends.geometry.chord_interval`)."""
        s = self.limiting
        return chord_interval(0.0, bore=self.bore, radius=self.radius, angle=self.angle, diameter=s.diameter)

    def reason(self) -> str | None:
        """Why the robot cannot pass (None if it can): the bend, the segment, by how much, what would pass."""
        if self.passable:
            return None
        head = (f"bend after section '{self.after_section}' ({math.degrees(self.angle):.1f} deg {self.turn}, "
                f"radius {self.radius * 1e3:.4g} mm = {self.radius_text} in a {self.bore * 1e3:.4g} mm bore)")
        s = self.limiting
        if not s.passable:
            if s.where == "bore":
                return (f"{head}: segment {s.name} ({s.diameter * 1e3:.4g} mm wide) does not fit the bore.")
            fix = (f"the elbow radius would have to be at least {self.radius_needed * 1e3:.4g} mm "
                   f"({self.radius_needed / self.bore:.3g} D)" if math.isfinite(self.radius_needed)
                   else "no elbow radius up to 100 D passes it")
            return (f"{head}: segment {s.name}, rigid {s.length * 1e3:.4g} mm long and "
                    f"{s.diameter * 1e3:.4g} mm wide, is {-s.clearance * 1e3:.4g} mm too long (binding "
                    f"{s.where}); the longest that passes at {s.diameter * 1e3:.4g} mm wide is "
                    f"{s.longest * 1e3:.4g} mm, or {fix}.")
        return (f"{head}: the joints must turn {math.degrees(self.joint_angle):.1f} deg, more than robot."
                "joint_angle allows.")

    def as_document(self) -> dict:
        s = self.limiting
        flexible = s.flexible
        return {"after_section": self.after_section, "section_index": self.index,
                "angle_deg": math.degrees(self.angle), "radius_m": self.radius,
                "radius_assumed": self.radius_assumed, "direction_deg": math.degrees(self.direction),
                "turn": self.turn, "radius_over_bore": self.radius / self.bore, "inner_diameter_m": self.bore,
                "passable": self.passable, "reason": self.reason(), "limiting_segment": s.name,
                "longest_passable_length_m": None if flexible else _finite(s.longest),
                "clearance_m": None if flexible else _finite(s.clearance), "binding_position": s.where,
                "elbow_radius_needed_m": _finite(self.radius_needed),
                "joint_angle_deg": math.degrees(self.joint_angle), "joints_pass": self.joints_pass,
                "segments": [{"name": g.name, "rigid_length_m": g.length, "rest_diameter_m": g.diameter,
                              "longest_passable_length_m": _finite(g.longest),
                              "clearance_m": _finite(g.clearance),
                              "passable": g.passable, "passes_bent": g.passes_bent,
                              "least_bend_radius_m": _finite(g.least_bend_radius)} for g in self.segments],
                "steering": None if self.steering is None else self.steering.as_document(),
                "steering_note": self.steering_note,
                "gait": None if self.steps is None else self.steps.as_document()}


class ReducerPlan(NamedTuple):
    """A change of bore between two sections: the segments pass if they fit the smaller bore (a named
    tuple: a long route has one per section, built 4× faster than a frozen dataclass)."""

    after_section: str
    before: float  # [m] bore before
    after: float  # [m] bore after
    widest_segment: float  # [m] D₀ of the widest segment

    @property
    def passable(self) -> bool:
        return self.widest_segment < min(self.before, self.after)

    def as_document(self) -> dict:
        return {"after_section": self.after_section, "from_inner_diameter_m": self.before,
                "to_inner_diameter_m": self.after, "passable": self.passable,
                "reason": _reducer_reason(min(self.before, self.after), self.widest_segment)}


def _reducer_reason(small: float, widest: float) -> str:
    """Why a rigid segment D₀ = ``widest`` [m] passes a change of bore whose smaller bore is ``small`` [m]."""
    return (f"a rigid cylinder passes from one bore into the other if it fits the smaller "
            f"({small * 1e3:.4g} mm): the widest segment is {widest * 1e3:.4g} mm")


class Reducers(Sequence):
    """Every change of bore of a route, in travel order, as columns (a long route has one per section):
    ``after_section`` (names), the bores ``before`` and ``after`` [m] and the ``widest_segment``'s D₀ [m];
    ``reducers[i]`` is its :class:`ReducerPlan`, a slice is :class:`Reducers`."""

    def __init__(self, after_section: list[str], before: np.ndarray, after: np.ndarray,
                 widest_segment: float) -> None:
        self.after_section, self.before, self.after = after_section, before, after
        self.widest_segment = widest_segment

    def __len__(self) -> int:
        return len(self.after_section)

    def __getitem__(self, index):
        if isinstance(index, slice):
            return Reducers(self.after_section[index], self.before[index], self.after[index],
                            self.widest_segment)
        return ReducerPlan(self.after_section[index], float(self.before[index]), float(self.after[index]),
                           self.widest_segment)

    @property
    def passable(self) -> np.ndarray:
        """Per reducer: the widest segment fits the smaller bore."""
        return self.widest_segment < np.minimum(self.before, self.after)


def reducer_columns(reducers: Reducers) -> dict:
    """:meth:`ReducerPlan.as_document` of each of ``reducers`` as columns (key → one value per reducer), for
    a column-wise JSON writer; each distinct sentence is worded once."""
    if not reducers:
        return {}
    bores, index = np.unique(np.minimum(reducers.before, reducers.after), return_inverse=True)
    reasons = [_reducer_reason(bore, reducers.widest_segment) for bore in bores.tolist()]
    return {"after_section": reducers.after_section, "from_inner_diameter_m": reducers.before,
            "to_inner_diameter_m": reducers.after, "passable": reducers.passable,
            "reason": Picked(reasons, index.ravel())}


def _finite(value: float) -> float | None:
    return float(value) if math.isfinite(value) else None


def joint_angle(lengths, radius: float, angle: float) -> float:
    """The largest angle [rad] between neighbouring segments laid as chords of the bend's centreline:
    asin(L₁/2R) + asin(L₂/2R), at most θ (a chord longer than 2R spans the whole turn)."""
    def half(length):
        return math.asin(min(length / (2 * radius), 1.0))

    return min(max(half(a) + half(b) for a, b in pairwise(lengths)), angle)


def plan_bends(mission) -> tuple[tuple[BendPlan, ...], Reducers]:
    """Every bend and reducer of ``mission``'s route, in travel order."""
    route = mission.route
    widest = max(seg.pam.geometry.initial_diameter for seg in mission.segments)
    changes = np.flatnonzero(route.diameter[:-1] != route.diameter[1:])  # one pass over the columns
    reducers = Reducers(route.name[changes].tolist(), route.diameter[changes], route.diameter[changes + 1],
                        widest)
    if route.bend_angle is None:
        return (), reducers
    steering = mission.steering
    muscle = options = None
    if steering is not None:
        from pampipe.bends.gait import steering_steps  # locomotion imports planning, which imports this
        from pampipe.pneumatics.options import gait_options

        muscle = Muscle.from_pam(steering.pam, where=f"{mission.source}: robot.steering.pam")
        options = gait_options(mission.gait, source=mission.source)
    lengths = [seg.pam.rigid_length for seg in mission.segments]
    limit = mission.joint_angle
    assumed = route.bend_radius_assumed
    out = []
    for i in np.flatnonzero(route.bend_angle > 0).tolist():
        angle, radius = float(route.bend_angle[i]), float(route.bend_radius[i])
        bore = float(route.diameter_low[i])
        if i + 1 < len(route):
            bore = min(bore, float(route.diameter_low[i + 1]))
        segments = tuple(_segment(seg, bore, radius, angle, mission.bend_model) for seg in mission.segments)
        needed = math.nan
        worst = min(segments, key=lambda s: math.inf if s.flexible else s.clearance)  # BendPlan.limiting
        if not worst.passable and worst.where != "bore":
            needed = elbow_radius_needed(bore=bore, angle=angle, diameter=worst.diameter, length=worst.length)
        turn = joint_angle(lengths, radius, angle)
        command = steps = None
        direction = float(route.bend_direction[i])
        if muscle is not None and angle >= STEERING_LEAST_ANGLE:
            command = steer(muscle, curvature=1 / radius, direction=direction, radius=steering.radius,
                            supply=mission.supply_pressure)
            steps = steering_steps(muscle, command, supply=mission.supply_pressure, options=options)
        out.append(BendPlan(i, str(route.name[i]), angle, radius, bore, segments, turn,
                            limit is None or turn <= limit, command, needed, steps, direction,
                            assumed is not None and bool(assumed[i])))
    return tuple(out), reducers


def _segment(seg, bore: float, radius: float, angle: float, model: str) -> SegmentPassage:
    g = seg.pam.geometry
    passage = rigid_passage(bore=bore, radius=radius, angle=angle, diameter=g.initial_diameter)
    length = seg.pam.rigid_length
    least = flexible_bend_radius(rest_length=g.initial_length, rest_diameter=g.initial_diameter,
                                 braid_length=g.braid_length)
    bent = (passage.where != "bore" and least <= radius + (bore - g.initial_diameter) / 2
            and seg.pam.fitting_length == 0)
    rigid = passage.longest >= length
    only_bent = model == "flexible" and not rigid and bent
    return SegmentPassage(seg.name, length, g.initial_diameter, passage.longest, passage.where,
                          rigid or only_bent, only_bent, least, bent)
