"""Fills through the supply hose inside the tether: the hose in series with the muscle's valve
(docs/physics.md §16.3).

Quasi-steady: at each chamber pressure p (absolute) of a fill, one mass flow ṁ passes the hose, from the
compressor's pressure p_s at the entry to p_r at the robot, and the valve, from p_r into the chamber:

* the hose: isothermal compressible flow in a pipe of length L (the deployed tether) and bore d,
  ``fluids.compressible.isothermal_gas`` (ṁ from p_s and p_r), with the Darcy friction factor of
  ``fluids.friction.friction_factor`` (Clamond's Colebrook solution; 64/Re in laminar flow) at the flow's own
  Reynolds number Re = 4ṁ/(πdμ), found by fixed-point iteration; μ of air by Sutherland's law;
* the valve: ISO 6358, ṁ = C·ρ₀·p_r·√(T₀/T)·φ(p/p_r) (:func:`pampipe.pneumatics.timing.mass_flow`).

ṁ_hose falls and ṁ_valve rises with p_r, so they meet once. The curve ṁ(p) is tabulated by sweeping p_r from
where the valve chokes (ṁ_hose(p_r) = C·ρ₀·√(T₀/T)·p_r: below the chamber pressure b·p_r the flow is that one)
up to p_s (no flow), each p_r giving ṁ = ṁ_hose(p_r) and the chamber pressure that passes it through the valve
(φ inverted), and read between its points by monotone cubic interpolation. The air stored in the hose is not
drawn on (a fill is supplied at the steady flow of the moment): the fill times are upper bounds.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from pampipe.pneumatics.options import Gas, Valve
from pampipe.pneumatics.timing import FLOW_REGULARISATION, GAS_CONSTANT, ISO_DENSITY, ISO_TEMPERATURE

#: Points of a tabulated supply curve (Chebyshev–Lobatto in p_r: dense where the valve chokes and near p_s).
CURVE_POINTS = 40
#: Relative change of the friction factor that ends its fixed-point iteration.
FRICTION_TOLERANCE = 1e-10


def air_viscosity(temperature: float) -> float:
    """μ [Pa·s] of air by Sutherland's law, μ = 1.716e-5·(T/273.15)^1.5·(273.15 + 110.4)/(T + 110.4)."""
    return 1.716e-5 * (temperature / 273.15) ** 1.5 * (273.15 + 110.4) / (temperature + 110.4)


def hose_flow(inlet: float, outlet: float, *, hose, length: float, temperature: float) -> float:
    """ṁ [kg/s] through ``length`` [m] of ``hose`` from absolute ``inlet`` to ``outlet`` [Pa]: isothermal
    flow (``fluids.compressible.isothermal_gas``) with the Darcy friction factor at its own Reynolds number
    (``fluids.friction.friction_factor``); 0 where outlet ≥ inlet; below the outlet pressure at which the
    hose chokes (``fluids.compressible.P_isothermal_critical_flow``), the choked flow."""
    from fluids.compressible import P_isothermal_critical_flow, isothermal_gas
    from fluids.friction import friction_factor

    if outlet >= inlet:
        return 0.0
    d = hose.inner_diameter
    density, viscosity, relative = inlet / (GAS_CONSTANT * temperature), air_viscosity(temperature), \
        hose.roughness / d
    fd, flow = 0.02, 0.0
    for _ in range(200):
        try:
            critical = P_isothermal_critical_flow(P=inlet, fd=fd, D=d, L=length)
        except (ArithmeticError, ValueError):  # a long hose: the critical pressure underflows to 0
            critical = 0.0
        flow = isothermal_gas(density, fd, P1=inlet, P2=max(outlet, critical * (1 + 1e-12)), L=length, D=d)
        reynolds = 4.0 * flow / (math.pi * d * viscosity)
        new = friction_factor(Re=max(reynolds, 1e-12), eD=relative)
        if abs(new - fd) <= FRICTION_TOLERANCE * fd:
            break
        fd = new
    return float(flow)


def _ratio(phi: np.ndarray, valve: Valve) -> np.ndarray:
    """r = p₂/p₁ at which the valve's regularised φ(r) (:func:`~pampipe.pneumatics.timing.flow_function`)
    takes the value ``phi`` ∈ [0, 1]: its inverse (r ≤ b where φ = 1)."""
    b, m, eps = valve.critical_pressure_ratio, valve.subsonic_index, FLOW_REGULARISATION
    x = (np.clip(phi, 0.0, 1.0) * ((1 + eps) ** m - eps**m) + eps**m) ** (1 / m) - eps
    return b + np.sqrt(np.clip(1.0 - x, 0.0, 1.0)) * (1 - b)


@dataclass(frozen=True)
class SupplyCurve:
    """ṁ [kg/s] of a fill through the hose and the valve against the chamber's gauge pressure [Pa]."""

    pressure: np.ndarray  # gauge, ascending: the first where the valve (or hose) chokes, the last the supply
    flow: np.ndarray  # [kg/s], falling to 0 at the supply

    @cached_property
    def _curve(self):
        from scipy.interpolate import PchipInterpolator

        return PchipInterpolator(self.pressure, self.flow, extrapolate=False)

    def __call__(self, pressure) -> np.ndarray:
        p = np.asarray(pressure, dtype=float)
        inside = np.clip(p, self.pressure[0], self.pressure[-1])
        return np.where(p <= self.pressure[0], self.flow[0], np.maximum(self._curve(inside), 0.0))


#: Largest ratio between neighbouring hose lengths of a :class:`SupplyCurves` grid: a flow read between two is
#: interpolated linearly in log L, within about (ln 1.05)²/32 ≈ 1e-4 of its own curve (ṁ ~ L^(-1/2)).
GRID_RATIO = 1.05


class SupplyCurves:
    """The supply curves of many hose lengths: one per length where they are few, else one per point of a
    geometric grid spanning them (ratio :data:`GRID_RATIO`), a length between two read linearly in log L."""

    def __init__(self, hose, lengths, *, supply: float, valve: Valve, gas: Gas):
        lengths = np.asarray(lengths, dtype=float)
        low, high = float(lengths.min()), float(lengths.max())
        grid = np.unique(lengths)
        if high > low and grid.size > 1 + math.log(high / low) / math.log(GRID_RATIO):
            grid = np.geomspace(low, high, 2 + int(math.log(high / low) / math.log(GRID_RATIO)))
        self.curves = [supply_curve(hose, float(length), supply=supply, valve=valve, gas=gas)
                       for length in grid]
        self.below = np.clip(np.searchsorted(grid, lengths, side="right") - 1, 0, grid.size - 1)
        above = np.minimum(self.below + 1, grid.size - 1)
        with np.errstate(divide="ignore", invalid="ignore"):
            weight = np.log(lengths / grid[self.below]) / np.log(grid[above] / grid[self.below])
        self.weight = np.where(above > self.below, weight, 0.0)

    def flow(self, pressure: np.ndarray, which: np.ndarray) -> np.ndarray:
        """ṁ [kg/s] at gauge ``pressure`` (rows, ...) for the lengths ``which`` (rows,) index."""
        out = np.empty_like(pressure)
        below, weight = self.below[which], self.weight[which]
        for k in np.unique(below).tolist():
            mine = below == k
            value = self.curves[k](pressure[mine])
            upper = weight[mine] > 0
            if upper.any():
                t = weight[mine][upper][:, None]
                value[upper] = (1 - t) * value[upper] + t * self.curves[k + 1](pressure[mine][upper])
            out[mine] = value
        return out


def supply_curve(hose, length: float, *, supply: float, valve: Valve, gas: Gas,
                 points: int = CURVE_POINTS) -> SupplyCurve:
    """The fill's :class:`SupplyCurve` through ``length`` [m] of ``hose`` from the gauge ``supply`` [Pa]."""
    from scipy.optimize import brentq

    atm, temperature = gas.atmospheric_pressure, gas.temperature
    inlet = supply + atm
    choked = valve.sonic_conductance * ISO_DENSITY * (ISO_TEMPERATURE / temperature) ** 0.5  # ṁ/p_r, choked

    def through(outlet: float) -> float:
        return hose_flow(inlet, outlet, hose=hose, length=length, temperature=temperature)

    lowest = 1e-6 * inlet
    start = lowest
    if through(lowest) > choked * lowest:  # the valve chokes where the hose delivers C·ρ₀·√(T₀/T)·p_r
        start = brentq(lambda p: through(p) - choked * p, lowest, inlet, xtol=1e-9 * inlet, rtol=1e-13)
    nodes = start + (inlet - start) * 0.5 * (1.0 - np.cos(np.pi * np.arange(points) / (points - 1)))
    flow = np.array([through(p) for p in nodes[:-1]] + [0.0])
    flow[0] = min(flow[0], choked * nodes[0])
    chamber = _ratio(flow / (choked * nodes), valve) * nodes
    return SupplyCurve(chamber - atm, flow)
