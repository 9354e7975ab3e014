"""Random arguments for the exported anchoring law, and the safety property it must keep (issue 27).

The law runs on the robot, fed by live sensors: a bore, an incline, a friction and a payload that may be
anything a broken sensor or a bad cast sends. :func:`arguments` draws rows inside the law's domain, at
its edges, just outside them and far outside (NaN, ±inf, ±1e300, angles beyond ±90°, negative bores and
frictions). :func:`unsafe_ok` is the property: an OK answer must come only for arguments inside the
domain, and with a pressure that, by `plan`'s own model (:class:`pampipe.model.muscle.Muscle`,
:func:`pampipe.model.no_slip.anchor_load`), presses on the wall and holds the load with the safety factor.
"""

from __future__ import annotations

import math

import numpy as np

from pampipe.export.law import DOMAIN, Law, Reason
from pampipe.model.no_slip import anchor_load
from pampipe.planning.problem import mission_muscles

#: Values no sensor should send, mixed into every column.
WILD = np.array([math.nan, math.inf, -math.inf, 1e300, -1e300, 1e30, -1e30, -1.0, -0.0, 0.0, 1e-300,
                 -1e-300, 4.9e-324, 1e6, -1e6])


def arguments(rng: np.random.Generator, count: int, law: Law) -> np.ndarray:
    """``count`` rows (D [m], φ [rad], μ, m [kg]): half inside the domain, half at or beyond its edges."""
    inside = np.column_stack([
        rng.uniform(0.9 * law.narrowest, 1.1 * law.widest, count),
        rng.uniform(-math.pi / 2, math.pi / 2, count),
        rng.uniform(0.0, 1.5, count),
        rng.uniform(0.0, 50.0, count)])
    edges = np.array([[law.narrowest, law.widest, 10.0, 10.0 + 1e-12],  # D at and beyond its limits
                      [-math.pi / 2, math.pi / 2, np.nextafter(math.pi / 2, 4), 3.0],  # φ
                      [0.0, 10.0, np.nextafter(10.0, 20), -1e-12],  # μ
                      [0.0, 1e5, np.nextafter(1e5, 2e5), -1e-12]])  # m
    outside = inside.copy()
    for column, (low, high, _) in enumerate(DOMAIN.values()):
        pick = rng.random(count) < 0.5
        span = max(high - low, 1.0)
        beyond = np.where(rng.random(count) < 0.5, low - rng.exponential(span, count),
                          high + rng.exponential(span, count))
        choice = rng.integers(0, 3, count)
        value = np.where(choice == 0, beyond, np.where(choice == 1, rng.choice(WILD, count),
                                                       rng.choice(edges[column], count)))
        outside[:, column] = np.where(pick, value, outside[:, column])
    rows = np.where((rng.random(count) < 0.5)[:, None], inside, outside)
    return rows


def in_domain(rows: np.ndarray) -> np.ndarray:
    """Row mask: every argument finite and within :data:`pampipe.export.law.DOMAIN` (written out again)."""
    d, phi, mu, m = rows.T
    with np.errstate(invalid="ignore"):
        return ((d > 0) & (d <= 10) & (np.abs(phi) <= math.pi / 2) & (mu >= 0) & (mu <= 10)
                & (m >= 0) & (m <= 1e5))


def unsafe_ok(mission, rows: np.ndarray, codes: np.ndarray, pressure: np.ndarray, *,
              rtol: float = 1e-9) -> np.ndarray:
    """Row mask of OK answers that are unsafe: outside the domain, or slipping or off the wall by the model.

    With M the robot's mass plus the payload, segment i anchored alone must satisfy, at its pressure P:
    P ≥ P_a(κW) (it presses on the wall) and μπF_r(P, D, κW) ≥ SF·W, W = g(M|sin φ| + μ cos φ (M − m_i))
    + tether drag, to ``rtol`` (the closed form and the model differ by rounding only).
    """
    ok = codes == int(Reason.OK)
    bad = ok & ~in_domain(rows)
    good = ok & ~bad
    if not np.any(good):
        return bad
    d, phi, mu, payload = rows[good].T
    total = sum(s.mass for s in mission.segments) + payload
    for i, (segment, muscle) in enumerate(zip(mission.segments, mission_muscles(mission), strict=True)):
        p = pressure[good, i]
        load = anchor_load(total, segment.mass, phi, mu, mission.tether_drag)
        hold = muscle.holding_capacity(p, d, load, kappa=mission.kappa, friction=mu)
        contact = muscle.anchoring_pressure(d, mission.kappa * load)
        slips = ~(hold >= mission.safety_factor * load * (1 - rtol))
        off_wall = ~(p >= contact - rtol * np.maximum(np.abs(contact), 1e3))
        unsafe = np.zeros_like(ok)
        unsafe[good] = slips | off_wall | ~np.isfinite(p)
        bad |= unsafe
    return bad
