"""What each muscle must do in one pipe section: contact pressure, no-slip pressure, planned target.

The thresholds, loads and anchored lengths (and the reason a section cannot be crossed) are the
planner's, :func:`pampipe.planning.plan_mission` (docs/physics.md §7-§8): contact (anchoring) at
P_a = −F_ax(0, L_p)/∂_P F_ax, no slip while μπF_r(P, D_p, κW) ≥ SF·W.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from pampipe.errors import InfeasibleError, InputError
from pampipe.model.muscle import Muscle
from pampipe.planning.planner import plan_mission
from pampipe.pneumatics.options import GaitOptions
from pampipe.pneumatics.timing import Chamber
from pampipe.specs.mission import Mission


@dataclass(frozen=True)
class MuscleNeed:
    """One segment in one section (SI): its muscle, thresholds, load and chamber."""

    name: str
    muscle: Muscle
    pipe_diameter: float  # D_p [m]
    contact_pressure: float  # P_a [Pa]: the braid touches the wall (no load)
    required_pressure: float  # [Pa]: least pressure with μπF_r ≥ SF·W (no slip), the plan's
    target_pressure: float  # [Pa]: the pressure the gait fills to (the plan's, so equal to the above)
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


def _chamber(muscle: Muscle, diameter: float) -> Chamber:
    """:meth:`Chamber.of_muscle`, once per muscle and bore: a route repeats its bores, and every plan
    builds its muscles anew, so the key is the muscle's content (structure and parameter vector)."""
    key = (muscle.structure, muscle.parameter_vector().tobytes(), diameter)
    chamber = _CHAMBERS.pop(key, None)
    if chamber is None:
        chamber = Chamber.of_muscle(muscle, diameter)
    _CHAMBERS[key] = chamber  # the most recent last; the least recent beyond 64 goes
    if len(_CHAMBERS) > 64:
        _CHAMBERS.pop(next(iter(_CHAMBERS)))
    return chamber


#: (structure, parameter bytes, bore) → Chamber, least recently used first.
_CHAMBERS: dict = {}


def vented_error(mission: Mission, options: GaitOptions, segment: int, section: int,
                 contact: float) -> InputError:
    """The error of a vented pressure not below the contact pressure of ``segment`` in ``section``."""
    return InputError(f"{mission.source}: gait.vented_pressure: {options.vented_pressure:.6g} Pa must be "
                      f"below the contact pressure of {mission.segments[segment].name} ({contact:.6g} Pa) "
                      f"in section {mission.route[section].name!r}.")


def find_section(mission: Mission, name: str | None) -> int:
    """Index of the route section called ``name`` (default: the first)."""
    if name is None:
        return 0
    for index, section in enumerate(mission.route):
        if section.name == name:
            return index
    raise InputError(f"{mission.source}: --section {name!r}: no such section; the route has "
                     f"{', '.join(repr(s.name) for s in mission.route)}.")


def section_needs(mission: Mission, index: int, options: GaitOptions, *, plan=None) -> tuple[MuscleNeed, ...]:
    """Thresholds, loads and chambers of the three segments in route section ``index``.

    The contact and no-slip pressures, the load and the anchored length are the plan's own
    (:func:`pampipe.planning.plan_mission`, whose arrays hold them), so gait and plan agree by construction.
    Raises :class:`InfeasibleError` with the plan's reason when the section cannot be crossed.
    ``plan``: ``plan_mission(mission)`` when already computed (the gait of every section plans once).
    """
    plan = plan_mission(mission) if plan is None else plan
    a, section = plan.arrays, mission.route[index]
    if index in a.reasons:
        raise InfeasibleError(f"section {section.name!r} cannot be crossed: {a.reasons[index]}")
    needs = []
    for i, (segment, muscle) in enumerate(zip(mission.segments, plan.muscles, strict=True)):
        d = float(a.diameter[index, i])  # the plan's bore: the worst of the section's range
        contact, required = float(a.anchoring_pressure[index, i]), float(a.pressure[index, i])
        if options.vented_pressure >= contact:
            raise vented_error(mission, options, i, index, contact)
        needs.append(MuscleNeed(segment.name, muscle, d, contact, required, required,
                                float(a.required_hold[index, i]), section.friction, mission.kappa,
                                mission.safety_factor, _chamber(muscle, d),
                                float(a.anchored_length[index, i])))
    return tuple(needs)
