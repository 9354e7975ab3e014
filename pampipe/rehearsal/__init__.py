"""`pampipe rehearse`: the whole route in time, from the model of `plan` and `gait` (docs/physics.md §16).

    from pampipe.rehearsal import rehearse_mission
    result = rehearse_mission(load_mission("mission.yaml"))    # -> Rehearsal
    result.time, result.free_air, result.tether.reach

* :mod:`.walk`: section by section, the sequential gait's stride, cycle time, cycles, time and free air, the
  supply hose and the compressor (all sections in one batch);
* :mod:`.optimal`: ``--optimal``, the time-optimal gait once per bore, as ratios;
* :mod:`.completion`: ``--confidence``, the chance of completing the route and where it first slips.
"""

from __future__ import annotations

import math

from pampipe.locomotion import gait_options
from pampipe.planning import plan_mission
from pampipe.planning.confidence import DEFAULT_SAMPLES, DEFAULT_SEED
from pampipe.planning.reach import route_reach
from pampipe.rehearsal.completion import completion
from pampipe.rehearsal.optimal import optimal_ratios
from pampipe.rehearsal.result import Rehearsal
from pampipe.rehearsal.walk import walk_route, walked_sections

__all__ = ["Rehearsal", "rehearse_mission"]


def rehearse_mission(mission, *, optimal: bool = False, confidence: float | None = None,
                     samples: int = DEFAULT_SAMPLES, seed: int = DEFAULT_SEED, progress=None) -> Rehearsal:
    """Rehearse ``mission`` (a :class:`~pampipe.specs.mission.Mission`): plan it (at ``confidence`` C with
    ``samples`` seeded draws when given), find the reach, walk to it with the gait of ``options`` (the
    optimal one with ``optimal``) and, with ``confidence``, the draws' completion probability."""
    plan = plan_mission(mission, confidence=confidence, samples=samples, seed=seed)
    options = gait_options(mission.gait, source=mission.source)
    tether = plan.tether or route_reach(mission, plan.muscles, plan.arrays, plan.bends)
    end = math.inf if tether.reach.reachable else tether.reach.distance  # reachable: every section whole
    ratios = None
    if optimal:
        rows = walked_sections(mission, plan, end)
        ratios = optimal_ratios(mission, plan, options, rows, progress=progress)
    if progress is not None:
        progress(f"walking {tether.reach.distance:.6g} m of the route ...")
    walk = walk_route(mission, plan, options, end, ratios=ratios)
    result = Rehearsal(str(mission.source), "optimal" if optimal else "sequential", walk, tether, plan,
                       mission.tether, options.gas)
    if confidence is None:
        return result
    if progress is not None:
        progress(f"the {samples} draws against the walk ...")
    done = completion(mission, plan, walk, level=confidence, samples=samples, seed=seed)
    return Rehearsal(result.mission, result.schedule, walk, tether, plan, mission.tether, options.gas, done)
