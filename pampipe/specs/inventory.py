"""A pipe inventory to design a muscle for, as frozen SI objects (docs/commands.md §8).

No I/O here: :func:`pampipe.io.inventory_file.load_inventory` builds these from an inventory file.
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import Enum
from pathlib import Path

import numpy as np

from pampipe.model.pam import Pam
from pampipe.specs.mission import LOAD_PATH_KAPPA


class Objective(str, Enum):
    """What the design minimises, over the pipes j (length ℓ_j) and segments i of the inventory.

    * ``max_pressure``: max_ij P_ij [Pa], the largest required pressure (epigraph form: min t with
      P_ij ≤ t).
    * ``air``: Σ_j ℓ_j Σ_i P_ij V_j / ΔL_j / Σ_j ℓ_j [J/m], the P·V of air per metre travelled, with
      V_j = πD_j²L_j/4 the volume inside the anchored braid and ΔL_j = L₀ − L(D_j) the stride.
    * ``speed``: Σ_j ℓ_j / ΔL_j / Σ_j ℓ_j [1/m], gait cycles per metre (1 / the length-weighted
      harmonic mean stride): the fewest cycles to travel the inventory.
    """

    MAX_PRESSURE = "max_pressure"
    AIR = "air"
    SPEED = "speed"

    @property
    def unit(self) -> str:
        return {"max_pressure": "Pa", "air": "J/m", "speed": "1/m"}[self.value]


@dataclass(frozen=True)
class Pipes:
    """The inventory's pipes, columnar and SI; a bore tolerance gives [diameter_low, diameter_high]."""

    name: tuple[str, ...]
    diameter: np.ndarray  # nominal bore [m]
    diameter_low: np.ndarray  # [m]
    diameter_high: np.ndarray  # [m]
    length: np.ndarray  # [m]
    incline: np.ndarray  # [rad] above horizontal (the load uses |sin|)
    friction: np.ndarray  # braid-wall Coulomb coefficient

    def __len__(self) -> int:
        return len(self.name)

    def subset(self, index) -> Pipes:
        """The pipes at ``index`` (an index array or a boolean mask)."""
        index = np.flatnonzero(index) if np.asarray(index).dtype == bool else np.asarray(index, dtype=int)
        return Pipes(tuple(self.name[i] for i in index), self.diameter[index], self.diameter_low[index],
                     self.diameter_high[index], self.length[index], self.incline[index],
                     self.friction[index])


@dataclass(frozen=True)
class DesignSpace:
    """Bounds of the free geometry and the design's constraints and options (SI, angles from the axis)."""

    initial_length: tuple[float, float]  # L₀ [m]
    initial_diameter: tuple[float, float]  # D₀ [m]
    braid_angle: tuple[float, float]  # α₀ [rad] from the axis
    clearance: float = 2e-3  # [m] D₀ ≤ smallest bore − clearance
    contact_margin: float = 0.05  # bore ≤ (1 − margin) D(B/√3)
    min_stride: float = 0.0  # [m] L₀ − L(D) ≥ min_stride in every pipe
    objective: Objective = Objective.MAX_PRESSURE
    sizes: int | None = None  # None: one muscle must serve every pipe; K: K muscles serving the most length
    starts: int = 16  # Latin-hypercube starts of the multi-start
    seed: int = 0


@dataclass(frozen=True)
class Inventory:
    """A design problem: the bladder material, the robot, the supply and the pipes to serve."""

    source: Path
    material: Pam  # its moduli and bladder thickness (and wall model) define the material
    segment_names: tuple[str, ...]  # rear to front
    segment_masses: tuple[float, ...]  # [kg]
    payload: float  # [kg]
    supply_pressure: float  # [Pa]
    safety_factor: float
    load_path: str
    tether_drag: float  # [N]
    pipes: Pipes
    space: DesignSpace
    material_file: Path | None = None
    network: str | None = None  # the network the pipes were read from, if any

    @property
    def kappa(self) -> float:
        """κ of the no-slip condition (docs/physics.md §8)."""
        return LOAD_PATH_KAPPA[self.load_path]

    @property
    def total_mass(self) -> float:
        """M = segment masses + payload [kg]."""
        return float(sum(self.segment_masses) + self.payload)

    @property
    def input_files(self) -> list[Path]:
        """Every file the inventory reads: itself and the material PAM file."""
        return [self.source, *([self.material_file] if self.material_file is not None else [])]
