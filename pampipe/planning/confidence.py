"""Pressure that holds with probability C under model and friction uncertainty (first order).

Sources: the covariance Σ_θ of the moduli θ written by `identify` (``Pam.covariance`` [Pa²]), the
standard deviation σ_μ of a section's wall friction (``friction: {value, sd}``) and that of its bore σ_D
(``inner_diameter: {value, sd}``). With the no-slip margin g(P; θ, μ, D) = μπF_r(P, D, κW(μ); θ) − SF·W(μ),
first-order propagation gives
    E[g] ≈ g(P; θ̂, μ̂, D̂),   Var[g] ≈ ∇_θg Σ_θ ∇_θgᵀ + (∂_μ g)² σ_μ² + (∂_D g)² σ_D²,
and the pressure that holds with probability C is the least P with E[g] − z_C·√Var[g] ≥ 0,
z_C = Φ⁻¹(C). At C = 0.5 this is the nominal plan. The probability is per segment and section
(each anchor separately), with the safety factor kept inside the requirement. D̂ is the element's
worst bore (the nominal bore without a tolerance). The gradients come from one CasADi function per
muscle structure, built once and mapped over the sections.
"""

from __future__ import annotations

import math
from functools import cache
from statistics import NormalDist

import casadi as ca
import numpy as np

from pampipe.errors import InputError
from pampipe.model import slip
from pampipe.model.muscle import PRESSURE_LIMIT, Muscle, Structure


@cache
def margin_function(structure: Structure) -> ca.Function:
    """(P, D, φ, μ, M, m_anchor, tether, κ, SF, p_muscle) → (g [N], ∂g/∂θ, ∂g/∂μ, ∂g/∂D), one structure."""
    names = ("pressure", "diameter", "incline", "friction", "total_mass", "anchor_mass", "tether_drag",
             "kappa", "safety_factor")
    p, d, phi, mu, mass, m_anchor, tether, kappa, sf = (ca.SX.sym(n) for n in names)
    sym = Muscle.symbolic(structure)
    load = slip.anchor_load(mass, m_anchor, phi, mu, tether)
    margin = sym.muscle.holding_capacity(p, d, load, kappa=kappa, friction=mu) - sf * load
    return ca.Function("slip_margin", [p, d, phi, mu, mass, m_anchor, tether, kappa, sf, sym.p],
                       [margin, ca.jacobian(margin, sym.muscle.theta), ca.jacobian(margin, mu),
                        ca.jacobian(margin, d)])


def z_value(confidence: float) -> float:
    """z_C = Φ⁻¹(C) for 0.5 ≤ C < 1."""
    if not (0.5 <= confidence < 1):
        raise InputError(f"--confidence: {confidence!r} must be a probability in [0.5, 1), e.g. 0.95.")
    return NormalDist().inv_cdf(confidence)


def check_uncertainty(mission) -> None:
    """--confidence needs at least one source of uncertainty, and muscles without diagnosed effects."""
    diagnosed = [seg.pam.name for seg in mission.segments if seg.pam.effects]
    if diagnosed:
        raise InputError(
            f"{mission.source}: --confidence does not yet propagate uncertainty through diagnosed effects; "
            f"the PAM(s) {', '.join(sorted(set(diagnosed)))} carry an 'effects:' block. Plan without "
            "--confidence, or use the PAM file written by `pampipe identify`.")
    route = mission.route
    if all(seg.pam.covariance is None for seg in mission.segments) and not (
            np.any(route.friction_sd > 0) or np.any(route.diameter_sd > 0)):
        raise InputError(
            f"{mission.source}: --confidence needs an uncertainty: no PAM file has an 'uncertainty:' "
            "covariance block (written by `pampipe identify`) and no route section gives "
            "'friction: {value: 0.3, sd: 0.05}' or 'inner_diameter: {value: 3 in, sd: 0.5 mm}'.")


class _Segment:
    """Mapped margin of one segment over all sections, with its uncertainty."""

    def __init__(self, mission, muscle: Muscle, index: int, diameter: np.ndarray):
        seg = mission.segments[index]
        route = mission.route
        self.sections = len(route)
        self.function = margin_function(muscle.structure).map(self.sections)
        self.row = lambda values: np.asarray(values, dtype=float).reshape(1, -1)
        total = sum(s.mass for s in mission.segments) + mission.payload
        self.fixed = [self.row(diameter), self.row(route.incline), self.row(route.friction), total, seg.mass,
                      mission.tether_drag, mission.kappa, mission.safety_factor, muscle.parameter_vector()]
        n = muscle.structure.n_theta
        self.covariance = seg.pam.covariance if seg.pam.covariance is not None else np.zeros((n, n))
        self.friction_sd = np.asarray(route.friction_sd, dtype=float)
        self.diameter_sd = np.asarray(route.diameter_sd, dtype=float)

    def lower_limit(self, pressure: np.ndarray, z: float) -> np.ndarray:
        """E[g] − z·√Var[g] [N] at the given pressures (one per section)."""
        margin, d_theta, d_mu, d_d = (np.asarray(v) for v in self.function(self.row(pressure), *self.fixed))
        d_theta = d_theta.reshape(self.sections, -1)
        variance = (np.einsum("si,ij,sj->s", d_theta, self.covariance, d_theta)
                    + (d_mu.ravel() * self.friction_sd) ** 2 + (d_d.ravel() * self.diameter_sd) ** 2)
        return margin.ravel() - z * np.sqrt(np.maximum(variance, 0.0))


def confidence_pressure(mission, muscles, nominal: np.ndarray, confidence: float, *, diameter: np.ndarray,
                        iterations: int = 60):
    """Least P ≥ P_nominal [Pa] holding with probability C, per element (S, 3); inf if none ≤ 100 MPa.

    ``diameter`` [m] is each element's bore (S, 3): its worst bore in the range.
    """
    z = z_value(confidence)
    check_uncertainty(mission)
    out = np.array(nominal, dtype=float)
    for i in range(len(mission.segments)):
        col = np.isfinite(nominal[:, i])
        if z == 0 or not col.any():
            continue
        seg = _Segment(mission, muscles[i], i, diameter[:, i])
        low = np.where(col, nominal[:, i], 1.0)
        high = np.maximum(1.1 * low, low + 1e4)
        for _ in range(int(math.log2(PRESSURE_LIMIT / 1e4)) + 1):  # grow the bracket up to 100 MPa
            short = col & (seg.lower_limit(high, z) < 0) & (high < PRESSURE_LIMIT)
            if not short.any():
                break
            high = np.where(short, np.minimum(2 * high, PRESSURE_LIMIT), high)
        reachable = col & (seg.lower_limit(high, z) >= 0)
        for _ in range(iterations):
            mid = 0.5 * (low + high)
            ok = seg.lower_limit(mid, z) >= 0
            high, low = np.where(ok, mid, high), np.where(ok, low, mid)
        out[:, i] = np.where(reachable, high, np.where(col, np.inf, nominal[:, i]))
    return out
