"""`pampipe plan`: the least anchoring pressure per route section and segment (docs/physics.md §5, §7, §8).

Library API::

    from pampipe.io.mission_schema import load_mission
    from pampipe.planning import plan_mission, max_payload

    plan = plan_mission(load_mission("mission.yaml"))          # -> MissionPlan
    plan.feasible, plan.sections[0].segments[0].pressure       # SI units
    plan.arrays.pressure                                       # (sections, 3) array, for long routes
    plan.arrays.diameter, plan.arrays.contact_margin           # worst bore [m], P - P_a(D_high) [Pa]
    plan.warnings, plan.coverage                               # sentences; pipes served (network routes)
    limit = max_payload(mission)                               # -> PayloadLimit (kg, limiting section)

A bore range (a tolerance) is planned in its worst bore (:func:`pampipe.planning.bores.worst_bores`).
"""

from pampipe.planning.payload import PayloadLimit, SectionPayload, max_payload
from pampipe.planning.planner import plan_mission
from pampipe.planning.result import MissionPlan, PlanArrays, SectionPlan, SegmentPlan

__all__ = ["MissionPlan", "PayloadLimit", "PlanArrays", "SectionPayload", "SectionPlan", "SegmentPlan",
           "max_payload", "plan_mission"]
