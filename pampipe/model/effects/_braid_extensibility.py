"""§9b braid extensibility: the fibres stretch under the braid's tension."""

from __future__ import annotations

from pampipe.model.effects._base import Effect, Parameter


class BraidExtensibility(Effect):
    """§9b: B = B₀(1 + c_B T), N fixed; T is the total braid tension (Eq. 11-12)."""

    name = "braid_extensibility"
    section = "9b"
    summary = "the braid fibres stretch under tension, so the anchored length grows with P and F_a"
    signature = "pressure"
    no_closed_form = ("the braid stretches under its own tension, so the anchored length depends on the "
                      "pressure through a fixed-point iteration and the holding force is not affine in P")
    parameters = (
        Parameter("compliance", "1/MN", "compliance", 1e-6, 0.0, 2e-5, 0.0,
                  "fibre strain per newton of total braid tension, c_B"),
    )

    def braid_strain(self, tension, values):
        return values["compliance"] * tension
