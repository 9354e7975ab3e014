"""No-slip requirement of an anchored segment (docs/physics.md §8 and the plan issue). Floats and symbols.

* Load on the single anchor in a section of incline φ and wall friction μ, with M the robot's
  total mass (segments + payload) and m_anchor the anchoring segment's mass:
  W = g·(M·|sin φ| + μ·cos φ·(M − m_anchor)) + tether_drag  [N].
  The second term is the sliding friction of the parts that move while resting on the wall.
* No slip: μ·π·F_r(P, D, κW) ≥ SF·W, where F_r = A·(F_ax(P, L_p) − κW) is the split-pipe force and
  π·F_r the total normal force on the wall (docs/physics.md §5.4); the muscle answers it
  (:meth:`pampipe.model.muscle.Muscle.least_holding_pressure` and friends).
"""

from __future__ import annotations

from pampipe.model import ops

STANDARD_GRAVITY = 9.80665  # [m/s²]


def anchor_load(total_mass, anchor_mass, incline, friction, tether_drag=0.0):
    """W [N] the single anchor must hold: g(M|sin φ| + μ cos φ (M − m_anchor)) + tether drag."""
    return incline_load(total_mass, anchor_mass, ops.fabs(ops.sin(incline)), ops.cos(incline), friction,
                        tether_drag)


def incline_load(total_mass, anchor_mass, rise, run, friction, tether_drag=0.0):
    """:func:`anchor_load` [N] from rise = |sin φ| and run = cos φ, computed once for every segment."""
    return STANDARD_GRAVITY * (total_mass * rise + friction * run * (total_mass - anchor_mass)) + tether_drag


def incline_load_affine(total_mass, anchor_mass, rise, run, tether_drag=0.0):
    """(∂W/∂μ [N], W at μ = 0 [N]) of :func:`incline_load`, which is affine in μ: W = μ·g·cos φ·(M − m)
    + (g·M·|sin φ| + drag), for many frictions at one incline (two passes over them, not five)."""
    slope = STANDARD_GRAVITY * (run * (total_mass - anchor_mass))
    return slope, STANDARD_GRAVITY * (total_mass * rise) + tether_drag
