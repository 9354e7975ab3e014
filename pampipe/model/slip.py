"""No-slip requirement of an anchored segment (docs/physics.md §8 and the plan issue). Floats and symbols.

* Load on the single anchor in a section of incline φ and wall friction μ, with M the robot's
  total mass (segments + payload) and m_anchor the anchoring segment's mass:
  W = g·(M·|sin φ| + μ·cos φ·(M − m_anchor)) + tether_drag  [N].
  The second term is the sliding friction of the parts that move while resting on the wall.
* No slip: μ·π·F_r(P, D, κW) ≥ SF·W, where F_r = A·(F_ax(P, L_p) − κW) is the split-pipe force and
  π·F_r the total normal force on the wall (docs/physics.md §5.4).
* Closed form: P_req = [W·(SF/(μπA) + κ) − F_ax(0, L_p)] / ∂_P F_ax.
"""

from __future__ import annotations

import math

from pampipe.model import ops
from pampipe.model.braid import amplification_factor, length_at_diameter
from pampipe.model.forces import axial_force_affine, radial_force

STANDARD_GRAVITY = 9.80665  # [m/s²]


def anchor_load(total_mass, anchor_mass, incline, friction, tether_drag=0.0):
    """W [N] the single anchor must hold: g(M|sin φ| + μ cos φ (M − m_anchor)) + tether drag."""
    return (STANDARD_GRAVITY * (total_mass * ops.fabs(ops.sin(incline))
                                + friction * ops.cos(incline) * (total_mass - anchor_mass))
            + tether_drag)


def holding_capacity(pressure, diameter, geometry, theta, reference_pressure, load, kappa,
                     friction, contact_theta=None):
    """μ·π·F_r(P, D, κW) [N]: the friction force the anchor can develop at pressure P under load W."""
    radial = radial_force(pressure, diameter, geometry, theta, reference_pressure, kappa * load,
                          contact_theta)
    return friction * math.pi * radial


def required_pressure(diameter, geometry, theta, reference_pressure, load, kappa, friction,
                      safety_factor):
    """P_req [Pa] = [W(SF/(μπA) + κ) − F_ax(0, L_p)] / ∂_P F_ax, the least pressure with no slip.

    Valid without contact increments (with them the requirement is no longer affine in P).
    """
    length = length_at_diameter(diameter, geometry)
    amp = amplification_factor(diameter, geometry)
    at_zero, slope = axial_force_affine(length, geometry, theta, reference_pressure)
    return (load * (safety_factor / (friction * math.pi * amp) + kappa) - at_zero) / slope


def largest_load(pressure, diameter, geometry, theta, reference_pressure, kappa, friction,
                 safety_factor):
    """W_max [N] held at pressure P: μπA(F_ax − κW) = SF·W  ⇒  W = μπA F_ax / (SF + κμπA)."""
    length = length_at_diameter(diameter, geometry)
    amp = amplification_factor(diameter, geometry)
    at_zero, slope = axial_force_affine(length, geometry, theta, reference_pressure)
    grip = friction * math.pi * amp
    return grip * (at_zero + pressure * slope) / (safety_factor + kappa * grip)
