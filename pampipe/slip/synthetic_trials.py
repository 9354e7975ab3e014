"""Synthetic slip tests from known μ and κ (`pampipe synth --slip-pipe`), stick-slip included.

Each trial holds a pressure and raises the axial load at ``load_rate``. The muscle's slip load is the
plan's model, :meth:`~pampipe.model.muscle.Muscle.largest_load` at safety factor 1 (F = μπF_r(P, D, κF)),
scattered by exp(N(0, ``scatter``²)). Until then the displacement is elastic (``compliance``·F); at the slip
the muscle slides 4 mm while the load falls to 80 %, or, with ``stick_slip``, slides 0.6 mm three times,
the load rising back to the slip load between the jumps; a ``held`` trial stops at 70 % of its slip load
and never slips (a censored trial). Then the load is let down to rest. Sensor noise:
N(0, ``load_noise``²) on the load, N(0, ``displacement_noise``²) on the displacement.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from pampipe.model.muscle import Muscle
from pampipe.specs.experiment import TestSpec


@dataclass(frozen=True)
class SlipProtocol:
    """What to generate (SI): one test per bore, one trial per pressure."""

    pipes: tuple[float, ...]  # [m]
    friction: float = 0.3
    load_coupling: float = 1.0
    scatter: float = 0.03  # relative sd of the slip loads
    stick_slip: bool = False
    pressures: tuple[float, ...] = (250e3, 300e3, 350e3, 400e3, 450e3, 500e3, 550e3, 600e3)  # [Pa]
    load_rate: float = 50.0  # [N/s]
    sample_time: float = 0.1  # [s]
    compliance: float = 2e-7  # [m/N]
    load_noise: float = 0.5  # [N]
    displacement_noise: float = 2e-6  # [m]
    pipe_material: str | None = None
    held: tuple[int, ...] = ()  # 1-based trials whose load stops at 70 % of the slip load (no slip: censored)


def generate_slip(muscle: Muscle, protocol: SlipProtocol, rng
                  ) -> list[tuple[TestSpec, dict[str, np.ndarray]]]:
    """[(test spec, SI columns)]: one slip test per bore of ``protocol``."""
    out = []
    for pipe in protocol.pipes:
        pressure = np.asarray(protocol.pressures, dtype=float)
        loads = np.asarray(muscle.largest_load(pressure, pipe, kappa=protocol.load_coupling,
                                               friction=protocol.friction, safety_factor=1.0), dtype=float)
        loads = loads * np.exp(protocol.scatter * rng.standard_normal(loads.size))
        parts = [_trial(p, f, protocol, rng, held=i + 1 in protocol.held)
                 for i, (p, f) in enumerate(zip(pressure, loads, strict=True)) if f > 0]
        columns = {key: np.concatenate([part[key] for part in parts]) for key in ("pressure", "axial_load",
                                                                                  "displacement")}
        columns["time"] = np.arange(columns["pressure"].size) * protocol.sample_time
        name = f"slip-{pipe * 1e3:.1f}mm"
        out.append((TestSpec(name, "slip", Path(f"data/{name}.csv"), pipe, 0.0,
                             pipe_material=protocol.pipe_material), columns))
    return out


def _trial(pressure: float, slip_load: float, protocol: SlipProtocol, rng, *, held: bool = False
           ) -> dict[str, np.ndarray]:
    step = protocol.load_rate * protocol.sample_time
    top = 0.7 * slip_load if held else slip_load
    load = [np.arange(0.0, top, step), [top]]
    shift = [np.zeros(load[0].size + 1)]
    offset = 0.0
    jumps, size = (3, 0.6e-3) if protocol.stick_slip else (1, 4e-3)
    if held:
        jumps = 0
    for j in range(jumps):
        if j:
            rise = np.arange(0.8 * slip_load, slip_load, step)
            load.append(rise)
            shift.append(np.full(rise.size, offset))
        slide = np.linspace(0.0, size, 8)[1:]
        load.append(np.linspace(slip_load, 0.8 * slip_load, slide.size))
        shift.append(offset + slide)
        offset += size
    down = np.arange(load[-1][-1], 0.0, -4 * step)
    rest = np.zeros(10)
    load += [down, rest]
    shift += [np.full(down.size + rest.size, offset)]
    load, shift = np.concatenate(load), np.concatenate(shift)
    displacement = protocol.compliance * load + shift
    n = load.size
    return {"pressure": np.full(n, pressure),
            "axial_load": load + protocol.load_noise * rng.standard_normal(n),
            "displacement": displacement + protocol.displacement_noise * rng.standard_normal(n)}
