"""§9j bladder prestrain: the bladder is strained at the muscle's rest length."""

from __future__ import annotations

from pampipe.model.bladder import split_moduli, strains, stress
from pampipe.model.effects._base import Effect, Parameter
from pampipe.model.forces import axial_levers


class Prestrain(Effect):
    """§9j: bladder prestrain, ε_k → ε_k + ε_k,pre in both stress laws (Ball & Garcia 2016).

    ΔF_ax = [σ₁(ε₁ + ε₁,pre) − σ₁(ε₁)]V_b/L − [σ₂(ε₂ + ε₂,pre) − σ₂(ε₂)]·lever₂ (Eq. 9 levers). A
    bladder that is stress-free at a zero-strain length L_z ≠ L₀ has ε₁,pre = (L₀ − L_z)/L₀ and
    ε₂,pre = (D₀ − D(L_z))/D₀; with ε₂,pre > 0 the hoop stress at L₀ pushes against the pressure,
    so the muscle needs a threshold pressure before it pulls at its rest length.
    """

    name = "prestrain"
    section = "9j"
    summary = "the bladder is strained at the rest length: a threshold pressure before the muscle pulls"
    signature = "stroke_ends"
    parameters = (
        Parameter("axial_prestrain", "-", "dimensionless", 1.0, -0.1, 0.1, 0.0, "ε₁,pre"),
        Parameter("hoop_prestrain", "-", "dimensionless", 1.0, -0.1, 0.1, 0.0, "ε₂,pre"),
    )
    no_closed_form = ("the prestrain adds stress terms to the anchored force that are not moduli increments, "
                      "which is all the closed form carries in the pipe")

    def axial_increment(self, state, values):
        g = state.geometry
        _, lever1, lever2 = axial_levers(state.length, g, state.diameter, stretched=True)
        a1, b1, a2, b2 = split_moduli(state.theta)
        eps1, eps2 = strains(state.length, state.diameter, g)
        pref, p = state.reference_pressure, state.pressure
        d1 = stress(eps1 + values["axial_prestrain"], p, a1, b1, pref) - stress(eps1, p, a1, b1, pref)
        d2 = stress(eps2 + values["hoop_prestrain"], p, a2, b2, pref) - stress(eps2, p, a2, b2, pref)
        return d1 * lever1 - d2 * lever2
