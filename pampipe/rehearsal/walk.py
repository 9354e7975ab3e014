"""The route in time, section by section: the gait's cycles, their time and their air (docs/physics.md
§16.3).

Every section the robot walks takes the sequential gait of `pampipe gait` from the plan's pressures, all
sections in one batch (:func:`pampipe.locomotion.table.sequential_table`): its stride s and cycle time t_c.

* cycles = ℓ_walked/s; time = cycles·t̄_c + the steering steps of the bend at its end (physics.md §14.5);
* free air per cycle: each fill of segment i from the vented pressure P_v to its plan P_i puts
  Δm = [(P + p_atm)·V(P)]_{P_v}^{P_i}/(R·T) into its chamber (isothermal gas, V(P) the gait's chamber),
  Δm/ρ_N normal cubic metres (ISO 8778: 20 °C, 100 kPa, ρ_N = 1.185 kg/m³, ISO 6358's reference air);
* a supply hose (``tether.hose``) as long as the distance walked: every fill runs through it
  (:mod:`pampipe.pneumatics.hose`), so t_c grows along the section; t̄_c is its mean over the walked part by
  3-point Gauss–Legendre in the distance (the fill times are smooth in the hose's length);
* a compressor (``tether.compressor``) of free-air delivery Q: where a cycle needs more air than Q·t_c, the
  fills wait for it, t_c → max(t_c, air per cycle/Q), and the section is ``compressor_limited``;
* with ``--optimal``, each section's cycle time and stride are scaled by those of the time-optimal gait
  over the sequential one in the section of its bore that needs most pressure
  (:mod:`pampipe.rehearsal.optimal`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from pampipe.locomotion.table import VALVES, sequential_table
from pampipe.pneumatics.hose import SupplyCurves
from pampipe.pneumatics.timing import GAS_CONSTANT, ISO_DENSITY, Chamber, transition_times

#: Gauss–Legendre nodes and weights over a section's walked part (weights summing to 1).
_NODES, _WEIGHTS = np.polynomial.legendre.leggauss(3)
NODES, WEIGHTS = 0.5 * (1.0 + _NODES), 0.5 * _WEIGHTS


@dataclass(frozen=True)
class Walk:
    """The rehearsed walk, one entry per route section (SI); a section not walked holds zeros (NaN for its
    stride and cycle time)."""

    entry: np.ndarray  # [m] distance of the section's entry: the hose deployed there
    walked: np.ndarray  # [m]
    stride: np.ndarray  # [m]
    cycle_time: np.ndarray  # [s] mean over the walked part, hose and compressor included
    gait_cycle_time: np.ndarray  # [s] the gait's own, its valves fed straight from the supply
    cycles: np.ndarray
    steering_time: np.ndarray  # [s] the steering steps of the bend at the section's end
    time: np.ndarray  # [s]
    air_per_cycle: np.ndarray  # [m³] normal
    free_air: np.ndarray  # [m³] normal
    compressor_limited: np.ndarray  # bool: the fills wait for the compressor somewhere in the section

    @property
    def end_time(self) -> np.ndarray:
        """[s] the time at each section's end (cumulative)."""
        return np.cumsum(self.time)


def free_air(chamber: Chamber, start, target, gas) -> np.ndarray:
    """Normal volume [m³] (ISO 8778) that fills ``chamber`` from gauge ``start`` to ``target`` [Pa]:
    [(P + p_atm)·V(P)]/(R·T)/ρ_N between the two."""
    atm, temperature = gas.atmospheric_pressure, gas.temperature

    def stored(pressure):
        return (pressure + atm) * chamber.volume(pressure) / (GAS_CONSTANT * temperature)

    return (stored(target) - stored(start)) / ISO_DENSITY


def walked_lengths(mission, plan, end: float) -> np.ndarray:
    """[m] of each section walked to ``end`` [m] from the entry: none of a section the plan cannot cross."""
    route = mission.route
    entry = np.concatenate([[0.0], np.cumsum(route.length)])
    walked = np.clip(end - entry[:-1], 0.0, route.length)
    walked[list(plan.arrays.reasons)] = 0.0
    return walked


def walked_sections(mission, plan, end: float) -> np.ndarray:
    """The indices of the sections walked to ``end`` [m] (:func:`walked_lengths`)."""
    return np.flatnonzero(walked_lengths(mission, plan, end) > 0)


def walk_route(mission, plan, options, end: float, *, ratios=None) -> Walk:
    """The walk of ``mission`` to ``end`` [m] from the entry at the pressures of ``plan``, with the gait
    ``options``; ``ratios``: (cycle-time ratio, stride ratio) per walked section of the optimal gait."""
    route = mission.route
    count = len(route)
    entry = np.concatenate([[0.0], np.cumsum(route.length)])
    walked = walked_lengths(mission, plan, end)
    rows = np.flatnonzero(walked > 0)
    table = sequential_table(mission, plan, options, rows)
    target = plan.arrays.pressure[rows]
    vented = np.full(target.shape, float(options.vented_pressure))
    rises = (VALVES > 0).sum(axis=0)  # fills of each segment per cycle
    air = free_air(table.chamber, vented, target, options.gas) @ rises
    tether = mission.tether
    hose = None if tether is None else tether.hose
    cycle, weights = table.cycle_time[:, None], np.ones(1)
    if hose is not None and rows.size:
        lengths = entry[rows, None] + walked[rows, None] * NODES[None, :]
        cycle, weights = _hose_cycles(mission, options, table, target, lengths), WEIGHTS
    gait, stride = table.cycle_time, table.stride
    if ratios is not None:
        cycle, gait, stride = cycle * ratios[0][:, None], gait * ratios[0], stride * ratios[1]
    limited = np.zeros(rows.size, dtype=bool)
    compressor = None if tether is None else tether.compressor
    if compressor is not None:
        wait = air / compressor.free_air_delivery
        limited = np.any(wait[:, None] > cycle, axis=1)
        cycle = np.maximum(cycle, wait[:, None])
    mean = cycle[:, 0] if weights.size == 1 else cycle @ weights
    out = {key: np.zeros(count) for key in ("cycles", "time", "air", "free", "steer")}
    for key in ("stride", "cycle", "gait"):
        out[key] = np.full(count, np.nan)
    out["stride"][rows], out["cycle"][rows], out["gait"][rows] = stride, mean, gait
    out["cycles"][rows] = walked[rows] / stride
    out["air"][rows] = air
    out["free"][rows] = out["cycles"][rows] * air
    for bend in plan.bends:
        if bend.passable and bend.steps is not None and end > entry[bend.index + 1] \
                and walked[bend.index] == route.length[bend.index]:
            out["steer"][bend.index] += bend.steps.extra_time
    out["time"][rows] = out["cycles"][rows] * mean
    out["time"] += out["steer"]
    flags = np.zeros(count, dtype=bool)
    flags[rows] = limited
    return Walk(entry[:-1], walked, out["stride"], out["cycle"], out["gait"], out["cycles"], out["steer"],
                out["time"], out["air"], out["free"], flags)


def _hose_cycles(mission, options, table, target, lengths) -> np.ndarray:
    """(k, nodes) [s] the cycle time of each walked section with the hose deployed to ``lengths`` (k, nodes):
    the table's phases, its fills replaced by fills through the hose (:mod:`pampipe.pneumatics.hose`)."""
    supply = mission.supply_pressure
    curves = SupplyCurves(mission.tether.hose, lengths.ravel(), supply=supply, valve=options.valve,
                          gas=options.gas)
    shape = (*lengths.shape, target.shape[1])  # (k, nodes, segments)
    length_of_row = np.broadcast_to(np.arange(lengths.size).reshape(lengths.shape)[..., None], shape).ravel()

    def fill_flow(pressure, at):
        return curves.flow(pressure, length_of_row[at])

    c = table.chamber
    fields = [np.broadcast_to(np.asarray(f)[:, None, :], shape) for f in
              (c.anchored_volume, c.rest_volume, c.anchoring_pressure, *c.shape)]
    chamber = Chamber(fields[0], fields[1], fields[2], tuple(fields[3:]))
    ends = np.broadcast_to(target[:, None, :], shape)
    fills = transition_times(chamber, float(options.vented_pressure), ends, supply=supply,
                             valve=options.valve, gas=options.gas, fill_flow=fill_flow).reshape(shape)
    durations = np.repeat(table.durations[:, None, :], lengths.shape[1], axis=1)
    for phase, valves in enumerate(VALVES):
        moving = int(np.flatnonzero(valves)[0])
        if valves[moving] > 0:
            durations[:, :, phase] = fills[:, :, moving]
    return durations.sum(axis=2)
