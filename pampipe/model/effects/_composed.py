"""The active effects composed once, and the forces a test measures with them (docs/physics.md §9).

A :class:`Composed` holds each active effect with its parameter values (nulls filled in) and applies their
hooks stage by stage; :meth:`Composed.axial_force` and :meth:`Composed.radial_force` then evaluate the
model in one pass: the pressure and load maps, the braid's kinematics (a fixed point on the braid tension
when the braid stretches, §9b), the axial force of Eq. 9 (:mod:`pampipe.model.forces`), the effects'
increments and factors, and the contact clip. Without effects both are exactly the baseline of
:mod:`pampipe.model.forces`.
"""

from __future__ import annotations

import math

from pampipe.model import ops
from pampipe.model.braid import amplification_factor, braid_length, diameter_at_length, turns
from pampipe.model.effects._base import Effect, State
from pampipe.model.forces import (
    anchoring_pressure,
    axial_force,
    contact_force_increment,
    contact_switch,
    tension_axial_part,
)

#: Fixed-point iterations on the braid tension for an extensible braid (docs/physics.md §9b); the
#: error contracts by the factor ≈ c_B·∂T/∂B·B per iteration (< 10⁻² for realistic compliances).
TENSION_ITERATIONS = 3


#: The hooks of :class:`~pampipe.model.effects._base.Effect`, in the order of the forward model.
HOOKS = ("pressure", "pressure_inverse", "load", "braid_strain", "axial_increment", "radial_factor",
         "radial_increment", "contact_increments")


class Composed:
    """The active effects, each with its SI parameter values, in the order given; hooks compose in it.

    ``stages[hook]`` lists the (effect, values) that override ``hook``, in order: the others leave that
    stage alone (the identity, or None), so a stage applies only those.
    """

    def __init__(self, active: list[tuple[Effect, dict]]):
        self.active = active
        self.stages = {hook: [(e, v) for e, v in active if _overrides(e, hook)] for hook in HOOKS}
        self.stretches = any(e.braid_strain(1.0, v) is not None for e, v in self.stages["braid_strain"])

    # ---------------------------------------------------------------------------------- the hooks
    def pressure(self, pressure):
        """P [Pa]: the measured pressure after every ``pressure`` hook."""
        for effect, values in self.stages["pressure"]:
            pressure = effect.pressure(pressure, values)
        return pressure

    def measured_pressure(self, pressure):
        """P_m [Pa] whose ``pressure`` hooks give ``pressure``: their inverses, last effect first."""
        for effect, values in reversed(self.stages["pressure_inverse"]):
            pressure = effect.pressure_inverse(pressure, values)
        return pressure

    def load(self, axial_load):
        """F_a,eff [N]: the axial load after every ``load`` hook."""
        for effect, values in self.stages["load"]:
            axial_load = effect.load(axial_load, values)
        return axial_load

    def braid_strain(self, tension):
        """Σ fibre strain [-] of the ``braid_strain`` hooks under the total braid tension T [N]."""
        total = None
        for effect, values in self.stages["braid_strain"]:
            term = effect.braid_strain(tension, values)
            if term is not None:
                total = term if total is None else total + term
        return total

    def _sum(self, hook: str, state: State, start):
        total = start
        for effect, values in self.stages[hook]:
            term = getattr(effect, hook)(state, values)
            if term is not None:
                total = total + term
        return total

    def radial_factor(self, state: State):
        """Π f [-] of the ``radial_factor`` hooks (1 without); P-independent for closed-form effects."""
        factor = 1.0
        for effect, values in self.stages["radial_factor"]:
            term = effect.radial_factor(state, values)
            if term is not None:
                factor = factor * term
        return factor

    def contact_increments(self, theta):
        """ΣΔθ [Pa] of the ``contact_increments`` hooks, a vector like ``theta``; None without."""
        total = None
        for effect, values in self.stages["contact_increments"]:
            delta = effect.contact_increments(theta.shape[0], values)
            if delta is not None:
                total = list(delta) if total is None else [t + d for t, d in zip(total, delta, strict=True)]
        return None if total is None else ops.column(total, like=theta)

    def refusals(self) -> dict[str, str]:
        """{name: why} of the effects the closed-form holding pressure cannot carry (see
        :mod:`pampipe.model.effects`)."""
        return {e.name: e.no_closed_form for e, _ in self.active if e.no_closed_form}

    # --------------------------------------------------------------------------------- the forces
    def axial_force(self, pressure, length, geometry, theta, reference_pressure, *, leg=0.0,
                    pressure_leg=0.0):
        """F [N] a test machine measures on the free muscle at (P_meas, L) (signs of the rates: ``leg``, L̇,
        ``pressure_leg``, Ṗ). On a stretching braid D follows the fixed point D = √(B'² − L²)/(Nπ),
        B' = B(1 + strain(T)), T = (F_ax + PπR_i² − σ₁V_b/L)·B/L (Eq. 12)."""
        pressure = self.pressure(pressure)
        base_b = braid_length(geometry)
        n_pi = turns(geometry) * math.pi
        diameter = diameter_at_length(length, geometry)
        force = axial_force(pressure, length, geometry, theta, reference_pressure, diameter=diameter)
        if self.stretches:
            for _ in range(TENSION_ITERATIONS):
                tension = (force + tension_axial_part(pressure, length, diameter, geometry, theta,
                                                      reference_pressure)) * base_b / length
                stretched = base_b * (1 + self.braid_strain(tension))
                diameter = ops.sqrt(stretched**2 - length**2) / n_pi
                force = axial_force(pressure, length, geometry, theta, reference_pressure, diameter=diameter,
                                    stretched=True)
        state = State(pressure, length, diameter, geometry, theta, reference_pressure, leg=leg,
                      pressure_leg=pressure_leg)
        return self._sum("axial_increment", state, force)

    def radial_force(self, pressure, diameter, geometry, theta, reference_pressure, axial_load=0.0,
                     contact_theta=None, *, smoothing=None, clip=True):
        """F_r [N] in a pipe of diameter D at measured pressure P: u = A(L)·(F_ax(P, L, D) + ΣΔF_ax − F_a)·Π f
        + ΣΔF_r, F_r = max(0, u) (``smoothing``, ``clip``: :func:`pampipe.model.forces.contact_switch`).
        L = L(D), or on a stretching braid the fixed point L = √(B'² − (NπD)²), T = (F_a + PπR_i² −
        σ₁V_b/L)·B/L."""
        pressure = self.pressure(pressure)
        load = self.load(axial_load)
        base_b = braid_length(geometry)
        n_pi = turns(geometry) * math.pi
        length = ops.sqrt(base_b**2 - (n_pi * diameter) ** 2)
        if self.stretches:  # fixed point on T (§9b)
            for _ in range(TENSION_ITERATIONS):
                tension = (load + tension_axial_part(pressure, length, diameter, geometry, theta,
                                                     reference_pressure)) * base_b / length
                stretched = base_b * (1 + self.braid_strain(tension))
                length = ops.sqrt(stretched**2 - (n_pi * diameter) ** 2)
        holding = axial_force(pressure, length, geometry, theta, reference_pressure, diameter=diameter,
                              stretched=self.stretches) - load
        if contact_theta is not None:
            anchoring = anchoring_pressure(diameter, geometry, theta, reference_pressure, load)
            holding = holding + contact_force_increment(pressure, length, geometry, contact_theta,
                                                        reference_pressure, anchoring)
        state = State(pressure, length, diameter, geometry, theta, reference_pressure, load, in_pipe=True)
        holding = self._sum("axial_increment", state, holding)
        unclipped = amplification_factor(diameter, geometry, length) * holding
        for effect, values in self.stages["radial_factor"]:
            factor = effect.radial_factor(state, values)
            if factor is not None:
                unclipped = unclipped * factor
        unclipped = self._sum("radial_increment", state, unclipped)
        return contact_switch(unclipped, smoothing, clip)


def _overrides(effect: Effect, hook: str) -> bool:
    """True when ``effect`` has its own ``hook`` (the base class's is the identity)."""
    return getattr(type(effect), hook) is not getattr(Effect, hook)
