"""`solve_inventory`: the muscle (or K muscles) for a pipe inventory, on any executor."""

from __future__ import annotations

import time
from concurrent.futures import Executor, Future

import numpy as np

from pampipe.design.evaluate import evaluate_pipes
from pampipe.design.result import DesignResult, size_result
from pampipe.design.single import DesignInfeasible, design_for
from pampipe.design.sizes import choose_sizes
from pampipe.errors import InputError
from pampipe.model.muscle import Muscle
from pampipe.runtime import progress
from pampipe.runtime.executors import SerialExecutor
from pampipe.specs.inventory import Inventory, Objective


class _Tally(Executor):
    """Counts the solves and IPOPT iterations of the tasks that pass through an executor.

    Counted from the finished futures when read, in the caller's thread: a done-callback of a process
    pool or Dask runs in the executor's own thread, possibly after ``result()`` has returned to the
    caller, so counting there made ``nlp_solves`` depend on the executor and the machine's load.
    """

    def __init__(self, inner: Executor):
        self.inner, self.futures = inner, []

    def submit(self, fn, /, *args, **kwargs) -> Future:
        future = self.inner.submit(fn, *args, **kwargs)
        self.futures.append(future)
        return future

    def _results(self) -> list:
        return [f.result() for f in self.futures if f.done() and not f.cancelled() and f.exception() is None]

    @property
    def solves(self) -> int:
        return len(self._results())

    @property
    def iterations(self) -> int:
        return sum(max(getattr(r, "iterations", 0), 0) for r in self._results())


def check_material(inventory: Inventory) -> Muscle:
    """The material's muscle; the design's closed forms need moduli and no diagnosed effects."""
    where = f"{inventory.source}: material"
    muscle = Muscle.from_pam(inventory.material, where=where)
    if muscle.has_effects:
        raise InputError(f"{where}: the PAM '{inventory.material.name}' carries diagnosed effects "
                         f"({', '.join(inventory.material.effects)}); the design NLP uses the closed-form "
                         "holding pressure of the baseline model (with contact increments), so give a "
                         "material PAM without an 'effects:' block.")
    return muscle


def solve_inventory(inventory: Inventory, *, pool: Executor | None = None) -> DesignResult:
    """Design the muscle(s) for ``inventory`` (see :mod:`pampipe.design`); the starts run on ``pool``.

    Without ``design.sizes`` one muscle must serve every pipe: if none can, the result has
    ``feasible=False`` and names the binding constraint. With ``sizes: K``, up to K muscles serve
    the most length; the result is infeasible only if no muscle serves any bore.
    """
    started = time.perf_counter()
    check_material(inventory)
    with progress.overall("design starts", planned_starts(inventory)):
        return _solve(inventory, _Tally(pool or SerialExecutor()), started)


def planned_starts(inventory: Inventory) -> int:
    """The starts one muscle takes: ``starts`` for the largest pressure, as many again and the best of
    those for another objective. Sizes (``design.sizes``) and an infeasible inventory's deletion filter
    add more on the way (:func:`pampipe.runtime.progress.overall` counts them as they come)."""
    space = inventory.space
    return space.starts if space.objective is Objective.MAX_PRESSURE else 2 * space.starts + 1


def _solve(inventory: Inventory, tally: _Tally, started: float) -> DesignResult:
    """:func:`solve_inventory`'s work, its starts counted on ``tally``."""
    material_table = evaluate_pipes(inventory, _material_geometry(inventory))
    pipes = inventory.pipes
    name = inventory.material.name
    try:
        if inventory.space.sizes is None:
            design = design_for(inventory, pipes, tally)
            table = evaluate_pipes(inventory, design.geometry)
            sizes = (size_result(inventory, design, table, table.served, f"{name}-design"),)
            assignment, rounds = np.where(table.served, 0, -1), 0
        else:
            plan = choose_sizes(inventory, inventory.space.sizes, tally)
            served = np.array([(plan.assignment == k).any() for k in range(len(plan.designs))])
            length = [pipes.length[plan.assignment == k].sum() for k in range(len(plan.designs))]
            order = sorted(np.flatnonzero(served), key=lambda k: (-length[k], k))
            sizes = tuple(size_result(inventory, plan.designs[k], plan.tables[k], plan.assignment == k,
                                      f"{name}-size{n + 1}") for n, k in enumerate(order))
            relabel = {int(k): n for n, k in enumerate(order)}
            assignment = np.array([relabel.get(int(a), -1) for a in plan.assignment])
            rounds = plan.rounds
    except DesignInfeasible as exc:
        best = ()
        if exc.best is not None:
            table = evaluate_pipes(inventory, exc.best.geometry)
            none = np.zeros(len(pipes), dtype=bool)
            best = (size_result(inventory, exc.best, table, none, f"{name}-best"),)
        return DesignResult(inventory, best, np.full(len(pipes), -1), material_table, feasible=False,
                            binding=exc.binding, reason=str(exc), solves=tally.solves,
                            iterations=tally.iterations, wall_time=time.perf_counter() - started)
    return DesignResult(inventory, sizes, assignment, material_table, rounds=rounds, solves=tally.solves,
                        iterations=tally.iterations, wall_time=time.perf_counter() - started)


def _material_geometry(inventory: Inventory) -> tuple[float, float, float]:
    g = inventory.material.geometry
    return g.initial_length, g.initial_diameter, g.braid_angle
