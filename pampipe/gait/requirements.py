"""What each muscle must do in one pipe section: contact pressure, no-slip pressure, planned target.

The planned pressures (and the reason a section cannot be crossed) come from the planner,
:func:`pampipe.plan.plan_mission`; the thresholds from the model (docs/physics.md §7-§8): contact
(anchoring) at P_a = −F_ax(0, L_p)/∂_P F_ax, no slip while μπF_r(P, D_p, κW) ≥ SF·W.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from pampipe.errors import InfeasibleError, InputError
from pampipe.gait.options import GaitOptions
from pampipe.gait.pneumatics import Chamber
from pampipe.mission import Mission, Section
from pampipe.model import slip
from pampipe.model.muscle import Muscle
from pampipe.plan import plan_mission


@dataclass(frozen=True)
class MuscleNeed:
    """One segment in one section (SI): its muscle, thresholds, load and chamber."""

    name: str
    muscle: Muscle
    pipe_diameter: float  # D_p [m]
    contact_pressure: float  # P_a [Pa]: the braid touches the wall (no load)
    required_pressure: float  # [Pa]: least pressure with μπF_r ≥ SF·W (no slip), as plan computes it
    target_pressure: float  # [Pa]: the planned pressure of this segment
    load: float  # W [N] it must hold alone
    friction: float
    kappa: float
    safety_factor: float
    chamber: Chamber
    anchored_length: float  # L(D_p) [m]

    @property
    def rest_length(self) -> float:
        return self.muscle.geometry.initial_length

    def holding_ratio(self, pressure):
        """μπF_r(P, D_p, κW) / (SF·W): ≥ 1 means the segment holds alone with the safety factor."""
        capacity = self.muscle.holding_capacity(np.asarray(pressure, dtype=float), self.pipe_diameter,
                                                self.load, kappa=self.kappa, friction=self.friction)
        return capacity / max(self.safety_factor * self.load, 1e-9)


def find_section(mission: Mission, name: str | None) -> Section:
    """The route section called ``name`` (default: the first)."""
    if name is None:
        return mission.route[0]
    for section in mission.route:
        if section.name == name:
            return section
    raise InputError(f"{mission.source}: --section {name!r}: no such section; the route has "
                     f"{', '.join(repr(s.name) for s in mission.route)}.")


def section_needs(mission: Mission, section: Section, options: GaitOptions) -> tuple[MuscleNeed, ...]:
    """Thresholds, loads and chambers of the three segments in ``section``.

    Raises :class:`InfeasibleError` with the reason when the section cannot be crossed.
    """
    muscles = tuple(Muscle.from_pam(segment.pam, where=f"{mission.source}: robot.segments[{i}]")
                    for i, segment in enumerate(mission.segments))
    targets = _planned_pressures(mission, section)
    total_mass = sum(s.mass for s in mission.segments) + mission.payload
    needs = []
    for segment, muscle, target in zip(mission.segments, muscles, targets, strict=True):
        d = section.diameter
        load = float(slip.anchor_load(total_mass, segment.mass, section.incline, section.friction,
                                      mission.tether_drag))
        contact = float(muscle.anchoring_pressure(d))
        required = float(muscle.least_holding_pressure(d, load, kappa=mission.kappa,
                                                       friction=section.friction,
                                                       safety_factor=mission.safety_factor))
        if options.vented_pressure >= contact:
            raise InputError(f"{mission.source}: gait.vented_pressure: {options.vented_pressure:.6g} Pa "
                             f"must be below the contact pressure of {segment.name} "
                             f"({contact:.6g} Pa) in section {section.name!r}.")
        needs.append(MuscleNeed(segment.name, muscle, d, contact, required, max(target, required), load,
                                section.friction, mission.kappa, mission.safety_factor,
                                Chamber.of_muscle(muscle, d), float(muscle.anchored_length(d))))
    return tuple(needs)


def _planned_pressures(mission: Mission, section: Section) -> list[float]:
    """The plan's pressure of each segment in ``section``; InfeasibleError with the plan's reason."""
    for planned in plan_mission(mission).sections:
        if planned.name == section.name:
            if not planned.feasible:
                raise InfeasibleError(f"section {section.name!r} cannot be crossed: {planned.reason}")
            return [float(s.pressure) for s in planned.segments]
    raise InputError(f"{mission.source}: the plan has no section {section.name!r}.")
