"""Optional physical effects missing from the paper's model (docs/physics.md §9): a pluggable library.

Each effect is a small strategy object (in the style of pysindy's feature libraries): a name, named
bounded parameters with units and a null value, and one or more *hooks* that modify a stage of the
forward model. At its null value every hook is the identity, so the model reduces exactly to the
baseline (docs/physics.md §4-§7). Hooks work on floats, numpy arrays and CasADi symbols alike.

Stages of the forward model, in order (hooks of several effects compose):

1. ``pressure(P)``: the true gauge pressure from the measured one (sensor offset and gain);
2. ``load(F_a)``: the effective axial load of a pipe test (preload, pulley friction);
3. ``braid_strain(T)``: fibre strain under the total braid tension T (B = B₀(1 + strain), N fixed);
4. ``axial_increment(state)``: ΔF [N] added to the muscle's axial force F_ax (free and anchored);
5. ``radial_factor(state)`` and ``radial_increment(state)``: u ← u·factor + ΔF_r before the contact
   clip F_r = max(0, u), u = A(F_ax − F_a) (docs/physics.md §5.3).

Adding an effect: subclass :class:`Effect`, declare ``name``, ``parameters`` and override the hooks
it needs, then list it in :data:`LIBRARY`. Parameter values are SI inside (``values[name]``).

The closed-form least holding pressure (:meth:`pampipe.model.muscle.Muscle.required_pressure`, which
``pampipe export`` compiles to C) carries an effect whose anchored force stays of the form
A·f·(F₀ + F₁P − F_a + ((P − P_a)₊/P_ref)(C₀ + C₁P)): an affine pressure map with its inverse
(``pressure_inverse``), any load map, a radial factor f that does not depend on P, and contact
increments Δθ (``contact_increments``) as its only in-pipe force increment. An effect that breaks
this says why in ``no_closed_form``.
"""

from __future__ import annotations

import math
import sys
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any, ClassVar

from pampipe.model import ops
from pampipe.model.bladder import split_moduli, strains, stress
from pampipe.model.braid import amplification_factor, braid_length, diameter_at_length, turns
from pampipe.model.forces import (
    anchoring_pressure,
    axial_levers,
    bladder_force,
    bladder_volume,
    contact_force_increment,
    contact_switch,
    wall_section,
)

#: Fixed-point iterations on the braid tension for an extensible braid (docs/physics.md §9b); the
#: error contracts by the factor ≈ c_B·∂T/∂B·B per iteration (< 10⁻² for realistic compliances).
TENSION_ITERATIONS = 3


@dataclass(frozen=True)
class Parameter:
    """One named parameter of an effect: display unit, SI bounds and null value.

    ``dimension`` is the :mod:`pampipe.units.quantities` dimension used to read it from a PAM file; ``scale``
    is the SI value of one display ``unit`` (the NLP works in display units, which are O(1)).
    """

    name: str
    unit: str
    dimension: str
    scale: float
    lower: float
    upper: float
    null: float = 0.0
    description: str = ""

    @property
    def json_key(self) -> str:
        """The JSON key with its SI unit suffix (docs/formats.md §1), e.g. ``f0_N``."""
        return f"{self.name}_{self.si_suffix}" if self.si_suffix else self.name

    @property
    def si_suffix(self) -> str:
        return {"force": "N", "pressure": "Pa", "area": "N_per_Pa", "compliance": "per_N",
                "dimensionless": ""}[self.dimension]


@dataclass(frozen=True)
class State:
    """What the hooks see at one evaluation point (SI): the muscle, its moduli and the test."""

    pressure: Any  # effective gauge pressure [Pa]
    length: Any  # [m]
    diameter: Any  # [m] (the pipe diameter when anchored)
    geometry: Any
    theta: Any  # moduli [Pa]
    reference_pressure: Any  # [Pa]
    axial_load: Any = 0.0  # effective F_a [N] (pipe tests)
    leg: Any = 0.0  # sign of the length rate: +1 lengthening, −1 shortening, 0 at rest
    in_pipe: bool = False
    pressure_leg: Any = 0.0  # sign of the pressure rate: +1 filling, −1 venting, 0 held


class Effect:
    """Base class: every hook is the identity, so a bare Effect is the baseline model."""

    name: ClassVar[str] = ""
    section: ClassVar[str] = ""  # docs/physics.md section
    summary: ClassVar[str] = ""
    signature: ClassVar[str] = ""  # the residual signature (diagnose) that points to this effect
    parameters: ClassVar[tuple[Parameter, ...]] = ()
    tests: ClassVar[frozenset[str]] = frozenset({"axial", "radial"})  # test kinds it changes
    no_closed_form: ClassVar[str] = ""  # why the closed-form holding pressure cannot carry it ("" if it can)

    @property
    def null_values(self) -> dict[str, float]:
        return {p.name: p.null for p in self.parameters}

    def pressure(self, pressure, values):
        return pressure

    def pressure_inverse(self, pressure, values):
        """The measured pressure whose ``pressure`` hook gives ``pressure`` (closed-form effects)."""
        return pressure

    def contact_increments(self, size: int, values):
        """Δθ [Pa] (``size`` entries, ordered like θ) this effect adds once anchored; None if none."""
        return None

    def load(self, axial_load, values):
        return axial_load

    def braid_strain(self, tension, values):
        return None

    def axial_increment(self, state: State, values):
        return None

    def radial_factor(self, state: State, values):
        return None

    def radial_increment(self, state: State, values):
        return None


class BraidFriction(Effect):
    """§9a: F_meas = F_ax + sgn(L̇)(f₀ + f₁P); the anchored (quiescent) muscle sits mid-band."""

    name = "braid_friction"
    section = "9a"
    summary = "Coulomb friction between braid fibres: the lengthening leg lies above the shortening leg"
    signature = "length_rate"
    parameters = (
        Parameter("f0", "N", "force", 1.0, 0.0, 500.0, 0.0, "friction force at zero pressure"),
        Parameter("f1", "N/MPa", "area", 1e-6, 0.0, 1e-3, 0.0, "friction force per unit pressure"),
    )
    tests = frozenset({"axial"})

    def axial_increment(self, state, values):
        if state.in_pipe:
            return None
        return state.leg * (values["f0"] + values["f1"] * state.pressure)


class PressureHysteresis(Effect):
    """§9k: F_meas = F_ax − sgn(Ṗ)(h₀ + h₁P), the isometric counterpart of braid friction (§9a).

    At a held length the braid still slides while the pressure changes: filling (Ṗ > 0) the muscle
    pulls itself shorter and friction holds it back, venting it lets go and friction holds it in:
    the venting leg lies 2(h₀ + h₁P) above the filling leg. Keyed to the sign of dP/dt of each row
    (``pressure_leg``); the anchored muscle sits mid-band, as with §9a.
    """

    name = "pressure_hysteresis"
    section = "9k"
    summary = "braid friction while the pressure changes: the venting leg lies above the filling leg"
    signature = "pressure_rate"
    parameters = (
        Parameter("h0", "N", "force", 1.0, 0.0, 500.0, 0.0, "half the band at zero pressure"),
        Parameter("h1", "N/MPa", "area", 1e-6, 0.0, 1e-3, 0.0, "half the band per unit pressure"),
    )
    tests = frozenset({"axial"})

    def axial_increment(self, state, values):
        if state.in_pipe:
            return None
        return -state.pressure_leg * (values["h0"] + values["h1"] * state.pressure)


class Prestrain(Effect):
    """§9j: bladder prestrain, ε_k → ε_k + ε_k,pre in both stress laws (Ball & Garcia 2016).

    ΔF_ax = [σ₁(ε₁ + ε₁,pre) − σ₁(ε₁)]V_b/L − [σ₂(ε₂ + ε₂,pre) − σ₂(ε₂)]·lever₂ (Eq. 9 levers). A
    bladder that is stress-free at a zero-strain length L_z ≠ L₀ has ε₁,pre = (L₀ − L_z)/L₀ and
    ε₂,pre = (D₀ − D(L_z))/D₀; with ε₂,pre > 0 the hoop stress at L₀ pushes against the pressure,
    so the muscle needs a threshold pressure before it pulls at its rest length.
    """

    name = "prestrain"
    section = "9j"
    summary = "the bladder is strained at the rest length: a threshold pressure before the muscle pulls"
    signature = "stroke_ends"
    parameters = (
        Parameter("axial_prestrain", "-", "dimensionless", 1.0, -0.1, 0.1, 0.0, "ε₁,pre"),
        Parameter("hoop_prestrain", "-", "dimensionless", 1.0, -0.1, 0.1, 0.0, "ε₂,pre"),
    )
    no_closed_form = ("the prestrain adds stress terms to the anchored force that are not moduli increments, "
                      "which is all the closed form carries in the pipe")

    def axial_increment(self, state, values):
        g = state.geometry
        _, lever1, lever2 = _levers(state.length, state.diameter, g, True)
        a1, b1, a2, b2 = split_moduli(state.theta)
        eps1, eps2 = strains(state.length, state.diameter, g)
        pref, p = state.reference_pressure, state.pressure
        d1 = stress(eps1 + values["axial_prestrain"], p, a1, b1, pref) - stress(eps1, p, a1, b1, pref)
        d2 = stress(eps2 + values["hoop_prestrain"], p, a2, b2, pref) - stress(eps2, p, a2, b2, pref)
        return d1 * lever1 - d2 * lever2


class BraidExtensibility(Effect):
    """§9b: B = B₀(1 + c_B T), N fixed; T is the total braid tension (Eq. 11-12)."""

    name = "braid_extensibility"
    section = "9b"
    summary = "the braid fibres stretch under tension, so the anchored length grows with P and F_a"
    signature = "pressure"
    no_closed_form = ("the braid stretches under its own tension, so the anchored length depends on the "
                      "pressure through a fixed-point iteration and the holding force is not affine in P")
    parameters = (
        Parameter("compliance", "1/MN", "compliance", 1e-6, 0.0, 2e-5, 0.0,
                  "fibre strain per newton of total braid tension, c_B"),
    )

    def braid_strain(self, tension, values):
        return values["compliance"] * tension


class EndEffects(Effect):
    """§9c: tapered ends. V = (π/4)D²(L − c_v D) and a contact length L_c = L − 2ℓ_e.

    ΔF_ax = −P ∂(−πc_vD³/4)/∂L|_braid = −3c_v P D L/(4πN²); in the pipe the wall and hoop terms of
    Eq. 14 (2PR_iL − 2σ₂tL) act only on L_c, with ℓ_e = κ_e(D − D₀)/2 (end fitting ≈ D₀).
    """

    name = "end_effects"
    section = "9c"
    summary = "non-cylindrical ends: less enclosed volume and a shorter contact length"
    signature = "stroke_ends"
    no_closed_form = ("the tapered ends add pressure-dependent terms to the anchored force that shift its "
                      "zero away from the anchoring pressure at which contact stiffening starts")
    parameters = (
        Parameter("volume_taper", "-", "dimensionless", 1.0, 0.0, 2.0, 0.0, "c_v in V = πD²(L − c_v D)/4"),
        Parameter("end_length", "-", "dimensionless", 1.0, 0.0, 4.0, 0.0,
                  "κ_e in ℓ_e = κ_e(D − D₀)/2"),
    )

    def axial_increment(self, state, values):
        n2 = turns(state.geometry) ** 2
        taper = values["volume_taper"]
        return -3 * taper * state.pressure * state.diameter * state.length / (4 * math.pi * n2)

    def radial_increment(self, state, values):
        g = state.geometry
        _, r_i, t = wall_section(state.length, g, state.diameter)
        _, _, a2, b2 = split_moduli(state.theta)
        eps_hoop = strains(state.length, state.diameter, g)[1]
        sigma_hoop = stress(eps_hoop, state.pressure, a2, b2, state.reference_pressure)
        end = values["end_length"] * (state.diameter - g.initial_diameter) / 2
        return -2 * end * (2 * state.pressure * r_i - 2 * sigma_hoop * t)


class ContactStiffening(Effect):
    """§9d: E_k ← E_k + ΔE_k (P − P_anchor)₊/P_ref once anchored (compatible at P_anchor)."""

    name = "contact_stiffening"
    section = "9d"
    summary = "the bladder stiffens after it touches the pipe (the paper's own diagnosis, Fig. 9/10)"
    signature = "contact"
    parameters = (
        Parameter("axial_increment", "MPa", "pressure", 1e6, -20e6, 20e6, 0.0,
                  "ΔE₁ per P_ref above anchoring"),
        Parameter("hoop_increment", "MPa", "pressure", 1e6, -20e6, 20e6, 0.0,
                  "ΔE₂ per P_ref above anchoring"),
    )
    tests = frozenset({"radial"})

    def contact_increments(self, size, values):
        zeros = [0.0] * (size // 4 - 1)
        return [values["axial_increment"], *zeros, *zeros, 0.0, values["hoop_increment"], *zeros, *zeros, 0.0]

    def axial_increment(self, state, values):
        if not state.in_pipe:
            return None
        delta = _vector(self.contact_increments(state.theta.shape[0], values), like=state.theta)
        anchoring = anchoring_pressure(state.diameter, state.geometry, state.theta,
                                       state.reference_pressure, state.axial_load)
        return contact_force_increment(state.pressure, state.length, state.geometry, delta,
                                       state.reference_pressure, anchoring)


class PressureOffset(Effect):
    """§9e: P = g_P·P_meas + P_off (sensor offset and gain)."""

    name = "pressure_offset"
    section = "9e"
    summary = "the pressure sensor reads off by a constant (and a gain)"
    signature = "pressure"
    parameters = (
        Parameter("offset", "kPa", "pressure", 1e3, -60e3, 60e3, 0.0, "P_off"),
        Parameter("gain", "-", "dimensionless", 1.0, 0.8, 1.2, 1.0, "g_P"),
    )

    def pressure(self, pressure, values):
        return values["gain"] * pressure + values["offset"]

    def pressure_inverse(self, pressure, values):
        return (pressure - values["offset"]) / values["gain"]


class AxialPreload(Effect):
    """§9g: F_a,eff = F_a(1 + μ_p) + F₀ in pipe tests (fixture preload, pulley friction)."""

    name = "axial_preload"
    section = "9g"
    summary = "an axial tension the test does not report: clamping, rope and fitting weight, pulley friction"
    signature = "axial_load"
    parameters = (
        Parameter("preload", "N", "force", 1.0, -1000.0, 1000.0, 0.0, "F₀"),
        Parameter("pulley_friction", "-", "dimensionless", 1.0, 0.0, 0.5, 0.0, "μ_p on the hanging load"),
    )
    tests = frozenset({"radial"})

    def load(self, axial_load, values):
        return axial_load * (1 + values["pulley_friction"]) + values["preload"]


class WallFriction(Effect):
    """§9f: a locked-in tension λμ_wπF_r, so F_r = A(F_ax − F_a)/(1 + λμ_wπA)."""

    name = "wall_friction"
    section = "9f"
    summary = "braid-pipe friction locks in axial tension during anchoring, lowering the radial force"
    signature = "contact"
    parameters = (
        Parameter("lock", "-", "dimensionless", 1.0, 0.0, 1.0, 0.0, "λμ_w, the locked-in friction share"),
    )
    tests = frozenset({"radial"})

    def radial_factor(self, state, values):
        amp = amplification_factor(state.diameter, state.geometry, state.length)
        return 1 / (1 + values["lock"] * math.pi * amp)


#: The registry: every effect the package knows, by name (docs/commands.md §6.1 names).
LIBRARY: dict[str, Effect] = {e.name: e for e in (
    BraidFriction(), BraidExtensibility(), EndEffects(), ContactStiffening(), PressureOffset(),
    AxialPreload(), WallFriction(), PressureHysteresis(), Prestrain())}


def get_effect(name: str) -> Effect:
    """The effect called ``name``; KeyError lists the known names."""
    try:
        return LIBRARY[name]
    except KeyError:
        raise KeyError(f"unknown effect {name!r}; known effects: {', '.join(LIBRARY)}") from None


Active = Mapping[str, Mapping[str, Any]]  # effect name -> {parameter name: SI value}


def _resolved(effects: Active | None):
    """[(Effect, values with nulls filled in)] in registry order."""
    if not effects:
        return []
    out = []
    for name, given in effects.items():
        effect = get_effect(name)
        values = effect.null_values
        values.update(given)
        out.append((effect, values))
    return out


def _compose(active, hook, value):
    for effect, values in active:
        value = getattr(effect, hook)(value, values)
    return value


def _sum(active, hook, state, start):
    total = start
    for effect, values in active:
        term = getattr(effect, hook)(state, values)
        if term is not None:
            total = total + term
    return total


def refusals(effects: Active | None) -> dict[str, str]:
    """{name: why} of the active effects the closed-form holding pressure cannot carry (see the top)."""
    return {e.name: e.no_closed_form for e, _ in _resolved(effects) if e.no_closed_form}


def effective_load(effects: Active | None, axial_load):
    """F_a,eff [N]: the axial load after every ``load`` hook."""
    return _compose(_resolved(effects), "load", axial_load)


def measured_pressure(effects: Active | None, pressure):
    """P_m [Pa] whose ``pressure`` hooks give ``pressure``: their inverses, last effect first."""
    for effect, values in reversed(_resolved(effects)):
        pressure = effect.pressure_inverse(pressure, values)
    return pressure


def radial_factor(effects: Active | None, state: State):
    """Π f [-] of the ``radial_factor`` hooks (1 without); P-independent for closed-form effects."""
    factor = 1.0
    for effect, values in _resolved(effects):
        term = effect.radial_factor(state, values)
        if term is not None:
            factor = factor * term
    return factor


def contact_increments(effects: Active | None, theta):
    """ΣΔθ [Pa] of the ``contact_increments`` hooks, a vector like ``theta``; None without."""
    total = None
    for effect, values in _resolved(effects):
        delta = effect.contact_increments(theta.shape[0], values)
        if delta is not None:
            total = list(delta) if total is None else [t + d for t, d in zip(total, delta, strict=True)]
    return None if total is None else _vector(total, like=theta)


def _stretch(active, tension):
    total = None
    for effect, values in active:
        term = effect.braid_strain(tension, values)
        if term is not None:
            total = term if total is None else total + term
    return total


def _levers(length, diameter, geometry, stretched):
    """Eq. 9 levers for any braid length B' = √(L² + (NπD)²) (N fixed): thick levers depend on D only."""
    if geometry.wall == "thick" or not stretched:
        return axial_levers(length, geometry, diameter)
    n2 = turns(geometry) ** 2
    v_b = bladder_volume(geometry)
    circ2 = n2 * math.pi**2 * diameter**2  # (NπD)² = B'² − L²
    return ((2 * length**2 - circ2) / (4 * math.pi * n2), v_b / length, v_b * length / circ2)


def _axial_force(pressure, length, diameter, geometry, theta, pref, stretched=False):
    """F_ax (Eq. 9) at an explicit (L, D) pair on a possibly stretched braid."""
    levers = _levers(length, diameter, geometry, stretched)
    return pressure * levers[0] + bladder_force(pressure, length, geometry, theta, pref,
                                                diameter=diameter, levers=levers)


def _tension_axial_part(pressure, length, diameter, geometry, theta, pref):
    """T cos α − (pull) = PπR_i² − σ₁V_b/L [N] (Eq. 12), with pull = F_ax (free) or F_a (pipe)."""
    _, r_i, _ = wall_section(length, geometry, diameter) if geometry.wall == "thick" else (0, diameter / 2, 0)
    a1, b1, _, _ = split_moduli(theta)
    eps_axial = strains(length, diameter, geometry)[0]
    sigma_axial = stress(eps_axial, pressure, a1, b1, pref)
    return pressure * math.pi * r_i**2 - sigma_axial * bladder_volume(geometry) / length


def axial_force_with_effects(pressure, length, geometry, theta, reference_pressure=1e6,
                             effects: Active | None = None, *, leg=0.0, pressure_leg=0.0):
    """F [N] a test machine measures on the free muscle at (P_meas, L), with ``effects`` switched on.

    ``leg`` is the sign of the length rate (+1 lengthening, −1 shortening), ``pressure_leg`` that
    of the pressure rate (+1 filling, −1 venting). Without effects this is exactly
    :func:`pampipe.model.forces.axial_force` (Eq. 9).
    """
    active = _resolved(effects)
    pressure = _compose(active, "pressure", pressure)
    base_b = braid_length(geometry)
    n_pi = turns(geometry) * math.pi
    diameter = diameter_at_length(length, geometry)
    force = _axial_force(pressure, length, diameter, geometry, theta, reference_pressure)
    if any(e.braid_strain(1.0, v) is not None for e, v in active):
        for _ in range(TENSION_ITERATIONS):
            tension = (force + _tension_axial_part(pressure, length, diameter, geometry, theta,
                                                   reference_pressure)) * base_b / length
            stretched = base_b * (1 + _stretch(active, tension))
            diameter = ops.sqrt(stretched**2 - length**2) / n_pi
            force = _axial_force(pressure, length, diameter, geometry, theta, reference_pressure, True)
    state = State(pressure, length, diameter, geometry, theta, reference_pressure, leg=leg,
                  pressure_leg=pressure_leg)
    return _sum(active, "axial_increment", state, force)


def radial_force_with_effects(pressure, diameter, geometry, theta, reference_pressure=1e6, axial_load=0.0,
                              contact_theta=None, effects: Active | None = None, *, smoothing=None,
                              clip=True):
    """F_r [N] of the muscle in a pipe of diameter D at measured pressure P, with ``effects`` on.

    u = A(L)·(F_ax(P, L, D) + Σ ΔF_ax − F_a)·Π factor + Σ ΔF_r, F_r = max(0, u) (or the softplus of
    width ``smoothing`` [N]). L = L(D) unless the braid stretches. Without effects this is exactly
    :func:`pampipe.model.forces.radial_force`.
    """
    active = _resolved(effects)
    pressure = _compose(active, "pressure", pressure)
    load = _compose(active, "load", axial_load)
    base_b = braid_length(geometry)
    n_pi = turns(geometry) * math.pi
    length = ops.sqrt(base_b**2 - (n_pi * diameter) ** 2)
    if any(e.braid_strain(1.0, v) is not None for e, v in active):  # fixed point on T (§9b)
        for _ in range(TENSION_ITERATIONS):
            tension = (load + _tension_axial_part(pressure, length, diameter, geometry, theta,
                                                  reference_pressure)) * base_b / length
            stretched = base_b * (1 + _stretch(active, tension))
            length = ops.sqrt(stretched**2 - (n_pi * diameter) ** 2)
    stretchy = any(e.braid_strain(1.0, v) is not None for e, v in active)
    holding = _axial_force(pressure, length, diameter, geometry, theta, reference_pressure, stretchy) - load
    if contact_theta is not None:
        anchoring = anchoring_pressure(diameter, geometry, theta, reference_pressure, load)
        holding = holding + contact_force_increment(pressure, length, geometry, contact_theta,
                                                    reference_pressure, anchoring)
    state = State(pressure, length, diameter, geometry, theta, reference_pressure, load, in_pipe=True)
    holding = _sum(active, "axial_increment", state, holding)
    unclipped = amplification_factor(diameter, geometry, length) * holding
    for effect, values in active:
        factor = effect.radial_factor(state, values)
        if factor is not None:
            unclipped = unclipped * factor
    unclipped = _sum(active, "radial_increment", state, unclipped)
    return contact_switch(unclipped, smoothing, clip)


def _vector(entries, *, like):
    """A column of ``entries`` of the same kind as ``like`` (CasADi when any entry is symbolic)."""
    import numpy as np

    ca = sys.modules.get("casadi")  # an entry can only be a symbol once CasADi is loaded
    if ca is not None and any(isinstance(e, ca.SX | ca.MX) for e in (*entries, like)):
        return ca.vertcat(*entries)
    return np.array([float(e) for e in entries])
