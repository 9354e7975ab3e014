"""§9c end effects: tapered, non-cylindrical ends."""

from __future__ import annotations

import math

from pampipe.model.bladder import split_moduli, strains, stress
from pampipe.model.braid import turns
from pampipe.model.effects._base import Effect, Parameter
from pampipe.model.forces import wall_section


class EndEffects(Effect):
    """§9c: tapered ends. V = (π/4)D²(L − c_v D) and a contact length L_c = L − 2ℓ_e.

    ΔF_ax = −P ∂(−πc_vD³/4)/∂L|_braid = −3c_v P D L/(4πN²); in the pipe the wall and hoop terms of
    Eq. 14 (2PR_iL − 2σ₂tL) act only on L_c, with ℓ_e = κ_e(D − D₀)/2 (end fitting ≈ D₀).
    """

    name = "end_effects"
    section = "9c"
    summary = "non-cylindrical ends: less enclosed volume and a shorter contact length"
    signature = "stroke_ends"
    no_closed_form = ("the tapered ends add pressure-dependent terms to the anchored force that shift its "
                      "zero away from the anchoring pressure at which contact stiffening starts")
    parameters = (
        Parameter("volume_taper", "-", "dimensionless", 1.0, 0.0, 2.0, 0.0, "c_v in V = πD²(L − c_v D)/4"),
        Parameter("end_length", "-", "dimensionless", 1.0, 0.0, 4.0, 0.0,
                  "κ_e in ℓ_e = κ_e(D − D₀)/2"),
    )

    def axial_increment(self, state, values):
        n2 = turns(state.geometry) ** 2
        taper = values["volume_taper"]
        return -3 * taper * state.pressure * state.diameter * state.length / (4 * math.pi * n2)

    def radial_increment(self, state, values):
        g = state.geometry
        _, r_i, t = wall_section(state.length, g, state.diameter)
        _, _, a2, b2 = split_moduli(state.theta)
        eps_hoop = strains(state.length, state.diameter, g)[1]
        sigma_hoop = stress(eps_hoop, state.pressure, a2, b2, state.reference_pressure)
        end = values["end_length"] * (state.diameter - g.initial_diameter) / 2
        return -2 * end * (2 * state.pressure * r_i - 2 * sigma_hoop * t)
