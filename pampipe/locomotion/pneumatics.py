"""Pneumatic timing of one muscle: chamber volume from the braid model, ISO 6358 valve flow, gas law.

Works on floats, numpy arrays and CasADi symbols (the optimal-control problem uses the same code).
Pressures named ``pressure`` are gauge [Pa]; the gas law uses absolute pressure p = P + p_atm.

* **Chamber volume** V(P) [m³] is the gas volume inside the braid, V = πD²L/4 − V_b (incompressible
  bladder, docs/physics.md §4.3). Below the anchoring pressure P_a the muscle is free and follows the
  free-contraction curve L_free(P) (docs/physics.md §7); above it the braid is held by the pipe, so
  L = L(D_p) and V = V_p is constant. V(P) = V_p − (V_p − V₀)·q(z), z = max(0, 1 − P/P_a), where q is
  a polynomial with q(0) = 0 and q(1) = 1 fitted (least squares) to the exact free-contraction volume.
  The corner of max at contact is rounded over w = 0.4 % of P_a, z = ½(y + √(y² + w²)), so that the
  optimiser sees smooth dynamics (V changes by < 0.1 % of V_p there).
* **Valve** (ISO 6358-1): ṁ = C·ρ₀·p₁·√(T₀/T₁)·φ(r), r = p₂/p₁, with φ = 1 when choked (r ≤ b)
  and φ = [1 − ((r − b)/(1 − b))²]^m otherwise. ρ₀ = 1.185 kg/m³ and T₀ = 293.15 K are the ISO
  reference conditions. φ is regularised as ((x + ε)^m − ε^m)/((1 + ε)^m − ε^m), x = 1 − s²,
  ε = 10⁻⁶, so its slope stays finite when the pressures meet (an error below 1 % for pressure
  differences above 1 kPa, none under choked flow).
* **Gas** (polytropic chamber, isothermal by default): ṗ = n·(R·T·ṁ − p·V̇)/V with V̇ = V′(P)·ṗ, i.e.
  ṗ = n·R·T·ṁ / (V + n·p·V′(P)) [Pa/s]. n = 1 is exact mass conservation at constant temperature
  (thin rubber walls and second-long fills exchange heat well, the usual choice for PAMs); n = 1.4
  is the adiabatic limit, the fastest possible pressure rise.
* **Transition time** with the valve fully open: the ODE is autonomous and monotone, so
  t = ∫_{P₀}^{P₁} dP/ṗ(P) [s], integrated by CVODES (built once; parameters: the end pressures,
  chamber, valve and gas).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache

import casadi as ca
import numpy as np

from pampipe.errors import SolverError
from pampipe.locomotion.options import Gas, Valve
from pampipe.model import forces

GAS_CONSTANT = 287.05  # R of dry air [J/(kg·K)]
ISO_DENSITY = 1.185  # ρ₀ [kg/m³] (ISO 6358 reference air)
ISO_TEMPERATURE = 293.15  # T₀ [K]
FLOW_REGULARISATION = 1e-6  # ε of the subsonic branch
SHAPE_DEGREE = 5  # degree of the free-contraction volume polynomial q(z)
CONTACT_SMOOTHING = 0.004  # w: width of the smooth contact corner, as a fraction of P_a
CHAMBER_SIZE = 3 + SHAPE_DEGREE  # entries of Chamber.as_vector
FLOW_SIZE = 7  # entries of flow_vector


def _is_symbolic(*values) -> bool:
    return any(isinstance(v, ca.SX | ca.MX | ca.DM) for v in values)


def _fmax(a, b):
    return ca.fmax(a, b) if _is_symbolic(a, b) else np.maximum(a, b)


@dataclass(frozen=True)
class Chamber:
    """Gas volume of one muscle in one pipe: V(P) = V_p − (V_p − V₀)·q(max(0, 1 − P/P_a)).

    ``shape`` holds q's coefficients c₁…c_K (q = Σ c_j z^j, Σ c_j = 1). Fields may be CasADi symbols.
    """

    anchored_volume: float  # V_p [m³], braid held by the pipe
    rest_volume: float  # V₀ [m³], at P = 0 (length L₀)
    anchoring_pressure: float  # P_a [Pa] gauge, contact with the wall
    shape: tuple  # c₁…c_K

    @classmethod
    def rigid(cls, volume: float) -> Chamber:
        """A chamber of constant volume (for checks against closed forms)."""
        return cls(volume, volume, 1.0, (1.0,) + (0.0,) * (SHAPE_DEGREE - 1))

    @classmethod
    def of_muscle(cls, muscle, pipe_diameter: float) -> Chamber:
        """Fit V(P) to the exact free-contraction volume V(L_free(P)) of a :class:`Muscle`."""
        geometry = muscle.geometry
        anchoring = float(muscle.anchoring_pressure(pipe_diameter))
        bladder = forces.bladder_volume(geometry)
        anchored = float(muscle.enclosed_volume(muscle.anchored_length(pipe_diameter))) - bladder
        rest = float(muscle.enclosed_volume(geometry.initial_length)) - bladder
        pressures = np.linspace(0.0, anchoring, 200)
        volumes = muscle.enclosed_volume(muscle.free_length(pressures)) - bladder
        z = 1 - pressures / anchoring
        q = (anchored - volumes) / (anchored - rest)
        basis = np.stack([z**j for j in range(1, SHAPE_DEGREE + 1)], axis=1)
        # q = Σ c_j z^j with c_K = 1 − Σ_{j<K} c_j, so that q(1) = 1 exactly
        reduced = basis[:, :-1] - basis[:, -1:]
        head, *_ = np.linalg.lstsq(reduced, q - basis[:, -1], rcond=None)
        shape = tuple(float(c) for c in np.append(head, 1 - head.sum()))
        return cls(anchored, rest, anchoring, shape)

    def as_vector(self) -> np.ndarray:
        """[V_p, V₀, P_a, c₁…c_K] (SI), the layout of :meth:`from_vector`."""
        return np.array([self.anchored_volume, self.rest_volume, self.anchoring_pressure, *self.shape],
                        dtype=float)

    @classmethod
    def from_vector(cls, v) -> Chamber:
        """The chamber of a vector (numbers or a CasADi symbol) laid out as :meth:`as_vector`."""
        return cls(v[0], v[1], v[2], tuple(v[3 + j] for j in range(SHAPE_DEGREE)))

    def _depth(self, pressure):
        """(z, dz/dP): z = smooth max(0, 1 − P/P_a) = ½(y + √(y² + w²)), y = 1 − P/P_a."""
        y = 1 - pressure / self.anchoring_pressure
        root = (y**2 + CONTACT_SMOOTHING**2) ** 0.5
        return 0.5 * (y + root), -0.5 * (1 + y / root) / self.anchoring_pressure

    def volume(self, pressure):
        """V(P) [m³] at gauge pressure P."""
        z, _ = self._depth(pressure)
        q = sum(self.shape[j] * z ** (j + 1) for j in range(len(self.shape)))
        return self.anchored_volume - (self.anchored_volume - self.rest_volume) * q

    def compliance(self, pressure):
        """dV/dP [m³/Pa] = −(V_p − V₀)·q′(z)·dz/dP: positive while free, → 0 once the pipe holds it."""
        z, dz = self._depth(pressure)
        dq = sum((j + 1) * self.shape[j] * z**j for j in range(len(self.shape)))
        return -(self.anchored_volume - self.rest_volume) * dq * dz


def flow_vector(supply: float, valve: Valve, gas: Gas) -> np.ndarray:
    """[p_supply (gauge), p_atm, T, n, C, b, m] (SI), the layout of :func:`unpack_flow`."""
    return np.array([supply, gas.atmospheric_pressure, gas.temperature, gas.polytropic_index,
                     valve.sonic_conductance, valve.critical_pressure_ratio, valve.subsonic_index],
                    dtype=float)


def unpack_flow(v) -> tuple:
    """(supply, valve, gas) of a vector (numbers or a CasADi symbol) laid out as :func:`flow_vector`."""
    return v[0], Valve(v[4], v[5], v[6]), Gas(v[2], v[3], v[1])


def flow_function(ratio, valve: Valve):
    """φ(r) of ISO 6358: 1 when choked (r ≤ b), [1 − ((r − b)/(1 − b))²]^m above, 0 for r ≥ 1."""
    b, m, eps = valve.critical_pressure_ratio, valve.subsonic_index, FLOW_REGULARISATION
    s = _fmax((ratio - b) / (1 - b), 0)
    x = _fmax(1 - s**2, 0)
    return ((x + eps) ** m - eps**m) / ((1 + eps) ** m - eps**m)


def mass_flow(upstream, downstream, valve: Valve, gas: Gas):
    """ṁ [kg/s] ≥ 0 through the valve from absolute pressure p₁ = upstream to p₂ = downstream [Pa].

    ṁ = C·ρ₀·p₁·√(T₀/T)·φ(p₂/p₁) (ISO 6358-1); zero when p₂ ≥ p₁.
    """
    return (valve.sonic_conductance * ISO_DENSITY * upstream * (ISO_TEMPERATURE / gas.temperature) ** 0.5
            * flow_function(downstream / upstream, valve))


def pressure_rate(pressure, command, chamber: Chamber, *, supply: float, valve: Valve, gas: Gas):
    """ṗ [Pa/s] of a chamber at gauge pressure P under valve command u ∈ [−1, 1].

    u > 0 opens the valve towards the supply (gauge ``supply``) by the fraction u, u < 0 towards
    the atmosphere: ṁ = u⁺·ṁ(p_s → p) − u⁻·ṁ(p → p_atm), ṗ = n·R·T·ṁ / (V + n·p·V′).
    The command's sign must be known for symbolic use: pass ``command`` as (fill, vent) ≥ 0 then.
    """
    atm = gas.atmospheric_pressure
    absolute = pressure + atm
    fill, vent = command if isinstance(command, tuple) else (_fmax(command, 0), _fmax(-command, 0))
    flow = (fill * mass_flow(supply + atm, absolute, valve, gas)
            - vent * mass_flow(absolute, atm, valve, gas))
    n = gas.polytropic_index
    capacity = chamber.volume(pressure) + n * absolute * chamber.compliance(pressure)
    return n * GAS_CONSTANT * gas.temperature * flow / capacity


@cache
def _transition_integrator() -> ca.Function:
    """CVODES on dt/ds = (P₁ − P₀)/ṗ(P₀ + s(P₁ − P₀)), s ∈ [0, 1]: t(1) is the transition time [s].

    Parameters: [P₀, P₁, u, flow vector, chamber vector]. Adams at relative tolerance 1e-12.
    """
    t, s = ca.SX.sym("t"), ca.SX.sym("s")
    q = ca.SX.sym("q", 3 + FLOW_SIZE + CHAMBER_SIZE)
    supply, valve, gas = unpack_flow(q[3:3 + FLOW_SIZE])
    chamber = Chamber.from_vector(q[3 + FLOW_SIZE:])
    span = q[1] - q[0]
    rate = pressure_rate(q[0] + s * span, (ca.fmax(q[2], 0), ca.fmax(-q[2], 0)), chamber, supply=supply,
                         valve=valve, gas=gas)
    return ca.integrator("transition_time", "cvodes", {"x": t, "t": s, "p": q, "ode": span / rate}, 0.0, 1.0,
                         {"reltol": 1e-12, "abstol": 1e-12, "linear_multistep_method": "adams",
                          "max_num_steps": 100000})


def transition_time(chamber: Chamber, start: float, target: float, *, supply: float, valve: Valve,
                    gas: Gas) -> float:
    """Time [s] to go from gauge ``start`` to ``target`` with the valve fully open (u = ±1).

    Filling when target > start (target must be below the supply), venting otherwise:
    t = ∫ dP/ṗ(P), finite because ṗ vanishes only at the supply (filling) and at 0 Pa (venting).
    """
    if target == start:
        return 0.0
    command = 1.0 if target > start else -1.0
    if command > 0 and target >= supply:
        raise SolverError(f"cannot fill to {target:.6g} Pa: the supply is {supply:.6g} Pa (gauge)",
                          status="unreachable")
    if command < 0 and target <= 0:
        raise SolverError(f"cannot vent to {target:.6g} Pa gauge: venting stops at the atmosphere",
                          status="unreachable")
    q = np.concatenate([[start, target, command], flow_vector(supply, valve, gas), chamber.as_vector()])
    try:
        time = float(_transition_integrator()(x0=0.0, p=q)["xf"])
    except RuntimeError:
        time = np.inf
    if not np.isfinite(time) or time < 0:
        raise SolverError(f"the pressure never reached {target:.6g} Pa from {start:.6g} Pa "
                          "(is the valve too small?)", status="unreachable")
    return time
