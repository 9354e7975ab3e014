"""Whole-array evaluation: the free-contraction root, and prebuilt CasADi functions built once.

The prebuilt functions take the geometry vector g = [L₀, D₀, α₀, t₀] and the moduli θ as inputs, so
one build serves every muscle of a given wall model and moduli degree. Called with 1×n rows for
the scalar inputs they evaluate n points at once.
"""

from __future__ import annotations

from functools import cache

import casadi as ca
import numpy as np

from pampipe.errors import SolverError
from pampipe.model import forces
from pampipe.model.pam import Geometry, Wall


def symbolic_geometry(wall: Wall) -> tuple[ca.SX, Geometry]:
    """A 4-vector symbol g and the Geometry whose fields are its entries."""
    g = ca.SX.sym("geometry", 4)
    return g, Geometry(g[0], g[1], g[2], g[3], wall)


@cache
def radial_force_function(wall: Wall, degree: int) -> ca.Function:
    """F_r(P, D_p, F_a, g, θ, Δθ, P_ref) [N], contact switch and contact increments included."""
    pressure, diameter, load, pref = (ca.SX.sym(n) for n in ("pressure", "diameter", "axial_load",
                                                            "reference_pressure"))
    g, geometry = symbolic_geometry(wall)
    n = 4 * (degree + 1)
    theta, contact = ca.SX.sym("theta", n), ca.SX.sym("contact", n)
    radial = forces.radial_force(pressure, diameter, geometry, theta, pref, load, contact)
    return ca.Function("radial_force", [pressure, diameter, load, g, theta, contact, pref], [radial],
                       ["pressure", "diameter", "axial_load", "geometry", "theta", "contact",
                        "reference_pressure"], ["radial_force"])


@cache
def axial_force_function(wall: Wall, degree: int) -> ca.Function:
    """F_ax(P, L, g, θ, P_ref) [N] (Eq. 9)."""
    pressure, length, pref = ca.SX.sym("pressure"), ca.SX.sym("length"), ca.SX.sym("reference_pressure")
    g, geometry = symbolic_geometry(wall)
    theta = ca.SX.sym("theta", 4 * (degree + 1))
    force = forces.axial_force(pressure, length, geometry, theta, pref)
    return ca.Function("axial_force", [pressure, length, g, theta, pref], [force],
                       ["pressure", "length", "geometry", "theta", "reference_pressure"],
                       ["axial_force"])


def free_length(pressure, geometry: Geometry, theta, reference_pressure: float = 1e6,
                *, axial_load: float = 0.0, grid: int = 400, iterations: int = 60) -> np.ndarray:
    """L_free(P) [m]: the largest root of F_ax(P, L) = F_a in (B/√3, L₀] (docs/physics.md §7).

    ``axial_load`` F_a [N] is a tension hanging on the free muscle (0: free contraction).
    Vectorized over pressures: a downward scan from L₀ brackets the first sign change, then
    bisection. Where F_ax(P, L₀) ≤ F_a the muscle cannot contract and L_free = L₀.
    """
    pressure = np.atleast_1d(np.asarray(pressure, dtype=float))
    top, bottom = geometry.initial_length, geometry.shortest_length * (1 + 1e-9)
    lengths = np.linspace(top, bottom, grid)
    at_zero, slope = forces.axial_force_affine(lengths, geometry, theta, reference_pressure)
    force = at_zero[None, :] + pressure[:, None] * slope[None, :] - axial_load  # pressures × lengths
    negative = force < 0
    negative[:, 0] = False  # the scan starts at the rest length L₀
    first = np.argmax(negative, axis=1)
    found = negative[np.arange(pressure.size), first]
    blocked = at_zero[0] + pressure * slope[0] - axial_load <= 0  # cannot contract at all
    if not np.all(found | blocked):
        bad = pressure[~(found | blocked)][0]
        raise SolverError(f"no free-contraction length in (B/sqrt(3), L0] at {bad:.6g} Pa: the "
                          "moduli never balance the pressure force", status="no_root")
    high = lengths[np.maximum(first - 1, 0)]
    low = lengths[first]
    for _ in range(iterations):
        mid = 0.5 * (high + low)
        f0, f1 = forces.axial_force_affine(mid, geometry, theta, reference_pressure)
        positive = f0 + pressure * f1 - axial_load >= 0
        high = np.where(positive, mid, high)
        low = np.where(positive, low, mid)
    result = 0.5 * (high + low)
    return np.where(found, result, top)
