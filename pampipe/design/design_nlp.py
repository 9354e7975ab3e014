"""The design NLP, built once per (material structure, objective, number of groups) from the symbolic Muscle.

Decision variables x = (u_L, u_D, u_α, t): the rest length, rest diameter and braid angle as
fractions of their bounds (L₀ = L_lo + u_L (L_hi − L_lo), …) and the epigraph variable t = P/P_s
(P_s the supply pressure). The bladder material (moduli θ, P_ref, contact increments, wall
thickness t₀) and the groups of :mod:`pampipe.design.groups` enter through the parameter ``p``, so
one solver serves every inventory of the same material structure.

For every group g (bore D, friction μ, loads W), with F_ax(P, L_p) = F₀ + F₁P at L_p = L(D) and
P*(W) = :meth:`Muscle.required_pressure` (docs/physics.md §7, §8):

    P*(W_max)/P_s − t ≤ 0                  every segment holds with the safety factor at ≤ t·P_s
    F₁/D² > 0, b(W_min)/D² > 0, b(W_max)/D² > 0   the pressure grips (b: slope above contact, §9d)
    (1 − m)·D(B/√3)/D − 1 ≥ 0              contact margin: D(B/√3) = D₀√(2/3)/sin α₀ (§2)
    (L₀ − L_p − s_min)/L₀ ≥ 0              the stride per cycle is at least s_min (§8)
    E₁ᵗ, E₂ᵗ ≥ 0 at (ε(L_p), 0) and (ε(L_p), P_s)   the moduli law is stable at the anchored strain (§6)

and the clearance D₀ ≤ D_min − c is a bound on u_D. The objective is t (``max_pressure``, the
epigraph of max P*), or the ``air`` or ``speed`` sums of :class:`pampipe.specs.inventory.Objective` with
t fixed at 1 (every pressure ≤ supply). Rows of unused or objective-only groups have no bounds.
"""

from __future__ import annotations

import math
from functools import cache

import casadi as ca
import numpy as np

from pampipe.design.groups import COLUMNS
from pampipe.model import ops
from pampipe.model.muscle import Muscle, Structure
from pampipe.model.pam import Geometry, Pam
from pampipe.runtime import ipopt as nlp
from pampipe.specs.inventory import Objective

#: Constraint rows per group, in the order of :func:`group_rows`.
ROWS = ("pressure", "slope", "grip_light", "grip_heavy", "reach", "stride", "axial_stability_0",
        "axial_stability_supply", "hoop_stability_0", "hoop_stability_supply")
#: Lower bounds of the rows (the pressure row is an upper bound: ≤ 0).
GRIP_FLOOR = 1e-6  # F₁/D² > 0 with a margin far below any real muscle's (≈ 0.1 … 1)
ROW_LOWER = (-math.inf, GRIP_FLOOR, GRIP_FLOOR, GRIP_FLOOR, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
ROW_UPPER = (0.0, *(math.inf,) * (len(ROWS) - 1))
SPACE = 6  # L_lo, L_hi, D_lo, D_hi, α_lo, α_hi
GLOBALS = ("kappa", "safety_factor", "supply", "contact_margin", "min_stride", "segments", "air_norm",
           "speed_norm")
MODULI_SCALE = 1e6  # [Pa] tangent moduli are compared in MPa
IPOPT_OPTIONS = {"tol": 1e-10, "max_iter": 400}


def material_structure(pam: Pam) -> Structure:
    """The NLP's key for a material: wall model, moduli degree and whether contact increments exist."""
    m = pam.moduli
    return Structure(pam.geometry.wall, m.degree, bool(np.any(m.contact_vector())))


def material_vector(pam: Pam) -> np.ndarray:
    """[t₀, P_ref, θ, (Δθ)]: the material's entries of ``p``."""
    m = pam.moduli
    parts = [[pam.geometry.bladder_thickness, m.reference_pressure], m.as_vector()]
    if material_structure(pam).contact:
        parts.append(m.contact_vector())
    return np.concatenate([np.asarray(v, dtype=float) for v in parts])


def design_geometry(u, space, thickness, wall: str) -> Geometry:
    """The muscle's geometry at the fractions ``u`` of the bounds ``space`` (floats, arrays or symbols)."""
    return Geometry(space[0] + (space[1] - space[0]) * u[0], space[2] + (space[3] - space[2]) * u[1],
                    space[4] + (space[5] - space[4]) * u[2], thickness, wall)


def design_muscle(u, space, material, structure: Structure) -> Muscle:
    """The designed muscle: geometry from ``u`` and ``space``, moduli from the material vector."""
    n = structure.n_theta
    contact = material[2 + n:2 + 2 * n] if structure.contact else None
    return Muscle(design_geometry(u, space, material[0], structure.wall), material[2:2 + n], material[1],
                  contact=contact)


def group_rows(u, space, material, q, glob, structure: Structure):
    """(constraint rows of :data:`ROWS`, air term [J], speed term [-]) of one group; floats or symbols."""
    muscle = design_muscle(u, space, material, structure)
    g = muscle.geometry
    diameter, friction, load_max, load_min, load_mean, length = (q[i] for i in range(len(COLUMNS)))
    kappa, safety_factor, supply, margin, min_stride, segments = (glob[i] for i in range(6))
    c = muscle.affine_coefficients(diameter)
    pref = muscle.reference_pressure

    def required(load):
        return muscle.required_pressure(diameter, load, kappa=kappa, friction=friction,
                                        safety_factor=safety_factor)

    def grip(load):
        anchoring = (kappa * load - c.at_zero) / c.slope
        return (c.slope + (c.contact_at_zero + c.contact_slope * anchoring) / pref) / diameter**2

    stride = g.initial_length - c.length
    reach = (1 - margin) * math.sqrt(2 / 3) * g.initial_diameter / ops.sin(g.braid_angle)
    stable = [v / MODULI_SCALE for p in (0.0 * supply, supply)
              for v in muscle.drucker_tangent_moduli(p, c.length)]
    rows = [required(load_max) / supply, c.slope / diameter**2, grip(load_min), grip(load_max),
            reach / diameter - 1, (stride - min_stride) / g.initial_length,
            stable[0], stable[2], stable[1], stable[3]]
    air = segments * length * required(load_mean) * muscle.enclosed_volume(c.length) / stride
    return rows, air, length / stride


@cache
def group_function(structure: Structure) -> ca.Function:
    """(u, space, material, q, glob) → (rows, air, speed) of one group, as a CasADi SX function."""
    n_material = 2 + structure.n_theta * (2 if structure.contact else 1)
    u, space = ca.SX.sym("u", 3), ca.SX.sym("space", SPACE)
    material = ca.SX.sym("material", n_material)
    q, glob = ca.SX.sym("q", len(COLUMNS)), ca.SX.sym("glob", len(GLOBALS))
    rows, air, speed = group_rows(u, space, material, q, glob, structure)
    return ca.Function("design_group", [u, space, material, q, glob], [ca.vertcat(*rows), air, speed])


@cache
def build(structure: Structure, objective: Objective, size: int) -> tuple[ca.Function, ca.Function]:
    """(IPOPT solver, (x, p) → (f, g) evaluator) for ``size`` groups; built once per process and key."""
    group = group_function(structure)
    n_material = group.size1_in(2)
    x = ca.MX.sym("x", 4)
    p = ca.MX.sym("p", SPACE + n_material + len(COLUMNS) * size + len(GLOBALS))
    space = p[:SPACE]
    material = p[SPACE:SPACE + n_material]
    q = ca.reshape(p[SPACE + n_material:SPACE + n_material + len(COLUMNS) * size], len(COLUMNS), size)
    glob = p[-len(GLOBALS):]
    rows, air, speed = group.map(size)(x[:3], space, material, q, glob)
    rows = ca.vertcat(rows[0, :] - x[3], rows[1:, :])
    g = ca.vec(rows.T)  # row kind major: all groups' pressure rows first, then all slope rows, ...
    if objective is Objective.MAX_PRESSURE:
        f = x[3]
    elif objective is Objective.AIR:
        f = glob[GLOBALS.index("air_norm")] * ca.sum2(air)
    else:
        f = glob[GLOBALS.index("speed_norm")] * ca.sum2(speed)
    problem = {"x": x, "p": p, "f": f, "g": g}
    # the starts may leave the model's domain (NaN); IPOPT then backs off, and CasADi need not warn
    solver = nlp.nlpsol(f"design_{objective.value}", problem, ipopt=IPOPT_OPTIONS)
    return solver, ca.Function("design_fg", [x, p], [f, g])


def constraint_bounds(active: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(lbg, ubg) for groups whose rows are ``active`` (bool, one per group row of the block)."""
    lower = np.where(active[None, :], np.array(ROW_LOWER)[:, None], -np.inf)
    upper = np.where(active[None, :], np.array(ROW_UPPER)[:, None], np.inf)
    return lower.ravel(), upper.ravel()
