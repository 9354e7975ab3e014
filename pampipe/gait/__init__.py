"""`pampipe gait`: the peristaltic schedule, its pneumatic timing, and the time-optimal gait.

* :func:`sequential_gait`: one transition at a time, valves fully open (docs/physics.md §8).
* :func:`optimal_gait`: the minimum-time cycle that never lets go of the wall (:mod:`.optimal`).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from pampipe.gait.optimal import WarmStart, solve_optimal
from pampipe.gait.options import GaitOptions, gait_options
from pampipe.gait.requirements import find_section, section_needs
from pampipe.gait.result import GaitResult, evaluate
from pampipe.gait.schedule import ControlPlan, sequential_plan, simulate
from pampipe.mission import Mission

__all__ = ["GaitOptions", "GaitResult", "gait_options", "optimal_gait", "sequential_gait"]


def sequential_gait(mission: Mission, section: str | None = None, *,
                    options: GaitOptions | None = None, samples: int = 100) -> GaitResult:
    """The sequential schedule in ``section`` (default: the first), simulated ``samples`` per step."""
    options = options or gait_options(mission.gait, source=mission.source)
    where = find_section(mission, section)
    needs = section_needs(mission, where, options)
    plan = sequential_plan(needs, supply=mission.supply_pressure, options=options)
    return evaluate(where.name, "sequential", needs, plan, supply=mission.supply_pressure,
                    options=options, samples=samples)


def optimal_gait(mission: Mission, section: str | None = None, *, options: GaitOptions | None = None,
                 baseline: GaitResult | None = None, refine: int = 10,
                 warm_start: WarmStart | None = None) -> GaitResult:
    """The time-optimal gait in ``section``, re-simulated exactly on a grid ``refine``× finer than
    the optimiser's. ``baseline`` (the sequential gait) is the initial guess, unless ``warm_start``
    (``GaitResult.warm_start`` of an earlier optimal gait of the same structure) is given.
    """
    options = options or gait_options(mission.gait, source=mission.source)
    baseline = baseline or sequential_gait(mission, section, options=options)
    needs = baseline.needs
    n = options.intervals
    guess = ControlPlan(baseline.plan.durations, np.repeat(baseline.plan.commands, n, axis=1),
                        baseline.plan.start)
    nodes = simulate(needs, guess, supply=mission.supply_pressure, options=options, samples=1).pressures
    plan, info, after = solve_optimal(needs, guess, nodes, supply=mission.supply_pressure, options=options,
                                      warm_start=warm_start)
    result = evaluate(baseline.section, "optimal", needs, plan, supply=mission.supply_pressure,
                      options=options, samples=refine, solver=info)
    return replace(result, warm_start=after)
