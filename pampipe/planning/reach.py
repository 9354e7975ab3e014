"""How far the robot reaches along its route with a tether (docs/physics.md §16.2).

The robot stops for good at the first point along the route where

* some segment's least holding pressure, under the load W + T(x) with the tether's tension T(x) there, exceeds
  its pressure limit: the supply, or its PAM's rated ``max_pressure`` when lower (``limit`` ``supply`` or
  ``rating``);
* the reel runs out: the distance from the entry reaches the tether's length (``tether_length``);
* it meets a section the plan cannot cross for another reason (the pipe's bore, no grip, …: ``limit`` null and
  ``reason`` the plan's reason code), or a bend it cannot pass (``reason`` ``bend``, at the section's end).

Every section before the first infeasible one holds at its largest tension, so only that section is
searched: T(x) = max(0, T_in + k·x) is affine in x (:mod:`pampipe.planning.tension`), and the least holding
pressure rises with the load, so the tension T* at which it reaches the limit is found by a root search on
the plan's own elements (:func:`~pampipe.planning.problem.build_elements` of that section with ``drag`` =
tether_drag + T: worst bores and effects included), and x = (T* − T_in)/k exactly, within the section.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from pampipe.planning.feasibility import pressure_limits
from pampipe.planning.problem import build_elements
from pampipe.planning.tension import tension_slope, tensions
from pampipe.specs.tether import Tether

#: Reasons of the plan whose stop point is searched inside the section (the tension may be the cause).
PRESSURE_REASONS = ("above_supply", "above_rating")


@dataclass(frozen=True)
class Reach:
    """Where the robot stops for good (or the route's end), SI."""

    reachable: bool
    distance: float  # [m] from the entry
    section: str  # the section it stops in (the last one when reachable)
    limit: str | None  # "supply" | "rating" | "tether_length" | None
    tension: float  # [N] the tether's tension there
    reason: str | None = None  # the plan's reason code, or "bend", where the stop is not the tether's doing
    index: int = -1  # the section's index in the route

    def as_document(self) -> dict:
        return {"reachable": self.reachable, "distance_m": self.distance, "section": self.section,
                "limit": self.limit, "tension_N": self.tension, "reason": self.reason}

    def sentence(self, *, tether: bool = True) -> str:
        """The reach in words (``tether``: with the tension there)."""
        where = f"{self.distance:.6g} m from the entry, in section {self.section!r}"
        if self.reachable:
            return f"reach: the whole route, {self.distance:.6g} m" + (
                f" (tether tension at the end {self.tension:.4g} N)" if tether else "")
        why = {"supply": "the least holding pressure reaches the supply",
               "rating": "the least holding pressure reaches a muscle's rated pressure",
               "tether_length": "the tether on the reel runs out"}.get(self.limit or "")
        if why is None:
            why = ("the robot cannot pass the bend at its end" if self.reason == "bend"
                   else f"the plan cannot cross it ({self.reason})")
        return f"reach: {where}: {why}" + (f" (tether tension {self.tension:.4g} N)" if tether else "")


@dataclass(frozen=True)
class TetherPlan:
    """The tether's tension at each section's entry and end [N], and the reach."""

    tension_in: np.ndarray  # (S,) after the previous bend
    tension_out: np.ndarray  # (S,) before the section's own bend
    reach: Reach
    length: float  # [m] on the reel

    @property
    def largest(self) -> np.ndarray:
        """max(T_in, T_out) [N]: the tension the robot carries in each section."""
        return np.maximum(self.tension_in, self.tension_out)

    def section_document(self, s: int) -> dict:
        return {"tension_in_N": float(self.tension_in[s]), "tension_out_N": float(self.tension_out[s])}

    def reason(self) -> str | None:
        """Why the robot cannot complete the route because of the tether itself (the reel), else None."""
        if self.reach.limit != "tether_length":
            return None
        return (f"the tether ({self.length:.6g} m on the reel) runs out {self.reach.distance:.6g} m from the "
                f"entry, in section {self.reach.section!r}: give a longer tether (tether.length).")


def plan_tether(mission, muscles, arrays, bends) -> TetherPlan:
    """The tensions along ``mission``'s route and the reach, from the plan's ``arrays`` (its reasons and
    codes) and ``bends`` (:class:`~pampipe.bends.plan.BendPlan`)."""
    t_in, t_out = tensions(mission.route, mission.tether)
    stops = [_stop(mission, muscles, arrays, t_in, t_out), _reel(mission, t_in, t_out), _bend(mission, bends,
                                                                                           t_out)]
    stops = [s for s in stops if s is not None]
    if not stops:
        route = mission.route
        end = Reach(True, float(route.length.sum()), str(route.name[-1]), None, float(t_out[-1]),
                    index=len(route) - 1)
        return TetherPlan(t_in, t_out, end, mission.tether.length)
    return TetherPlan(t_in, t_out, min(stops, key=lambda r: r.distance), mission.tether.length)


def route_reach(mission, muscles, arrays, bends) -> TetherPlan:
    """:func:`plan_tether`, also for a mission without a tether: no tension, an endless reel, so the reach is
    the first section the plan cannot cross or the first bend the robot cannot pass."""
    if mission.tether is None:
        mission = dataclasses.replace(mission, tether=Tether(0.0, 0.0, 0.0, math.inf))
    return plan_tether(mission, muscles, arrays, bends)


def _entries(route) -> np.ndarray:
    """The distance [m] of each section's entry from the route's entry (S + 1, the last the route's end)."""
    return np.concatenate([[0.0], np.cumsum(route.length)])


def _reel(mission, t_in, t_out) -> Reach | None:
    """The point where the reel runs out, if inside the route."""
    route, length = mission.route, mission.tether.length
    entries = _entries(route)
    if length >= entries[-1]:
        return None
    s = int(np.searchsorted(entries, length, side="right") - 1)
    x = length - entries[s]
    tension = _tension_inside(mission, s, t_in[s], x)
    return Reach(False, float(length), str(route.name[s]), "tether_length", tension, index=s)


def _tension_inside(mission, s: int, t_in: float, x: float) -> float:
    """T(x) = max(0, T_in + k·x) [N] at ``x`` from the entry of section ``s``."""
    slope = float(tension_slope(mission.route[[s]], mission.tether)[0])
    return max(0.0, float(t_in) + slope * x)


def _bend(mission, bends, t_out) -> Reach | None:
    """The end of the section before the first bend the robot cannot pass."""
    blocked = [b for b in bends if not b.passable]
    if not blocked:
        return None
    b = min(blocked, key=lambda bend: bend.index)
    entries = _entries(mission.route)
    return Reach(False, float(entries[b.index + 1]), b.after_section, None, float(t_out[b.index]), "bend",
                 b.index)


def _stop(mission, muscles, arrays, t_in, t_out) -> Reach | None:
    """The stop inside (or at the entry of) the first section the plan cannot cross."""
    if not arrays.reasons:
        return None
    route = mission.route
    s = min(arrays.reasons)
    code = arrays.reason_codes.get(s)
    entry = float(_entries(route)[s])
    limits = pressure_limits(mission)
    word = "rating" if limits.min() < mission.supply_pressure else "supply"
    if code not in PRESSURE_REASONS:
        limit = word if code == "beyond_reach" else None
        return Reach(False, entry, str(route.name[s]), limit, float(t_in[s]),
                     None if limit is not None else code, s)
    largest = max(float(t_in[s]), float(t_out[s]))
    margin = _margin(mission, muscles, s, limits)
    x, tension = 0.0, float(t_in[s])
    if margin(0.0) <= 0 < margin(largest) and t_out[s] > t_in[s]:
        from scipy.optimize import brentq  # only here: SciPy's import would double a plan's start-up

        crossing = brentq(margin, 0.0, largest, xtol=1e-12 * max(largest, 1.0), rtol=4 * np.finfo(float).eps)
        if crossing > t_in[s]:
            length = float(route.length[s])
            x, tension = min((crossing - t_in[s]) / (t_out[s] - t_in[s]) * length, length), crossing
    binding = int(np.argmax(_ratios(mission, muscles, s, limits, tension * (1 + 1e-9))))
    limit = "rating" if limits[binding] < mission.supply_pressure else "supply"
    return Reach(False, float(entry + x), str(route.name[s]), limit, float(tension), index=s)


def _ratios(mission, muscles, s: int, limits, tension: float) -> np.ndarray:
    """Each segment's least holding pressure over its limit in section ``s`` under ``tension`` [N]."""
    elements = build_elements(mission, muscles, route=mission.route[[s]],
                              drag=np.array([mission.tether_drag + tension]))
    return np.where(elements.valid[0], elements.least_pressure[0], math.inf) / limits


def _margin(mission, muscles, s: int, limits):
    """f(T) = max over the segments of P*/limit − 1 in section ``s`` under tension T: ≤ 0 where it holds."""
    def margin(tension: float) -> float:
        return float(np.max(_ratios(mission, muscles, s, limits, tension))) - 1.0
    return margin
