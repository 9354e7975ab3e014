"""What each muscle must do in one pipe section: contact pressure, no-slip pressure, planned target.

The planned pressures (and the reason a section cannot be crossed) come from the planner,
:func:`pampipe.plan.plan_mission`; the thresholds from the model (docs/physics.md §7-§8): contact
(anchoring) at P_a = −F_ax(0, L_p)/∂_P F_ax, no slip while μπF_r(P, D_p, κW) ≥ SF·W.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np
from scipy.optimize import brentq

from pampipe.errors import InfeasibleError, InputError
from pampipe.gait.options import GaitOptions
from pampipe.gait.pneumatics import Chamber
from pampipe.mission import Mission, Section
from pampipe.model import braid, forces, slip
from pampipe.model.pam import Pam
from pampipe.plan import plan_mission
from pampipe.simulate import require_moduli


@dataclass(frozen=True)
class MuscleNeed:
    """One segment in one section (SI): its thresholds, its load and its chamber."""

    name: str
    pam: Pam
    pipe_diameter: float  # D_p [m]
    contact_pressure: float  # P_a [Pa]: the braid touches the wall (no load)
    required_pressure: float  # [Pa]: least pressure with μπF_r ≥ SF·W (no slip)
    target_pressure: float  # [Pa]: the planned pressure of this segment
    load: float  # W [N] it must hold alone
    friction: float
    kappa: float
    safety_factor: float
    chamber: Chamber
    anchored_length: float  # L(D_p) [m]

    @property
    def rest_length(self) -> float:
        return self.pam.geometry.initial_length

    def holding_ratio(self, pressure):
        """μπF_r(P, D_p, κW) / (SF·W): ≥ 1 means the segment holds alone with the safety factor."""
        theta = self.pam.moduli.as_vector()
        contact = self.pam.moduli.contact_vector()
        capacity = slip.holding_capacity(np.asarray(pressure, dtype=float), self.pipe_diameter,
                                         self.pam.geometry, theta, self.pam.moduli.reference_pressure,
                                         self.load, self.kappa, self.friction,
                                         contact if np.any(contact) else None)
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
    for i, segment in enumerate(mission.segments):
        require_moduli(segment.pam, source=f"{mission.source}: robot.segments[{i}]")
    targets = _planned_pressures(mission, section)
    total_mass = sum(s.mass for s in mission.segments) + mission.payload
    needs = []
    for segment, target in zip(mission.segments, targets, strict=True):
        pam, d = segment.pam, section.diameter
        geometry, theta, pref = pam.geometry, pam.moduli.as_vector(), pam.moduli.reference_pressure
        load = float(slip.anchor_load(total_mass, segment.mass, section.incline, section.friction,
                                      mission.tether_drag))
        contact = float(forces.anchoring_pressure(d, geometry, theta, pref))
        need = MuscleNeed(segment.name, pam, d, contact, math.nan, target, load, section.friction,
                          mission.kappa, mission.safety_factor,
                          Chamber.of_muscle(geometry, theta, pref, d),
                          float(braid.length_at_diameter(d, geometry)))
        required = _required_pressure(need, mission.supply_pressure)
        if options.vented_pressure >= contact:
            raise InputError(f"{mission.source}: gait.vented_pressure: {options.vented_pressure:.6g} Pa "
                             f"must be below the contact pressure of {segment.name} "
                             f"({contact:.6g} Pa) in section {section.name!r}.")
        needs.append(replace(need, required_pressure=required,
                             target_pressure=max(need.target_pressure, required)))
    return tuple(needs)


def _required_pressure(need: MuscleNeed, supply: float) -> float:
    """Least P with holding_ratio(P) = 1: closed form without contact increments, else a root."""
    moduli = need.pam.moduli
    if not np.any(moduli.contact_vector()):
        return float(slip.required_pressure(need.pipe_diameter, need.pam.geometry, moduli.as_vector(),
                                            moduli.reference_pressure, need.load, need.kappa,
                                            need.friction, need.safety_factor))
    low = float(forces.anchoring_pressure(need.pipe_diameter, need.pam.geometry, moduli.as_vector(),
                                          moduli.reference_pressure, need.kappa * need.load))
    return float(brentq(lambda p: float(need.holding_ratio(p)) - 1.0, low, 2 * supply + low,
                        xtol=1e-6))


def _planned_pressures(mission: Mission, section: Section) -> list[float]:
    """The plan's pressure of each segment in ``section``; InfeasibleError with the plan's reason."""
    for planned in plan_mission(mission).sections:
        if planned.name == section.name:
            if not planned.feasible:
                raise InfeasibleError(f"section {section.name!r} cannot be crossed: {planned.reason}")
            return [float(s.pressure) for s in planned.segments]
    raise InputError(f"{mission.source}: the plan has no section {section.name!r}.")
