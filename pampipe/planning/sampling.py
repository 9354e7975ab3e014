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

import math
from dataclasses import dataclass
from functools import cache, cached_property, partial

import numpy as np

from pampipe.planning.classes import Classes, Problem
from pampipe.planning.convex import chunk_statistics
from pampipe.planning.evaluator import Evaluator
from pampipe.planning.family import families
from pampipe.planning.law import settle
from pampipe.planning.quantiles import lower_rank, order_statistics, share_at_most, upper_rank
from pampipe.planning.sources import MuscleDraws, draw_muscles, keyed_normal
from pampipe.runtime.heap import retain_freed_memory

LEVELS = (0.9, 0.99, 0.999)  # the pressures every confidence plan reports
#: Memory a chunk may use for its draws × classes arrays [B].
MEMORY_BUDGET = 64 << 20
#: How many times more classes a chunk sampled from candidate draws takes (:func:`by_candidates`): its
#: arrays are a block of at most family.LARGEST_BLOCK classes, its Python work per chunk (the families, their
#: first blocks) is shared. 10⁵ all-distinct sections at 10⁴ draws: 48 chunks of 2,112 classes sampled in
#: 8.2 s CPU against 9.4–10.0 s in 190 chunks (16), the same bits and peak memory; 12 chunks (256) no faster.
CANDIDATE_CHUNKS = 64
#: Bytes one draw of one class costs at the peak of a chunk (the temporaries of the closed form over a
#: range's bores, the sorted copies): the peak resident memory grew by 137–167 B per draw and class for
#: chunks of 21 and 180 classes at 10⁴ draws (the riser robot, 180 kinds of section).
BYTES_PER_DRAW = 200
#: The share of a segment's margin to its pressure limit (the supply, or its PAM's rating), limit − P_C, that
#: covering the undetermined directions may add to its C-quantile P_C before the segment is stopped (exit 3,
#: docs/physics.md §15): within it, even a truth ten open widths out along a direction (linearly) still holds
#: at the limit, so the direction cannot turn a plan that holds at the supply into one that does not.
OPEN_SHARE = 0.1


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
    open_base: np.ndarray  # [Pa] P_C without the undetermined directions (NaN: none open)
    open_shift: np.ndarray  # [Pa] what covering the undetermined directions adds to P_C (NaN: none open)
    open_direction: np.ndarray  # the direction (index in ``unresolved``) that adds most alone (−1: none)
    stopped: np.ndarray  # bool: the open directions move P_C by more than OPEN_SHARE of its margin


def sample_chunk(task: tuple[Problem, Classes]) -> ChunkResult:
    """The sampled plan of one chunk of classes (a picklable task for
    :func:`pampipe.runtime.executors.run_all`)."""
    problem, classes = task
    retain_freed_memory()  # MB-sized temporaries in a loop: reuse them, no page faults (pampipe.runtime.heap)
    draws = muscle_draws(problem)
    n, count, m = problem.samples, len(classes), len(problem.structures)
    drawn = cache(partial(class_deviations, problem, classes))  # on first use, once per chunk
    shape = (count, m)
    out = ChunkResult(np.full(shape, np.inf), np.zeros(shape), np.zeros(shape),
                      {f"{c:g}": np.full(shape, np.inf) for c in LEVELS}, np.full((*shape, 2), np.inf),
                      np.full(shape, np.nan), {k: np.full(shape, np.nan) for k in problem.active},
                      {k: np.full(shape, np.nan) for k in problem.active},
                      None if problem.supply is None else np.full(shape, -np.inf),
                      np.full(shape, np.nan), np.full(shape, np.nan), np.full(shape, -1),
                      np.zeros(shape, dtype=bool))
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
        ev = Evaluator(problem, draws, classes, i, rows, Deviations(drawn, 0, take),
                       Deviations(drawn, 1, take))
        supply = None if problem.supply is None else problem.supply[i]
        plain = supply is None and not problem.uncertainties[i].unresolved and ev.drag_draws is None
        found = by_families(ev, problem.active, ranks, share=True) if plain else None
        if found is not None:  # the classes' statistics from a few draws each (pampipe.planning.family)
            (planned, *rest), out.holding[rows, i] = found
            out.pressure[rows, i] = planned
            out.contact[rows, i] = ev.touch_share(problem.active, planned)
        else:
            rest = _whole_rows(out, problem, ev, supply, ranks, rows, i)
        out.band[rows, i] = np.stack(rest[:2], axis=1)
        for key, value in zip(out.levels, rest[2:], strict=True):
            out.levels[key][rows, i] = value
        certain = ev.evaluate(())[0][0]
        out.certain[rows, i] = certain
        for name in problem.active:
            alone = by_families(ev, (name,), alone_ranks, share=False) if plain and not ev.monotone(name) \
                else None
            high, low = ev.alone(name, alone_ranks) if alone is None else alone[0]
            out.shifts[name][rows, i] = high - certain
            out.low_shifts[name][rows, i] = low - certain
    return out


def by_families(ev: Evaluator, sources, ranks: list[int], share: bool):
    """(settled order statistics (len(ranks), C), shares or None) of the evaluator's classes with
    ``sources`` drawn, from the candidate draws of each family (:mod:`pampipe.planning.family`); None
    where they do not apply (the whole rows are evaluated then)."""
    found = families(ev, sources)
    if found is None:
        return None
    return chunk_statistics(found, ranks, ev.problem.samples, ev.mu.size, share)


def _whole_rows(out: ChunkResult, problem: Problem, ev: Evaluator, supply, ranks, rows, i: int) -> list:
    """Segment i's plan from every draw of every class (payload, undetermined directions, tether draws):
    fills the pressure, holding, contact, payload and open-direction entries; returns the other
    statistics (band, levels)."""
    n = problem.samples
    least, touch, held = ev.evaluate(problem.active, supply, raw=True)
    base = None
    if problem.uncertainties[i].unresolved:
        least, touch, held, base, which = cover_open(problem, ev, least, touch, held, supply)
        out.open_direction[rows, i] = which
    (planned, *rest), out.holding[rows, i] = order_statistics(least, ranks, share=True, overwrite=True,
                                                              settle=settle)
    out.pressure[rows, i] = planned
    if base is not None:
        out.open_base[rows, i] = base
        out.open_shift[rows, i], out.stopped[rows, i] = stop_open(planned, base, problem.limits[i])
    out.contact[rows, i] = share_at_most(touch, planned)
    if held is not None:
        out.payload[rows, i] = order_statistics(held, [lower_rank(n, problem.level)])[0]
    return rest


def cover_open(problem: Problem, ev: Evaluator, least, touch, held, supply):
    """The draws held over the open width of every undetermined direction (docs/physics.md §15): per draw,
    the worst of the muscle at q̂ and at q̂ ± s·v for each unresolved direction v on its own (s its open
    width). Returns (raw P* (n, C), touch (n, C), payload (n, C) or None, P_C without the open directions
    (C,) [Pa], the direction whose cover alone adds most to P_C (C,))."""
    rank = [upper_rank(problem.samples, problem.level)]
    base = order_statistics(least, rank, settle=settle)[0]  # a copy: ``least`` keeps its order
    covered = np.array(least)
    most, which = np.full(base.shape, -np.inf), np.full(base.shape, -1)
    for k, direction in enumerate(problem.uncertainties[ev.i].unresolved):
        one = np.array(least)
        for sign in (1.0, -1.0):
            shifted, t, h = ev.evaluate(problem.active, supply, nominal=ev.nominal + sign * direction.scale
                                        * direction.step, raw=True)
            np.maximum(one, shifted, out=one)  # NaN (does not hold) stays NaN: the worst
            touch = np.maximum(touch, t)  # touching the largest bore at every point of the width
            held = None if held is None else np.minimum(held, h)
        np.maximum(covered, one, out=covered)
        alone = order_statistics(one, rank, settle=settle, overwrite=True)[0]
        more = alone > most
        most[more], which[more] = alone[more], k
    return covered, touch, held, base, which


def stop_open(planned: np.ndarray, base: np.ndarray, limit: float) -> tuple[np.ndarray, np.ndarray]:
    """(ΔP = P_C covered − P_C without the open directions [Pa], stopped): a segment whose plan without them
    is within its pressure ``limit`` [Pa] stops where ΔP exceeds OPEN_SHARE of its margin limit − P_C
    (ΔP = inf, a muscle that no longer holds somewhere in the width, always does)."""
    with np.errstate(invalid="ignore"):
        shift = planned - base
        return shift, (base <= limit) & ~(shift <= OPEN_SHARE * (limit - base))


def by_candidates(problem: Problem, classes: Classes) -> bool:
    """True where every segment's classes are sampled from candidate draws (:mod:`pampipe.planning.family`):
    no payload, no undetermined direction left open, no tether draws, no contact increments or effects.
    Their chunks then hold no draws × classes arrays, and may be :data:`CANDIDATE_CHUNKS` times larger."""
    return (problem.supply is None and classes.drag_draws is None
            and not any(u.unresolved for u in problem.uncertainties)
            and not any(s.contact or s.effects for s in problem.structures))


class Deviations:
    """One kind of a chunk's class deviations (``kind`` 0: bore δ [m], 1: friction δ, of
    :func:`class_deviations`) for the chunk's classes ``take`` (a slice or rows), as the evaluator takes
    them: ``.T`` is the (C, n) array. ``drawn`` draws both kinds of every class of the chunk on its first
    call and keeps them (``functools.cache``), so the chunk's segments share one draw; the candidates'
    path (:mod:`pampipe.planning.family`) draws each statement's row itself and never calls it."""

    def __init__(self, drawn, kind: int, take):
        self._drawn, self._kind, self._take = drawn, kind, take

    @cached_property
    def T(self) -> np.ndarray:
        return self._drawn()[self._kind][self._take]


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
