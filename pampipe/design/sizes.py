"""K muscle sizes that together serve the most pipe length (``design.sizes: K``).

1. *Intervals.* Sort the distinct nominal bores b₁ < … < b_n. One muscle serving every pipe of the
   bores b_i … b_j is the design NLP on those pipes; if it exists, it exists for every sub-interval
   (fewer constraints, a wider smallest bore), so for each i a two-pointer sweep finds the widest
   reach(i) = the largest j served, with O(n) NLP solves.
2. *Enumeration.* A dynamic programme over i picks at most K disjoint intervals [i, reach(i)] of
   largest total length (taking the widest interval from i is never worse: the next one can only
   start later and reach further).
3. *Assign and refit* (the k-means-like alternation). Each pipe goes to the size that serves it at
   the least pressure (a size may serve pipes outside its interval, or only some pipes of a bore);
   each size is refitted to its pipes (with the inventory's objective; the interval sweep only asks
   whether the largest pressure can stay within the supply), starting from its current design, so
   every assigned pipe stays served and the covered length never falls; repeat until the assignment
   is stable (at least one refit).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from pampipe.design.evaluate import PipeTable, evaluate_pipes
from pampipe.design.single import DesignInfeasible, SizeDesign, design_for
from pampipe.specs.inventory import Inventory

MAX_ROUNDS = 8  # assign-and-refit rounds (the tested inventories settle in 1 to 3)


@dataclass(frozen=True)
class SizePlan:
    """K designs, the pipe → size assignment (-1: unserved) and each size's table on every pipe."""

    designs: tuple[SizeDesign, ...]
    assignment: np.ndarray  # (pipes,) int
    tables: tuple[PipeTable, ...]
    reach: tuple[int, ...]  # reach(i) per distinct bore (-1 where a bore alone cannot be served)
    bores: np.ndarray  # the distinct nominal bores [m]
    rounds: int


def choose_sizes(inventory: Inventory, k: int, pool) -> SizePlan:
    """Up to ``k`` muscles serving the most length of ``inventory`` (InfeasibleError if none serves any)."""
    pipes = inventory.pipes
    bores, which = np.unique(pipes.diameter, return_inverse=True)
    cache: dict[tuple[int, int], SizeDesign | None] = {}

    def design(i: int, j: int) -> SizeDesign | None:
        if (i, j) not in cache:
            try:
                cache[i, j] = design_for(inventory, pipes.subset((which >= i) & (which <= j)), pool,
                                         diagnose=False, polish=False)
            except DesignInfeasible:
                cache[i, j] = None
        return cache[i, j]

    reach = []
    j = -1
    for i in range(len(bores)):
        j = max(j, i - 1)
        while j + 1 < len(bores) and design(i, j + 1) is not None:
            j += 1
        reach.append(j)
    intervals = _best_intervals(reach, np.bincount(which, weights=pipes.length, minlength=len(bores)), k)
    if not intervals:
        try:
            design_for(inventory, pipes.subset(which == 0), pool)
        except DesignInfeasible as exc:
            raise DesignInfeasible("no muscle within the design bounds serves all the pipes of even one "
                                   f"bore; for the narrowest, {bores[0] * 1e3:.4g} mm: {exc}", exc.binding,
                                   exc.best) from None
    designs = [design(i, j) for i, j in intervals]
    return _assign_and_refit(inventory, designs, pool, tuple(reach), bores)


def _best_intervals(reach: list[int], length: np.ndarray, k: int) -> list[tuple[int, int]]:
    """At most k disjoint intervals [i, reach(i)] of largest total length (ties: the earliest bores)."""
    n = len(reach)
    prefix = np.concatenate([[0.0], np.cumsum(length)])
    best = np.zeros((k + 1, n + 2))
    take = np.zeros((k + 1, n + 1), dtype=bool)
    for m in range(1, k + 1):
        for i in range(n - 1, -1, -1):
            skip = best[m, i + 1]
            best[m, i] = skip
            if reach[i] >= i:
                value = prefix[reach[i] + 1] - prefix[i] + best[m - 1, reach[i] + 1]
                if value > skip:
                    best[m, i], take[m, i] = value, True
    out, m, i = [], k, 0
    while m > 0 and i < n:
        if take[m, i]:
            out.append((i, reach[i]))
            i, m = reach[i] + 1, m - 1
        else:
            i += 1
    return out


def _assign(inventory: Inventory, tables: list[PipeTable]) -> np.ndarray:
    """Each pipe to the serving size of least largest pressure (lowest index among equals), else -1."""
    largest = np.stack([np.where(t.served, t.largest, np.inf) for t in tables])
    best = np.argmin(largest, axis=0)
    return np.where(np.isfinite(largest.min(axis=0)), best, -1)


def _assign_and_refit(inventory: Inventory, designs: list[SizeDesign], pool, reach, bores) -> SizePlan:
    tables = [evaluate_pipes(inventory, d.geometry) for d in designs]
    assignment = _assign(inventory, tables)
    rounds = 0
    while rounds < MAX_ROUNDS:
        rounds += 1
        refitted = []
        for s, d in enumerate(designs):
            mine = assignment == s
            if not mine.any():
                refitted.append(d)
                continue
            try:
                x = d.run.problem.space
                u = [(g - x[2 * c]) / (x[2 * c + 1] - x[2 * c]) if x[2 * c + 1] > x[2 * c] else 0.0
                     for c, g in enumerate(d.geometry)]
                refitted.append(design_for(inventory, inventory.pipes.subset(mine), pool, extra=np.array(u),
                                           diagnose=False))
            except DesignInfeasible:
                refitted.append(d)
        new_tables = [evaluate_pipes(inventory, d.geometry) for d in refitted]
        new_assignment = _assign(inventory, new_tables)
        covered = inventory.pipes.length[new_assignment >= 0].sum()
        if covered < inventory.pipes.length[assignment >= 0].sum():
            break  # never give up covered length (a refit only loses pipes through round-off)
        designs, tables = refitted, new_tables
        if np.array_equal(new_assignment, assignment):
            break
        assignment = new_assignment
    return SizePlan(tuple(designs), assignment, tuple(tables), reach, bores, rounds)
