"""`rehearse --optimal`: the time-optimal gait, solved once per bore, as ratios for every section
(docs/physics.md §16.3).

The optimal gait (`pampipe gait --optimal`, CasADi/IPOPT) is solved in one representative section per distinct
set of worst bores, the one of them that needs most pressure; each walked section of that bore then takes its
ratios optimal/sequential of cycle time and stride, applied to its own sequential gait (exact for the
representative, and for every section alike in pressures; an estimate for the others, whose pressures differ,
e.g. by the tether's tension). Each solve starts warm from the previous one of the same structure.
"""

from __future__ import annotations

import numpy as np

from pampipe.locomotion import optimal_gait, sequential_gait


def optimal_ratios(mission, plan, options, rows: np.ndarray, *,
                   progress=None) -> tuple[np.ndarray, np.ndarray]:
    """(cycle-time ratio, stride ratio) of the optimal over the sequential gait for each of ``rows``
    (walked route sections), one IPOPT solve per distinct set of worst bores."""
    a = plan.arrays
    bores, kind = np.unique(a.diameter[rows], axis=0, return_inverse=True)
    kind = np.asarray(kind).reshape(-1)
    cycle, stride = np.ones(rows.size), np.ones(rows.size)
    warm = None
    for k in range(bores.shape[0]):
        mine = np.flatnonzero(kind == k)
        representative = int(rows[mine[np.argmax(a.pressure[rows[mine]].max(axis=1))]])
        if progress is not None:
            name = mission.route.name[representative]
            progress(f"optimal gait {k + 1} of {bores.shape[0]} (section {name}) ...")
        sequential = sequential_gait(mission, representative, options=options, mission_plan=plan)
        best = optimal_gait(mission, options=options, baseline=sequential, warm_start=warm)
        warm = best.warm_start
        cycle[mine] = best.cycle_time / sequential.cycle_time
        stride[mine] = best.stride / sequential.stride
    return cycle, stride
