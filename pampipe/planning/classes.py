"""The data of a confidence plan's sampling (docs/physics.md §15): the classes of alike sections and what
every chunk of classes shares (:mod:`.sampling` samples them, :mod:`.evaluator` evaluates one class's draws).

A **class** is the set of sections that state the same bores (range, and each segment's worst bore in it),
bore sd, incline, friction and friction sd: they carry the same load and the same draws.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from pampipe.model.muscle import Structure
from pampipe.planning.sources import MuscleUncertainty
from pampipe.runtime.alike import unique_rows


@dataclass(frozen=True)
class Classes:
    """The classes of alike sections: one row each, (C,) or (C, segments) arrays, SI."""

    low: np.ndarray  # smallest bore of the range [m]
    high: np.ndarray  # largest bore of the range [m]
    worst: np.ndarray  # (C, segments) each segment's worst bore of the range [m]
    valid: np.ndarray  # (C, segments) bool
    bore_sd: np.ndarray  # [m]
    mu: np.ndarray
    mu_sd: np.ndarray
    incline: np.ndarray  # [rad]
    drag: np.ndarray | None = None  # [N] the constant load of each class (None: the mission's tether_drag)
    drag_draws: np.ndarray | None = None  # (C, n) [N] that load in each draw of the tether's friction

    def __len__(self) -> int:
        return self.low.size

    def part(self, rows: slice) -> Classes:
        return Classes(*(None if getattr(self, f.name) is None else getattr(self, f.name)[rows]
                         for f in dataclasses.fields(self)))


def section_classes(route, elements, drag=None, drag_draws=None) -> tuple[Classes, np.ndarray]:
    """(the classes, the class of each section (S,)). With a tether, ``drag`` [N] (S,) is each section's
    constant load (:func:`~pampipe.planning.tension.section_drag`), a column of the classes; with its
    ``drag_draws`` (S, n) every section is a class of its own (its tension draws are its own)."""
    valid = np.asarray(elements.valid, dtype=bool)
    m = valid.shape[1]
    columns = [route.diameter_low, route.diameter_high, elements.diameter, valid, route.diameter_sd,
               route.friction, route.friction_sd, route.incline]
    tethered = np.ndim(drag) == 1
    if tethered:
        columns += [drag] + ([np.arange(len(route))] if drag_draws is not None else [])
    table = np.column_stack(columns).astype(float)
    rows, first, inverse = unique_rows(table)
    classes = Classes(rows[:, 0], rows[:, 1], rows[:, 2:2 + m], rows[:, 2 + m:2 + 2 * m] > 0.5,
                      *(rows[:, 2 + 2 * m + k] for k in range(4)),
                      drag=rows[:, 2 + 2 * m + 4] if tethered else None,
                      drag_draws=None if drag_draws is None else drag_draws[first])
    return classes, inverse


@dataclass(frozen=True)
class Problem:
    """What every chunk shares: the muscles' sources, the seed, the mission's constants (SI)."""

    structures: tuple[Structure, ...]
    uncertainties: tuple[MuscleUncertainty, ...]
    samples: int
    seed: int
    level: float
    active: tuple[str, ...]  # sources with a spread, in sources.SOURCES order
    kappa: float
    kappa_sd: float
    safety_factor: float
    total_mass: float  # [kg] robot and payload
    masses: tuple[float, ...]  # [kg] per segment
    tether_drag: float  # [N]
    payload: float  # [kg]
    supply: tuple[float, ...] | None  # [Pa] per segment, the pressure of the payload at confidence (or None)
    key: str  # draws_key of the muscles' sources, draws, seed and κ sd: names the draws in every process
    twins: tuple[int, ...] = ()  # per segment, the first with the same inputs and draws (segment_twins)
    limits: tuple[float, ...] = ()  # [Pa] per segment, its pressure limit (supply or rating)
