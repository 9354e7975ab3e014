"""Why a section cannot be planned: one plain sentence per infeasible section (the plan issue, item 3).

Reasons, checked in this order for each section (the first that applies is reported):
1. zero wall friction: no anchor can grip;
2. the pipe is narrower than a muscle at rest (D_p ≤ D₀);
3. the pipe is wider than the braid can ever reach (D_p ≥ D(B/√3), docs/physics.md §2);
4. the pipe is wider than the muscle reaches at supply pressure (L_free(P_supply) > L(D_p),
   i.e. the unloaded anchoring pressure exceeds the supply, docs/physics.md §7);
5. no pressure up to the model's 100 MPa limit holds the load;
6. the pressure needed to hold the load exceeds the supply (with the largest payload it allows).
"""

from __future__ import annotations

import numpy as np

from pampipe.errors import SolverError
from pampipe.model.braid import diameter_at_length
from pampipe.model.muscle import Muscle
from pampipe.plan.problem import Elements
from pampipe.plan.solve import Solution


def element_feasible(elements: Elements, solution: Solution, supply: float) -> np.ndarray:
    """True where the element's minimum pressure exists and is within the supply, shape (S, 3)."""
    return elements.valid & np.isfinite(solution.pressure) & (solution.pressure <= supply)


def section_reasons(mission, muscles, elements: Elements, solution: Solution,
                    payloads: np.ndarray, *, confidence: float | None = None) -> dict[int, str]:
    """{section index: one sentence} for the sections that cannot be planned (feasible ones are absent).

    ``payloads`` are the element payload limits [kg] of :func:`pampipe.plan.payload.element_payloads`.
    """
    feasible = element_feasible(elements, solution, mission.supply_pressure).all(axis=1)
    return {s: _reason(mission, muscles, s, elements, solution, payloads[s], confidence)
            for s in np.flatnonzero(~feasible).tolist()}


def _names(mission, mask) -> str:
    names = [seg.name for seg, bad in zip(mission.segments, mask, strict=True) if bad]
    if len(names) == len(mission.segments):
        return "the muscles"
    return " and ".join(names)


def _reason(mission, muscles, s: int, e: Elements, solution: Solution, payloads: np.ndarray,
            confidence: float | None) -> str:
    sec, supply = mission.route[s], mission.supply_pressure
    pipe = f"the {sec.diameter * 1e3:.4g} mm pipe"
    pams = [seg.pam for seg in mission.segments]
    if sec.friction <= 0:
        return (f"the wall friction is zero, so no muscle can grip the wall of {pipe} and the robot "
                "can neither hold on nor push itself along.")
    narrow = np.array([sec.diameter <= p.geometry.initial_diameter for p in pams])
    if narrow.any():
        rest = min(p.geometry.initial_diameter for p, n in zip(pams, narrow, strict=True) if n)
        return (f"{pipe} is not wider than {_names(mission, narrow)} at rest ({rest * 1e3:.4g} mm), so "
                "it cannot expand against the wall to anchor.")
    wide = np.array([sec.diameter >= p.geometry.largest_diameter for p in pams])
    if wide.any():
        reach = min(p.geometry.largest_diameter for p, w in zip(pams, wide, strict=True) if w)
        return (f"{pipe} is wider than the braid of {_names(mission, wide)} can ever open (at most "
                f"{reach * 1e3:.4g} mm, where the contractile force vanishes), so it cannot anchor.")
    short = e.free_anchoring[s] > supply
    if short.any():
        i = int(np.argmax(e.free_anchoring[s]))
        return (f"{pipe} is wider than {_names(mission, short)} reach{'es' if short.sum() == 1 else ''} "
                f"at the {supply / 1e3:.4g} kPa supply{_free_diameter(muscles[i], supply)}; "
                f"touching the wall needs {e.free_anchoring[s, i] / 1e3:.4g} kPa.")
    pressure = solution.pressure[s]
    stuck = ~np.isfinite(pressure)
    if stuck.any():
        i = int(np.argmax(stuck))
        return (f"{_names(mission, stuck)} cannot hold the {e.load[s, i]:.4g} N load at any pressure up "
                "to 100 MPa in this pipe.")
    i = int(np.argmax(pressure))
    hold = (f"{mission.segments[i].name} needs {pressure[i] / 1e3:.4g} kPa to hold "
            f"{e.load[s, i]:.4g} N with safety factor {mission.safety_factor:g}"
            f"{'' if confidence is None else f' at {confidence:.3g} confidence'}, more than the "
            f"{supply / 1e3:.4g} kPa supply")
    if confidence is not None:
        return hold + "."
    payload = float(payloads.min())
    if payload >= 0:
        return f"{hold}; at the supply the robot can carry at most {payload:.3g} kg of payload here."
    return f"{hold}; at the supply it cannot even carry its own weight here, with no payload."


def _free_diameter(muscle: Muscle, supply: float) -> str:
    """' (it only opens to X mm)' from the free-contraction root, or '' if that root fails."""
    try:
        length = muscle.free_length([supply])[0]
    except SolverError:
        return ""
    return f" (it only opens to {diameter_at_length(length, muscle.geometry) * 1e3:.4g} mm)"
