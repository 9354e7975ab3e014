"""The tether a robot drags behind it, the supply hose inside it and the compressor (docs/formats.md §4,
docs/physics.md §16). Frozen SI objects, built by :mod:`pampipe.io.tether_schema`.
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Hose:
    """The supply hose inside the tether: from the entry to the robot, as long as the robot has gone."""

    inner_diameter: float  # [m]
    roughness: float  # [m] absolute wall roughness ε


@dataclass(frozen=True)
class Compressor:
    """The compressor at the entry: ``free_air_delivery`` [m³/s] of air at the ISO 8778 reference
    atmosphere (20 °C, 100 kPa absolute: normal cubic metres per second)."""

    free_air_delivery: float  # [m³/s], normal


@dataclass(frozen=True)
class Tether:
    """The cable-pulling model of docs/physics.md §16.1: weight per length w [N/m], friction μ_t on the
    pipe wall (and its standard deviation), the tension at the entry [N] and the length on the reel [m]."""

    weight: float  # w [N/m]
    friction: float  # μ_t
    back_tension: float  # [N] at the entry (reel brake, guide)
    length: float  # [m] on the reel
    friction_sd: float = 0.0
    hose: Hose | None = None
    compressor: Compressor | None = None
