"""The inventory reduced to the few numbers the design NLP needs: one group per (bore, friction).

Every segment i in every pipe j must hold alone the anchor load (docs/physics.md §8)
W_ij = g(M|sin φ_j| + μ_j cos φ_j (M − m_i)) + tether drag  [N].
For one bore D and friction μ the least holding pressure P*(D, W, μ) rises with W (a heavier load
both delays contact and needs more grip), so among the pipes and segments of a group only the
largest load W_max can bind the pressure constraints: the group stands for all of them, exactly.

The objectives sum over pipes: without contact increments P* is affine in W (docs/physics.md §8,
P* = (κW − F₀)/F₁ + SF·W/(μπA F₁)), so Σ_j ℓ_j Σ_i P*(W_ij) = n·ℓ_g P*(W̄_g) with the
length-weighted mean load W̄_g; with contact increments this is the first-order approximation
(the reported objective is always evaluated pipe by pipe).

A pipe with a bore tolerance constrains at both ends of its range and counts in the objectives at
its nominal bore. The NLP is built for a fixed number of groups (a power of two); the unused rows
are copies of group 0 whose constraints have no bounds and whose objective weight is 0.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from pampipe.model.no_slip import anchor_load
from pampipe.specs.inventory import Inventory, Pipes

#: Columns of one group in the NLP's parameter vector.
COLUMNS = ("diameter", "friction", "load_max", "load_min", "load_mean", "length")
SMALLEST_BLOCK = 4


def segment_loads(inventory: Inventory, pipes: Pipes | None = None) -> np.ndarray:
    """W_ij [N], shape (pipes, segments): the load each segment holds alone in each pipe."""
    pipes = inventory.pipes if pipes is None else pipes
    mass, tether = inventory.total_mass, inventory.tether_drag
    return np.stack([anchor_load(mass, m, pipes.incline, pipes.friction, tether) * np.ones(len(pipes))
                     for m in inventory.segment_masses], axis=1)


@dataclass(frozen=True)
class Groups:
    """One row per distinct (bore, friction): what the NLP needs of the pipes it stands for (SI)."""

    diameter: np.ndarray  # D [m]
    friction: np.ndarray  # μ
    load_max: np.ndarray  # largest W over its constraining pipes and segments [N] (0: none)
    load_min: np.ndarray  # smallest such W [N]
    load_mean: np.ndarray  # length-weighted mean W of the pipes counted at this nominal bore [N]
    length: np.ndarray  # pipe length counted in the objectives here [m]
    constrained: np.ndarray  # bool: some pipe's bore range ends here
    smallest_bore: float  # [m] the smallest bore any pipe may have (for the clearance)

    def __len__(self) -> int:
        return len(self.diameter)

    def block(self, size: int) -> np.ndarray:
        """The (len(COLUMNS), size) parameter block, padded with copies of group 0 of length 0."""
        rows = np.stack([getattr(self, c) for c in COLUMNS])
        pad = np.repeat(rows[:, :1], size - len(self), axis=1)
        pad[COLUMNS.index("length")] = 0.0  # no weight in the objectives
        return np.concatenate([rows, pad], axis=1)

    @property
    def widest_bore(self) -> float:
        """[m] the widest bore a served pipe may have."""
        return float(self.diameter[self.constrained].max())


def block_size(n: int) -> int:
    """The NLP's number of group rows for n groups: the next power of two, at least 4."""
    return max(SMALLEST_BLOCK, 1 << (max(n, 1) - 1).bit_length())


def make_groups(inventory: Inventory, pipes: Pipes | None = None) -> Groups:
    """Group ``pipes`` (default: the whole inventory) by (bore, friction)."""
    pipes = inventory.pipes if pipes is None else pipes
    if len(pipes) == 0:
        raise ValueError("no pipes to group")
    loads = segment_loads(inventory, pipes)
    n = len(pipes)
    # constraint elements: both ends of each bore range; objective elements: the nominal bore
    d = np.concatenate([pipes.diameter_low, pipes.diameter_high, pipes.diameter])
    mu = np.tile(pipes.friction, 3)
    role = np.repeat([0, 0, 1], n)  # 0: constrains, 1: counts in the objectives
    w_max = np.tile(loads.max(axis=1), 3)
    w_min = np.tile(loads.min(axis=1), 3)
    w_mean = np.tile(loads.mean(axis=1), 3)
    length = np.tile(pipes.length, 3)
    keys, inverse = np.unique(np.stack([d, mu], axis=1), axis=0, return_inverse=True)
    inverse = inverse.ravel()
    g = len(keys)
    cons = role == 0
    constrained = np.bincount(inverse[cons], minlength=g) > 0
    load_max = np.zeros(g)
    np.maximum.at(load_max, inverse[cons], w_max[cons])
    load_min = np.full(g, np.inf)
    np.minimum.at(load_min, inverse[cons], w_min[cons])
    obj = role == 1
    weight = np.bincount(inverse[obj], weights=length[obj], minlength=g)
    weighted = np.bincount(inverse[obj], weights=(length * w_mean)[obj], minlength=g)
    load_mean = np.where(weight > 0, weighted / np.where(weight > 0, weight, 1.0), load_max)
    load_min = np.where(constrained, load_min, load_mean)
    load_max = np.where(constrained, load_max, load_mean)
    return Groups(keys[:, 0].copy(), keys[:, 1].copy(), load_max, load_min, load_mean, weight, constrained,
                  float(pipes.diameter_low.min()))
