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
  t = ∫_{P₀}^{P₁} dP/ṗ(P) [s], by composite Gauss–Legendre on panels cut at the choke point and
  graded toward the contact corner and the end where ṗ vanishes (vectorised: every section's
  transitions in one pass; ~1e-15 relative, where CVODES at rtol 1e-12 erred by ~2e-10).
"""

from __future__ import annotations

from dataclasses import dataclass

import casadi as ca
import numpy as np

from pampipe.errors import SolverError
from pampipe.model import forces
from pampipe.pneumatics.options import Gas, Valve

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
        fitted = chambers_of_muscle(muscle, [pipe_diameter])
        return cls(float(fitted.anchored_volume[0]), float(fitted.rest_volume[0]),
                   float(fitted.anchoring_pressure[0]), tuple(float(c[0]) for c in fitted.shape))

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


#: Pressures of the free-contraction curve each chamber fit reads (0 … P_a).
FIT_POINTS = 200
#: Degree of the Chebyshev interpolant of L_free(P) that serves fits of many bores at once.
FREE_LENGTH_DEGREE = 64
#: Largest error of that interpolant, relative to L₀, at the check points (else the exact root everywhere).
FREE_LENGTH_TOLERANCE = 1e-13


def free_lengths(muscle, pressures) -> np.ndarray:
    """L_free(P) [m] (:meth:`Muscle.free_length`) at many pressures at once.

    Few pressures: the exact root at each. Many (the fits of many bores): the exact root at the
    Chebyshev points of the pressures' range where the muscle moves from L₀, the interpolant of
    degree :data:`FREE_LENGTH_DEGREE` between them (L_free is analytic there), checked against the
    exact root half-way between the points; where that check errs by more than
    :data:`FREE_LENGTH_TOLERANCE`·L₀ (a curve that is not smooth), the exact root everywhere.
    """
    pressures = np.asarray(pressures, dtype=float)
    flat = pressures.ravel()
    if flat.size <= 8 * FREE_LENGTH_DEGREE:
        return muscle.free_length(flat).reshape(pressures.shape)
    rest = muscle.geometry.initial_length
    sign = -1.0 if muscle.geometry.extensile else 1.0
    moving = sign * muscle.axial_force(flat, rest) > 0  # as free_length: else it stays at L₀
    out = np.full(flat.shape, rest)
    if np.any(moving):
        curve = free_length_curve(muscle, float(flat[moving].min()), float(flat[moving].max()))
        out[moving] = muscle.free_length(flat[moving]) if curve is None else curve(flat[moving])
    return out.reshape(pressures.shape)


def free_length_curve(muscle, low: float, high: float):
    """The Chebyshev interpolant of degree :data:`FREE_LENGTH_DEGREE` of L_free(P) on [low, high] [Pa],
    or None where it errs by more than :data:`FREE_LENGTH_TOLERANCE`·L₀ against the exact root half-way
    between its points (a curve that is not smooth there)."""
    curve = np.polynomial.Chebyshev.interpolate(muscle.free_length, FREE_LENGTH_DEGREE, domain=[low, high])
    nodes = np.cos(np.pi * (np.arange(FREE_LENGTH_DEGREE) + 1.0) / (FREE_LENGTH_DEGREE + 1))
    between = low + 0.5 * (high - low) * (nodes + 1.0)
    error = np.max(np.abs(curve(between) - muscle.free_length(between)))
    return curve if error <= FREE_LENGTH_TOLERANCE * muscle.geometry.initial_length else None


def chambers_of_muscle(muscle, diameters) -> Chamber:
    """:meth:`Chamber.of_muscle` at many bores at once: a :class:`Chamber` whose fields are arrays.

    V(P) = V_p − (V_p − V₀)·q(z) with q = Σ c_j z^j (Σ c_j = 1) fitted by least squares to the exact
    free-contraction volume V(L_free(P)) − V_b at :data:`FIT_POINTS` pressures from 0 to P_a(D_p).
    """
    diameters = np.atleast_1d(np.asarray(diameters, dtype=float))
    geometry = muscle.geometry
    anchoring = np.asarray(muscle.anchoring_pressure(diameters), dtype=float) * np.ones(diameters.shape)
    bladder = forces.bladder_volume(geometry)
    anchored = np.asarray(muscle.enclosed_volume(muscle.anchored_length(diameters)), dtype=float) - bladder
    rest = float(muscle.enclosed_volume(geometry.initial_length)) - bladder
    pressures = np.linspace(0.0, anchoring, FIT_POINTS, axis=1)
    volumes = muscle.enclosed_volume(free_lengths(muscle, pressures)) - bladder
    z = 1 - pressures / anchoring[:, None]
    q = (anchored[:, None] - volumes) / (anchored - rest)[:, None]
    basis = z[..., None] ** np.arange(1, SHAPE_DEGREE + 1)
    # q = Σ c_j z^j with c_K = 1 − Σ_{j<K} c_j, so that q(1) = 1 exactly
    reduced = basis[..., :-1] - basis[..., -1:]
    head = np.einsum("nij,nj->ni", np.linalg.pinv(reduced), q - basis[..., -1])
    shape = np.concatenate([head, 1 - head.sum(axis=1, keepdims=True)], axis=1)
    return Chamber(anchored, np.full(diameters.shape, rest), anchoring, tuple(shape.T))


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


def pressure_rate(pressure, command, chamber: Chamber, *, supply: float, valve: Valve, gas: Gas,
                  supplied=None):
    """ṗ [Pa/s] of a chamber at gauge pressure P under valve command u ∈ [−1, 1].

    u > 0 opens the valve towards the supply (gauge ``supply``) by the fraction u, u < 0 towards
    the atmosphere: ṁ = u⁺·ṁ(p_s → p) − u⁻·ṁ(p → p_atm), ṗ = n·R·T·ṁ / (V + n·p·V′).
    The command's sign must be known for symbolic use: pass ``command`` as (fill, vent) ≥ 0 then.
    ``supplied`` [kg/s]: the filling mass flow when the supply reaches the valve through a hose
    (:mod:`pampipe.pneumatics.hose`), in place of the valve's ṁ(p_s → p).
    """
    atm = gas.atmospheric_pressure
    absolute = pressure + atm
    fill, vent = command if isinstance(command, tuple) else (_fmax(command, 0), _fmax(-command, 0))
    inflow = mass_flow(supply + atm, absolute, valve, gas) if supplied is None else supplied
    flow = (fill * inflow
            - vent * mass_flow(absolute, atm, valve, gas))
    n = gas.polytropic_index
    capacity = chamber.volume(pressure) + n * absolute * chamber.compliance(pressure)
    return n * GAS_CONSTANT * gas.temperature * flow / capacity


#: Gauss–Legendre nodes per panel of :func:`transition_times`.
GAUSS_NODES = 12
#: Geometric steps 2^0 … 2^(k−1) of the panels around the contact corner and toward the ends.
_STEPS = 2.0 ** np.arange(40)


def _cuts(start, target, anchoring, *, supply: float, valve: Valve, gas: Gas) -> np.ndarray:
    """Panel ends (rows, cuts), sorted, inside [lo, hi] = the pressures each transition spans [Pa].

    1/ṗ is analytic on each panel: the kink of φ at r = b (choked | subsonic) is a cut; panels double
    away from the contact corner at P_a (the volume's smoothed max, complex singularities at
    P_a(1 ± i w)) and away from the end where ṗ → 0 outside the span (filling: the supply; venting:
    0 Pa gauge, where φ ~ √(p − p_atm)). Every panel is then at most as long as its distance to a
    singularity, so 12 nodes reach ~1e-15.
    """
    atm, b = gas.atmospheric_pressure, valve.critical_pressure_ratio
    lo, hi = np.minimum(start, target), np.maximum(start, target)
    fill = target > start
    choke = np.where(fill, b * (supply + atm) - atm, atm / b - atm)
    around = CONTACT_SMOOTHING * np.concatenate([[0.0], _STEPS[:32], -_STEPS[:32]])  # to 10⁷ P_a
    contact = anchoring[:, None] * (1 + around[None, :])
    ends = np.where(fill[:, None], supply - (supply - hi)[:, None] * _STEPS[None, :],
                    lo[:, None] * _STEPS[None, :])
    cuts = np.concatenate([lo[:, None], hi[:, None], choke[:, None], contact, ends], axis=1)
    return np.sort(np.clip(cuts, lo[:, None], hi[:, None]), axis=1)


def transition_times(chamber: Chamber, start, target, *, supply: float, valve: Valve, gas: Gas,
                     fill_flow=None) -> np.ndarray:
    """Times [s] to go from gauge ``start`` to ``target`` with the valve fully open (u = ±1), one per row.

    ``chamber``'s fields, ``start`` and ``target`` broadcast together (the answer is flat, in that
    order). Filling when target > start (target must be below the supply), venting otherwise:
    t = ∫ dP/|ṗ(P)| over the span, by composite Gauss–Legendre on the panels of :func:`_cuts`
    (vectorised over rows: the gait of every section in one pass). Agrees with an adaptive
    quadrature (QUADPACK at 2e-14) to ~1e-15. ``fill_flow(pressure, rows)`` [kg/s], if given, is the
    filling mass flow at the gauge pressures ``pressure`` of the filling ``rows`` (a supply hose,
    :mod:`pampipe.pneumatics.hose`), in place of the valve's own from the supply.
    """
    start, target, *fields = (np.ravel(v) for v in np.broadcast_arrays(
        *(np.asarray(v, dtype=float) for v in (start, target, chamber.anchored_volume, chamber.rest_volume,
                                               chamber.anchoring_pressure, *chamber.shape))))
    fill = target > start
    for bad, words in ((fill & (target >= supply), "the supply is {supply:.6g} Pa (gauge)"),
                       (~fill & (target <= 0) & (target != start), "venting stops at the atmosphere")):
        if np.any(bad):
            k = int(np.argmax(bad))
            raise SolverError(f"cannot {'fill' if fill[k] else 'vent'} to {target[k]:.6g} Pa"
                              f"{' gauge' if not fill[k] else ''}: {words.format(supply=supply)}",
                              status="unreachable")
    cuts = _cuts(start, target, fields[2], supply=supply, valve=valve, gas=gas)
    low, high = cuts[:, :-1], cuts[:, 1:]
    keep = high > low
    row = np.nonzero(keep)[0]
    low, high = low[keep], high[keep]
    nodes, weights = np.polynomial.legendre.leggauss(GAUSS_NODES)
    half = 0.5 * (high - low)
    pressure = (0.5 * (low + high))[:, None] + half[:, None] * nodes[None, :]
    at = row[:, None]
    panel_chamber = Chamber(*(f[at] for f in fields[:3]), tuple(f[at] for f in fields[3:]))
    supplied = None
    if fill_flow is not None:
        supplied, filling = np.zeros_like(pressure), fill[row]
        if filling.any():
            supplied[filling] = fill_flow(pressure[filling], row[filling])
    with np.errstate(divide="ignore", invalid="ignore"):
        rate = np.abs(pressure_rate(pressure, np.where(fill, 1.0, -1.0)[at], panel_chamber, supply=supply,
                                    valve=valve, gas=gas, supplied=supplied))
        panels = half * (weights[None, :] / rate).sum(axis=1)
    times = np.bincount(row, weights=panels, minlength=start.size)
    if not np.all(np.isfinite(times)):
        k = int(np.argmax(~np.isfinite(times)))
        raise SolverError(f"the pressure never reached {target[k]:.6g} Pa from {start[k]:.6g} Pa "
                          "(is the valve too small?)", status="unreachable")
    return times


def transition_time(chamber: Chamber, start: float, target: float, *, supply: float, valve: Valve,
                    gas: Gas) -> float:
    """Time [s] to go from gauge ``start`` to ``target`` with the valve fully open (u = ±1).

    Filling when target > start (target must be below the supply), venting otherwise:
    t = ∫ dP/ṗ(P), finite because ṗ vanishes only at the supply (filling) and at 0 Pa (venting);
    :func:`transition_times` of one row.
    """
    if target == start:
        return 0.0
    return float(transition_times(chamber, start, target, supply=supply, valve=valve, gas=gas)[0])
