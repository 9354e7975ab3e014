"""Optional physical effects missing from the paper's model (docs/physics.md §9): a pluggable library.

Each effect is a small strategy object, one module each (``_braid_friction.py``, …) over the protocol of
:mod:`._base`: a name, named bounded parameters with units and a null value, and one or more *hooks* that
modify a stage of the forward model. At its null value every hook is the identity, so the model reduces
exactly to the baseline (docs/physics.md §4-§7). Hooks work on floats, numpy arrays and CasADi symbols alike.

Stages of the forward model, in order (hooks of several effects compose):

1. ``pressure(P)``: the true gauge pressure from the measured one (sensor offset and gain);
2. ``load(F_a)``: the effective axial load of a pipe test (preload, pulley friction);
3. ``braid_strain(T)``: fibre strain under the total braid tension T (B = B₀(1 + strain), N fixed);
4. ``axial_increment(state)``: ΔF [N] added to the muscle's axial force F_ax (free and anchored);
5. ``radial_factor(state)`` and ``radial_increment(state)``: u ← u·factor + ΔF_r before the contact
   clip F_r = max(0, u), u = A(F_ax − F_a) (docs/physics.md §5.3).

:func:`compose` resolves the active effects once into a :class:`Composed`, which applies the hooks and
evaluates the forces with them (:mod:`._composed`).

Adding an effect: a module ``_name.py`` with a subclass of :class:`Effect` that declares ``name``,
``parameters`` and overrides the hooks it needs, then list it in :data:`LIBRARY` below. Parameter values are
SI inside (``values[name]``).

The closed-form least holding pressure (:meth:`pampipe.model.muscle.Muscle.required_pressure`, which
``pampipe export`` compiles to C) carries an effect whose anchored force stays of the form
A·f·(F₀ + F₁P − F_a + ((P − P_a)₊/P_ref)(C₀ + C₁P)): an affine pressure map with its inverse
(``pressure_inverse``), any load map, a radial factor f that does not depend on P, and contact
increments Δθ (``contact_increments``) as its only in-pipe force increment. An effect that breaks
this says why in ``no_closed_form``.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from pampipe.model.effects._axial_preload import AxialPreload
from pampipe.model.effects._base import Effect, Parameter, State
from pampipe.model.effects._braid_extensibility import BraidExtensibility
from pampipe.model.effects._braid_friction import BraidFriction
from pampipe.model.effects._composed import TENSION_ITERATIONS, Composed
from pampipe.model.effects._contact_stiffening import ContactStiffening
from pampipe.model.effects._end_effects import EndEffects
from pampipe.model.effects._pressure_hysteresis import PressureHysteresis
from pampipe.model.effects._pressure_offset import PressureOffset
from pampipe.model.effects._prestrain import Prestrain
from pampipe.model.effects._wall_friction import WallFriction

__all__ = ["LIBRARY", "TENSION_ITERATIONS", "Active", "AxialPreload", "BraidExtensibility", "BraidFriction",
           "Composed", "ContactStiffening", "Effect", "EndEffects", "Parameter", "PressureHysteresis",
           "PressureOffset", "Prestrain", "State", "WallFriction", "axial_force_with_effects", "compose",
           "get_effect", "radial_force_with_effects"]

#: The registry: every effect the package knows, by name (docs/commands.md §6.1 names).
LIBRARY: dict[str, Effect] = {e.name: e for e in (
    BraidFriction(), BraidExtensibility(), EndEffects(), ContactStiffening(), PressureOffset(),
    AxialPreload(), WallFriction(), PressureHysteresis(), Prestrain())}

Active = Mapping[str, Mapping[str, Any]]  # effect name -> {parameter name: SI value}


def get_effect(name: str) -> Effect:
    """The effect called ``name``; KeyError lists the known names."""
    try:
        return LIBRARY[name]
    except KeyError:
        raise KeyError(f"unknown effect {name!r}; known effects: {', '.join(LIBRARY)}") from None


def compose(effects: Active | None) -> Composed:
    """The active ``effects`` (name → given SI values, nulls filled in) composed once, in the order given."""
    active = []
    for name, given in (effects or {}).items():
        effect = get_effect(name)
        values = effect.null_values
        values.update(given)
        active.append((effect, values))
    return Composed(active)


def axial_force_with_effects(pressure, length, geometry, theta, reference_pressure=1e6,
                             effects: Active | None = None, *, leg=0.0, pressure_leg=0.0):
    """F [N] a test machine measures on the free muscle at (P_meas, L), with ``effects`` switched on.

    ``leg`` is the sign of the length rate (+1 lengthening, −1 shortening), ``pressure_leg`` that
    of the pressure rate (+1 filling, −1 venting). Without effects this is exactly
    :func:`pampipe.model.forces.axial_force` (Eq. 9). See :meth:`Composed.axial_force`.
    """
    return compose(effects).axial_force(pressure, length, geometry, theta, reference_pressure, leg=leg,
                                        pressure_leg=pressure_leg)


def radial_force_with_effects(pressure, diameter, geometry, theta, reference_pressure=1e6, axial_load=0.0,
                              contact_theta=None, effects: Active | None = None, *, smoothing=None,
                              clip=True):
    """F_r [N] of the muscle in a pipe of diameter D at measured pressure P, with ``effects`` on.

    u = A(L)·(F_ax(P, L, D) + Σ ΔF_ax − F_a)·Π factor + Σ ΔF_r, F_r = max(0, u) (or the softplus of
    width ``smoothing`` [N]). L = L(D) unless the braid stretches. Without effects this is exactly
    :func:`pampipe.model.forces.radial_force`. See :meth:`Composed.radial_force`.
    """
    return compose(effects).radial_force(pressure, diameter, geometry, theta, reference_pressure, axial_load,
                                         contact_theta, smoothing=smoothing, clip=clip)
