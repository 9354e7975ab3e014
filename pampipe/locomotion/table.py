"""The sequential gait of many route sections at once: the numbers of `pampipe gait`'s step table.

The sequential schedule (:func:`~pampipe.locomotion.schedule.sequential_plan`) moves one segment per
phase, valve fully open, from the vented pressure P_v to the plan's pressure P_i (rise) or back (fall),
for exactly the transition time t = ∫ dP/|ṗ| (:func:`~pampipe.pneumatics.timing.transition_times`).
So, with no simulation (docs/physics.md §8.5):

* the pressures at the end of each step are the levels the schedule fills or vents to (P_i or P_v;
  a closed valve keeps its pressure);
* each phase lasts the transition time of its moving segment, and the cycle their sum;
* the stride is L_free,2(P_v) − L_2(D_p): within each phase a held segment keeps its ends, so the rear
  moves by the change of the lengths behind it, and over a cycle these changes add up to the middle
  segment's free length at P_v minus its anchored length (max with L(D_p), as the simulation clamps).

These agree with the simulated gait (:func:`~pampipe.locomotion.sequential_gait`) to its integrator's
tolerance; every section's chambers are fitted at once per distinct muscle
(:func:`~pampipe.pneumatics.timing.chambers_of_muscle`), every transition integrated in one pass.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from pampipe.locomotion.requirements import vented_error
from pampipe.locomotion.schedule import MIDDLE, PHASES
from pampipe.pneumatics.options import GaitOptions
from pampipe.pneumatics.timing import Chamber, chambers_of_muscle, transition_times

#: +1 (fill), −1 (vent) or 0 for each segment in each phase of the sequential schedule (6, 3).
VALVES = np.array([[{"rise": 1, "fall": -1}.get(role, 0) for role in phase.roles] for phase in PHASES])


@dataclass(frozen=True)
class SequentialTable:
    """The sequential gait of ``sections`` (route indices), SI: one row per section."""

    sections: np.ndarray  # (n,) route indices
    durations: np.ndarray  # (n, 6) [s] of the transitions into steps II … VII
    pressures: np.ndarray  # (n, 7, 3) [Pa] gauge at the end of steps I … VII
    cycle_time: np.ndarray  # (n,) [s]
    stride: np.ndarray  # (n,) [m]
    chamber: Chamber | None = None  # (n, 3) fields: each segment's chamber in each section


def _muscle_key(muscle) -> tuple:
    """What makes two muscles the same physics: segments with one PAM share their chamber fits."""
    def values(v):
        return None if v is None else tuple(np.ravel(np.asarray(v, dtype=float)).tolist())
    effects = repr(sorted((muscle.effects or {}).items()))
    return (muscle.geometry, values(muscle.theta), float(muscle.reference_pressure), values(muscle.contact),
            effects)


def _chambers(muscles, diameter: np.ndarray) -> Chamber:
    """The chamber of every (section, segment) of ``diameter`` (n, 3): one fit per muscle and bore."""
    fields = np.empty((*diameter.shape, 3 + len(Chamber.rigid(1.0).shape)))
    groups: dict[tuple, list[int]] = {}
    for i, muscle in enumerate(muscles):
        groups.setdefault(_muscle_key(muscle), []).append(i)
    for columns in groups.values():
        bores, where = np.unique(diameter[:, columns], return_inverse=True)
        fitted = chambers_of_muscle(muscles[columns[0]], bores)
        table = np.column_stack([fitted.anchored_volume, fitted.rest_volume, fitted.anchoring_pressure,
                                 *fitted.shape])
        fields[:, columns] = table[where.reshape(len(diameter), len(columns))]
    return Chamber(fields[..., 0], fields[..., 1], fields[..., 2], tuple(np.moveaxis(fields[..., 3:], -1, 0)))


def sequential_table(mission, plan, options: GaitOptions, sections) -> SequentialTable:
    """The sequential gait of route ``sections`` (crossable ones) of ``mission`` from its ``plan``.

    Raises InputError when the vented pressure is not below a contact pressure, as `gait` does.
    """
    sections = np.asarray(sections, dtype=int)
    if sections.size == 0:
        return SequentialTable(sections, np.zeros((0, len(PHASES))), np.zeros((0, len(PHASES) + 1, 3)),
                               np.zeros(0), np.zeros(0))
    a = plan.arrays
    contact, target = a.anchoring_pressure[sections], a.pressure[sections]
    vented = options.vented_pressure
    if np.any(vented >= contact):
        k, i = np.argwhere(vented >= contact)[0]
        raise vented_error(mission, options, int(i), int(sections[k]), float(contact[k, i]))
    chamber = _chambers(plan.muscles, a.diameter[sections])
    fill, vent = (transition_times(chamber, start, end, supply=mission.supply_pressure, valve=options.valve,
                                   gas=options.gas).reshape(target.shape)
                  for start, end in ((vented, target), (target, vented)))
    level = np.full(target.shape, float(vented))
    level[:, MIDDLE] = target[:, MIDDLE]
    pressures, durations = [level.copy()], []
    for k in range(len(PHASES)):
        moving = int(np.flatnonzero(VALVES[k])[0])
        rising = VALVES[k, moving] > 0
        durations.append((fill if rising else vent)[:, moving])
        level[:, moving] = target[:, moving] if rising else vented
        pressures.append(level.copy())
    durations = np.stack(durations, axis=1)
    cycle = durations[:, 0]
    for k in range(1, durations.shape[1]):
        cycle = cycle + durations[:, k]  # in the order np.sum adds six numbers
    middle = plan.muscles[MIDDLE]
    anchored = a.anchored_length[sections, MIDDLE]
    stride = np.maximum(float(middle.free_length(max(vented, 0.0))[0]), anchored) - anchored
    return SequentialTable(sections, durations, np.stack(pressures, axis=1), cycle, stride, chamber)
