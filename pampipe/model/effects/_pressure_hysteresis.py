"""§9k pressure hysteresis: braid friction at a held length while the pressure changes."""

from __future__ import annotations

from pampipe.model.effects._base import Effect, Parameter


class PressureHysteresis(Effect):
    """§9k: F_meas = F_ax − sgn(Ṗ)(h₀ + h₁P), the isometric counterpart of braid friction (§9a).

    At a held length the braid still slides while the pressure changes: filling (Ṗ > 0) the muscle
    pulls itself shorter and friction holds it back, venting it lets go and friction holds it in:
    the venting leg lies 2(h₀ + h₁P) above the filling leg. Keyed to the sign of dP/dt of each row
    (``pressure_leg``); the anchored muscle sits mid-band, as with §9a.
    """

    name = "pressure_hysteresis"
    section = "9k"
    summary = "braid friction while the pressure changes: the venting leg lies above the filling leg"
    signature = "pressure_rate"
    parameters = (
        Parameter("h0", "N", "force", 1.0, 0.0, 500.0, 0.0, "half the band at zero pressure"),
        Parameter("h1", "N/MPa", "area", 1e-6, 0.0, 1e-3, 0.0, "half the band per unit pressure"),
    )
    tests = frozenset({"axial"})

    def axial_increment(self, state, values):
        if state.in_pipe:
            return None
        return -state.pressure_leg * (values["h0"] + values["h1"] * state.pressure)
