"""§9a braid friction: Coulomb friction between the braid's fibres while the length changes."""

from __future__ import annotations

from pampipe.model.effects._base import Effect, Parameter


class BraidFriction(Effect):
    """§9a: F_meas = F_ax + sgn(L̇)(f₀ + f₁P); the anchored (quiescent) muscle sits mid-band."""

    name = "braid_friction"
    section = "9a"
    summary = "Coulomb friction between braid fibres: the lengthening leg lies above the shortening leg"
    signature = "length_rate"
    parameters = (
        Parameter("f0", "N", "force", 1.0, 0.0, 500.0, 0.0, "friction force at zero pressure"),
        Parameter("f1", "N/MPa", "area", 1e-6, 0.0, 1e-3, 0.0, "friction force per unit pressure"),
    )
    tests = frozenset({"axial"})

    def axial_increment(self, state, values):
        if state.in_pipe:
            return None
        return state.leg * (values["f0"] + values["f1"] * state.pressure)
