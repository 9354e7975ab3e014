"""The one door to the muscle model: a :class:`Muscle` answers every physical question about one PAM.

A muscle is its rest geometry, its moduli θ [Pa] with reference pressure P_ref, optional contact
increments Δθ (docs/physics.md §9d) and optional diagnosed effects (docs/physics.md §9). Every
command asks it, so plan, gait, simulate, synth, identify, diagnose and every plot see one model:

* forces: :meth:`~Muscle.axial_force` F_ax (Eq. 9), :meth:`~Muscle.radial_force` F_r (§5.3);
* anchoring: :meth:`~Muscle.anchoring_pressure`, :meth:`~Muscle.free_length` (§7);
* holding: :meth:`~Muscle.holding_capacity` μπF_r, :meth:`~Muscle.least_holding_pressure`,
  :meth:`~Muscle.largest_load` (§8).

Without effects F_ax is affine in P at a fixed length, so anchoring, the least holding pressure and
the largest load have closed forms (the fast path); with effects they are found by vectorised
bisection on the same forces. Fields may be floats or CasADi symbols: :meth:`Muscle.symbolic` builds
a muscle whose parameters are one symbol vector ``p``, for NLPs built once and fed through ``p``.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass

import numpy as np

from pampipe.errors import InputError, SolverError
from pampipe.model import braid, forces, ops
from pampipe.model import effects as effects_library
from pampipe.model.bladder import drucker_tangent_moduli
from pampipe.model.pam import Geometry, Pam

#: Largest gauge pressure the model accepts [Pa] (a PAM bursts long before).
PRESSURE_LIMIT = 1e8
#: Bisection halvings: [0, 100 MPa] / 2⁸⁰ ≈ 1e-16 Pa, below round-off.
BISECTION_STEPS = 80


@dataclass(frozen=True)
class Structure:
    """What a symbolic muscle depends on: the key of every NLP built from it.

    The parameter vector is [L₀, D₀, α₀, t₀, P_ref, θ, Δθ (with ``contact``), effect parameters
    (SI, in the order of ``effects`` and of each effect's ``parameters``)].
    """

    wall: str = "thick"
    degree: int = 3
    contact: bool = False
    effects: tuple[str, ...] = ()

    @property
    def n_theta(self) -> int:
        return 4 * (self.degree + 1)

    def names(self) -> list[str]:
        """A label for every entry of the parameter vector."""
        k = self.degree + 1
        theta = [f"{law}.{part}{j}" for law in ("axial", "hoop") for part in "ab" for j in range(k)]
        out = ["initial_length", "initial_diameter", "braid_angle", "bladder_thickness",
               "reference_pressure", *theta]
        if self.contact:
            out += [f"contact.{name}" for name in theta]
        for name in self.effects:
            out += [f"{name}.{p.name}" for p in effects_library.get_effect(name).parameters]
        return out

    @property
    def size(self) -> int:
        return len(self.names())


@dataclass(frozen=True)
class SymbolicMuscle:
    """A :class:`Muscle` whose every parameter is an entry of the CasADi SX vector ``p``."""

    muscle: Muscle
    p: object  # casadi.SX, Structure.size × 1
    structure: Structure

    def pack(self, muscle: Muscle) -> np.ndarray:
        """The numeric ``p`` of a muscle of the same structure."""
        if muscle.structure != self.structure:
            raise ValueError(f"a muscle of structure {muscle.structure} cannot fill {self.structure}")
        return muscle.parameter_vector()


#: Where :meth:`Muscle.free_length` evaluates inside its bracket at each step (31 interior points).
_SECTIONS = np.arange(1, 32) / 32.0


class Muscle:
    """One PAM: geometry, moduli, contact increments and effects, and the physics asked of it.

    ``theta`` are the moduli [Pa] ordered [a₁, b₁, a₂, b₂] (docs/physics.md §6), ``contact`` the
    increments Δθ [Pa] in the same order (None: none), ``effects`` maps effect names of
    :mod:`pampipe.model.effects` to their SI parameters (None or empty: the baseline model).
    Floats, numpy arrays and CasADi symbols are accepted alike.
    """

    def __init__(self, geometry: Geometry, theta, reference_pressure=1e6, *, contact=None,
                 effects: Mapping[str, Mapping[str, object]] | None = None, name: str = "muscle"):
        self.geometry = geometry
        self.theta = theta
        self.reference_pressure = reference_pressure
        self.contact = contact
        self.effects = {k: dict(v) for k, v in effects.items()} if effects else None
        self.name = name
        try:
            self._composed = effects_library.compose(self.effects)  # the active effects, composed once
        except KeyError as exc:
            raise InputError(str(exc.args[0])) from None

    def __repr__(self) -> str:
        """``Muscle('name', L0=… mm, D0=… mm, alpha0=… deg, t0=… mm, theta=[…] MPa, effects=[…])``."""
        g = self.geometry
        try:
            theta = "[" + ", ".join(f"{float(v) / 1e6:.4g}" for v in np.ravel(self.theta)) + "] MPa"
        except (TypeError, ValueError, RuntimeError):  # CasADi symbols
            theta = "symbolic"
        effects = f", effects={sorted(self.effects)}" if self.effects else ""
        contact = ", contact" if self.contact is not None else ""
        return (f"Muscle({self.name!r}, L0={g.initial_length * 1e3:.4g} mm, "
                f"D0={g.initial_diameter * 1e3:.4g} mm, alpha0={np.degrees(g.braid_angle):.4g} deg, "
                f"t0={g.bladder_thickness * 1e3:.4g} mm, "
                f"theta={theta}{contact}{effects})")

    # ------------------------------------------------------------------------------ construction
    @classmethod
    def from_pam(cls, pam: Pam, *, where: str | None = None) -> Muscle:
        """The muscle of a PAM with identified moduli (InputError if it has none, or is no Pam)."""
        if not isinstance(pam, Pam):
            raise InputError(f"{where or 'pam'}: a {type(pam).__name__} is not a PAM; give a "
                             "pampipe.model.pam.Pam, e.g. pampipe.load_pam('PAM.yaml').")
        if pam.moduli is None:
            raise InputError(f"{where or 'PAM file'}: the PAM '{pam.name}' has no 'moduli:' block; run "
                             "`pampipe identify EXPERIMENT.yaml -o PAM.yaml` first, or add the block by "
                             "hand.")
        m = pam.moduli
        contact = m.contact_vector() if np.any(m.contact_vector()) else None
        return cls(pam.geometry, m.as_vector(), m.reference_pressure, contact=contact, effects=pam.effects,
                   name=pam.name)

    @classmethod
    def symbolic(cls, structure: Structure) -> SymbolicMuscle:
        """A muscle of ``structure`` whose parameters are the entries of one SX vector ``p``."""
        import casadi as ca

        g = ca.SX.sym("geometry", 4)
        pref = ca.SX.sym("reference_pressure")
        theta = ca.SX.sym("theta", structure.n_theta)
        parts = [g, pref, theta]
        contact = None
        if structure.contact:
            contact = ca.SX.sym("contact", structure.n_theta)
            parts.append(contact)
        values = {}
        for name in structure.effects:
            params = _effect(name).parameters
            symbols = ca.SX.sym(name, len(params))
            parts.append(symbols)
            values[name] = {p.name: symbols[i] for i, p in enumerate(params)}
        geometry = Geometry(g[0], g[1], g[2], g[3], structure.wall)
        muscle = cls(geometry, theta, pref, contact=contact, effects=values, name="symbolic")
        return SymbolicMuscle(muscle, ca.vertcat(*parts), structure)

    @property
    def structure(self) -> Structure:
        n = self.theta.shape[0] if hasattr(self.theta, "shape") else len(self.theta)
        return Structure(self.geometry.wall, n // 4 - 1, self.contact is not None,
                         tuple(self.effects or ()))

    def parameter_vector(self) -> np.ndarray:
        """This muscle's values in the layout of :class:`Structure` (numeric muscles only)."""
        parts = [self.geometry.as_vector(), [self.reference_pressure], np.asarray(self.theta, dtype=float)]
        if self.contact is not None:
            parts.append(np.asarray(self.contact, dtype=float))
        for name, given in (self.effects or {}).items():
            values = _effect(name).null_values | dict(given)
            parts.append([float(values[p.name]) for p in _effect(name).parameters])
        return np.concatenate([np.ravel(np.asarray(v, dtype=float)) for v in parts])

    @property
    def has_effects(self) -> bool:
        """True when diagnosed effects change the model (the affine fast path does not apply)."""
        return bool(self.effects)

    # ---------------------------------------------------------------------------------- geometry
    def anchored_length(self, diameter):
        """L(D_p) = √(B² − (NπD_p)²) [m] (Eq. 3): the length of the muscle anchored in the pipe."""
        return braid.length_at_diameter(diameter, self.geometry)

    def amplification_factor(self, diameter):
        """A(D_p) = 2πN²D_p/L(D_p) [-] (docs/physics.md §5.5)."""
        return braid.amplification_factor(diameter, self.geometry)

    def enclosed_volume(self, length):
        """V = πD²L/4 [m³] inside the braid at length L (the air per pascal of gauge pressure)."""
        return braid.enclosed_volume(length, self.geometry)

    # ------------------------------------------------------------------------------------ forces
    def axial_force(self, pressure, length, *, leg=0.0, pressure_leg=0.0):
        """F_ax(P, L) [N] (Eq. 9, effects included): the tension the free muscle holds.

        ``leg`` is the sign of the length rate (braid friction, docs/physics.md §9a) and
        ``pressure_leg`` that of the pressure rate (pressure hysteresis).
        """
        if self.effects:
            return self._composed.axial_force(pressure, length, self.geometry, self.theta,
                                              self.reference_pressure, leg=leg, pressure_leg=pressure_leg)
        return forces.axial_force(pressure, length, self.geometry, self.theta, self.reference_pressure)

    def radial_force(self, pressure, diameter, axial_load=0.0, *, smoothing=None, clip=True):
        """F_r = max(0, A(F_ax(P, L_p) − F_a)) [N] (docs/physics.md §5.3), increments and effects included.

        ``smoothing`` [N] and ``clip``: see :func:`pampipe.model.forces.contact_switch`.
        """
        if self.effects:
            return self._composed.radial_force(pressure, diameter, self.geometry, self.theta,
                                              self.reference_pressure, axial_load, self.contact,
                                              smoothing=smoothing, clip=clip)
        return forces.radial_force(pressure, diameter, self.geometry, self.theta, self.reference_pressure,
                                   axial_load, self.contact, smoothing, clip=clip)

    def radial_force_terms(self, pressure, diameter, axial_load=0.0) -> dict:
        """Eq. 14 term by term [N], before the contact clip; the values sum to the unclipped F_r.

        ``extensions`` holds what contact increments and diagnosed effects add to the paper's terms.
        """
        terms = forces.radial_force_terms(pressure, diameter, self.geometry, self.theta,
                                          self.reference_pressure, axial_load)
        if self.effects or self.contact is not None:
            total = self.radial_force(pressure, diameter, axial_load, clip=False)
            terms["extensions"] = total - sum(terms.values())
        return terms

    def contact_pressure(self, radial, diameter, *, paper_literal: bool = False):
        """Mean wall contact pressure F_r/(D·L_p) [Pa] (docs/physics.md §5.6; F_r/(πDL) if paper_literal)."""
        return forces.contact_pressure(radial, diameter, self.anchored_length(diameter), paper_literal)

    def drucker_tangent_moduli(self, pressure, length):
        """(E₁ᵗ, E₂ᵗ) [Pa] at (P, L) on the free-contraction path: both ≥ 0 for stability (§6)."""
        return drucker_tangent_moduli(pressure, length, braid.diameter_at_length(length, self.geometry),
                                      self.geometry, self.theta, self.reference_pressure)

    # --------------------------------------------------------------------------------- anchoring
    def anchoring_pressure(self, diameter, axial_load=0.0, *, anchored: Anchored | None = None):
        """Least pressure [Pa] at which the muscle presses on a wall of diameter D_p under F_a.

        Closed form (F_a − F_ax(0, L_p))/∂_P F_ax without effects (docs/physics.md §7; may be
        negative: the muscle already presses at 0 Pa); with effects, bisection on F_r > 0 over
        [0, 100 MPa] (0 if it presses at 0 Pa, inf if it never does). Numeric inputs only.
        ``anchored``: :meth:`affine_coefficients` at ``diameter``, when already computed.
        """
        if anchored is not None:
            return (axial_load - anchored.at_zero) / anchored.slope
        if not self.effects:
            return forces.anchoring_pressure(diameter, self.geometry, self.theta, self.reference_pressure,
                                             axial_load)
        diameter, axial_load = np.broadcast_arrays(np.asarray(diameter, float), np.asarray(axial_load, float))

        def pressing(p):
            return self.radial_force(p, diameter, axial_load) > 0

        return _least(pressing, diameter.shape)

    def free_length(self, pressure, axial_load: float = 0.0, *, grid: int = 400, iterations: int = 60,
                    braid_limit: bool = False):
        """L_free(P) [m]: the root of F_ax(P, L) = F_a nearest L₀ toward B/√3 (docs/physics.md §7, §14.4).

        A contractile braid scans down from L₀ through (B/√3, L₀], an extensile one (α₀ > 54.74°) up
        from L₀ through [L₀, B/√3): the first sign change is bracketed, then narrowed 32× per step (31
        points) to adjacent floats, as bisection would end. Where the pressure cannot move the muscle
        from L₀ (F_ax(P, L₀) ≤ F_a contractile, ≥ F_a extensile) L_free = L₀.
        Where the moduli never balance the pressure force (a pressure beyond the braid's limit),
        SolverError, or with ``braid_limit`` the braid's limit B/√3, where the braid locks. Numeric
        inputs only.
        """
        pressure = np.atleast_1d(np.asarray(pressure, dtype=float))
        g = self.geometry
        sign = -1.0 if g.extensile else 1.0  # the extensile braid pushes: −F_ax > 0 until it stops
        end = g.shortest_length * (1 - 1e-9 if g.extensile else 1 + 1e-9)
        lengths = np.linspace(g.initial_length, end, grid)
        force = sign * (self.axial_force(pressure[:, None], lengths[None, :]) - axial_load)
        negative = force < 0
        negative[:, 0] = False  # the scan starts at the rest length L₀
        first = np.argmax(negative, axis=1)
        found = negative[np.arange(pressure.size), first]
        blocked = force[:, 0] <= 0  # cannot move at all
        if not braid_limit and not np.all(found | blocked):
            bad = pressure[~(found | blocked)][0]
            raise SolverError(f"no free length between L0 and B/sqrt(3) at {bad:.6g} Pa: the moduli never "
                              "balance the pressure force", status="no_root")
        high, low = lengths[np.maximum(first - 1, 0)], lengths[first]  # high: still moving; low: past
        rows = np.arange(pressure.size)
        for _ in range(iterations):  # 31 points a step: the bracket shrinks 32× (5 bisections) per evaluation
            points = high[:, None] + (low - high)[:, None] * _SECTIONS[None, :]
            moving = sign * (self.axial_force(pressure[:, None], points) - axial_load) >= 0
            stop = np.argmin(moving, axis=1)  # the first point past the root (0 where none is)
            past = ~moving[rows, stop]
            before = high, low
            low = np.where(past, points[rows, stop], low)
            high = np.where(past, np.where(stop > 0, points[rows, stop - 1], high), points[:, -1])
            if np.array_equal(high, before[0]) and np.array_equal(low, before[1]):
                break  # every bracket is a fixed point (adjacent or equal floats): more steps change nothing
        return np.where(found, 0.5 * (high + low), np.where(blocked, g.initial_length, g.shortest_length))

    # ----------------------------------------------------------------------------------- holding
    def holding_capacity(self, pressure, diameter, load, *, kappa, friction):
        """μ·π·F_r(P, D_p, κW) [N] (docs/physics.md §8): the friction force the anchor develops."""
        return friction * math.pi * self.radial_force(pressure, diameter, kappa * load)

    def required_pressure(self, diameter, load, *, kappa, friction, safety_factor):
        """Closed-form least holding pressure P* [Pa] (floats or symbols; not valid everywhere, see below).

        Above the loaded anchoring pressure P_a = (κW − F₀)/F₁ the holding force is
        x·(F₁ + (C₀ + C₁P)/P_ref) with x = P − P_a (C: contact increments, docs/physics.md §9d), so
        μπA·hold = SF·W gives x = 2R/(b + √(b² + 4aR)) with a = C₁/P_ref, b = F₁ + (C₀ + C₁P_a)/P_ref,
        R = SF·W/(μπA), and P* = max(P_a + x, 0) (docs/physics.md §8.3); without contact increments
        a = 0 and x = R/F₁. Diagnosed effects with a closed form are folded in
        (:mod:`pampipe.model.effects`: the load map gives κW, radial factors scale A, contact
        stiffening adds to C, and P* is mapped back through the inverse pressure map); the others
        raise ValueError (:meth:`closed_form_refusals`). Valid where F₁ > 0, μ > 0 and b > 0 or
        a > 0: :meth:`closed_form_pressure` checks that. The exported C code is generated from this.
        """
        return ops.fmax(self._closed_form(diameter, load, kappa, friction, safety_factor)[0], 0.0)

    def closed_form_pressure(self, diameter, load, *, kappa, friction, safety_factor,
                             anchored: Anchored | None = None):
        """:meth:`required_pressure` where its derivation holds, inf elsewhere [Pa] (floats or symbols).

        Holds where F₁ > 0, μ > 0, the quadratic a x² + b x = R has a positive root (b > 0 or a > 0)
        and P* ≤ 100 MPa. The last test is made before the floor at 0, where it is false for NaN, so
        that C's NaN-ignoring fmax agrees with numpy's maximum. ``anchored``: the muscle's
        coefficients at ``diameter`` (:meth:`affine_coefficients`), when already computed.
        """
        inner, valid = self._closed_form(diameter, load, kappa, friction, safety_factor, anchored)
        ok = ops.logical_and(valid, inner <= PRESSURE_LIMIT)
        return ops.if_else(ok, ops.fmax(inner, 0.0), math.inf)

    def closed_form_refusals(self) -> dict[str, str]:
        """{effect: why} of this muscle's effects that :meth:`required_pressure` cannot carry."""
        return self._composed.refusals()

    def _closed_form(self, diameter, load, kappa, friction, safety_factor, anchored=None):
        """(P* before its floor at 0 [Pa], where its derivation holds) of :meth:`required_pressure`."""
        refused = self.closed_form_refusals()
        if refused:
            raise ValueError(f"no closed-form holding pressure with the effect(s) {', '.join(refused)}")
        c = self._coefficients(diameter) if anchored is None else anchored
        anchoring = (self._composed.load(kappa * load) - c.at_zero) / c.slope
        target = safety_factor * load / (friction * math.pi * c.amplification)
        if self._contact_theta() is None:  # a = 0 and b = F₁: x = R/F₁
            inner = anchoring + target / c.slope
            valid = ops.logical_and(c.slope > 0, friction > 0)
        else:
            a = c.contact_slope / self.reference_pressure
            b = c.slope + (c.contact_at_zero + c.contact_slope * anchoring) / self.reference_pressure
            inner = anchoring + 2 * target / (b + ops.sqrt(b**2 + 4 * a * target))
            valid = ops.logical_and(ops.logical_and(c.slope > 0, friction > 0), ops.logical_or(b > 0, a > 0))
        return self._composed.measured_pressure(inner), valid

    def least_holding_pressure(self, diameter, load, *, kappa, friction, safety_factor,
                               anchored: Anchored | None = None):
        """Least P [Pa] with μπF_r(P, D_p, κW) ≥ SF·W while pressing on the wall (docs/physics.md §8).

        Without effects the closed form :meth:`closed_form_pressure`; with effects, bisection on the
        model. inf where no pressure up to 100 MPa holds. Numeric inputs (broadcast arrays) only.
        ``anchored``: :meth:`affine_coefficients` at ``diameter``, when already computed.
        """
        d, w, mu = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in (diameter, load, friction)))
        if self.effects:
            anchoring = self.anchoring_pressure(d, kappa * w)

            def holds(p):
                return self.holding_capacity(p, d, w, kappa=kappa, friction=mu) >= safety_factor * w

            return np.maximum(_least(holds, d.shape), anchoring)
        with np.errstate(divide="ignore", invalid="ignore"):
            return self.closed_form_pressure(d, w, kappa=kappa, friction=mu, safety_factor=safety_factor,
                                             anchored=anchored)

    def largest_load(self, pressure, diameter, *, kappa, friction, safety_factor):
        """W_max [N] held at pressure P: μπF_r(P, D_p, κW) = SF·W (docs/physics.md §8).

        Without effects, W_max = μπA·k·F_ax(P) / (SF + κμπA·k) with the contact stiffening factor
        k = 1 + (C₀ + C₁P)/(P_ref F₁); with effects, bisection (the capacity falls as W grows while
        SF·W rises). Negative (−1 with effects) where the unloaded muscle does not grip at P.
        """
        p, d, mu = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in (pressure, diameter, friction)))
        if self.effects:
            unloaded = self.holding_capacity(p, d, 0.0, kappa=kappa, friction=mu)
            low, high = np.zeros(p.shape), unloaded / safety_factor
            for _ in range(BISECTION_STEPS):
                mid = 0.5 * (low + high)
                ok = self.holding_capacity(p, d, mid, kappa=kappa, friction=mu) >= safety_factor * mid
                low, high = np.where(ok, mid, low), np.where(ok, high, mid)
            return np.where(unloaded > 0, low, -1.0)
        per_friction, axial = self.grip_terms(p, d)
        grip = mu * per_friction
        return grip * axial / (safety_factor + kappa * grip)

    def grip_terms(self, pressure, diameter):
        """(πA·k, F_ax(P, L_p)) [-, N] of the fast path: W_max = μ·πAk·F_ax/(SF + κμ·πAk).

        k = 1 + (C₀ + C₁P)/(P_ref F₁) is the contact stiffening factor (:meth:`largest_load`); both terms
        are independent of μ, κ and SF, so a fit over those computes them once. Baseline and contact
        increments only (ValueError with effects).
        """
        c = self.affine_coefficients(diameter)
        contact = c.contact_at_zero + c.contact_slope * pressure
        stiffening = 1 + contact / (self.reference_pressure * c.slope)
        return math.pi * c.amplification * stiffening, c.at_zero + c.slope * pressure

    def affine_coefficients(self, diameter) -> Anchored:
        """The fast path's per-pipe numbers at L_p = L(D_p) (baseline and contact increments only)."""
        if self.effects:
            raise ValueError("a muscle with diagnosed effects has no affine coefficients")
        return self._coefficients(diameter)

    def _contact_theta(self):
        """Δθ [Pa] once anchored: the contact increments plus those of closed-form effects (None: none)."""
        extra = self._composed.contact_increments(self.theta)
        if extra is None:
            return self.contact
        return extra if self.contact is None else self.contact + extra

    def _coefficients(self, diameter) -> Anchored:
        """:class:`Anchored` at L_p = L(D_p), with the closed-form effects' radial factor and Δθ folded in."""
        g, pref = self.geometry, self.reference_pressure
        length = braid.length_at_diameter(diameter, g)
        at_zero, slope = forces.axial_force_affine(length, g, self.theta, pref, diameter=diameter)
        contact = self._contact_theta()
        if contact is None:
            c0 = c1 = 0.0
        else:
            c0, c1 = forces.bladder_force_affine(length, g, contact, pref, diameter=diameter)
        amplification = braid.amplification_factor(diameter, g, length)
        if self.effects:
            state = effects_library.State(None, length, diameter, g, self.theta, pref, in_pipe=True)
            amplification = amplification * self._composed.radial_factor(state)
        return Anchored(length, amplification, at_zero, slope, c0, c1)


@dataclass(frozen=True)
class Anchored:
    """At the anchored length: F_ax(P, L_p) = F₀ + F₁P, contact increment ((P − P_a)₊/P_ref)(C₀ + C₁P)."""

    length: object  # L_p [m]
    amplification: object  # A [-] (times the radial factor of closed-form effects)
    at_zero: object  # F₀ [N]
    slope: object  # F₁ [N/Pa]
    contact_at_zero: object  # C₀ [N] (0.0 without contact increments)
    contact_slope: object  # C₁ [N/Pa] (0.0 without contact increments)


def _effect(name: str):
    try:
        return effects_library.get_effect(name)
    except KeyError as exc:
        raise InputError(str(exc.args[0])) from None


def _least(predicate: Callable[[np.ndarray], np.ndarray], shape) -> np.ndarray:
    """Least P in [0, 100 MPa] where ``predicate`` (monotone: False then True) holds; inf if never."""
    low, high = np.zeros(shape), np.full(shape, PRESSURE_LIMIT)
    at_zero, reachable = predicate(low), predicate(high)
    for _ in range(BISECTION_STEPS):
        mid = 0.5 * (low + high)
        ok = predicate(mid)
        high, low = np.where(ok, mid, high), np.where(ok, low, mid)
    return np.where(at_zero, 0.0, np.where(reachable, high, np.inf))
