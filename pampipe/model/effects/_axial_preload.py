"""§9g axial preload: an axial tension the pipe test does not report."""

from __future__ import annotations

from pampipe.model.effects._base import Effect, Parameter


class AxialPreload(Effect):
    """§9g: F_a,eff = F_a(1 + μ_p) + F₀ in pipe tests (fixture preload, pulley friction)."""

    name = "axial_preload"
    section = "9g"
    summary = "an axial tension the test does not report: clamping, rope and fitting weight, pulley friction"
    signature = "axial_load"
    parameters = (
        Parameter("preload", "N", "force", 1.0, -1000.0, 1000.0, 0.0, "F₀"),
        Parameter("pulley_friction", "-", "dimensionless", 1.0, 0.0, 0.5, 0.0, "μ_p on the hanging load"),
    )
    tests = frozenset({"radial"})

    def load(self, axial_load, values):
        return axial_load * (1 + values["pulley_friction"]) + values["preload"]
