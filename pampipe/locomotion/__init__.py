"""`pampipe gait`: the peristaltic schedule, its pneumatic timing, and the time-optimal gait.

* :func:`sequential_gait`: one transition at a time, valves fully open (docs/physics.md §8).
* :func:`optimal_gait`: the minimum-time cycle that never lets go of the wall (:mod:`.optimal`).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from pampipe.locomotion.optimal import WarmStart, problem_key, solve_optimal
from pampipe.locomotion.replay import simulate
from pampipe.locomotion.requirements import find_section, section_needs
from pampipe.locomotion.result import GaitResult, evaluate
from pampipe.locomotion.schedule import ControlPlan, sequential_plan
from pampipe.pneumatics.options import GaitOptions, gait_options
from pampipe.specs.mission import Mission

__all__ = ["GaitOptions", "GaitResult", "gait_options", "optimal_gait", "sequential_gait"]


def sequential_gait(mission: Mission, section: str | int | None = None, *,
                    options: GaitOptions | None = None, samples: int = 100, mission_plan=None) -> GaitResult:
    """The sequential schedule in ``section`` (a name or a route index; default: the first), simulated
    ``samples`` per step.

    ``mission_plan`` is ``plan_mission(mission)`` when already computed. The step table of many sections
    at once, without simulation: :func:`pampipe.locomotion.table.sequential_table`.
    """
    options = options or gait_options(mission.gait, source=mission.source)
    index = section if isinstance(section, int) else find_section(mission, section)
    needs = section_needs(mission, index, options, plan=mission_plan)
    name = mission.route[index].name
    plan = sequential_plan(needs, supply=mission.supply_pressure, options=options)
    return evaluate(name, "sequential", needs, plan, supply=mission.supply_pressure, options=options,
                    samples=samples)


def optimal_gait(mission: Mission, section: str | None = None, *, options: GaitOptions | None = None,
                 baseline: GaitResult | None = None, refine: int = 10,
                 warm_start: WarmStart | None = None) -> GaitResult:
    """The time-optimal gait in ``section``, re-simulated exactly on a grid ``refine``× finer than
    the optimiser's.

    ``warm_start`` (``GaitResult.warm_start`` of an earlier optimal gait of the same structure)
    starts IPOPT from that solution, and then no sequential schedule is computed. Otherwise the
    sequential schedule is the initial guess: ``baseline`` if given (its section and thresholds
    are used as they are), else computed here.
    """
    options = options or gait_options(mission.gait, source=mission.source)
    if baseline is not None:
        name, needs = baseline.section, baseline.needs
    else:
        index = find_section(mission, section)
        name, needs = mission.route[index].name, section_needs(mission, index, options)
    supply = mission.supply_pressure
    guess = nodes = None
    if warm_start is None or warm_start.key != problem_key(needs, options):
        start = baseline.plan if baseline is not None else sequential_plan(needs, supply=supply,
                                                                           options=options)
        guess = ControlPlan(start.durations, np.repeat(start.commands, options.intervals, axis=1),
                            start.start)
        nodes = simulate(tuple(n.chamber for n in needs), guess, supply=supply, options=options,
                         samples=1).pressures
    plan, info, after = solve_optimal(needs, guess, nodes, supply=supply, options=options,
                                      warm_start=warm_start)
    result = evaluate(name, "optimal", needs, plan, supply=supply, options=options, samples=refine,
                      solver=info)
    return replace(result, warm_start=after)
