"""What a plan warns about, and the coverage of a whole-network plan (docs/commands.md §6 `plan`, §7.2, §7.3).

Warnings are sentences an engineer should read before trusting the numbers: defaults the mission file
left to pampipe (no safety factor), plans that barely touch the wall (the contact margin
P − P_a(D_high, 0) under :data:`~pampipe.planning.result.CONTACT_MARGIN` of P_a(D_high, 0)), bore standard
deviations that only ``--confidence`` uses, and network pipes whose length is shorter than their rise.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from pampipe.planning.result import CONTACT_MARGIN, PlanArrays, thin_contact

if TYPE_CHECKING:
    from pampipe.network import Coverage

#: Sections named one by one in a warning; the others are counted.
LISTED = 10


def plan_warnings(mission, arrays: PlanArrays, confidence: float | None) -> tuple[str, ...]:
    """The mission's own warnings, then those of the plan, in that order."""
    out = list(mission.warnings)
    out += _thin_contact(arrays)
    route = arrays.route
    if confidence is None and np.any(route.diameter_sd > 0):
        out.append(f"{int(np.count_nonzero(route.diameter_sd > 0))} section(s) give the bore's sd, which "
                   "only --confidence uses; this plan holds over each bore's tolerance range.")
    origin = route.origin
    if origin is not None and origin.clipped.any():
        names = route.name[origin.clipped]
        out.append(f"{_listed(names)}: the network's length is shorter than the elevation difference; "
                   "planned as vertical (±90 deg). Check these pipes.")
    return tuple(out)


def _thin_contact(a: PlanArrays) -> list[str]:
    """One sentence per section (the first :data:`LISTED`) whose plan barely touches the largest bore."""
    with np.errstate(invalid="ignore"):
        thin = thin_contact(a.pressure, a.largest_bore_anchoring) & a.feasible
    rows = np.flatnonzero(thin.any(axis=1) & a.complete)
    out = []
    for s in rows[:LISTED].tolist():
        i = int(np.argmin(np.where(thin[s], a.contact_margin[s], np.inf)))
        ranged = a.route.diameter_high[s] > a.route.diameter_low[s]
        advice = ("a bore wider than the stated range would not be gripped: widen the tolerance if the pipe "
                  "may be wider." if ranged else
                  "in a slightly wider pipe it would not grip; give the bore's tolerance so that the plan "
                  "covers it.")
        out.append(f"{a.route.name[s]}: {a.segment_names[i]} is planned only "
                   f"{a.contact_margin[s, i] / 1e3:.3g} kPa above first touching the largest bore "
                   f"({a.route.diameter_high[s] * 1e3:.4g} mm) at "
                   f"{a.largest_bore_anchoring[s, i] / 1e3:.4g} kPa, under {CONTACT_MARGIN:.0%} of it"
                   + (f": {advice}" if not out else "."))
    if rows.size > LISTED:
        out.append(f"... and {rows.size - LISTED} more section(s) with a contact margin under "
                   f"{CONTACT_MARGIN:.0%} (thin_contact_margin in the JSON).")
    return out


def _listed(names: np.ndarray) -> str:
    shown = ", ".join(names[:LISTED].tolist())
    return shown + (f" and {names.size - LISTED} more" if names.size > LISTED else "")


def route_coverage(route, reasons: dict[int, str]) -> Coverage:
    """Pipes and length a network plan serves (the whole network's, or the route's pipes); ``reasons`` maps
    infeasible sections to reason codes."""
    from pampipe.network import coverage  # network routes only: keep it off plan's start-up path

    feasible = np.ones(len(route), dtype=bool)
    feasible[list(reasons)] = False
    per_pipe = [None] * len(route)
    for s, code in reasons.items():
        per_pipe[s] = code
    return coverage(route, feasible=feasible, reasons=per_pipe)
