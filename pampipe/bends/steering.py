"""The steering module's least-pressure command for a bend (docs/physics.md §14.4).

Three extensile PAMs in parallel at radius r from the module's axis, PAM k at φ_k = 2π(k − 1)/3. With
constant curvature κ toward the direction φ_b (the centre of the turn), PAM k is L_k = L_c(1 − κ r
cos(φ_k − φ_b)) long, L_c the mean; hence κ_x = −2 Σ L_k cos φ_k / (3 r L_c), κ_y likewise with sin.
Each length is the free length of the same braid/bladder model at zero axial load, F_ax(P_k, L_k) = 0
(:class:`pampipe.model.muscle.Muscle`). Two NLPs, built once per muscle structure and fed through ``p``:

* least pressure: min Σ P_k subject to κ = κ* along φ_b and 0 across it, 0 ≤ P_k ≤ supply;
* most curvature: max κ along φ_b subject to 0 across it (where κ* cannot be reached: what can).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cache

import numpy as np

from pampipe.errors import SolverError
from pampipe.model.muscle import Muscle, Structure

COUNT = 3
#: Pressure scale of the decision variables [Pa] (the NLP works in bar).
PRESSURE_SCALE = 1e5
#: Strain margin below the braid's limit B/√3, where the extensile force vanishes.
LIMIT_MARGIN = 1e-6
#: Curvature agreement (relative) at which a bend counts as reached by the most-curvature solve.
REACHED = 1e-6


@dataclass(frozen=True)
class SteeringCommand:
    """The triad command for one bend: pressures [Pa], lengths [m], the curvature reached [1/m].

    ``reached`` is False where no pressures up to the supply reach κ*; ``reason`` then says why (the supply
    or the braid's limit) and the pressures are those of the largest curvature the module can reach.
    """

    pressures: tuple[float, ...]
    lengths: tuple[float, ...]
    curvature: float  # [1/m] reached along the bend's direction
    target: float  # [1/m] κ* = 1/R
    reached: bool
    reason: str | None

    @property
    def fills(self) -> tuple[int, ...]:
        """The PAMs (1 to 3) the command fills: those above zero pressure, on the outside of the turn."""
        return tuple(k + 1 for k, pressure in enumerate(self.pressures) if pressure > 0)

    def as_document(self) -> dict:
        return {"pressures_Pa": list(self.pressures), "lengths_m": list(self.lengths),
                "fills": list(self.fills),
                "curvature_1_per_m": self.curvature, "target_curvature_1_per_m": self.target,
                "reached": self.reached, "reason": self.reason}


def curvature_of_lengths(lengths, radius: float) -> float:
    """κ = 2√(ΣL_k² − L₁L₂ − L₂L₃ − L₃L₁) / (r ΣL_k) [1/m] of three parallel actuators 120° apart
    (Webster & Jones 2010, Eq. 8)."""
    a, b, c = (float(v) for v in lengths)
    return 2 * math.sqrt(max(a * a + b * b + c * c - a * b - b * c - c * a, 0.0)) / (radius * (a + b + c))


def _angles() -> np.ndarray:
    return 2 * np.pi * np.arange(COUNT) / COUNT


@cache
def _solvers(structure: Structure):
    """(least-pressure, most-curvature) IPOPT solvers for muscles of ``structure``; x = [P/1e5 (3), ε (3)],
    L_k = L₀(1 + ε_k); p = [muscle parameters, κ*, cos φ_b, sin φ_b, r]."""
    import casadi as ca

    from pampipe.runtime import ipopt as nlp

    sym = Muscle.symbolic(structure)
    x = ca.SX.sym("x", 2 * COUNT)
    q = ca.SX.sym("q", 4)
    target, cos_b, sin_b, radius = q[0], q[1], q[2], q[3]
    l0 = sym.muscle.geometry.initial_length
    pressure = PRESSURE_SCALE * x[:COUNT]
    length = l0 * (1 + x[COUNT:])
    force = ca.vertcat(*[sym.muscle.axial_force(pressure[k], length[k]) for k in range(COUNT)])
    mean = ca.sum1(length) / COUNT
    phi = _angles()
    kx = -2 * sum(length[k] * math.cos(phi[k]) for k in range(COUNT)) / (3 * radius * mean)
    ky = -2 * sum(length[k] * math.sin(phi[k]) for k in range(COUNT)) / (3 * radius * mean)
    along, across = kx * cos_b + ky * sin_b, -kx * sin_b + ky * cos_b
    p = ca.vertcat(sym.p, q)
    least = nlp.nlpsol("steering_least_pressure", {
        "x": x, "p": p, "f": ca.sum1(x[:COUNT]),
        "g": ca.vertcat(force, radius * (along - target), radius * across)})
    most = nlp.nlpsol("steering_most_curvature", {
        "x": x, "p": p, "f": -radius * along + 1e-6 * ca.sum1(x[:COUNT]),
        "g": ca.vertcat(force, radius * across)})
    return least, most


def steer(muscle: Muscle, *, curvature: float, direction: float, radius: float,
          supply: float) -> SteeringCommand:
    """The least-pressure triad that bends the module to ``curvature`` κ* [1/m] toward ``direction`` φ_b
    [rad] (from PAM 1 toward PAM 2), PAMs at ``radius`` r [m], pressures at most ``supply`` [Pa]."""
    from pampipe.runtime import ipopt as nlp  # CasADi: loaded only when a bend needs steering

    g = muscle.geometry
    least, most = _solvers(muscle.structure)
    limit = g.shortest_length / g.initial_length - 1 - LIMIT_MARGIN  # B/√3 over L₀, minus one
    p = np.concatenate([muscle.parameter_vector(),
                        [curvature, math.cos(direction), math.sin(direction), radius]])
    bounds = {"lbx": [0.0] * COUNT + [0.0] * COUNT,
              "ubx": [supply / PRESSURE_SCALE] * COUNT + [limit] * COUNT}
    start = _start(curvature, direction, radius, limit)
    best, _ = nlp.solve(most, what="the steering module's largest curvature", x0=start, p=p,
                        lbg=[0.0] * (COUNT + 1), ubg=[0.0] * (COUNT + 1), **bounds)
    most_bent = _command(best["x"], g.initial_length, radius, curvature, direction, True, None)
    if most_bent.curvature >= curvature * (1 - REACHED):
        try:
            solution, _ = nlp.solve(least, what="the steering module's least-pressure command",
                                    x0=np.asarray(best["x"]).ravel(), p=p, lbg=[0.0] * (COUNT + 2),
                                    ubg=[0.0] * (COUNT + 2), **bounds)
            return _command(solution["x"], g.initial_length, radius, curvature, direction, True, None)
        except SolverError:
            return most_bent  # κ* is at the edge of what the module reaches: the most-curvature point
    x = np.asarray(best["x"]).ravel()
    at_supply = bool(np.any(x[:COUNT] * PRESSURE_SCALE >= supply * (1 - 1e-4)))
    at_braid = bool(np.any(x[COUNT:] >= limit * (1 - 1e-4)))
    reason = _reason(most_bent, supply, at_supply, at_braid, g.shortest_length)
    return SteeringCommand(most_bent.pressures, most_bent.lengths, most_bent.curvature, curvature, False,
                           reason)


def _reason(command: SteeringCommand, supply, at_supply, at_braid, braid_limit) -> str:
    reachable, curvature = command.curvature, command.target
    radius_text = f"a bend radius of {1e3 / reachable:.4g} mm" if reachable > 0 else "no bend"
    if at_braid:
        why = f"the braid's limit (an extensile PAM stops at B/sqrt(3) = {braid_limit * 1e3:.4g} mm)"
    elif at_supply:
        why = f"the supply ({supply / 1e3:.4g} kPa)"
    else:
        why = (f"the bladder: the model's free length saturates near {max(command.lengths) * 1e3:.4g} "
               f"mm (at {max(command.pressures) / 1e3:.4g} kPa), short of B/sqrt(3) = "
               f"{braid_limit * 1e3:.4g} mm")
    return (f"the module reaches at most {reachable:.4g} 1/m ({radius_text}) of the {curvature:.4g} 1/m "
            f"the bend needs (radius {1e3 / curvature:.4g} mm); limited by {why}")


def _command(x, l0, radius, target, direction, reached, reason) -> SteeringCommand:
    x = np.asarray(x, dtype=float).ravel()
    pressures = x[:COUNT] * PRESSURE_SCALE
    pressures = np.where(pressures < 1.0, 0.0, pressures)  # IPOPT leaves ~1e-6 Pa at a zero bound
    lengths = l0 * (1 + x[COUNT:])
    phi = _angles()
    mean = lengths.mean()
    kx = -2 * np.sum(lengths * np.cos(phi)) / (3 * radius * mean)
    ky = -2 * np.sum(lengths * np.sin(phi)) / (3 * radius * mean)
    along = kx * math.cos(direction) + ky * math.sin(direction)
    return SteeringCommand(tuple(pressures.tolist()), tuple(lengths.tolist()), float(along), target, reached,
                           reason)


def _start(curvature, direction, radius, limit) -> np.ndarray:
    """A start: the PAMs on the outside of the turn at a mid pressure, the others at rest."""
    phi = _angles()
    outside = -np.cos(phi - direction)  # > 0 on the outside of the turn
    pressure = np.where(outside > 0, 1.0, 0.0)
    strain = np.clip(np.where(outside > 0, curvature * radius * outside, 0.0), 0.0, 0.5 * limit)
    return np.concatenate([pressure, strain])
