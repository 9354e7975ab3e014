"""The sampled holding law of a confidence plan, per class of alike sections, in chunks (docs/physics.md §15).

A **class** is the set of sections that state the same bores (range, and each segment's worst bore in it),
bore sd, incline, friction and friction sd: they carry the same load and, since the muscle draws are the
route's and the bore and friction draws are keyed by their statement (:func:`sources.keyed_normal`), the
same draws. One evaluation over the n draws serves every section of a class, so a route of 10⁵ sections
of a few hundred kinds costs a few hundred evaluations.

Classes are sampled in **chunks** of at most :func:`chunk_classes` classes (a memory budget,
:data:`MEMORY_BUDGET`), each chunk a task of :func:`pampipe.runtime.executors.run_all`. A task is plain
numbers
and the seed; the worker draws the route's muscle draws itself from the seed (:func:`sources.draw_muscles`,
once per process), so serial, local processes and a Dask cluster give bit-identical results.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from pampipe.model.muscle import Structure
from pampipe.planning.evaluator import Evaluator
from pampipe.planning.law import settle
from pampipe.planning.quantiles import lower_rank, order_statistics, share_at_most, upper_rank
from pampipe.planning.sources import MuscleDraws, MuscleUncertainty, draw_muscles, keyed_normal
from pampipe.runtime.heap import retain_freed_memory

LEVELS = (0.9, 0.99, 0.999)  # the pressures every confidence plan reports
#: Memory a chunk may use for its draws × classes arrays [B].
MEMORY_BUDGET = 64 << 20
#: Bytes one draw of one class costs at the peak of a chunk (the temporaries of the closed form over a
#: range's bores, the sorted copies): the peak resident memory grew by 137–167 B per draw and class for
#: chunks of 21 and 180 classes at 10⁴ draws (the riser robot, 180 kinds of section).
BYTES_PER_DRAW = 200
#: An undetermined direction "moves" a hold when ± its open width moves P* by more than this [Pa] (1 kPa).
MOVES = 1e3


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
    rows, first, inverse = np.unique(table, axis=0, return_index=True, return_inverse=True)
    classes = Classes(rows[:, 0], rows[:, 1], rows[:, 2:2 + m], rows[:, 2 + m:2 + 2 * m] > 0.5,
                      *(rows[:, 2 + 2 * m + k] for k in range(4)),
                      drag=rows[:, 2 + 2 * m + 4] if tethered else None,
                      drag_draws=None if drag_draws is None else drag_draws[first])
    return classes, np.asarray(inverse).reshape(-1)


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


_DRAWS: dict[str, MuscleDraws] = {}


def drawn_muscles(key: str, uncertainties: tuple, samples: int, seed: int, kappa_sd: float) -> MuscleDraws:
    """:func:`draw_muscles`, drawn once per process for the same arguments, named by their ``key``
    (:func:`evaluator.draws_key`; the last kept)."""
    draws = _DRAWS.get(key)  # one lookup: a Dask worker may run chunks in several threads
    if draws is None:
        draws = draw_muscles(list(uncertainties), samples, seed, kappa_sd)
        _DRAWS.clear()
        _DRAWS[key] = draws
    return draws


def muscle_draws(problem: Problem) -> MuscleDraws:
    """The route's muscle draws, drawn once per process (and problem) from the seed (named by its key: no
    hash of the sources per chunk)."""
    return drawn_muscles(problem.key, problem.uncertainties, problem.samples, problem.seed, problem.kappa_sd)


def chunk_classes(samples: int, budget: int = MEMORY_BUDGET) -> int:
    """Classes per chunk so that a chunk's draws × classes arrays stay within ``budget`` bytes."""
    return max(1, budget // (BYTES_PER_DRAW * samples))


@dataclass(frozen=True)
class ChunkResult:
    """One chunk's sampled plan, (C, segments) arrays (placeholders where an element is not valid)."""

    pressure: np.ndarray
    holding: np.ndarray
    contact: np.ndarray
    levels: dict[str, np.ndarray]
    band: np.ndarray  # (C, segments, 2)
    certain: np.ndarray
    shifts: dict[str, np.ndarray]
    low_shifts: dict[str, np.ndarray]
    payload: np.ndarray | None
    undetermined: np.ndarray  # (C, 3): segment, index in its ``unresolved``, ΔP [Pa]; segment −1: none


def sample_chunk(task: tuple[Problem, Classes]) -> ChunkResult:
    """The sampled plan of one chunk of classes (a picklable task for
    :func:`pampipe.runtime.executors.run_all`)."""
    problem, classes = task
    retain_freed_memory()  # MB-sized temporaries in a loop: reuse them, no page faults (pampipe.runtime.heap)
    draws = muscle_draws(problem)
    n, count, m = problem.samples, len(classes), len(problem.structures)
    bore, friction = class_deviations(problem, classes)
    shape = (count, m)
    out = ChunkResult(np.full(shape, np.inf), np.zeros(shape), np.zeros(shape),
                      {f"{c:g}": np.full(shape, np.inf) for c in LEVELS}, np.full((*shape, 2), np.inf),
                      np.full(shape, np.nan), {k: np.full(shape, np.nan) for k in problem.active},
                      {k: np.full(shape, np.nan) for k in problem.active},
                      None if problem.supply is None else np.full(shape, -np.inf),
                      np.tile([-1.0, -1.0, 0.0], (count, 1)))
    half = 1.959964 * math.sqrt(n * problem.level * (1 - problem.level))
    band = [max(math.floor(n * problem.level - half) - 1, 0),
            min(math.ceil(n * problem.level + half) - 1, n - 1)]
    ranks = [upper_rank(n, problem.level), *band, *(upper_rank(n, level) for level in LEVELS)]
    alone_ranks = [upper_rank(n, problem.level), upper_rank(n, 1 - problem.level)]
    for i in range(m):
        rows = np.flatnonzero(classes.valid[:, i])
        twin = problem.twins[i] if problem.twins else i
        if rows.size == 0 or twin != i:  # a twin's draws and inputs are the same: so is its plan
            _copy(out, twin, i)
            continue
        take = slice(None) if rows.size == count else rows  # every class: no copy
        ev = Evaluator(problem, draws, classes, i, rows, bore[take].T, friction[take].T)
        supply = None if problem.supply is None else problem.supply[i]
        least, touch, held = ev.evaluate(problem.active, supply, raw=True)
        (planned, *rest), out.holding[rows, i] = order_statistics(least, ranks, share=True, overwrite=True,
                                                                  settle=settle)
        out.pressure[rows, i] = planned
        out.contact[rows, i] = share_at_most(touch, planned)
        out.band[rows, i] = np.stack(rest[:2], axis=1)
        for key, value in zip(out.levels, rest[2:], strict=True):
            out.levels[key][rows, i] = value
        del least, touch
        if held is not None:
            out.payload[rows, i] = order_statistics(held, [lower_rank(n, problem.level)])[0]
        certain = ev.evaluate(())[0][0]
        out.certain[rows, i] = certain
        for name in problem.active:
            high, low = ev.alone(name, alone_ranks)
            out.shifts[name][rows, i] = high - certain
            out.low_shifts[name][rows, i] = low - certain
        for k, direction in enumerate(problem.uncertainties[i].unresolved):
            moved = ev.moves(direction)
            new = (np.abs(moved) > MOVES) & (out.undetermined[rows, 0] < 0)
            out.undetermined[rows[new]] = np.column_stack([np.full(new.sum(), i), np.full(new.sum(), k),
                                                           moved[new]])
    return out


def class_deviations(problem: Problem, classes: Classes) -> tuple[np.ndarray, np.ndarray]:
    """(bore δ [m], friction δ) (C, n): each class's draws of its bore and friction statements, a row
    each (the evaluator takes (n, C) views)."""
    n, count = problem.samples, len(classes)
    bore = np.zeros((count, n))
    friction = np.zeros((count, n))
    for c in range(count):
        if classes.bore_sd[c] > 0:
            statement = (classes.low[c], classes.high[c], classes.bore_sd[c])
            bore[c] = keyed_normal(problem.seed, "bore", statement, n) * classes.bore_sd[c]
        if classes.mu_sd[c] > 0:
            statement = (classes.mu[c], classes.mu_sd[c])
            friction[c] = keyed_normal(problem.seed, "friction", statement, n) * classes.mu_sd[c]
    return bore, friction


def _copy(out: ChunkResult, j: int, i: int) -> None:
    """Segment j's sampled plan as segment i's (in place; not the undetermined flags, which name j)."""
    for a in (out.pressure, out.holding, out.contact, out.band, out.certain, out.payload,
              *out.levels.values(), *out.shifts.values(), *out.low_shifts.values()):
        if a is not None:
            a[:, i] = a[:, j]


def segment_twins(problem: Problem, draws: MuscleDraws, worst: np.ndarray, valid: np.ndarray) -> tuple:
    """For each segment i, the first segment j ≤ i with the same muscle, mass, pressure limit, worst bores
    (``worst``, ``valid``: (S, segments)) and the same draws of every source: its plan is i's."""
    out = []
    for i in range(len(problem.structures)):
        out.append(next(j for j in range(i + 1) if j == i or _alike(problem, draws, worst, valid, i, j)))
    return tuple(out)


def _alike(problem: Problem, draws: MuscleDraws, worst, valid, i: int, j: int) -> bool:
    ui, uj = problem.uncertainties[i], problem.uncertainties[j]
    same = (problem.structures[i] == problem.structures[j] and problem.masses[i] == problem.masses[j]
            and (problem.supply is None or problem.supply[i] == problem.supply[j])
            and ui.fit_key == uj.fit_key and not ui.unresolved and not uj.unresolved
            and np.array_equal(ui.nominal, uj.nominal) and np.array_equal(worst[:, i], worst[:, j])
            and np.array_equal(valid[:, i], valid[:, j]))
    return same and all(np.array_equal(d[i], d[j]) for d in (*draws.params.values(), draws.model_error))
