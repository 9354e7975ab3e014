"""Braid kinematics and the Gaylord force (docs/physics.md §2-§3, Eqs. 1-5).

Every function works on floats and on CasADi SX/MX alike. ``geometry`` is a
:class:`pampipe.model.pam.Geometry` whose fields may be floats or symbols. SI units.
"""

from __future__ import annotations

import math

from pampipe.model import ops


def braid_length(geometry):
    """B = L₀ / cos α₀ [m] (Eq. 1): length of one inextensible fibre."""
    return geometry.initial_length / ops.cos(geometry.braid_angle)


def turns(geometry):
    """N = L₀ tan α₀ / (π D₀) [-] (Eq. 2): turns of one fibre about the axis."""
    return geometry.initial_length * ops.tan(geometry.braid_angle) / (math.pi * geometry.initial_diameter)


def diameter_at_length(length, geometry):
    """D(L) = √(B² − L²) / (Nπ) [m] (Eq. 3)."""
    b = braid_length(geometry)
    return ops.sqrt(b**2 - length**2) / (turns(geometry) * math.pi)


def length_at_diameter(diameter, geometry):
    """L(D) = √(B² − (NπD)²) [m] (Eq. 3, inverted): the anchored length in a pipe of diameter D."""
    b = braid_length(geometry)
    return ops.sqrt(b**2 - (turns(geometry) * math.pi * diameter) ** 2)


def braid_angle_at_length(length, geometry):
    """α(L) = arccos(L/B) [rad] (Eq. 4), from the axis."""
    return ops.arccos(length / braid_length(geometry))


def dlength_ddiameter(diameter, geometry):
    """dL/dD = −(Nπ)² D / L(D) [-]."""
    n_pi = turns(geometry) * math.pi
    return -(n_pi**2) * diameter / length_at_diameter(diameter, geometry)


def amplification_factor(diameter, geometry, length=None):
    """A(D) = 2πN²D / L(D) = 2N tan α = (2/π)(−dL/dD) [-] (docs/physics.md §5.3, §5.5).

    ``length`` replaces L(D) where the anchored length differs (a stretching braid, docs/physics.md §9b).
    """
    if length is None:
        length = length_at_diameter(diameter, geometry)
    return 2 * math.pi * turns(geometry) ** 2 * diameter / length


def enclosed_volume(length, geometry):
    """V = πD²L/4 = L(B² − L²)/(4πN²) [m³]: volume inside the braid."""
    b = braid_length(geometry)
    return length * (b**2 - length**2) / (4 * math.pi * turns(geometry) ** 2)


def gaylord_force(pressure, length, geometry):
    """F_G = P(3L² − B²)/(4πN²) [N] (Eq. 5): contractile force of a bladder-less braid."""
    b = braid_length(geometry)
    return pressure * (3 * length**2 - b**2) / (4 * math.pi * turns(geometry) ** 2)
