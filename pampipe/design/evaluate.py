"""A designed muscle pipe by pipe, through :class:`~pampipe.model.muscle.Muscle` (the numbers plan gives).

For every pipe j and segment i: the least holding pressure P_ij = max over the bore range of
:meth:`Muscle.least_holding_pressure` (docs/physics.md §8; inf outside the model's domain), the
unloaded anchoring pressure, the stride L₀ − L(D) and the air P·V per metre (docs/physics.md §7-§8),
and whether the pipe is served: it passes at rest with the clearance, stays within the contact margin,
strides at least the minimum, keeps the moduli law stable, and every segment holds at ≤ supply.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from pampipe.design.groups import segment_loads
from pampipe.model.muscle import Muscle
from pampipe.model.pam import Geometry, Pam
from pampipe.specs.inventory import Inventory, Objective, Pipes

#: Relative slack of the served test on the NLP's constraints (IPOPT meets them to ~1e-10).
SLACK = 1e-7


def designed_pam(inventory: Inventory, geometry: tuple[float, float, float], name: str) -> Pam:
    """The designed PAM: the geometry and the material's wall, thickness, moduli, covariance and the maker's
    limits (max_pressure, max_contraction), so that a plan of the designed muscle obeys them."""
    material = inventory.material
    g = material.geometry
    pam = Pam(name, Geometry(*geometry, g.bladder_thickness, g.wall), material.moduli, material.covariance,
              max_pressure=material.max_pressure, max_contraction=material.max_contraction)
    return pam if material.uncertainty is None else pam.with_uncertainty(material.uncertainty.moduli_part())


@dataclass(frozen=True)
class PipeTable:
    """Per-pipe numbers of one muscle (SI); ``reason`` is None where the pipe is served."""

    pressure: np.ndarray  # (pipes, segments) [Pa], inf where no pressure holds
    anchoring_pressure: np.ndarray  # (pipes,) [Pa], unloaded, at the nominal bore
    stride: np.ndarray  # (pipes,) [m] at the nominal bore
    air_per_metre: np.ndarray  # (pipes,) [J/m] Σ_i P_ij V / ΔL at the nominal bore
    served: np.ndarray  # (pipes,) bool
    reason: tuple[str | None, ...]

    @property
    def largest(self) -> np.ndarray:
        """(pipes,) the largest pressure over the segments [Pa]."""
        return self.pressure.max(axis=1)


def evaluate_pipes(inventory: Inventory, geometry: tuple[float, float, float], pipes: Pipes | None = None
                   ) -> PipeTable:
    """The numbers of the muscle of ``geometry`` (L₀, D₀, α₀) in every pipe of ``pipes``."""
    pipes = inventory.pipes if pipes is None else pipes
    space = inventory.space
    muscle = Muscle.from_pam(designed_pam(inventory, geometry, "design"))
    g = muscle.geometry
    loads = segment_loads(inventory, pipes)
    kappa, sf = inventory.kappa, inventory.safety_factor
    reach = (1 - space.contact_margin) * g.largest_diameter
    with np.errstate(all="ignore"):
        pressure = np.full(loads.shape, -np.inf)
        for bore in (pipes.diameter_low, pipes.diameter_high):
            inside = (bore > g.initial_diameter) & (bore < g.largest_diameter)
            safe = np.where(inside, bore, 0.5 * (g.initial_diameter + g.largest_diameter))
            p = muscle.least_holding_pressure(safe[:, None], loads, kappa=kappa,
                                              friction=pipes.friction[:, None], safety_factor=sf)
            pressure = np.maximum(pressure, np.where(inside[:, None], p, np.inf))
        nominal_ok = (pipes.diameter > g.initial_diameter) & (pipes.diameter < g.largest_diameter)
        nominal = np.where(nominal_ok, pipes.diameter, 0.5 * (g.initial_diameter + g.largest_diameter))
        length = muscle.anchored_length(nominal)
        stride = np.where(nominal_ok, g.initial_length - length, np.nan)
        anchoring = np.where(nominal_ok, muscle.anchoring_pressure(nominal), np.inf)
        air = np.where(nominal_ok, pressure.sum(axis=1) * muscle.enclosed_volume(length) / stride, np.inf)
        stable = _stable(muscle, inventory, pipes)
    served = []
    for j in range(len(pipes)):
        served.append(_reason(inventory, g, reach, pipes, j, pressure[j], stride[j], stable[j]))
    return PipeTable(pressure, anchoring, stride, air, np.array([r is None for r in served]), tuple(served))


def _stable(muscle: Muscle, inventory: Inventory, pipes: Pipes) -> np.ndarray:
    """(pipes,) bool: tangent moduli ≥ 0 at both bore ends, at 0 Pa and at the supply (docs/physics.md §6)."""
    g = muscle.geometry
    ok = np.ones(len(pipes), dtype=bool)
    for bore in (pipes.diameter_low, pipes.diameter_high):
        inside = (bore > g.initial_diameter) & (bore < g.largest_diameter)
        length = muscle.anchored_length(np.where(inside, bore, g.initial_diameter))
        for p in (0.0, inventory.supply_pressure):
            e1, e2 = muscle.drucker_tangent_moduli(p, length)
            ok &= ~inside | ((e1 >= -SLACK * 1e6) & (e2 >= -SLACK * 1e6))
    return ok


def _reason(inventory: Inventory, g, reach: float, pipes: Pipes, j: int, pressure: np.ndarray,
            stride: float, stable: bool) -> str | None:
    space, supply = inventory.space, inventory.supply_pressure
    low, high = pipes.diameter_low[j], pipes.diameter_high[j]
    if pipes.friction[j] <= 0:
        return "no wall friction: no muscle grips"
    if g.initial_diameter > low - space.clearance + SLACK * low:
        return (f"narrower than the muscle at rest plus the clearance ({g.initial_diameter * 1e3:.4g} + "
                f"{space.clearance * 1e3:.4g} mm)")
    if high > reach * (1 + SLACK):
        return (f"wider than the braid opens to with the contact margin ({reach * 1e3:.4g} mm of "
                f"{g.largest_diameter * 1e3:.4g} mm)")
    if not stride >= space.min_stride * (1 - SLACK):
        return f"stride {stride * 1e3:.4g} mm, less than the {space.min_stride * 1e3:.4g} mm minimum"
    if not stable:
        return "the moduli law is unstable at the anchored strain (a tangent modulus < 0)"
    worst = float(pressure.max())
    if not math.isfinite(worst):
        return "no pressure up to 100 MPa holds the load"
    if worst > supply * (1 + SLACK):
        return f"needs {worst / 1e3:.4g} kPa, more than the {supply / 1e3:.4g} kPa supply"
    return None


def objective_value(objective: Objective, table: PipeTable, pipes: Pipes, served: np.ndarray) -> float:
    """The objective over the ``served`` pipes (max pressure [Pa], air [J/m] or cycles per metre [1/m])."""
    if not served.any():
        return math.nan
    if objective is Objective.MAX_PRESSURE:
        return float(table.largest[served].max())
    weight = pipes.length[served]
    values = table.air_per_metre[served] if objective is Objective.AIR else 1 / table.stride[served]
    return float((weight * values).sum() / weight.sum())
