"""Slip-test data from known μ and κ, written apart from pampipe's synth and slip code.

The slip load of a muscle anchored at pressure P in a bore D is the closed form of the no-slip condition
μ·π·A·(F_ax(P, L_p) − κF) = F:  F = μπA·F_ax / (1 + κμπA), with A = 2πN²D/L_p and L_p = √(B² − (NπD)²)
computed here from the braid geometry, and F_ax(P, L_p) the muscle's free axial force (the moduli model).
Each trial ramps the load from rest at its own rate; the displacement follows the load elastically plus
noise until the slip load (scattered by ``scatter``, relative), then slides several mm (or, with
``stick_slip``, slips in three jumps with the load falling back and rising between them); then the load
is let down to rest. ``hold_below`` trials stop at 70 % of their slip load: they never slip (censored).
"""

from __future__ import annotations

import math

import numpy as np


def amplification(geometry, diameter: float) -> float:
    """A = 2πN²D/L_p from L₀, D₀, α₀ (Eqs. 1-3, written out)."""
    braid = geometry.initial_length / math.cos(geometry.braid_angle)
    turns = geometry.initial_length * math.tan(geometry.braid_angle) / (math.pi * geometry.initial_diameter)
    length = math.sqrt(braid**2 - (turns * math.pi * diameter) ** 2)
    return 2 * math.pi * turns**2 * diameter / length, length


def true_slip_load(muscle, pressure: float, diameter: float, mu: float, kappa: float, exponent: float = 0.0,
                   reference: float = 2e5) -> float:
    """The slip load [N]; with ``exponent`` n ≠ 0, μ = mu·(p/reference)^n, p = F_r/(D·L_p), by bisection."""
    a, length = amplification(muscle.geometry, diameter)
    axial = float(muscle.axial_force(pressure, length))
    grip = mu * math.pi * a
    if exponent == 0.0:
        return grip * axial / (1 + kappa * grip)
    low, high = 0.0, 20 * math.pi * a * axial
    for _ in range(100):
        mid = 0.5 * (low + high)
        radial = max(a * (axial - kappa * mid), 0.0)
        friction = mu * (max(radial, 1e-12) / (diameter * length) / reference) ** exponent
        low, high = (mid, high) if friction * math.pi * radial >= mid else (low, mid)
    return low


def trial_rows(rng, slip_load: float, pressure: float, *, rate: float, compliance=2e-7, noise=2e-6,
               load_noise=0.3, stick_slip=False, held=False, dt=0.02):
    """(pressure, load, displacement) rows of one trial, starting and ending at rest."""
    top = 0.7 * slip_load if held else slip_load
    n = max(int(top / rate / dt), 40)
    load = list(np.linspace(0.0, top, n))
    shift = [0.0] * n
    if not held:
        jumps = 3 if stick_slip else 1
        offset = 0.0
        for j in range(jumps):
            if j:  # stick again: the load rises back to (about) the slip load
                rise = np.linspace(0.8 * slip_load, slip_load * rng.uniform(0.97, 1.02), 15)
                load += list(rise)
                shift += [offset] * rise.size
            slide = np.linspace(0, 1, 8)[1:] * (0.6e-3 if stick_slip else 4e-3)
            load += list(np.linspace(slip_load, 0.8 * slip_load, slide.size))
            shift += list(offset + slide)
            offset += slide[-1]
        last = offset
    else:
        last = 0.0
    down = np.linspace(load[-1], 0.0, 30)[1:]
    load += list(down)
    shift += [last] * down.size
    load, shift = np.array(load), np.array(shift)
    displacement = compliance * load + shift + rng.normal(0, noise, load.size)
    rest = np.zeros(10)  # rest between trials
    load = np.concatenate([rest, load + rng.normal(0, load_noise, load.size), rest])
    displacement = np.concatenate([rest + displacement[0], displacement, rest + displacement[-1]])
    pressures = pressure + rng.normal(0, 200.0, load.size)
    return pressures, load, displacement


def slip_test(muscle, diameter: float, pressures, *, mu: float, kappa: float, scatter: float = 0.02,
              stick_slip=False, hold_below=(), seed: int = 0, exponent: float = 0.0,
              rate_gain: float = 0.0) -> dict[str, np.ndarray]:
    """SI columns (time, pressure, axial_load, displacement) of one slip test: one trial per pressure.

    ``rate_gain``: the slip load grows by this share per 50 N/s of load rate above 50 N/s (a viscous grip).
    """
    rng = np.random.default_rng(seed)
    parts = []
    for i, p in enumerate(pressures):
        load = true_slip_load(muscle, p, diameter, mu, kappa, exponent) * math.exp(rng.normal(0, scatter))
        rate = rng.uniform(20, 80)
        load *= 1 + rate_gain * (rate - 50) / 50
        parts.append(trial_rows(rng, load, p, rate=rate, stick_slip=stick_slip and i % 2 == 0,
                                held=i in hold_below))
    pressure = np.concatenate([p[0] for p in parts])
    load = np.concatenate([p[1] for p in parts])
    displacement = np.concatenate([p[2] for p in parts])
    return {"time": 0.02 * np.arange(load.size), "pressure": pressure, "axial_load": load,
            "displacement": displacement}


def write(path, columns) -> None:
    """The columns as a CSV file in lab units (s, kPa, N, mm)."""
    table = np.column_stack([columns["time"], columns["pressure"] / 1e3, columns["axial_load"],
                             columns["displacement"] * 1e3])
    np.savetxt(path, table, delimiter=",", fmt="%.6f",
               header="time [s],pressure [kPa],axial_load [N],displacement [mm]", comments="")
