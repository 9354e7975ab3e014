"""The gait schedule of every route section, as `pampipe gait` computes it, for a constant C table.

Each crossable section gets the seven steps of the sequential gait (docs/physics.md §8.1, §8.5) from
:func:`pampipe.locomotion.table.sequential_table`, which computes every section at once: the valve action of
each segment during the transition into the step (+1 fill from the supply, −1 vent, 0 closed; the sign of
the gait's valve command), the anchored segments, the transition's duration and the pressures at the end
of the step.
"""

from __future__ import annotations

from dataclasses import dataclass

from pampipe.export.law import Law, Reason
from pampipe.locomotion.schedule import ANCHORS, STEPS
from pampipe.locomotion.table import VALVES, sequential_table
from pampipe.planning.planner import plan_mission
from pampipe.pneumatics.options import gait_options


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

    The mission is planned once; the law's reason of each section is read one by one, then the gaits of
    all crossable sections are computed together (:func:`~pampipe.locomotion.table.sequential_table`),
    so the work is linear in sections and vectorised. ``progress(text)`` hears every tenth of a route of
    :data:`PROGRESS_FROM` sections or more.
    """
    options = gait_options(mission.gait, source=mission.source)
    plan = plan_mission(mission)
    count = len(mission.route)
    step = max(1, count // 10)
    reasons = []
    for index, section in enumerate(mission.route):
        if progress is not None and count >= PROGRESS_FROM and index and index % step == 0:
            progress(f"gait table: {index} of {count} sections ...")
        reason, _ = law.evaluate(section.diameter, section.incline, section.friction, mission.payload)
        if reason == Reason.OK and index in plan.arrays.reasons:
            reason = Reason.ABOVE_SUPPLY  # the closed form and the plan's bisection split at the supply
        reasons.append(reason)
    crossable = [index for index, reason in enumerate(reasons) if reason == Reason.OK]
    if progress is not None and count >= PROGRESS_FROM:
        progress(f"gait table: the gaits of {len(crossable)} crossable sections ...")
    table = sequential_table(mission, plan, options, crossable)
    row = {index: k for k, index in enumerate(crossable)}
    names = [segment.name for segment in mission.segments]
    out = []
    for index, (section, reason) in enumerate(zip(mission.route, reasons, strict=True)):
        fields = (section.name, section.diameter, section.incline, section.friction, section.length, reason)
        if index not in row:
            out.append(SectionGait(*fields, 0.0, 0.0, ()))
            continue
        k = row[index]
        steps = tuple(GaitStep(STEPS[j], tuple(int(v) for v in (VALVES[j - 1] if j else [0] * len(names))),
                               tuple(n in ANCHORS[j] for n in range(len(names))),
                               0.0 if j == 0 else float(table.durations[k, j - 1]),
                               tuple(float(v) for v in table.pressures[k, j]))
                      for j in range(len(STEPS)))
        out.append(SectionGait(*fields, float(table.cycle_time[k]), float(table.stride[k]), steps))
    return tuple(out)
