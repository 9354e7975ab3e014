"""§9e pressure offset: the pressure sensor reads off by a constant and a gain."""

from __future__ import annotations

from pampipe.model.effects._base import Effect, Parameter


class PressureOffset(Effect):
    """§9e: P = g_P·P_meas + P_off (sensor offset and gain)."""

    name = "pressure_offset"
    section = "9e"
    summary = "the pressure sensor reads off by a constant (and a gain)"
    signature = "pressure"
    parameters = (
        Parameter("offset", "kPa", "pressure", 1e3, -60e3, 60e3, 0.0, "P_off"),
        Parameter("gain", "-", "dimensionless", 1.0, 0.8, 1.2, 1.0, "g_P"),
    )

    def pressure(self, pressure, values):
        return values["gain"] * pressure + values["offset"]

    def pressure_inverse(self, pressure, values):
        return (pressure - values["offset"]) / values["gain"]
