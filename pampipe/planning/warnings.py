"""What a plan warns about, and the coverage of a whole-network plan (docs/commands.md §4.2, §4.3, §7).

Warnings are sentences an engineer should read before trusting the numbers: defaults the mission file
left to pampipe (no safety factor), plans that barely touch the wall (the contact margin
P − P_a(D_high, 0) below what a 1 mm wider bore or a 1° braid angle error costs,
:mod:`pampipe.planning.contact`; not with ``--confidence``, whose contact probability replaces it),
bore standard deviations that only ``--confidence`` uses, and network pipes whose length is shorter
than their rise.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from pampipe.planning.result import PlanArrays

if TYPE_CHECKING:
    from pampipe.specs.network import Coverage

#: Sections named one by one in a warning; the others are counted.
LISTED = 10


def plan_warnings(mission, arrays: PlanArrays, confidence: float | None) -> tuple[str, ...]:
    """The mission's own warnings, then those of the plan, in that order."""
    out = list(mission.warnings)
    out += _thin_contact(arrays) if confidence is None else []
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
    """One sentence per section (the first :data:`LISTED`) where a 1 mm / 1° error costs more than the
    contact margin (:mod:`pampipe.planning.contact`)."""
    thin = a.thin & a.feasible
    rows = np.flatnonzero(thin.any(axis=1) & a.complete)
    out = []
    for s in rows[:LISTED].tolist():
        i = int(np.argmin(np.where(thin[s], a.contact_margin[s], np.inf)))
        ranged = a.route.diameter_high[s] > a.route.diameter_low[s]
        bore, angle = a.contact_cost[s, i]
        advice = ("a bore wider than the stated range would not be gripped" if ranged else
                  "give the bore's tolerance so that the plan covers it")
        out.append(f"{a.route.name[s]}: {a.segment_names[i]} is planned only "
                   f"{a.contact_margin[s, i] / 1e3:.3g} kPa above first touching the largest bore "
                   f"({a.route.diameter_high[s] * 1e3:.4g} mm) at "
                   f"{a.largest_bore_anchoring[s, i] / 1e3:.4g} kPa; "
                   f"a bore 1 mm wider would cost {bore / 1e3:.3g} kPa and a braid angle 1 deg off "
                   f"{angle / 1e3:.3g} kPa"
                   + (f": {advice}, or plan with --confidence and the sds of bore and geometry."
                      if not out else "."))
    if rows.size > LISTED:
        out.append(f"... and {rows.size - LISTED} more section(s) whose contact margin a 1 mm / 1 deg error "
                   "would take (thin_contact_margin in the JSON).")
    return out


def _listed(names: np.ndarray) -> str:
    shown = ", ".join(names[:LISTED].tolist())
    return shown + (f" and {names.size - LISTED} more" if names.size > LISTED else "")


def route_coverage(route, reasons: dict[int, str]) -> Coverage:
    """Pipes and length a network plan serves (the whole network's, or the route's pipes); ``reasons`` maps
    infeasible sections to reason codes."""
    from pampipe.specs.network import coverage  # network routes only: keep it off plan's start-up path

    feasible = np.ones(len(route), dtype=bool)
    feasible[list(reasons)] = False
    per_pipe = [None] * len(route)
    for s, code in reasons.items():
        per_pipe[s] = code
    return coverage(route, feasible=feasible, reasons=per_pipe)
