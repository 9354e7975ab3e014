"""The gait through a bend: steering steps added to the 7-step schedule where the robot enters and leaves
each bend (docs/physics.md §14.5).

Entering a bend, the steering module's valves fill its PAMs to the bend's command (step ``steer-in``, as long
as the slowest PAM's fill); leaving it, they vent them to the gait's ``vented_pressure`` (step
``steer-out``). Each PAM is a chamber of the gas volume it has at its commanded length, V = πD²L/4 − V_b
(the largest it reaches, so the times are upper bounds), behind a valve of the mission's ``gait:`` block
(:func:`pampipe.pneumatics.timing.transition_time`). The peristaltic steps through the bend are those
of a straight section of the same length (its arc is part of the route's length).
"""

from __future__ import annotations

from dataclasses import dataclass

from pampipe.model.forces import bladder_volume
from pampipe.pneumatics.options import GaitOptions
from pampipe.pneumatics.timing import Chamber, transition_time


@dataclass(frozen=True)
class SteeringSteps:
    """The two steering steps of one bend [s]."""

    fill: float  # [s] steer-in
    vent: float  # [s] steer-out

    @property
    def extra_time(self) -> float:
        """fill + vent [s]: the time the bend adds to the route."""
        return self.fill + self.vent

    def as_document(self) -> dict:
        return {"steps": [{"step": "steer-in", "valve_action": "fill the steering PAMs to the command",
                           "duration_s": self.fill},
                          {"step": "steer-out", "valve_action": "vent the steering PAMs",
                           "duration_s": self.vent}],
                "extra_time_s": self.extra_time}


def steering_steps(muscle, command, *, supply: float, options: GaitOptions) -> SteeringSteps:
    """Fill and vent times [s] of the steering ``command`` (a :class:`SteeringCommand`) for ``muscle``."""
    fill = vent = 0.0
    for pressure, length in zip(command.pressures, command.lengths, strict=True):
        if pressure <= options.vented_pressure:
            continue
        volume = float(muscle.enclosed_volume(length)) - bladder_volume(muscle.geometry)
        chamber = Chamber.rigid(volume)
        target = min(pressure, supply * (1 - 1e-3))
        fill = max(fill, transition_time(chamber, 0.0, target, supply=supply, valve=options.valve,
                                         gas=options.gas))
        vent = max(vent, transition_time(chamber, target, options.vented_pressure, supply=supply,
                                         valve=options.valve, gas=options.gas))
    return SteeringSteps(fill, vent)


def route_time(bends, route_length: float, speed: float) -> dict:
    """The bends' effect on the route's time: 2 steering steps per bend (with a steering module), their
    time, and the route's time at ``speed`` [m/s] (the walked section's, as an estimate for the route)."""
    steps = [b.steps for b in bends if b.steps is not None]
    extra = sum(s.extra_time for s in steps)
    walking = route_length / speed if speed > 0 else float("inf")
    return {"count": len(bends), "passable": sum(b.passable for b in bends), "extra_steps": 2 * len(steps),
            "extra_time_s": extra, "route_length_m": route_length, "walking_time_s": walking,
            "route_time_s": walking + extra, "extra_share": extra / (walking + extra),
            "per_bend": [{"after_section": b.after_section, "angle_deg": b.angle * 57.29577951308232,
                          "extra_time_s": None if b.steps is None else b.steps.extra_time} for b in bends]}
