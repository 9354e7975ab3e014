"""§9f wall friction: braid-pipe friction locks in axial tension during anchoring."""

from __future__ import annotations

import math

from pampipe.model.braid import amplification_factor
from pampipe.model.effects._base import Effect, Parameter


class WallFriction(Effect):
    """§9f: a locked-in tension λμ_wπF_r, so F_r = A(F_ax − F_a)/(1 + λμ_wπA)."""

    name = "wall_friction"
    section = "9f"
    summary = "braid-pipe friction locks in axial tension during anchoring, lowering the radial force"
    signature = "contact"
    parameters = (
        Parameter("lock", "-", "dimensionless", 1.0, 0.0, 1.0, 0.0, "λμ_w, the locked-in friction share"),
    )
    tests = frozenset({"radial"})

    def radial_factor(self, state, values):
        amp = amplification_factor(state.diameter, state.geometry, state.length)
        return 1 / (1 + values["lock"] * math.pi * amp)
