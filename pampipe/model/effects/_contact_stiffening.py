"""§9d contact stiffening: the bladder stiffens once it touches the pipe."""

from __future__ import annotations

from pampipe.model import ops
from pampipe.model.effects._base import Effect, Parameter
from pampipe.model.forces import anchoring_pressure, contact_force_increment


class ContactStiffening(Effect):
    """§9d: E_k ← E_k + ΔE_k (P − P_anchor)₊/P_ref once anchored (compatible at P_anchor)."""

    name = "contact_stiffening"
    section = "9d"
    summary = "the bladder stiffens after it touches the pipe (the paper's own diagnosis, Fig. 9/10)"
    signature = "contact"
    parameters = (
        Parameter("axial_increment", "MPa", "pressure", 1e6, -20e6, 20e6, 0.0,
                  "ΔE₁ per P_ref above anchoring", fit_lower=0.0),  # it stiffens: a fit keeps ΔE ≥ 0
        Parameter("hoop_increment", "MPa", "pressure", 1e6, -20e6, 20e6, 0.0,
                  "ΔE₂ per P_ref above anchoring", fit_lower=0.0),
    )
    tests = frozenset({"radial"})

    def contact_increments(self, size, values):
        zeros = [0.0] * (size // 4 - 1)
        return [values["axial_increment"], *zeros, *zeros, 0.0, values["hoop_increment"], *zeros, *zeros, 0.0]

    def axial_increment(self, state, values):
        if not state.in_pipe:
            return None
        delta = ops.column(self.contact_increments(state.theta.shape[0], values), like=state.theta)
        anchoring = anchoring_pressure(state.diameter, state.geometry, state.theta,
                                       state.reference_pressure, state.axial_load)
        return contact_force_increment(state.pressure, state.length, state.geometry, delta,
                                       state.reference_pressure, anchoring)
