"""Whether a rigid cylinder passes a pipe elbow; how tight a deflated muscle bends (docs/physics.md §14).

Plane of the bend, centre of the elbow at the origin: the centreline is the arc of radius R over the polar
angles φ ∈ [−θ/2, θ/2], continued by the straight inlet and outlet pipes tangent to it; the bore is D = 2a,
so the walls are R_i = R − a (inner) and R_o = R + a (outer). e(φ) = (cos φ, sin φ), t(φ) = (−sin φ, cos φ).

* The region on the inner side of the outer wall is the convex set C_o = {p: max_φ p·e(φ) ≤ R_o}; the inner
  wall bounds the convex set K_i = {p: max_φ p·e(φ) < R_i} that the cylinder may not enter.
* The cylinder (length L, diameter d) must turn through every axis direction t(ψ), ψ ∈ [−θ/2, θ/2]. At
  direction ψ it has the most room against the inner wall: its inner side on the tangent p·e(ψ) = R_i, its
  outer side on p·e(ψ) = R_i + d. Its length is then at most the chord of C_o common to both lines,
  ``chord(ψ)``, and the longest cylinder that passes is L* = min_ψ chord(ψ).
* Along a line p = h·e(ψ) + τ·t(ψ) the outer wall is met forward at τ_c = √(R_o² − h²) if that point lies on
  the arc (atan(τ_c/h) ≤ θ/2 − ψ), else on the outlet wall at f(θ/2 − ψ), f(δ) = (R_o − h cos δ)/sin δ;
  backward likewise with θ/2 + ψ. Both ends on the arc give the classical 2√(R_o² − (R_i + d)²).

Lengths in m, angles in rad. Floats only (this is geometry, not the muscle model).
"""

from __future__ import annotations

import math
from dataclasses import dataclass


@dataclass(frozen=True)
class Passage:
    """The longest rigid cylinder of one diameter that passes one bend, and where it binds.

    ``longest`` [m] is L* (0 when the cylinder is not narrower than the bore); it binds in the symmetric
    mid-bend position (axis direction ψ = 0), and ``where`` says where its ends lie:
    ``"mid-bend, ends on the arc"`` or ``"mid-bend, ends in the straight pipes"`` (or ``"bore"``: it does not
    fit the pipe; ``"straight"``: no bend).
    """

    longest: float  # [m]
    where: str


def _meets_arc(h: float, outer: float, room: float) -> bool:
    """True where a line at distance h [m] from the centre meets the outer circle within ``room`` [rad] of arc
    ahead of its foot: atan(τ_c/h) ≤ room, τ_c = √(R_o² − h²)."""
    return math.atan2(math.sqrt(max(outer * outer - h * h, 0.0)), h) <= room


def _end(h: float, outer: float, room: float) -> float:
    """E(h, room) [m]: distance along a line at distance h from the centre to the outer wall, with ``room``
    [rad] of arc left ahead of the line's foot: τ_c on the arc (:func:`_meets_arc`), else the straight wall,
    (R_o − h cos room)/sin room."""
    if _meets_arc(h, outer, room):
        return math.sqrt(max(outer * outer - h * h, 0.0))
    if room <= 0.0:
        return math.inf
    return (outer - h * math.cos(room)) / math.sin(room)


def chord_interval(direction: float, *, bore: float, radius: float, angle: float,
                   diameter: float) -> tuple[float, float]:
    """(τ_back, τ_front) [m]: where a cylinder of ``diameter`` d on the inner wall's tangent at direction ψ
    may lie, along t(ψ) from the tangent point R_i·e(ψ) (τ_back ≤ 0 ≤ τ_front).

    The inner side lies on p·e(ψ) = R_i, the outer side on p·e(ψ) = R_i + d; each line meets the outer wall
    backward and forward (:func:`_end`), and the interval is the overlap of the two.
    """
    a = bore / 2
    inner, outer = radius - a, radius + a
    ahead, behind = angle / 2 - direction, angle / 2 + direction
    fronts, backs = [], []
    for h in (inner, inner + diameter):
        fronts.append(_end(h, outer, ahead))
        backs.append(_end(h, outer, behind))
    return -min(backs), min(fronts)


def rigid_passage(*, bore: float, radius: float, angle: float, diameter: float) -> Passage:
    """L* = min over ψ of chord(ψ) = chord(0) = 2·E(R_i + d, θ/2) [m] (docs/physics.md §14.2).

    chord(ψ), the length of :func:`chord_interval`, is E(h, θ/2 − ψ) + E(h, θ/2 + ψ) with h = R_i + d (the
    outer side binds: E, :func:`_end`, falls with h), and E is convex and non-increasing in the room left, so
    the symmetric direction ψ = 0 binds. Both ends lie on the arc where the bend holds the classical chord
    2√(R_o² − h²), else in the straight pipes. ``bore`` D [m], ``radius`` R [m] of the centreline (R ≥ D/2),
    ``angle`` θ [rad] in (0, π], ``diameter`` d [m] of the cylinder. A straight run (θ = 0) passes any length.
    """
    if diameter >= bore:
        return Passage(0.0, "bore")
    if angle <= 0.0:
        return Passage(math.inf, "straight")
    a = bore / 2
    h, outer = radius - a + diameter, radius + a
    where = ("mid-bend, ends on the arc" if _meets_arc(h, outer, angle / 2)
             else "mid-bend, ends in the straight pipes")
    return Passage(2 * _end(h, outer, angle / 2), where)


def flexible_bend_radius(*, rest_length: float, rest_diameter: float, braid_length: float) -> float:
    """ρ_min = (D₀/2)/(B/L₀ − 1) [m]: the least centreline radius a deflated muscle bends to (§14.3).

    The centreline keeps its rest length L₀ (the fibres do not stretch and the deflated bladder buckles on
    the inner side); the outer side, D₀/2 from the centreline, is L₀(1 + D₀/(2ρ)) long and may grow only
    until its fibres lie straight along the axis, at the braid length B = L₀/cos α₀.
    """
    return rest_diameter / 2 / (braid_length / rest_length - 1)


def elbow_radius_needed(*, bore: float, angle: float, diameter: float, length: float,
                        largest: float = 100.0) -> float:
    """The least centreline radius R [m] at which a cylinder of ``length`` and ``diameter`` passes (inf if
    none up to ``largest`` bores); L* grows with R, so bisection on R ∈ [D/2, largest·D]."""
    if diameter >= bore:
        return math.inf

    def passes(radius: float) -> bool:
        return rigid_passage(bore=bore, radius=radius, angle=angle, diameter=diameter).longest >= length

    low, high = bore / 2, largest * bore
    if passes(low):
        return low
    if not passes(high):
        return math.inf
    for _ in range(50):
        mid = 0.5 * (low + high)
        if passes(mid):
            high = mid
        else:
            low = mid
    return high
