"""The gait schedule of every route section, as `pampipe gait` computes it, for a constant C table.

Each crossable section gets the seven steps of the sequential gait (docs/physics.md §8.1, §8.5) from
:func:`pampipe.locomotion.sequential_gait`: the valve action of each segment during the transition into the
step (+1 fill from the supply, −1 vent, 0 closed; the sign of the gait's valve command), the anchored
segments, the transition's duration and the pressures at the end of the step.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from pampipe.errors import InfeasibleError
from pampipe.export.law import Law, Reason
from pampipe.locomotion import gait_options, sequential_gait
from pampipe.planning import plan_mission


@dataclass(frozen=True)
class GaitStep:
    """One step of the cycle (SI): valves during its transition, anchors, duration, end pressures."""

    step: str
    valves: tuple[int, ...]  # +1 fill, −1 vent, 0 closed, per segment
    anchored: tuple[bool, ...]
    duration: float  # [s]
    pressures: tuple[float, ...]  # [Pa] gauge


@dataclass(frozen=True)
class SectionGait:
    """One route section: its numbers, the law's reason code with the mission's payload, the steps."""

    name: str
    diameter: float  # [m]
    incline: float  # [rad]
    friction: float
    length: float  # [m]
    reason: Reason
    cycle_time: float  # [s], 0 where not crossable
    stride: float  # [m], 0 where not crossable
    steps: tuple[GaitStep, ...]  # empty where not crossable

    def as_document(self) -> dict:
        return {"name": self.name, "reason_code": int(self.reason), "cycle_time_s": self.cycle_time,
                "stride_m": self.stride, "steps": len(self.steps)}


#: Routes of at least this many sections report the gait table's progress, every tenth of the way.
PROGRESS_FROM = 100


def section_gaits(mission, law: Law, *, progress=None) -> tuple[SectionGait, ...]:
    """The gait table of every section of ``mission`` (sections the law refuses have no steps).

    The mission is planned once and every section's gait reads that plan, so the work is linear in
    sections; sections whose segments need the same (same bore, load, friction) share one gait.
    ``progress(text)`` hears every tenth of a route of :data:`PROGRESS_FROM` sections or more.
    """
    options = gait_options(mission.gait, source=mission.source)
    plan = plan_mission(mission)
    cache: dict = {}
    out = []
    count = len(mission.route)
    step = max(1, count // 10)
    for index, section in enumerate(mission.route):
        if progress is not None and count >= PROGRESS_FROM and index and index % step == 0:
            progress(f"gait table: {index} of {count} sections ...")
        reason, _ = law.evaluate(section.diameter, section.incline, section.friction, mission.payload)
        result = None
        if reason == Reason.OK:
            try:
                result = sequential_gait(mission, index, options=options, mission_plan=plan, cache=cache)
            except InfeasibleError:  # the closed form and the plan's bisection split at the supply
                reason = Reason.ABOVE_SUPPLY
        fields = (section.name, section.diameter, section.incline, section.friction, section.length, reason)
        if result is None:
            out.append(SectionGait(*fields, 0.0, 0.0, ()))
            continue
        names = result.names
        steps = []
        for k, state in enumerate(result.steps):
            valves = (0,) * len(names) if k == 0 else tuple(
                int(v) for v in np.sign(result.plan.commands[k - 1, 0]))
            steps.append(GaitStep(state.step, valves, tuple(n in state.anchored for n in names),
                                  state.duration, tuple(state.pressures[n] for n in names)))
        out.append(SectionGait(*fields, result.cycle_time, result.stride, tuple(steps)))
    return tuple(out)
