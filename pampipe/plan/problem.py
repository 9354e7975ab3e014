"""The planning problem of one mission, as per-element arrays (docs/physics.md §5, §7, §8).

An *element* is one (section s, segment i) pair. The gait of docs/physics.md §8 anchors, in steps
I…VII, the segments {2}, {1,2}, {1}, {1,3}, {3}, {2,3}, {2}: every segment is the only anchor in
some step, so in every section each segment must hold the section's whole load alone.

* Load on the single anchor i in section s (incline φ, wall friction μ, M = segment masses + payload):
  W = g·(M·|sin φ| + μ·cos φ·(M − m_i)) + tether_drag  [N]  (:func:`pampipe.model.slip.incline_load`).
* No slip: μπF_r(P, D_s, κW) ≥ SF·W, asked of the segment's :class:`~pampipe.model.muscle.Muscle`.
* Contact: P ≥ max(P_a(κW), 0), the pressure at which the loaded muscle presses on the wall.
"""

from __future__ import annotations

from dataclasses import dataclass
from operator import attrgetter

import numpy as np

from pampipe.model.muscle import Anchored, Muscle
from pampipe.model.slip import STANDARD_GRAVITY, incline_load

#: Sections per pass over the element table: a pass's temporaries stay in cache, so memory is the
#: table itself, linear in elements (benchmarks/bench_plan.py).
CHUNK = 1 << 14


def chunks(count: int):
    """Slices of at most :data:`CHUNK` sections covering ``range(count)``."""
    return (slice(start, min(start + CHUNK, count)) for start in range(0, count, CHUNK))


@dataclass(frozen=True)
class Elements:
    """Per-element arrays of shape (sections, segments), SI; invalid elements hold finite placeholders.

    Each array is the transposed view of a (segments, sections) block, so that a segment's column is
    contiguous; arrays equal for every segment (``friction``, ``load_per_payload``, and ``diameter``
    where every element is valid) are broadcast views. ``amplification``, ``at_zero``, ``slope`` and
    the contact terms are the muscles' :meth:`~pampipe.model.muscle.Muscle.affine_coefficients`
    (NaN for a muscle with effects, which has none; the contact terms are None if no muscle has them).
    """

    diameter: np.ndarray  # D_s [m] (a placeholder inside the muscle's range where invalid)
    length: np.ndarray  # anchored length L_p = L(D_s) [m]
    volume: np.ndarray  # V(L_p) = πD²L/4 [m³], the air the segment takes per pascal
    load: np.ndarray  # W [N], required hold
    load_per_payload: np.ndarray  # ∂W/∂payload = g(|sin φ| + μ cos φ) [N/kg]
    friction: np.ndarray  # μ [-]
    anchoring: np.ndarray  # P_a(κW) [Pa]: the loaded muscle reaches the wall
    free_anchoring: np.ndarray  # P_a(0) [Pa]: the unloaded muscle reaches the wall
    kappa: float  # κ of the load path
    safety_factor: float  # SF
    valid: np.ndarray  # inside the model's domain: D₀ < D < D(B/√3) and μ > 0
    amplification: np.ndarray  # A(D_s) [-]
    at_zero: np.ndarray  # F₀ = F_ax(0, L_p) [N]
    slope: np.ndarray  # F₁ = ∂_P F_ax(L_p) [N/Pa]
    contact_at_zero: np.ndarray | None  # C₀ [N]
    contact_slope: np.ndarray | None  # C₁ [N/Pa]
    affine: tuple[bool, ...]  # per segment: its muscle has affine coefficients (no effects)

    @property
    def lower_bound(self) -> np.ndarray:
        """Contact constraint as a bound: P ≥ max(P_a(κW), 0) [Pa]."""
        return np.maximum(self.anchoring, 0.0)

    def coefficients(self, segment: int, index=slice(None)) -> Anchored | None:
        """The :class:`~pampipe.model.muscle.Anchored` coefficients of one segment at the sections
        ``index`` selects (None for a muscle with effects)."""
        if not self.affine[segment]:
            return None
        contact = [0.0 if c is None else c[index, segment]
                   for c in (self.contact_at_zero, self.contact_slope)]
        return Anchored(self.length[index, segment], self.amplification[index, segment],
                        self.at_zero[index, segment], self.slope[index, segment], *contact)


def mission_muscles(mission) -> tuple[Muscle, ...]:
    """The muscle of every segment, rear to front (InputError if a PAM has no moduli)."""
    return tuple(Muscle.from_pam(seg.pam, where=f"{mission.source}: robot.segments[{i}].pam")
                 for i, seg in enumerate(mission.segments))


def route_columns(route) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(diameter [m], incline [rad], friction) arrays of a route: a sequence of
    :class:`~pampipe.mission.Section`, or columns that carry those three arrays as attributes.
    """
    keys = ("diameter", "incline", "friction")
    if all(hasattr(route, key) for key in keys):
        return tuple(np.asarray(getattr(route, key), dtype=float) for key in keys)
    return tuple(np.fromiter(map(attrgetter(key), route), dtype=float, count=len(route)) for key in keys)


def build_elements(mission, muscles: tuple[Muscle, ...], *, payload: float | None = None,
                   route=None) -> Elements:
    """Evaluate the muscles once per element for ``mission`` (payload [kg] overrides the mission's;
    ``route``, columns as :func:`route_columns` reads them, overrides its route).

    A muscle without effects is evaluated once per element (:meth:`Muscle.affine_coefficients`) and
    everything else follows from its coefficients; sin φ and cos φ are taken once per section; the
    work runs over :data:`CHUNK` sections at a time.
    """
    payload = mission.payload if payload is None else float(payload)
    diameter, incline, friction = route_columns(mission.route if route is None else route)
    count, segments = diameter.shape[0], len(muscles)
    total_mass = sum(seg.mass for seg in mission.segments) + payload
    valid = np.empty((segments, count), dtype=bool)
    for i, muscle in enumerate(muscles):
        g = muscle.geometry
        np.logical_and(diameter > g.initial_diameter, diameter < g.largest_diameter, out=valid[i])
        valid[i] &= friction > 0
    shared_diameter = bool(valid.all())
    affine = tuple(not m.has_effects for m in muscles)
    contact = any(m.contact is not None for m, a in zip(muscles, affine, strict=True) if a)
    keys = ["length", "volume", "load", "anchoring", "free_anchoring", "amplification", "at_zero", "slope"]
    keys += [] if shared_diameter else ["diameter"]
    keys += ["contact_at_zero", "contact_slope"] if contact else []
    blocks = {key: np.empty((segments, count)) for key in keys}
    per_kg = np.empty(count)
    for part in chunks(count):
        d, mu = diameter[part], friction[part]
        rise, run = np.abs(np.sin(incline[part])), np.cos(incline[part])
        per_kg[part] = STANDARD_GRAVITY * (rise + mu * run)
        for i, (seg, muscle) in enumerate(zip(mission.segments, muscles, strict=True)):
            g = muscle.geometry
            safe = d if shared_diameter else np.where(valid[i, part], d, 0.5 * (g.initial_diameter
                                                                                 + g.largest_diameter))
            load = incline_load(total_mass, seg.mass, rise, run, mu, mission.tether_drag)
            values = {"load": load}
            if affine[i]:
                c = muscle.affine_coefficients(safe)
                values.update(length=c.length, amplification=c.amplification, at_zero=c.at_zero,
                              slope=c.slope)
                if contact:
                    values.update(contact_at_zero=c.contact_at_zero, contact_slope=c.contact_slope)
            else:
                c = None
                values.update(length=muscle.anchored_length(safe), amplification=np.nan, at_zero=np.nan,
                              slope=np.nan, contact_at_zero=np.nan, contact_slope=np.nan)
            values.update(volume=muscle.enclosed_volume(values["length"]), diameter=safe,
                          anchoring=muscle.anchoring_pressure(safe, mission.kappa * load, anchored=c),
                          free_anchoring=muscle.anchoring_pressure(safe, 0.0, anchored=c))
            for key, block in blocks.items():
                block[i, part] = values[key]
    columns = {key: block.T for key, block in blocks.items()}
    for key, value in (("friction", friction), ("load_per_payload", per_kg), ("diameter", diameter)):
        columns.setdefault(key, np.broadcast_to(value[:, None], (count, segments)))
    columns.setdefault("contact_at_zero", None)
    columns.setdefault("contact_slope", None)
    return Elements(**columns, kappa=mission.kappa, safety_factor=mission.safety_factor, valid=valid.T,
                    affine=affine)
