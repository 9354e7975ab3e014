"""A mission as frozen SI objects: the robot's segments and the route's pipe sections (docs/formats.md §4).

No I/O here: :func:`pampipe.io.load_mission` builds these from a mission file, and the Python API
(:mod:`pampipe.api`) from a dict.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

from pampipe.model.pam import Pam

#: κ of the no-slip condition for each load path (docs/physics.md §8).
LOAD_PATH_KAPPA = {"through_anchor": 1.0, "distributed": 0.5, "none": 0.0}


@dataclass(frozen=True)
class Segment:
    """One segment of the robot (rear to front): its muscle and its mass."""

    name: str
    pam: Pam
    mass: float  # [kg]
    pam_file: Path | None = None  # the PAM file it names (None for an inline PAM)


@dataclass(frozen=True)
class Section:
    """One pipe section of the route, in travel order (SI)."""

    name: str
    length: float  # [m]
    diameter: float  # inner diameter [m]
    incline: float  # [rad] above horizontal
    friction: float  # braid-wall Coulomb coefficient
    friction_sd: float  # its standard deviation (0 = known exactly)


@dataclass(frozen=True)
class Mission:
    """The robot, its supply and safety factor, and the route (SI). ``source`` names where it came from."""

    source: Path
    segments: tuple[Segment, ...]
    payload: float  # [kg]
    supply_pressure: float  # [Pa] gauge
    safety_factor: float
    load_path: str
    tether_drag: float  # [N]
    route: tuple[Section, ...]
    gait: dict[str, Any]

    @property
    def input_files(self) -> list[Path]:
        """Every file the mission reads: itself and the PAM files its segments name."""
        return [self.source, *(seg.pam_file for seg in self.segments if seg.pam_file is not None)]

    @property
    def kappa(self) -> float:
        """κ of the no-slip condition (docs/physics.md §8)."""
        return LOAD_PATH_KAPPA[self.load_path]
