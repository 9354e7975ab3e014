"""What each muscle must do in one pipe section: contact pressure, no-slip pressure, planned target.

The pressures come from the planner (:func:`pampipe.plan.plan_mission`) when it is installed, and
from the closed forms of :mod:`pampipe.model.slip` otherwise; both use physics.md §7-§8:
contact (anchoring) at P_a = −F_ax(0, L_p)/∂_P F_ax, no slip while μπF_r(P, D_p, κW) ≥ SF·W.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np
from scipy.optimize import brentq

from pampipe.config import Mission, Section
from pampipe.errors import InfeasibleError, InputError
from pampipe.gait.options import GaitOptions
from pampipe.gait.pneumatics import Chamber
from pampipe.model import braid, muscle, slip
from pampipe.model.domain import check_pipe_diameter
from pampipe.model.pam import Pam
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
        contact = float(muscle.anchoring_pressure(d, geometry, theta, pref))
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
    low = float(muscle.anchoring_pressure(need.pipe_diameter, need.pam.geometry, moduli.as_vector(),
                                          moduli.reference_pressure, need.kappa * need.load))
    return float(brentq(lambda p: float(need.holding_ratio(p)) - 1.0, low, 2 * supply + low,
                        xtol=1e-6))


def _planned_pressures(mission: Mission, section: Section) -> list[float]:
    """The plan's pressure of each segment in ``section``; InfeasibleError with the plan's reason."""
    try:
        from pampipe.plan import plan_mission
    except ImportError:
        return _fallback_plan(mission, section)
    plan = plan_mission(mission)
    for sec in plan.sections:
        if sec.name == section.name:
            if not sec.feasible:
                raise InfeasibleError(f"section {section.name!r} cannot be crossed: {sec.reason}")
            return [float(s.pressure) for s in sec.segments]
    raise InputError(f"{mission.source}: the plan has no section {section.name!r}.")


def _fallback_plan(mission: Mission, section: Section) -> list[float]:
    """Planned pressure = max(no-slip pressure, contact) per segment, with the plan's reasons."""
    where = f"section {section.name!r} cannot be crossed"
    if section.friction <= 0:
        raise InfeasibleError(f"{where}: the wall friction is zero, so no pressure can hold the robot.")
    total_mass = sum(s.mass for s in mission.segments) + mission.payload
    pressures = []
    for segment in mission.segments:
        geometry, moduli = segment.pam.geometry, segment.pam.moduli
        try:
            check_pipe_diameter(geometry, section.diameter, where=f"{segment.name} in {section.name!r}")
        except InputError as exc:
            raise InfeasibleError(f"{where}: {exc}") from None
        theta, pref = moduli.as_vector(), moduli.reference_pressure
        load = slip.anchor_load(total_mass, segment.mass, section.incline, section.friction,
                                mission.tether_drag)
        required = float(slip.required_pressure(section.diameter, geometry, theta, pref, load,
                                                mission.kappa, section.friction, mission.safety_factor))
        contact = float(muscle.anchoring_pressure(section.diameter, geometry, theta, pref))
        pressure = max(required, contact)
        if pressure > mission.supply_pressure:
            raise InfeasibleError(
                f"{where}: {segment.name} needs {pressure / 1e3:.1f} kPa to hold {load:.1f} N with "
                f"safety factor {mission.safety_factor:g}, above the {mission.supply_pressure / 1e3:.1f} "
                "kPa supply.")
        pressures.append(pressure)
    return pressures
