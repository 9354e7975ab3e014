"""Why a section cannot be planned: one plain sentence per infeasible section (the plan issue, item 3).

Reasons, checked in this order for each section (the first that applies is reported; its code in
brackets, counted by a whole-network plan's coverage):
1. zero wall friction: no anchor can grip [``zero_friction``];
2. the pipe is narrower than a muscle at rest (D_low ≤ D₀) [``narrower_than_muscle``];
3. the pipe is wider than the braid can ever reach (D_high ≥ D(B/√3), docs/physics.md §2)
   [``wider_than_braid``];
4. the pipe is wider than the muscle reaches at supply pressure (L_free(P_supply) > L(D_p),
   i.e. the unloaded anchoring pressure exceeds the supply, docs/physics.md §7) [``beyond_reach``];
3b. anchoring in the largest bore would contract a muscle by more than its maker allows
   (1 − L(D_high)/L₀ > ``max_contraction`` of its PAM file) [``beyond_contraction``];
4. the pipe is wider than the muscle reaches at its pressure limit [``beyond_reach``];
5. no pressure up to the model's 100 MPa limit holds the load [``cannot_hold``];
6. the pressure needed to hold the load exceeds the supply (with the largest payload it allows)
   [``above_supply``], or the muscle's rated pressure (``max_pressure`` of its PAM file, when below the
   supply) [``above_rating``];
7. with ``--confidence``: a direction of the muscle's parameters that the test data leave undetermined
   moves a segment's C-quantile here by more than a tenth of its margin to its pressure limit, so no
   pressure and no probability can be given [``undetermined``]; this reason replaces the others, since it
   names the test to run first.

A segment's pressure limit is the supply, or its PAM's ``max_pressure`` when lower (:func:`pressure_limits`):
no plan asks more, and a margin that exists only above the rating is no margin.

With a bore range (a tolerance), each sentence names the bore that fails: the smallest for 2, the
largest for 3 and 4, the worst bore (where the pressure is largest) for 5 and 6.
"""

from __future__ import annotations

import math

import numpy as np

from pampipe.errors import SolverError
from pampipe.model.braid import diameter_at_length, length_at_diameter
from pampipe.model.muscle import Muscle
from pampipe.planning.problem import Elements
from pampipe.planning.quantiles import level_text, tail
from pampipe.planning.solve import Solution


def element_feasible(elements: Elements, solution: Solution, supply) -> np.ndarray:
    """True where the element's minimum pressure exists and is within ``supply`` [Pa] (a number, or one
    limit per segment), shape (S, 3)."""
    return elements.valid & np.isfinite(solution.pressure) & (solution.pressure <= supply)


def pressure_limits(mission) -> np.ndarray:
    """The highest pressure [Pa] a plan may ask of each segment: the supply, or the PAM's rated
    ``max_pressure`` when that is lower."""
    return np.array([min(mission.supply_pressure, math.inf if seg.pam.max_pressure is None
                         else seg.pam.max_pressure) for seg in mission.segments])


def within_contraction(mission) -> np.ndarray:
    """(S, 3): True where anchoring in the section's largest bore keeps each muscle within its PAM's
    ``max_contraction`` (1 − L(D_high)/L₀, docs/physics.md §2); True where none is stated."""
    out = np.ones((len(mission.route), len(mission.segments)), dtype=bool)
    for i, seg in enumerate(mission.segments):
        if seg.pam.max_contraction is not None:
            out[:, i] = _contraction(mission.route.diameter_high, seg.pam.geometry) <= seg.pam.max_contraction
    return out


def plan_feasible(mission, elements: Elements, solution: Solution) -> np.ndarray:
    """(S, 3): the element is feasible within its pressure limit and its maker's contraction limit."""
    return element_feasible(elements, solution, pressure_limits(mission)) & within_contraction(mission)


def _contraction(diameter, geometry) -> np.ndarray:
    """1 − L(D)/L₀ of an anchored muscle; 1 where D is beyond what the braid reaches (it cannot anchor)."""
    d = np.asarray(diameter, dtype=float)
    inside = (d > geometry.initial_diameter) & (d < geometry.largest_diameter)
    length = length_at_diameter(np.where(inside, d, geometry.initial_diameter), geometry)
    return np.where(inside, 1.0 - np.asarray(length, dtype=float) / geometry.initial_length,
                    np.where(d <= geometry.initial_diameter, 0.0, 1.0))


#: Reason codes in the order they are checked, with the words coverage reports use.
REASONS = {"zero_friction": "zero wall friction", "narrower_than_muscle": "narrower than the muscles at rest",
           "wider_than_braid": "wider than the braids can open",
           "beyond_reach": "wider than the muscles reach at the supply pressure",
           "beyond_contraction": "would contract the muscles beyond their rating",
           "cannot_hold": "no pressure holds the load", "above_supply": "needs more than the supply pressure",
           "above_rating": "needs more than the muscles' rated pressure",
           "undetermined": "the test data do not determine the holding force"}


def section_reasons(mission, muscles, elements: Elements, solution: Solution,
                    payloads: np.ndarray, *, confidence: float | None = None):
    """({section index: one sentence}, {section index: reason code}) for the sections that cannot be
    planned (feasible ones are absent).

    ``payloads`` are the element payload limits [kg] of :func:`pampipe.planning.payload.element_payloads`.
    The geometric reasons (1-3) are found for all sections at once; only the others need the plan.
    """
    feasible = plan_feasible(mission, elements, solution).all(axis=1)
    rows = np.flatnonzero(~feasible)
    contracted = ~within_contraction(mission)
    r = mission.route
    rest = np.array([seg.pam.geometry.initial_diameter for seg in mission.segments])
    reach = np.array([seg.pam.geometry.largest_diameter for seg in mission.segments])
    zero = (r.friction[rows] <= 0).tolist()
    narrow = r.diameter_low[rows, None] <= rest
    wide = r.diameter_high[rows, None] >= reach
    sentences, codes = {}, {}
    for k, s in enumerate(rows.tolist()):
        pipe, ranged = _pipe(r, s)

        def at(which: str, bore: float, ranged=ranged) -> str:
            return f", at its {which} bore of {_mm(bore)}," if ranged else ""

        if zero[k]:
            codes[s], sentences[s] = "zero_friction", (
                f"the wall friction is zero, so no muscle can grip the wall of {pipe} and the robot can "
                "neither hold on nor push itself along.")
        elif narrow[k].any():
            codes[s], sentences[s] = "narrower_than_muscle", (
                f"{pipe} is{at('smallest', r.diameter_low[s])} not wider than {_names(mission, narrow[k])} "
                f"at rest ({_mm(rest[narrow[k]].min())}), so it cannot expand against the wall to anchor.")
        elif wide[k].any():
            codes[s], sentences[s] = "wider_than_braid", (
                f"{pipe} is{at('largest', r.diameter_high[s])} wider than the braid of "
                f"{_names(mission, wide[k])} can ever open (at most {_mm(reach[wide[k]].min())}, where the "
                "contractile force vanishes), so it cannot anchor.")
        elif contracted[s].any():
            i = int(np.argmax(contracted[s]))
            pam = mission.segments[i].pam
            codes[s], sentences[s] = "beyond_contraction", (
                f"{pipe} is{at('largest', r.diameter_high[s])} so wide that {_names(mission, contracted[s])} "
                f"would contract by {_contraction(r.diameter_high[s], pam.geometry) * 100:.3g} % to anchor, "
                f"more than the maker's {pam.max_contraction * 100:.3g} % (max_contraction of "
                f"{pam.name}).")
        else:
            codes[s], sentences[s] = _loaded_reason(mission, muscles, s, elements, solution, payloads[s],
                                                    confidence, pipe, ranged)
    return sentences, codes


def _pipe(route, s: int) -> tuple[str, bool]:
    """('the 77.92 mm pipe (NPS 3 Sch 40 (ASME B36.10M) ± 1 mm)', has a range) of section ``s``."""
    ranged = bool(route.diameter_high[s] > route.diameter_low[s])
    pipe = f"the {_mm(route.diameter[s])} pipe"
    label = route.section_label(s)
    if ranged or label != _mm(route.diameter[s]):
        pipe += f" ({label})"
    return pipe, ranged


def _names(mission, mask) -> str:
    names = [seg.name for seg, bad in zip(mission.segments, mask, strict=True) if bad]
    if len(names) == len(mission.segments):
        return "the muscles"
    return " and ".join(names)


def _mm(length: float) -> str:
    return f"{length * 1e3:.4g} mm"


def _loaded_reason(mission, muscles, s: int, e: Elements, solution: Solution, payloads: np.ndarray,
                   confidence: float | None, pipe: str, ranged: bool) -> tuple[str, str]:
    """(code, sentence) of reasons 4-6 for section ``s``, whose pipe the muscles fit."""
    supply = mission.supply_pressure
    limits = pressure_limits(mission)

    def at(which: str, bore: float) -> str:
        return f", at its {which} bore of {_mm(bore)}," if ranged else ""

    def limit(i: int) -> str:
        if limits[i] < supply:
            return (f"the {limits[i] / 1e3:.4g} kPa rating of {mission.segments[i].name} (max_pressure of "
                    f"{mission.segments[i].pam.name}; the supply is {supply / 1e3:.4g} kPa)")
        return f"the {supply / 1e3:.4g} kPa supply"

    touch = np.maximum(e.free_anchoring[s], e.largest_bore_anchoring[s])
    short = touch > limits
    if short.any():
        i = int(np.argmax(touch / limits))
        largest = e.largest_bore_anchoring[s, i] >= e.free_anchoring[s, i]
        bore = at("largest", mission.route.diameter_high[s]) if largest else at("worst", e.diameter[s, i])
        return "beyond_reach", (
            f"{pipe} is{bore} wider than {_names(mission, short)} reach{'es' if short.sum() == 1 else ''} "
            f"at {limit(i)}{_free_diameter(muscles[i], limits[i])}; touching the wall "
            f"needs {touch[i] / 1e3:.4g} kPa.")
    pressure = solution.pressure[s]
    worst = f" in its worst bore, {_mm(e.diameter[s, int(np.argmax(pressure))])}," if ranged else ""
    stuck = ~np.isfinite(pressure)
    if stuck.any():
        i = int(np.argmax(stuck))
        sampled = "" if confidence is None else (
            f" in a share {level_text(confidence)} of the draws (in more than {level_text(tail(confidence))} "
            "of them it holds at no pressure: a friction at or below 0, or a muscle outside the model's "
            "domain)")
        return "cannot_hold", (f"{_names(mission, stuck)} cannot hold the {e.load[s, i]:.4g} N load at any "
                               f"pressure up to 100 MPa in this pipe{worst.rstrip(',')}{sampled}.")
    i = int(np.argmax(pressure / limits))
    hold = (f"{mission.segments[i].name} needs {pressure[i] / 1e3:.4g} kPa{worst} to hold "
            f"{e.load[s, i]:.4g} N with safety factor {mission.safety_factor:g}"
            f"{'' if confidence is None else f' at {level_text(confidence)} confidence'}, "
            f"more than {limit(i)}")
    code = "above_rating" if limits[i] < supply else "above_supply"
    if confidence is not None:
        return code, hold + "."
    payload = float(payloads.min())
    within = "at the supply" if code == "above_supply" else "within the rating"
    if payload >= 0:
        return code, f"{hold}; {within} the robot can carry at most {payload:.3g} kg of payload here."
    return code, f"{hold}; {within} it cannot even carry its own weight here, with no payload."


def _free_diameter(muscle: Muscle, supply: float) -> str:
    """' (it only opens to X mm)' from the free-contraction root, or '' if that root fails."""
    try:
        length = muscle.free_length([supply])[0]
    except SolverError:
        return ""
    return f" (it only opens to {diameter_at_length(length, muscle.geometry) * 1e3:.4g} mm)"


def undetermined_reasons(mission, sampled, sentences: dict, codes: dict) -> None:
    """Add (in place) the ``undetermined`` reason of every section where an unresolved direction stops a
    segment: covering its open width moves the segment's C-quantile by more than ``OPEN_SHARE`` of its
    margin to its pressure limit (:func:`pampipe.planning.sampling.stop_open`)."""
    from pampipe.planning.sampling import OPEN_SHARE  # with --confidence only: a plain plan never loads it

    r = mission.route
    limits = pressure_limits(mission)
    for s, (i, direction, delta, margin) in sampled.undetermined.items():
        pipe, _ = _pipe(r, s)
        bore = _mm(r.diameter_high[s])
        suggested = f" (the fit's own words: {direction.test})" if direction.test else ""
        pam = mission.segments[i].pam
        limit = "rating" if limits[i] < mission.supply_pressure else "supply"
        codes[s] = "undetermined"
        sentences[s] = (
            f"{mission.segments[i].name}'s fit ({pam.name}) leaves a direction of its parameters "
            f"undetermined that moves its {level_text(sampled.level)} quantile in {pipe} by "
            f"{delta / 1e3:.3g} kPa "
            f"across what the data allow, more than {OPEN_SHARE * 100:g} % of its {margin / 1e3:.3g} kPa "
            f"margin to the {limit}, so no pressure and no holding probability can be given. A radial test "
            f"at the {bore} bore, or a slip test in this pipe, would determine it{suggested}; or plan with "
            "--prior-from PAM (or a geometry '{value, sd}' in the PAM file) to rest the margin on a prior.")
